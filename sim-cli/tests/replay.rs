//! `--record FILE` and `sim-cli replay FILE` through the built binary
//! (docs/recording.md): the replay's JSON report and CSV equal the recorded
//! flight's byte for byte, and bad recordings are refused with exit status 2
//! and one line naming the problem.

mod support;

use support::{scratch, sim, sim_ok, text};

const EXAMPLES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/scripts/");

/// Runs `args`, expects exit status 2 and one stderr line containing `needle`.
#[track_caller]
fn refused(args: &[&str], needle: &str) {
    let out = sim(args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: stderr {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("sim-cli: error: "), "{stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Tolerance 0: the JSON and CSV print every f64 in its shortest round-trip
/// form, so equal text is equal bits.
#[test]
fn replays_equal_the_recorded_flights() {
    let dir = scratch("replay");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (model, fps, frames, script, extra) in [
        (
            "palmer",
            "30",
            "3600",
            "palmer_climb_turn.txt",
            &["--throttle", "0.3", "--bank", "-2"][..],
        ),
        ("bourg", "30", "900", "bourg_roll.txt", &[][..]),
        (
            "bourg",
            "60",
            "1000",
            "bourg_roll.txt",
            &["--origin", "37.6,-122.4,4"][..],
        ),
    ] {
        let script = format!("{EXAMPLES}{script}");
        let (rec, csv1, csv2) = (path("f.rec"), path("1.csv"), path("2.csv"));
        let mut args = vec![
            model,
            "--headless",
            "--json",
            "--fps",
            fps,
            "--frames",
            frames,
            "--script",
            &script,
            "--csv",
            &csv1,
            "--record",
            &rec,
        ];
        args.extend_from_slice(extra);
        let original = sim_ok(&args);
        let replayed = sim_ok(&["replay", &rec, "--json", "--csv", &csv2]);
        assert_eq!(original, replayed, "{model}");
        assert_eq!(
            std::fs::read(&csv1).unwrap(),
            std::fs::read(&csv2).unwrap(),
            "{model}"
        );
        // Without --json: the human summary and what was replayed.
        let summary = sim_ok(&["replay", &rec]);
        assert!(
            summary.starts_with(&format!("{model}: {frames} frames at {fps} fps")),
            "{summary}"
        );
        assert!(summary.contains(" frames, 0 resets"), "{summary}");
    }
}

/// `replay --realtime` paces the recorded frames at 1/fps of wall clock; the
/// report is the original's plus its `realtime` field.
#[test]
fn realtime_replays_take_the_flights_time() {
    let dir = scratch("replay-rt");
    let rec = dir.join("rt.rec").to_str().unwrap().to_owned();
    let script = format!("{EXAMPLES}bourg_roll.txt");
    let original = sim_ok(&[
        "bourg",
        "--headless",
        "--json",
        "--frames",
        "60",
        "--script",
        &script,
        "--record",
        &rec,
    ]);
    let start = std::time::Instant::now();
    let paced = sim_ok(&["replay", &rec, "--json", "--realtime"]);
    // 60 frames at 30 fps: 2 s of wall clock, less at most one frame period.
    let took = start.elapsed().as_secs_f64();
    assert!(took > 1.9, "{took} s");
    let mut paced: serde_json::Value = serde_json::from_str(&paced).unwrap();
    assert!(paced["realtime"]["overruns"].is_u64(), "{paced}");
    paced.as_object_mut().unwrap().remove("realtime");
    assert_eq!(
        paced,
        serde_json::from_str::<serde_json::Value>(&original).unwrap()
    );
}

#[test]
fn bad_recordings_are_refused_with_status_2_and_cut_ones_replayed_with_3() {
    let dir = scratch("replay-bad");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let rec = path("good.rec");
    sim_ok(&[
        "palmer",
        "--headless",
        "--frames",
        "100",
        "--throttle",
        "1",
        "--record",
        &rec,
    ]);
    let good = std::fs::read(&rec).unwrap();

    let write = |name: &str, bytes: &[u8]| {
        let p = path(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    // Cut (its end block lost, as when the recording run is killed): the
    // intact blocks are replayed, the status is 3 and stderr says where the
    // cut is (docs/recording.md, "A cut recording"). 100 frames at 30 fps fill
    // three one-second blocks and leave 10 frames in the last one.
    let cut = sim(&[
        "replay",
        &write("cut.rec", &good[..good.len() - 3]),
        "--json",
    ]);
    let stderr = text(&cut.stderr);
    assert_eq!(cut.status.code(), Some(3), "cut: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("cut at byte") && stderr.contains("the 100 frames before the cut"),
        "{stderr}"
    );
    let report: serde_json::Value = serde_json::from_str(&text(&cut.stdout)).unwrap();
    assert_eq!(report["frames"], 100, "{report}");
    // Cut inside the header: nothing to replay.
    refused(&["replay", &write("header.rec", &good[..40])], "truncated");
    let mut flipped = good.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10;
    refused(
        &["replay", &write("flip.rec", &flipped)],
        "corrupt recording",
    );
    let mut v9 = good.clone();
    v9[8] = 9;
    refused(&["replay", &write("v9.rec", &v9)], "format version 9");
    // A model no registry has (not `glider`: the `glider` feature adds one).
    let mut unknown = good.clone();
    let at = good.windows(6).position(|w| w == b"palmer").unwrap();
    unknown[at..at + 6].copy_from_slice(b"nosuch");
    refused(
        &["replay", &write("nosuch.rec", &unknown)],
        "model `nosuch`",
    );
    refused(
        &["replay", &write("text.rec", b"1-5 thrust-up\n")],
        "not a sim-cli recording",
    );
    refused(&["replay", &write("empty.rec", b"")], "truncated");
    refused(&["replay", &path("missing.rec")], "cannot read recording");
    // Over the size limit: refused before reading it all (a sparse file).
    let big = path("big.rec");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(64 * 1024 * 1024 + 1)
        .unwrap();
    refused(&["replay", &big], "larger than the 64 MiB limit");
    refused(&["replay", "/dev/zero"], "give a regular file or a pipe");
    // With --plot too, the recording is finished (the plot wrapper passes the end on).
    let (plotted, svg) = (path("plotted.rec"), path("p.svg"));
    let original = sim_ok(&[
        "bourg",
        "--headless",
        "--json",
        "--frames",
        "30",
        "--plot",
        &svg,
        "--record",
        &plotted,
    ]);
    assert_eq!(sim_ok(&["replay", &plotted, "--json"]), original);
    refused(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--plot",
            &svg,
            "--record",
            &svg,
        ],
        "also the --plot file",
    );
    // --record must not clobber the script.
    let script = path("s.txt");
    std::fs::write(&script, "1-2 throttle-up\n").unwrap();
    refused(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--script",
            &script,
            "--record",
            &script,
        ],
        "also the --script file",
    );
    assert_eq!(
        std::fs::read_to_string(&script).unwrap(),
        "1-2 throttle-up\n"
    );
}

/// `replay --plot` draws what the recorded run's `--plot` drew, byte for byte
/// (tolerance 0: the same samples through the same drawing), and refuses to
/// overwrite the recording or its own `--csv` (exit status 2, the recording
/// left as it was).
#[test]
fn replay_plots_equal_the_recorded_runs_plots() {
    let dir = scratch("replay-plot");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (model, script) in [
        ("palmer", "palmer_climb_turn.txt"),
        ("bourg", "bourg_roll.txt"),
    ] {
        let script = format!("{EXAMPLES}{script}");
        let (rec, plot1, plot2) = (path("p.rec"), path("1.svg"), path("2.svg"));
        sim_ok(&[
            model,
            "--headless",
            "--fps",
            "30",
            "--frames",
            "600",
            "--script",
            &script,
            "--plot",
            &plot1,
            "--record",
            &rec,
        ]);
        sim_ok(&["replay", &rec, "--plot", &plot2]);
        let (original, replayed) = (
            std::fs::read(&plot1).unwrap(),
            std::fs::read(&plot2).unwrap(),
        );
        assert!(original.starts_with(b"<svg"), "{model}");
        assert!(original == replayed, "{model}: the replay's plot differs");
        let recorded = std::fs::read(&rec).unwrap();
        refused(
            &["replay", &rec, "--plot", &rec],
            "would overwrite the recording",
        );
        let csv = path("r.csv");
        refused(
            &["replay", &rec, "--csv", &csv, "--plot", &csv],
            "would overwrite the --csv file",
        );
        assert_eq!(std::fs::read(&rec).unwrap(), recorded, "{model}");
    }
}
