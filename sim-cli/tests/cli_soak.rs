//! Soak through the built binary: one simulated hour of each model with a
//! random script, headless with `--json` and `--csv`, alternately trimmed in
//! cruise (3000 ft, 100 kt) and from the thesis's start. Each run either exits 0
//! with a report and CSV rows that are all finite with z ≥ 0, or exits 1 with
//! the one-line divergence error and finite CSV rows up to the frame before;
//! nothing else.
//!
//! Cost: by default 1, 5 and 10 fps (a debug binary steps about 15 000
//! frames a second here, so 30 and 100 fps would take minutes); with
//! `FDM_SOAK=full`, also 30 and 100 fps (docs/cli.md "Soak tests").

mod support;

use support::{csv_body, scratch, sim, text, write_file};

/// xorshift64*.
fn next(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_f491_4f6c_dd1d)
}

/// A random script over `frames` frames: 40 rules of 1 to 300 frames.
fn random_script(actions: &[&str], frames: u64, seed: u64) -> String {
    let mut s = seed | 1;
    let mut out = String::new();
    for _ in 0..40 {
        let start = 1 + next(&mut s) % frames;
        let end = (start + next(&mut s) % 300).min(frames);
        let action = actions[(next(&mut s) % actions.len() as u64) as usize];
        out.push_str(&format!("{start}-{end} {action}\n"));
    }
    out
}

fn soak(model: &str, actions: &[&str], fps: u32, seed: u64, cruise: bool) {
    let frames = 3600 * u64::from(fps);
    let dir = scratch("soak");
    let script = write_file(&dir, "s.txt", &random_script(actions, frames, seed));
    let csv = dir.join("run.csv");
    let csv = csv.to_str().unwrap();
    let (fps_s, frames_s) = (fps.to_string(), frames.to_string());
    let mut args = vec![
        model,
        "--headless",
        "--json",
        "--fps",
        &fps_s,
        "--frames",
        &frames_s,
        "--script",
        &script,
        "--csv",
        csv,
    ];
    if cruise {
        args.extend_from_slice(&["--altitude-ft", "3000", "--speed-kt", "100", "--trim"]);
    }
    let out = sim(&args);
    let rows = std::fs::read_to_string(csv).unwrap();
    let rows = csv_body(&rows, model);
    let header: Vec<&str> = rows.lines().next().unwrap().split(',').collect();
    let z = header.iter().position(|c| *c == "z").unwrap();
    let mut last_frame = None;
    for line in rows.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(v.iter().all(|x| x.is_finite()), "{model} {fps}: {line}");
        assert!(v[z] >= 0.0, "{model} {fps}: {line}");
        last_frame = Some(v[0]);
    }
    let stdout = text(&out.stdout);
    match out.status.code() {
        Some(0) => {
            assert!(!stdout.contains("null"), "{model} {fps}: {stdout}");
            let r: serde_json::Value = serde_json::from_str(&stdout).unwrap();
            assert!(r["position"][2].as_f64().unwrap() >= 0.0);
            assert_eq!(last_frame, Some(frames as f64));
            println!(
                "{model} {fps} fps (cruise {cruise}): finished, {}",
                r["status"]
            );
        }
        Some(1) => {
            let stderr = text(&out.stderr);
            let line = stderr.trim_end();
            let rest = line
                .strip_prefix("sim-cli: error: frame ")
                .unwrap_or_else(|| panic!("{line}"));
            let (n, message) = rest.split_once(": ").unwrap();
            let n: u64 = n.parse().unwrap();
            assert!(
                message.starts_with(&format!(
                    "the {model} model diverged (non-finite state) at dt = "
                )),
                "{line}"
            );
            assert!(stdout.is_empty());
            assert_eq!(last_frame, Some((n - 1) as f64));
            println!("{model} {fps} fps (cruise {cruise}): diverged at frame {n}");
        }
        code => panic!("{model} {fps}: exit {code:?}: {}", text(&out.stderr)),
    }
}

fn rates() -> &'static [u32] {
    if std::env::var("FDM_SOAK").is_ok_and(|v| v == "full") {
        &[1, 5, 10, 30, 100]
    } else {
        &[1, 5, 10]
    }
}

#[test]
fn palmer_soak_through_the_binary() {
    let actions = [
        "throttle-up",
        "throttle-down",
        "alpha-up",
        "alpha-down",
        "bank-right",
        "bank-left",
        "flaps-down",
        "flaps-up",
    ];
    for (i, &fps) in rates().iter().enumerate() {
        soak(
            "palmer",
            &actions,
            fps,
            0x7061_6c6d ^ u64::from(fps),
            i % 2 == 0,
        );
    }
}

#[test]
fn bourg_soak_through_the_binary() {
    let actions = [
        "thrust-up",
        "thrust-down",
        "pitch-up",
        "pitch-down",
        "roll-left",
        "roll-right",
        "yaw-left",
        "yaw-right",
        "flaps-down",
        "flaps-up",
        "trim-up",
        "trim-down",
    ];
    for (i, &fps) in rates().iter().enumerate() {
        soak(
            "bourg",
            &actions,
            fps,
            0x626f_7572 ^ u64::from(fps),
            i % 2 == 0,
        );
    }
}
