//! Helpers shared by the binary tests: run the built `sim-cli`, parse its JSON
//! report, scratch directories, reference files.

#![allow(dead_code)] // each test crate uses a different subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};

use serde_json::Value;

/// Runs sim-cli with `args` and stdin from /dev/null (as in CI, no terminal).
pub fn sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run sim-cli")
}

/// Runs sim-cli with `args`, checks it exited 0 (else fails naming the
/// arguments and showing stderr), and returns its stdout.
#[track_caller]
pub fn sim_ok(args: &[&str]) -> String {
    let out = sim(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: stderr {}",
        text(&out.stderr)
    );
    text(&out.stdout)
}

/// Lossy UTF-8 text of an output stream.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs a headless `--json` run, checks it succeeded with exactly one line of JSON
/// on stdout, and returns the parsed report.
#[track_caller]
pub fn report(args: &[&str]) -> Value {
    let out = sim(args);
    let stdout = text(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: stderr {}",
        text(&out.stderr)
    );
    assert_eq!(stdout.lines().count(), 1, "{args:?}: stdout {stdout:?}");
    serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{args:?}: {e}: {stdout}"))
}

/// A number of the report (panics with the field's name otherwise).
#[track_caller]
pub fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A JSON array of three numbers.
#[track_caller]
pub fn triple(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap_or_else(|| panic!("not an array: {v}"));
    assert_eq!(a.len(), 3, "{v}");
    [num(&a[0]), num(&a[1]), num(&a[2])]
}

/// Reads and parses `reference/NAME` of the workspace (serde_json with
/// `float_roundtrip`, so every decimal is read correctly rounded).
pub fn reference(name: &str) -> Value {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../reference")).join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("parsing {}: {e}", path.display()))
}

/// A fresh scratch directory for one test, removed when dropped.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A new, empty scratch directory under the system's temp directory.
pub fn scratch(tag: &str) -> Scratch {
    static N: AtomicU32 = AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!(
        "sim-cli-{tag}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    Scratch(dir)
}

/// Writes `content` to `dir/name` and returns the path as a string.
pub fn write_file(dir: &Path, name: &str, content: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.to_str().expect("UTF-8 temp path").to_owned()
}

/// A flight CSV's text after its first line, which must be the model line
/// `# model: MODEL` (docs/cli.md, "CSV output"): the header and the rows.
pub fn csv_body<'a>(csv: &'a str, model: &str) -> &'a str {
    let (first, body) = csv
        .split_once('\n')
        .unwrap_or_else(|| panic!("no line after the model line: {csv:?}"));
    assert_eq!(first, format!("# model: {model}"), "the CSV's model line");
    assert!(
        body.starts_with("frame,time_s,"),
        "the header follows the model line: {body:?}"
    );
    body
}
