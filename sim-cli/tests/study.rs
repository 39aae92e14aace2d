//! `sim-cli study`: the batch's files, `--run I` bit-identical to the
//! batch's row I (text equality of the rows: both print each f64 as its
//! shortest round-trip decimal, so equal text is equal bits), exit 2 for bad
//! study files and options.

mod support;

use support::{scratch, sim, text, write_file};

const STUDY: &str = r#"
model = "palmer"
runs = 6
seed = 3
duration_s = 30.0
stop = "touchdown"
script = """
1-5 throttle-down
"""
measures = ["touchdown_x_m", "touchdown_sink_rate_mps", "max_height_m", "time_to_height_s"]
target_height_m = 100.0
[initial]
altitude_ft = 100.0
speed_kt = 65.0
trim = true
[[dispersion]]
key = "initial.speed_kt"
distribution = "normal"
mean = 65.0
sd = 3.0
[[dispersion]]
key = "script_delay_s"
distribution = "uniform"
low = 0.0
high = 1.0
"#;

#[test]
fn batch_writes_runs_csv_and_summary_json() {
    let dir = scratch("study-batch");
    let file = write_file(&dir, "s.toml", STUDY);
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    let o = sim(&["study", &file, "--out", out_s, "--json", "--threads", "2"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["runs"], 6);
    assert_eq!(summary["seed"], 3);
    // The fingerprint of the maths that flew the runs (docs/studies.md).
    assert_eq!(
        summary["maths"],
        format!("{:#018x}", fdm_core::fingerprint::maths())
    );
    let statuses = summary["statuses"].as_object().unwrap();
    let counted: u64 = statuses.values().map(|v| v.as_u64().unwrap()).sum();
    assert_eq!(counted, 6);
    let x = &summary["measures"]["touchdown_x_m"];
    assert_eq!(x["count"], 6);
    for key in ["mean", "p1", "p5", "p50", "p95", "p99"] {
        assert!(x[key].is_f64(), "{key}: {x}");
    }
    assert_eq!(x["ci95"].as_array().unwrap().len(), 2);
    // Never reached 100 m: no values, nulls (never NaN).
    let t = &summary["measures"]["time_to_height_s"];
    assert_eq!(t["count"], 0);
    assert!(t["mean"].is_null());
    let on_disk = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&on_disk).unwrap(),
        summary
    );
    let csv = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "run,status,touchdown_x_m,touchdown_sink_rate_mps,max_height_m,time_to_height_s"
    );
    assert_eq!(lines.len(), 7);
    for (i, line) in lines[1..].iter().enumerate() {
        assert!(line.starts_with(&format!("{i},landed_")), "{line}");
        assert!(line.ends_with(','), "empty time_to_height_s cell: {line}");
    }
    // --run I: the same row, with the flight's own outputs.
    for run in ["0", "4"] {
        let flight_csv = dir.join(format!("flight-{run}.csv"));
        let o = sim(&[
            "study",
            &file,
            "--out",
            out_s,
            "--run",
            run,
            "--csv",
            flight_csv.to_str().unwrap(),
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert!(report["status"].as_str().unwrap().starts_with("landed"));
        let alone = std::fs::read_to_string(out.join(format!("run-{run}.csv"))).unwrap();
        let alone: Vec<&str> = alone.lines().collect();
        assert_eq!(alone[0], lines[0]);
        let i: usize = run.parse().unwrap();
        assert_eq!(alone[1], lines[1 + i]);
        assert!(
            std::fs::read_to_string(&flight_csv)
                .unwrap()
                .lines()
                .count()
                > 100
        );
    }
    // Another thread count, the same file.
    let out2 = dir.join("out2");
    let o = sim(&[
        "study",
        &file,
        "--out",
        out2.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(std::fs::read_to_string(out2.join("runs.csv")).unwrap(), csv);
}

#[test]
fn bad_input_exits_2_with_the_line_and_key() {
    let dir = scratch("study-bad");
    let cases = [
        (STUDY.replace("sd = 3.0", "sd = 0.0"), "dispersion.sd"),
        (STUDY.replace("runs = 6", "runs = 0"), "runs"),
        (STUDY.replace("\"palmer\"", "\"glider\""), "model"),
        (format!("{STUDY}\nwings = 2\n"), "wings"),
    ];
    for (content, key) in cases {
        let file = write_file(&dir, "bad.toml", &content);
        let o = sim(&["study", &file, "--out", dir.to_str().unwrap()]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("line ") && err.contains(key), "{key}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    let file = write_file(&dir, "s.toml", STUDY);
    for (args, needle) in [
        (vec!["--run", "6"], "--run 6"),
        (vec!["--memory-limit-mib", "0"], "MiB"),
        (vec!["--csv", "x.csv"], "--run"),
        (vec!["--run", "1", "--precision", "fast"], "exact"),
    ] {
        let mut argv = vec!["study", file.as_str(), "--out", dir.to_str().unwrap()];
        argv.extend(args);
        let o = sim(&argv);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{argv:?}: {err}");
        assert!(err.contains(needle), "{argv:?}: {err}");
    }
    let o = sim(&["study", "/nonexistent/s.toml"]);
    assert_eq!(o.status.code(), Some(2));
}
