//! A signal stops `sim-cli study` cleanly (issue 25; docs/studies.md
//! "Stopping a study", docs/cli.md "Exit status", 128 + N). A study of ten
//! chunks flies on one thread; once the first chunk's rows are in `runs.csv`
//! (so the second chunk is in flight) it gets SIGTERM or SIGINT, and must then
//!
//! * exit with status 128 + the signal and say `stopped by SIG...` on stderr
//!   (not the grace period's "did not finish its outputs" line),
//! * within 2 s of the signal (the 3 s grace period would end it otherwise;
//!   see `stops_cleanly` for the bound),
//! * having stopped inside the chunk in flight: K runs kept with one chunk ≤ K
//!   < two chunks (the signal comes right after the first chunk's rows appear,
//!   while the second chunk has seconds left to fly),
//! * leave `runs.csv` and `runs.arrow` byte-identical to those of the same
//!   study flown unstopped with `--runs K` (whole rows, runs 0..K in order,
//!   each the same bits), `runs.arrow` a complete Arrow file with K rows (read
//!   here by a minimal reader of the format's footer and record batches),
//! * write `summary.json` and print it (`--json`), equal to the unstopped
//!   `--runs K` summary plus `stopped_by`, `runs_completed` = K and
//!   `runs_planned` = N, and a complete `study.svg`.
//!
//! And `study --run I` stops at the next frame as `sim-cli palmer` does: the
//! flight's own outputs finished, `run-I.csv` not written.
//!
//! The signal is sent with the system's `kill` command.

#![cfg(target_os = "linux")]

mod support;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use support::{csv_body, scratch, sim, text, write_file};

/// Runs per chunk with `--threads 1`: 8 blocks of 1,024 runs
/// (sim-cli/src/study.rs).
const CHUNK_RUNS: u64 = 8 * 1024;

/// Ten chunks of 1 s runs: a chunk is a few seconds of flying in a debug
/// build, the whole study far longer than the test waits.
const RUNS: u64 = 10 * CHUNK_RUNS;

const STUDY: &str = r#"
model = "palmer"
runs = 81920
seed = 21
duration_s = 1.0
measures = ["max_height_m", "final_x_m", "final_height_m", "touchdown_x_m", "touchdown_y_m"]
[controls]
throttle = 1.0
alpha_deg = 4.0
[[dispersion]]
key = "initial.speed_kt"
distribution = "normal"
mean = 70.0
sd = 2.0
"#;

/// How long the test waits for something the study does anyway (its first
/// chunk on disk): generous, for a loaded machine; never reached normally.
const PATIENCE: Duration = Duration::from_secs(600);

/// Waits until `path` holds at least `lines` newlines, failing if `child`
/// ends first or after [`PATIENCE`]. Polls every 10 ms (the study writes the
/// rows once per chunk, seconds apart).
fn wait_for_lines(child: &mut Child, path: &Path, lines: usize) {
    let start = Instant::now();
    loop {
        let have = std::fs::read(path).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
        if have >= lines {
            return;
        }
        if let Some(status) = child.try_wait().expect("poll sim-cli") {
            panic!(
                "sim-cli ended ({status}) before {} had {lines} lines",
                path.display()
            );
        }
        assert!(
            start.elapsed() < PATIENCE,
            "{} has {have} lines after {PATIENCE:?}",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn kill(child: &Child, signal: &str) -> Instant {
    let sent = Instant::now();
    let status = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(status.success(), "kill -{signal}");
    sent
}

/// A little-endian integer of `N` bytes at `at`.
fn le<const N: usize>(bytes: &[u8], at: usize) -> [u8; N] {
    bytes[at..at + N].try_into().expect("inside the file")
}

/// Where field `id` of the flatbuffer table at `table` is, if present.
fn field(buf: &[u8], table: usize, id: usize) -> Option<usize> {
    let vtable = table - i32::from_le_bytes(le(buf, table)) as usize;
    let vtable_len = usize::from(u16::from_le_bytes(le(buf, vtable)));
    let slot = 4 + 2 * id;
    if slot + 2 > vtable_len {
        return None;
    }
    match u16::from_le_bytes(le(buf, vtable + slot)) {
        0 => None,
        offset => Some(table + usize::from(offset)),
    }
}

/// The table an offset field at `at` points to.
fn deref(buf: &[u8], at: usize) -> usize {
    at + u32::from_le_bytes(le(buf, at)) as usize
}

/// The rows of an Arrow IPC file, read as the format's readers do: the
/// magic `ARROW1` at both ends, the footer (flatbuffer `Footer`, field 3:
/// the record batches' blocks: offset i64, metadata length i32, body length
/// i64), and for each block the message at its offset (0xFFFFFFFF, the
/// metadata's length, a flatbuffer `Message` whose header, field 2, is a
/// `RecordBatch` whose field 0 is its `length` in rows).
fn arrow_rows(file: &[u8]) -> u64 {
    assert!(file.starts_with(b"ARROW1\0\0"), "Arrow magic at the start");
    assert!(
        file.ends_with(b"ARROW1"),
        "Arrow magic at the end: complete"
    );
    let footer_len = u32::from_le_bytes(le(file, file.len() - 10)) as usize;
    let footer = &file[file.len() - 10 - footer_len..file.len() - 10];
    let root = deref(footer, 0);
    let Some(batches) = field(footer, root, 3) else {
        return 0;
    };
    let vector = deref(footer, batches);
    let count = u32::from_le_bytes(le(footer, vector)) as usize;
    let mut rows = 0;
    for b in 0..count {
        let block = vector + 4 + 24 * b;
        let offset = i64::from_le_bytes(le(footer, block)) as usize;
        assert_eq!(le::<4>(file, offset), [0xff; 4], "continuation marker");
        let message = &file[offset + 8..];
        let root = deref(message, 0);
        assert_eq!(
            field(message, root, 1).map(|at| message[at]),
            Some(3),
            "a RecordBatch message"
        );
        let header = deref(message, field(message, root, 2).expect("header"));
        let length = field(message, header, 0).map_or(0, |at| i64::from_le_bytes(le(message, at)));
        rows += u64::try_from(length).expect("rows");
    }
    rows
}

fn stops_cleanly(signal: &str, number: i32) {
    let dir = scratch(&format!("study-signal-{signal}"));
    let file = write_file(&dir, "s.toml", STUDY);
    let out = dir.join("out");
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["study", &file, "--out", out.to_str().unwrap()])
        .args(["--threads", "1", "--json"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sim-cli");
    // The header and a first row: the first chunk is flown and being written
    // (rows are written only after their chunk has flown), the second next.
    wait_for_lines(&mut child, &out.join("runs.csv"), 2);
    let first_chunk = started.elapsed();
    let sent = kill(&child, signal);
    let result = child.wait_with_output().expect("wait for sim-cli");
    let stopping = sent.elapsed();
    let stderr = text(&result.stderr);
    eprintln!("{signal}: first chunk after {first_chunk:?}, stopped {stopping:?} after the signal");
    assert_eq!(
        result.status.code(),
        Some(128 + number),
        "{signal}: {stderr}"
    );
    assert!(
        stderr.contains(&format!("sim-cli: stopped by SIG{signal}")),
        "{stderr}"
    );
    assert!(
        !stderr.contains("did not finish"),
        "the grace period ended it: {stderr}"
    );
    // After the signal the study flies at most 16 frames of the block in
    // flight (tens of ms unoptimised), writes at most one chunk of rows and
    // summarises and plots K ≈ 10^4 runs (well under a second). 2 s leaves
    // room for a loaded machine and still catches a stop that only came at
    // the end of the chunk (seconds) or from the grace period (3 s).
    assert!(
        stopping < Duration::from_secs(2),
        "{signal}: stopped after {stopping:?}"
    );

    let csv = std::fs::read(out.join("runs.csv")).expect("runs.csv");
    let k = csv.iter().filter(|&&c| c == b'\n').count() as u64 - 1;
    assert!(csv.ends_with(b"\n"), "whole rows");
    assert!(
        (CHUNK_RUNS..2 * CHUNK_RUNS).contains(&k),
        "{signal}: {k} runs kept: not stopped inside the second chunk"
    );
    let arrow = std::fs::read(out.join("runs.arrow")).expect("runs.arrow");
    assert_eq!(arrow_rows(&arrow), k, "runs.arrow rows");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let printed: serde_json::Value = serde_json::from_slice(&result.stdout).expect("--json");
    assert_eq!(printed, summary, "stdout and summary.json");
    assert_eq!(summary["runs"], k);
    assert_eq!(summary["stopped_by"], format!("SIG{signal}"));
    assert_eq!(summary["runs_completed"], k);
    assert_eq!(summary["runs_planned"], RUNS);
    let plot = std::fs::read_to_string(out.join("study.svg")).expect("study.svg");
    assert!(plot.trim_end().ends_with("</svg>"), "plot unfinished");

    // The same study, unstopped, K runs: the same files.
    let whole = dir.join("whole");
    let k_text = k.to_string();
    let o = sim(&[
        "study",
        &file,
        "--out",
        whole.to_str().unwrap(),
        "--threads",
        "1",
        "--runs",
        &k_text,
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert!(
        std::fs::read(whole.join("runs.csv")).unwrap() == csv,
        "{signal}: runs.csv differs from the unstopped first {k} runs"
    );
    assert!(
        std::fs::read(whole.join("runs.arrow")).unwrap() == arrow,
        "{signal}: runs.arrow differs from the unstopped first {k} runs"
    );
    let mut unstopped: serde_json::Value =
        serde_json::from_slice(&std::fs::read(whole.join("summary.json")).unwrap()).unwrap();
    assert!(unstopped.get("stopped_by").is_none(), "{unstopped}");
    let object = unstopped.as_object_mut().unwrap();
    object.insert("stopped_by".into(), format!("SIG{signal}").into());
    object.insert("runs_completed".into(), k.into());
    object.insert("runs_planned".into(), RUNS.into());
    assert_eq!(summary, unstopped, "{signal}: the summary of the K runs");
}

#[test]
fn sigterm_stops_a_study_inside_a_chunk_and_writes_the_runs_flown() {
    stops_cleanly("TERM", 15);
}

#[test]
fn sigint_stops_a_study_inside_a_chunk_and_writes_the_runs_flown() {
    stops_cleanly("INT", 2);
}

/// The terminal summary says the study was stopped, first.
#[test]
fn the_text_summary_says_the_study_was_stopped() {
    let dir = scratch("study-signal-text");
    let file = write_file(&dir, "s.toml", STUDY);
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args([
            "study",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--threads",
            "1",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sim-cli");
    wait_for_lines(&mut child, &out.join("runs.csv"), 2);
    kill(&child, "TERM");
    let result = child.wait_with_output().expect("wait for sim-cli");
    assert_eq!(result.status.code(), Some(143), "{}", text(&result.stderr));
    let k = std::fs::read_to_string(out.join("runs.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    let stdout = text(&result.stdout);
    let first = stdout.lines().next().unwrap_or_default();
    assert_eq!(
        first,
        format!(
            "stopped by SIGTERM after {k} of {RUNS} runs: the summary is of runs 0 to {} only",
            k - 1
        )
    );
    assert!(
        stdout.contains(&format!("\n{k} runs, seed 21\n")),
        "{stdout}"
    );
}

/// `--run I`: the flight stops at the next frame, its CSV and report are
/// finished for the frames flown, and `run-I.csv` (the batch's row) is not
/// written, since the run was cut short.
#[test]
fn sigterm_stops_a_run_flown_alone_without_its_row() {
    let dir = scratch("study-signal-run");
    // One hour of flight: minutes unoptimised, far longer than the test waits.
    let file = write_file(
        &dir,
        "s.toml",
        &STUDY.replace("duration_s = 1.0", "duration_s = 3600.0"),
    );
    let out = dir.join("out");
    let flight = dir.join("flight.csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["study", &file, "--out", out.to_str().unwrap(), "--run", "3"])
        .args(["--csv", flight.to_str().unwrap(), "--json"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sim-cli");
    // The flight's CSV has rows: the flight alone is under way.
    wait_for_lines(&mut child, &flight, 3);
    let sent = kill(&child, "TERM");
    let result = child.wait_with_output().expect("wait for sim-cli");
    let stopping = sent.elapsed();
    let stderr = text(&result.stderr);
    assert_eq!(result.status.code(), Some(143), "{stderr}");
    assert!(stderr.contains("sim-cli: stopped by SIGTERM"), "{stderr}");
    assert!(!stderr.contains("did not finish"), "{stderr}");
    assert!(
        stopping < Duration::from_secs(2),
        "stopped after {stopping:?}"
    );
    let report: serde_json::Value = serde_json::from_slice(&result.stdout).expect("the report");
    let frames = report["frames"].as_u64().expect("frames flown");
    assert!((1..108_000).contains(&frames), "{frames} frames flown");
    let rows = std::fs::read_to_string(&flight).unwrap();
    let rows = csv_body(&rows, "palmer").lines().count() as u64;
    assert_eq!(
        rows,
        frames + 2,
        "the flight's CSV after its model line: header, frame 0, a row per frame"
    );
    assert!(
        !out.join("run-3.csv").exists(),
        "a run cut short has no batch row"
    );
}
