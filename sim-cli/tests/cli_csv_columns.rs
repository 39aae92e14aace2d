//! Every CSV column of `sim-cli --csv` (docs/cli.md, "CSV output") checked by
//! name: against the JSON report of a run stopped at the same frame (the same
//! quantity, so to the bit), and against a computation of its own (the
//! scripted controls, `|v|`, `atan(vz / vh)`, the Euler angles). A column
//! that carries another column's value, or a wrong value, fails here.

mod support;

use serde_json::Value;
use support::{csv_body, num, report, scratch, write_file};

/// One parsed CSV file: the header and the rows (after the model line).
struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Csv {
    fn read(path: &std::path::Path, model: &str) -> Self {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = csv_body(&text, model).lines();
        let header = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_owned)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        Self { header, rows }
    }

    fn get(&self, row: usize, column: &str) -> f64 {
        let i = self
            .header
            .iter()
            .position(|h| h == column)
            .unwrap_or_else(|| panic!("no column {column}"));
        self.rows[row][i]
    }
}

/// The JSON value a CSV column carries (docs/cli.md: "the same quantities as
/// the JSON report"); booleans as 0/1.
fn json_of(r: &Value, column: &str) -> f64 {
    let at = |v: &Value, i: usize| num(&v[i]);
    let b = |v: &Value| f64::from(u8::from(v.as_bool().expect("bool")));
    match column {
        "time_s" => num(&r["time_s"]),
        "x" | "y" | "z" => at(&r["position"], usize::from(column.as_bytes()[0] - b'x')),
        "vx" | "vy" | "vz" => at(&r["velocity"], usize::from(column.as_bytes()[1] - b'x')),
        "lat_deg" | "lon_deg" | "alt_m" => num(&r["geodetic"][column]),
        "roll_deg" => num(&r["attitude_deg"]["roll"]),
        "pitch_deg" => num(&r["attitude_deg"]["pitch"]),
        "fg_heading_deg" => num(&r["attitude_deg"]["heading"]),
        "throttle" | "alpha_deg" | "bank_deg" | "flaps_deg" => num(&r["controls"][column]),
        "euler_x_deg" => at(&r["euler_deg"], 0),
        "euler_y_deg" => at(&r["euler_deg"], 1),
        "euler_z_deg" => at(&r["euler_deg"], 2),
        "flaps" | "stalling" => b(&r[column]),
        // The CSV's status number for the report's status word (docs/cli.md).
        "status" => {
            let codes = [
                "on_ground",
                "airborne",
                "landed_safe",
                "landed_rough",
                "crashed",
                "diverged",
                "stalling",
            ];
            let word = r["status"].as_str().expect("status word");
            let i = codes.iter().position(|c| *c == word).expect("known status");
            f64::from(u8::try_from(i).unwrap())
        }
        other => num(&r[other]),
    }
}

/// Runs `model` with `script` for `frames` frames, with a CSV, and checks
/// that the CSV's row for each of `stops` carries, column by column, the
/// JSON report of a run stopped at that frame. Returns the CSV.
fn run_and_compare(model: &str, extra: &[&str], script: &str, frames: u64, stops: &[u64]) -> Csv {
    let dir = scratch(&format!("csvcol-{model}"));
    let script = write_file(&dir, "script.txt", script);
    let csv_path = dir.join("out.csv");
    let run = |frames: u64, csv: bool| {
        let frames = frames.to_string();
        let mut args = vec![
            model,
            "--headless",
            "--json",
            "--frames",
            &frames,
            "--script",
            &script,
        ];
        args.extend_from_slice(extra);
        if csv {
            args.extend(["--csv", csv_path.to_str().unwrap()]);
        }
        report(&args)
    };
    run(frames, true);
    let csv = Csv::read(&csv_path, model);
    assert_eq!(csv.rows.len() as u64, frames + 1, "{model}");
    for &stop in stops {
        let r = run(stop, false);
        let row = usize::try_from(stop).unwrap();
        assert_eq!(csv.get(row, "frame"), stop as f64);
        for column in csv.header.iter().skip(1) {
            let (got, want) = (csv.get(row, column), json_of(&r, column));
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{model} frame {stop}: CSV {column} = {got}, JSON {want}"
            );
        }
    }
    csv
}

#[test]
fn palmer_csv_columns() {
    // From --throttle 0.5 --alpha 4 on the runway: throttle +5 % on frames
    // 2..5, alpha +1° on 3..4, bank right on 4..9, flaps 20 on 6 and 40 on
    // 8, throttle -5 % on 40..41, alpha -1° on 45.
    let script = "2-5 throttle-up\n3-4 alpha-up\n4-9 bank-right\n6-6 flaps-down\n\
                  8-8 flaps-down\n40-41 throttle-down\n45-45 alpha-down\n";
    let frames = 300;
    let csv = run_and_compare(
        "palmer",
        &["--throttle", "0.5", "--alpha", "4", "--fps", "10"],
        script,
        frames,
        &[1, 7, 42, frames],
    );
    let header: Vec<&str> = csv.header.iter().map(String::as_str).collect();
    assert_eq!(
        header,
        [
            "frame",
            "time_s",
            "x",
            "y",
            "z",
            "vx",
            "vy",
            "vz",
            "lat_deg",
            "lon_deg",
            "alt_m",
            "roll_deg",
            "pitch_deg",
            "fg_heading_deg",
            "airspeed",
            "throttle",
            "alpha_deg",
            "bank_deg",
            "flaps_deg",
            "climb_angle_deg",
            "climb_rate",
            "heading_deg",
            "status"
        ]
    );
    let count = |lo: u64, hi: u64, f: u64| f.clamp(lo - 1, hi) + 1 - lo;
    let mut seen_climb = false;
    for (i, _) in csv.rows.iter().enumerate() {
        let f = i as u64;
        let g = |c: &str| csv.get(i, c);
        // The controls the script set, counted here.
        let throttle = 0.5 + 0.05 * count(2, 5, f) as f64 - 0.05 * count(40, 41, f) as f64;
        let alpha = 4.0 + count(3, 4, f) as f64 - count(45, 45, f) as f64;
        let bank = count(4, 9, f) as f64;
        let flaps = 20.0 * (count(6, 6, f) + count(8, 8, f)) as f64;
        assert!(
            (g("throttle") - throttle).abs() < 1e-12,
            "frame {f}: throttle {}",
            g("throttle")
        );
        assert_eq!(g("alpha_deg"), alpha, "frame {f}");
        assert_eq!(g("bank_deg"), bank, "frame {f}");
        assert_eq!(g("flaps_deg"), flaps, "frame {f}");
        // time: f steps of 0.1 s (f64 sums: within 1e-12).
        assert!((g("time_s") - 0.1 * f as f64).abs() < 1e-12, "frame {f}");
        // Derived quantities from the velocity columns (the same formulas,
        // evaluated here: 1e-12 relative for a different operation order).
        let (vx, vy, vz) = (g("vx"), g("vy"), g("vz"));
        let speed = (vx * vx + vy * vy + vz * vz).sqrt();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
        assert!(
            close(g("airspeed"), speed),
            "frame {f}: airspeed {} vs |v| {speed}",
            g("airspeed")
        );
        assert_eq!(g("climb_rate"), vz, "frame {f}");
        if vx.hypot(vy) > 1.0 {
            let climb = (vz / vx.hypot(vy)).atan().to_degrees();
            assert!(close(g("climb_angle_deg"), climb), "frame {f}: climb angle");
            let heading = vy.atan2(vx).to_degrees().rem_euclid(360.0);
            assert!(
                close(g("heading_deg"), heading) || (g("heading_deg") - heading).abs() > 359.999,
                "frame {f}: heading {} vs {heading}",
                g("heading_deg")
            );
            seen_climb |= climb.abs() > 0.5;
        }
        assert!(g("flaps_deg") <= 40.0 && g("throttle") <= 1.0);
    }
    assert!(seen_climb, "the flight never climbed or sank");
}

#[test]
fn bourg_csv_columns() {
    // Thrust +100 lb on 1..5, a roll on frame 1 (with the body velocity still
    // zero every element sees 0°, where the trailing-edge-up section's lift
    // coefficient is exactly 0: the stall flag is on for frame 1 only, see
    // fdm-core/tests/bourg_stall.rs), flaps down on 20, pitch pulses,
    // thrust -100 lb on 50..51.
    let script = "1-5 thrust-up\n1-1 roll-right\n20-20 flaps-down\n10-30 pitch-up\n\
                  33-34 yaw-left\n50-51 thrust-down\n";
    let frames = 90;
    let csv = run_and_compare("bourg", &[], script, frames, &[1, 2, 21, frames]);
    let header: Vec<&str> = csv.header.iter().map(String::as_str).collect();
    assert_eq!(
        header,
        [
            "frame",
            "time_s",
            "x",
            "y",
            "z",
            "vx",
            "vy",
            "vz",
            "lat_deg",
            "lon_deg",
            "alt_m",
            "roll_deg",
            "pitch_deg",
            "fg_heading_deg",
            "speed",
            "euler_x_deg",
            "euler_y_deg",
            "euler_z_deg",
            "thrust_lb",
            "flaps",
            "stalling",
            "pitch_trim",
            "status"
        ]
    );
    let count = |lo: u64, hi: u64, f: u64| f.clamp(lo - 1, hi) + 1 - lo;
    for (i, _) in csv.rows.iter().enumerate() {
        let f = i as u64;
        let g = |c: &str| csv.get(i, c);
        let thrust = 500.0 + 100.0 * count(1, 5, f) as f64 - 100.0 * count(50, 51, f) as f64;
        assert_eq!(g("thrust_lb"), thrust, "frame {f}");
        assert_eq!(g("flaps"), f64::from(u8::from(f >= 20)), "frame {f}");
        assert_eq!(g("stalling"), f64::from(u8::from(f == 1)), "frame {f}");
        assert!((g("time_s") - f as f64 / 30.0).abs() < 1e-5, "frame {f}");
        // speed = |velocity| in the model's f32.
        let v = [g("vx"), g("vy"), g("vz")].map(|x| x as f32);
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!(
            (g("speed") as f32 - speed).abs() <= 2.0 * f32::EPSILON * speed,
            "frame {f}: speed {} vs |v| {speed}",
            g("speed")
        );
        // FlightGear's attitude from the model's Euler angles: roll = x,
        // pitch = −y (the model's y is nose-down), heading = −z (the model's
        // z is toward west) in [0, 360). The local vertical at the aircraft
        // is tilted from the model's by its distance from the origin (about
        // 1.5 km: 0.014°), so 0.03° of tolerance.
        let close = |a: f64, b: f64| {
            let d = (a - b).rem_euclid(360.0);
            d.min(360.0 - d) < 0.03
        };
        assert!(close(g("roll_deg"), g("euler_x_deg")), "frame {f}: roll");
        assert!(close(g("pitch_deg"), -g("euler_y_deg")), "frame {f}: pitch");
        assert!(
            close(g("fg_heading_deg"), -g("euler_z_deg")),
            "frame {f}: heading"
        );
    }
    // The flight moved every attitude column and the sideways velocity.
    let last = csv.rows.len() - 1;
    for c in ["euler_x_deg", "euler_y_deg", "euler_z_deg", "vy"] {
        assert!(
            csv.get(last, c).abs() > 1e-3,
            "{c} stayed at {}",
            csv.get(last, c)
        );
    }
}
