//! The command-line contract of docs/cli.md, checked on the built binary: every kind of
//! bad input exits with status 2, one `sim-cli: error:` line on stderr and nothing on
//! stdout; help and `fgfs-command` work.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};

/// Runs sim-cli with `args` and stdin from /dev/null (as in CI, no terminal).
fn sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run sim-cli")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Asserts the usage-error shape and that the message contains every needle.
#[track_caller]
fn assert_usage_error(args: &[&str], needles: &[&str]) {
    let out = sim(args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: stderr {stderr:?}");
    assert!(
        out.stdout.is_empty(),
        "{args:?}: stdout {:?}",
        text(&out.stdout)
    );
    assert_eq!(
        stderr.lines().count(),
        1,
        "{args:?}: not one line: {stderr:?}"
    );
    assert!(
        stderr.starts_with("sim-cli: error: "),
        "{args:?}: {stderr:?}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    for needle in needles {
        assert!(
            stderr.contains(needle),
            "{args:?}: {stderr:?} lacks {needle:?}"
        );
    }
}

/// A fresh scratch directory for one test, removed when dropped.
struct Scratch(PathBuf);

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

fn scratch() -> Scratch {
    static N: AtomicU32 = AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!(
        "sim-cli-test-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    Scratch(dir)
}

/// Writes a script file and returns its path as a string.
fn script(dir: &Path, name: &str, content: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.to_str().unwrap().to_owned()
}

#[test]
fn bad_fps() {
    // A whole number of frames per second, 1..10000 (the ECS's frame rate is a u32).
    for fps in [
        "0", "-1", "NaN", "inf", "abc", "1e9", "", "29.97", "30.0", "10001",
    ] {
        assert_usage_error(
            &["palmer", "--headless", "--frames", "1", "--fps", fps],
            &["--fps"],
        );
    }
}

#[test]
fn headless_needs_a_length() {
    assert_usage_error(&["palmer", "--headless"], &["--frames", "--duration"]);
    assert_usage_error(
        &["bourg", "--headless", "--json"],
        &["--frames", "--duration"],
    );
}

#[test]
fn frames_and_duration_exclude_each_other() {
    assert_usage_error(
        &["bourg", "--headless", "--frames", "10", "--duration", "1"],
        &["--frames", "--duration"],
    );
}

#[test]
fn bad_lengths() {
    for args in [
        &["--frames", "-1"][..],
        &["--frames", "1.5"][..],
        &["--frames", "99999999999"][..],
        &["--duration", "-2"][..],
        &["--duration", "NaN"][..],
        &["--duration", "1e300"][..],
    ] {
        let mut argv = vec!["palmer", "--headless"];
        argv.extend_from_slice(args);
        assert_usage_error(&argv, &[args[0]]);
    }
}

#[test]
fn options_that_need_headless() {
    assert_usage_error(&["palmer", "--json"], &["--json needs --headless"]);
    assert_usage_error(&["bourg", "--frames", "3"], &["--frames needs --headless"]);
}

#[test]
fn unreadable_script() {
    let dir = scratch();
    let missing = dir.join("missing.txt");
    assert_usage_error(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--script",
            missing.to_str().unwrap(),
        ],
        &["cannot read script", "missing.txt"],
    );
}

#[test]
fn bad_script_lines_name_file_and_line() {
    let dir = scratch();
    let cases = [
        (
            "malformed.txt",
            "# header\n1-5 throttle-up\nthrottle-up\n",
            ":3: ",
            "START-END",
        ),
        (
            "action.txt",
            "1-5 throttle-up\n6-7 fly-upside-down\n",
            ":2: ",
            "unknown action `fly-upside-down`",
        ),
        (
            "order.txt",
            "\n\n5-3 throttle-up\n",
            ":3: ",
            "ends before it starts",
        ),
        ("zero.txt", "0-3 throttle-up\n", ":1: ", "counted from 1"),
        (
            "frame.txt",
            "1-x throttle-up\n",
            ":1: ",
            "not a frame number",
        ),
    ];
    for (name, content, line, message) in cases {
        let path = script(&dir, name, content);
        let file_and_line = format!("{path}{line}");
        assert_usage_error(
            &["palmer", "--headless", "--frames", "10", "--script", &path],
            &[&file_and_line, message],
        );
    }
}

/// The malformed-line hint's example is one of the model's own actions:
/// Palmer's names `throttle-up`, never Bourg's `thrust-up`, and Bourg's the other way round.
#[test]
fn the_malformed_line_hint_names_the_models_own_action() {
    let dir = scratch();
    let path = script(&dir, "malformed.txt", "throttle-up\n");
    for (model, own, other) in [
        ("palmer", "`1-5 throttle-up`", "thrust-up"),
        ("bourg", "`1-5 thrust-up`", "throttle-up`)"),
    ] {
        let out = sim(&[model, "--headless", "--frames", "10", "--script", &path]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{model}: {stderr}");
        assert!(stderr.contains(own), "{model}: {stderr}");
        assert!(!stderr.contains(other), "{model}: {stderr}");
    }
}

#[test]
fn script_actions_belong_to_the_model() {
    let dir = scratch();
    let path = script(&dir, "palmer.txt", "1-5 throttle-up\n");
    assert_usage_error(
        &["bourg", "--headless", "--frames", "10", "--script", &path],
        &[":1: unknown action `throttle-up`", "thrust-up"],
    );
}

#[test]
fn a_bad_script_runs_nothing_and_creates_no_csv() {
    let dir = scratch();
    let path = script(&dir, "bad.txt", "1-2 pitch-up\n2-1 pitch-up\n");
    let csv = dir.join("out.csv");
    assert_usage_error(
        &[
            "bourg",
            "--headless",
            "--frames",
            "10",
            "--script",
            &path,
            "--csv",
            csv.to_str().unwrap(),
        ],
        &[":2: "],
    );
    assert!(!csv.exists());
}

#[test]
fn unwritable_csv() {
    let dir = scratch();
    let csv = dir.join("no-such-dir").join("out.csv");
    assert_usage_error(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--csv",
            csv.to_str().unwrap(),
        ],
        &["cannot create CSV file", "out.csv"],
    );
    // A directory is not a file either.
    assert_usage_error(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--csv",
            dir.to_str().unwrap(),
        ],
        &["cannot create CSV file"],
    );
}

#[test]
fn bad_origin() {
    for origin in [
        "91,0,0",
        "-91,0,0",
        "0,181,0",
        "0,-180.5,0",
        "1,2",
        "1,2,3,4",
        "a,b,c",
        "NaN,0,0",
        "0,0,1e9",
        "",
    ] {
        let arg = format!("--origin={origin}");
        assert_usage_error(
            &["bourg", "--headless", "--frames", "1", &arg],
            &["--origin"],
        );
    }
    // A negative latitude as a separate argument is a value, not an option.
    assert_usage_error(
        &[
            "bourg",
            "--headless",
            "--frames",
            "1",
            "--origin",
            "-95,0,0",
        ],
        &["latitude", "-95"],
    );
}

#[test]
fn bad_fg_address_format() {
    for fg in [
        "localhost",
        "5500",
        ":5500",
        "host:",
        "host:0",
        "host:70000",
        "[::1]:5500",
        "a b:1",
        "300.0.0.1:5500",
    ] {
        assert_usage_error(
            &["palmer", "--headless", "--frames", "1", "--fg", fg],
            &["--fg"],
        );
    }
}

#[test]
fn palmer_controls_out_of_range() {
    for (option, value) in [
        ("--throttle", "1.5"),
        ("--throttle", "-0.1"),
        ("--alpha", "20.5"),
        ("--alpha", "-17"),
        ("--bank", "21"),
        ("--bank", "-20.01"),
        ("--alpha", "NaN"),
    ] {
        assert_usage_error(
            &["palmer", "--headless", "--frames", "1", option, value],
            &[option],
        );
    }
}

#[test]
fn bad_flaps() {
    for flaps in ["10", "-20", "20.0", "sixty", "60"] {
        assert_usage_error(
            &["palmer", "--headless", "--frames", "1", "--flaps", flaps],
            &["--flaps"],
        );
    }
}

#[test]
fn palmer_options_are_not_bourg_options() {
    assert_usage_error(
        &["bourg", "--headless", "--frames", "1", "--throttle", "0.5"],
        &["--throttle"],
    );
}

#[test]
fn missing_or_unknown_subcommand() {
    assert_usage_error(&[], &["missing subcommand"]);
    assert_usage_error(&["fly"], &["fly"]);
}

#[test]
fn interactive_without_a_terminal_points_to_headless() {
    assert_usage_error(&["palmer"], &["terminal", "--headless"]);
    assert_usage_error(&["bourg", "--fps", "60"], &["terminal", "--headless"]);
}

#[test]
fn valid_headless_input_passes_validation() {
    let dir = scratch();
    let path = script(&dir, "ok.txt", "# climb\n1-5 throttle-up\n7-7 flaps-down\n");
    // A socket of this test's own, so the datagrams go nowhere else (a fixed port
    // once steered a live FlightGear listening on it).
    let sink = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let fg = sink.local_addr().unwrap().to_string();
    for args in [
        vec![
            "palmer",
            "--headless",
            "--frames",
            "600",
            "--fps",
            "10",
            "--throttle",
            "1",
            "--alpha",
            "-16",
            "--bank",
            "-20",
            "--flaps",
            "40",
            "--json",
            "--script",
            &path,
            "--origin",
            "-33.9,151.2,6",
            "--fg",
            &fg,
        ],
        vec!["palmer", "--headless", "--duration", "0"],
    ] {
        let out = sim(&args);
        assert_ne!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            text(&out.stderr)
        );
        assert!(!text(&out.stderr).contains("panicked"));
    }
}

#[test]
fn help_lists_subcommands_and_units() {
    let out = sim(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    let help = text(&out.stdout);
    for word in ["palmer", "bourg", "fgfs-command"] {
        assert!(help.contains(word), "{help}");
    }
    let out = sim(&["palmer", "--help"]);
    assert_eq!(out.status.code(), Some(0));
    let help = text(&out.stdout);
    for word in [
        "--fps",
        "--headless",
        "--frames",
        "--duration",
        "--script",
        "--json",
        "--csv",
        "--fg",
        "--origin",
        "--throttle",
        "--alpha",
        "--bank",
        "--flaps",
        "seconds",
        "degrees",
        "(m)",
        "fraction",
    ] {
        assert!(help.contains(word), "palmer help lacks {word}: {help}");
    }
    let help = text(&sim(&["bourg", "--help"]).stdout);
    assert!(help.contains("--origin") && !help.contains("--throttle"));
}

#[test]
fn fgfs_command_palmer() {
    let out = sim(&["fgfs-command", "palmer"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stderr.is_empty());
    let stdout = text(&out.stdout);
    assert_eq!(stdout.lines().count(), 1);
    assert!(stdout.starts_with("fgfs "));
    for part in [
        "--native-fdm=socket,in,30,",
        "--fdm=null",
        "--aircraft=c172p",
        "--lat=39.8264",
        "--lon=-84.0483",
        "--heading=0",
        "--timeofday=noon",
        "--disable-real-weather-fetch",
    ] {
        assert!(stdout.contains(part), "{stdout} lacks {part}");
    }
}

#[test]
fn fgfs_command_bourg_with_options() {
    let out = sim(&[
        "fgfs-command",
        "bourg",
        "--fg",
        "10.0.0.2:5505",
        "--fps",
        "60",
        "--origin",
        "-33.9,151.2,6",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("--native-fdm=socket,in,60,10.0.0.2,5505,udp"),
        "{stdout}"
    );
    assert!(stdout.contains("--lat=-33.91"), "{stdout}");
    assert_usage_error(&["fgfs-command", "cessna"], &["cessna"]);
    assert_usage_error(&["fgfs-command", "bourg", "--fg", "x"], &["--fg"]);
}
