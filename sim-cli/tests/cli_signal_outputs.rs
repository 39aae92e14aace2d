//! A signal finishes every output (issue 23, item 3; docs/cli.md "Exit
//! status", 128 + N): a headless real-time flight with `--csv`, `--record`,
//! `--plot` and `--json` gets SIGTERM, SIGHUP, SIGINT or SIGQUIT after about a
//! second and must then
//!
//! * exit with status 128 + the signal and say `stopped by SIG...` on stderr,
//! * print the JSON report of the frames it flew,
//! * leave a complete recording (with its end marker: `replay` exits 0) whose
//!   replay prints that same report (apart from the pacing's `realtime` field),
//! * leave a complete SVG plot and a CSV with a row per frame flown.
//!
//! (Before the run loops looked at the stop request, the recording and the plot
//! were left at 0 bytes.) The signal is sent with the system's `kill` command.

#![cfg(target_os = "linux")]

mod support;

use std::process::{Command, Stdio};
use std::time::Duration;

use support::{csv_body, scratch, sim, text};

fn signal_finishes_every_output(signal: &str, number: i32) {
    let dir = scratch(&format!("signal-outputs-{signal}"));
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let (csv, rec, svg) = (path("f.csv"), path("f.rec"), path("f.svg"));
    let child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args([
            "palmer",
            "--headless",
            "--realtime",
            "--frames",
            "100000",
            "--throttle",
            "1",
            "--json",
            "--csv",
            &csv,
            "--record",
            &rec,
            "--plot",
            &svg,
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sim-cli");
    std::thread::sleep(Duration::from_millis(1200));
    let status = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(status.success(), "kill -{signal}");
    let out = child.wait_with_output().expect("wait for sim-cli");
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(128 + number), "{signal}: {stderr}");
    assert!(
        stderr.contains(&format!("stopped by SIG{signal}")),
        "{stderr}"
    );
    let report = text(&out.stdout);
    let json: serde_json::Value = serde_json::from_str(report.trim_end()).expect("the report");
    let frames = json["frames"].as_u64().expect("frames flown");
    assert!(
        (1..100_000).contains(&frames),
        "{signal}: {frames} frames flown"
    );
    // The recording is complete and replays to the report the run printed.
    let replay = sim(&["replay", &rec, "--json"]);
    assert_eq!(
        replay.status.code(),
        Some(0),
        "{signal}: {}",
        text(&replay.stderr)
    );
    // (The flight was paced, so its report also has `realtime`, which a
    // replay without --realtime does not.)
    let mut flown = json.clone();
    flown.as_object_mut().unwrap().remove("realtime");
    let replayed: serde_json::Value =
        serde_json::from_str(text(&replay.stdout).trim_end()).expect("the replay's report");
    assert_eq!(replayed, flown, "{signal}: replay differs");
    // The plot is a whole SVG document, the CSV a row per frame plus header and frame 0.
    let plot = std::fs::read_to_string(&svg).expect("the plot");
    assert!(
        plot.trim_end().ends_with("</svg>"),
        "{signal}: plot unfinished"
    );
    let rows = csv_body(&std::fs::read_to_string(&csv).expect("the CSV"), "palmer")
        .lines()
        .count() as u64;
    assert_eq!(rows, frames + 2, "{signal}: CSV rows");
}

#[test]
fn sigterm_finishes_recording_plot_csv_and_report() {
    signal_finishes_every_output("TERM", 15);
}

#[test]
fn sighup_finishes_recording_plot_csv_and_report() {
    signal_finishes_every_output("HUP", 1);
}

#[test]
fn sigint_finishes_recording_plot_csv_and_report() {
    signal_finishes_every_output("INT", 2);
}

#[test]
fn sigquit_finishes_recording_plot_csv_and_report() {
    signal_finishes_every_output("QUIT", 3);
}
