//! Signals on an interactive run (issue 12): the built `sim-cli palmer --csv` runs
//! in a pseudo-terminal, gets SIGTERM, SIGHUP, SIGINT or SIGQUIT after about a
//! second of flying, and must then
//!
//! * exit with status 128 + the signal,
//! * leave the terminal as it found it: canonical mode, echo, signal keys and
//!   output processing on (`icanon echo isig opost`, read back with tcgetattr on
//!   the pty), the main screen (the last alternate-screen switch it wrote is
//!   "leave") and the cursor shown (the last cursor switch is "show"),
//! * leave a CSV whose every line is a complete row: the header, frame 0 and the
//!   frames flown, numbered 0, 1, 2, ... without a gap.
//!
//! FlightGear datagrams go to a UDP socket this test binds on 127.0.0.1.

#![cfg(target_os = "linux")]

mod support;

use std::fs::File;
use std::io::Read as _;
use std::net::UdpSocket;
use std::os::fd::OwnedFd;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use rustix::fs::{fcntl_getfl, fcntl_setfl, Mode, OFlags};
use rustix::pty::{grantpt, openpt, ptsname, unlockpt, OpenptFlags};
use rustix::termios::{tcgetattr, tcsetwinsize, LocalModes, OutputModes, Termios, Winsize};
use support::{csv_body, scratch};

const ENTER_ALT: &[u8] = b"\x1b[?1049h";
const LEAVE_ALT: &[u8] = b"\x1b[?1049l";
const HIDE_CURSOR: &[u8] = b"\x1b[?25l";
const SHOW_CURSOR: &[u8] = b"\x1b[?25h";

/// A pseudo-terminal pair: the test keeps the master (reads what the program
/// writes) and a slave descriptor of its own (so the terminal's modes survive the
/// program's exit and can be read back).
struct Pty {
    master: OwnedFd,
    slave: OwnedFd,
}

fn open_pty() -> Pty {
    let master =
        openpt(OpenptFlags::RDWR | OpenptFlags::NOCTTY | OpenptFlags::CLOEXEC).expect("openpt");
    grantpt(&master).expect("grantpt");
    unlockpt(&master).expect("unlockpt");
    let name = ptsname(&master, Vec::new()).expect("ptsname");
    let slave = rustix::fs::open(
        name.as_c_str(),
        OFlags::RDWR | OFlags::NOCTTY | OFlags::CLOEXEC,
        Mode::empty(),
    )
    .expect("open the pty slave");
    tcsetwinsize(
        &master,
        Winsize {
            ws_row: 40,
            ws_col: 120,
            ws_xpixel: 0,
            ws_ypixel: 0,
        },
    )
    .expect("window size");
    Pty { master, slave }
}

/// Reads everything the program writes to the terminal until told to stop.
fn drain(master: OwnedFd) -> (Arc<Mutex<Vec<u8>>>, Arc<AtomicBool>, JoinHandle<()>) {
    let flags = fcntl_getfl(&master).expect("getfl");
    fcntl_setfl(&master, flags | OFlags::NONBLOCK).expect("setfl");
    let seen = Arc::new(Mutex::new(Vec::new()));
    let stop = Arc::new(AtomicBool::new(false));
    let (seen2, stop2) = (Arc::clone(&seen), Arc::clone(&stop));
    let handle = std::thread::spawn(move || {
        let mut master = File::from(master);
        let mut buf = [0_u8; 8192];
        loop {
            match master.read(&mut buf) {
                Ok(n) if n > 0 => seen2.lock().unwrap().extend_from_slice(&buf[..n]),
                _ => {
                    if stop2.load(Ordering::SeqCst) {
                        return;
                    }
                    std::thread::sleep(Duration::from_millis(5));
                }
            }
        }
    });
    (seen, stop, handle)
}

fn find_last(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).rposition(|w| w == needle)
}

fn cooked(t: &Termios) -> bool {
    t.local_modes
        .contains(LocalModes::ICANON | LocalModes::ECHO | LocalModes::ISIG)
        && t.output_modes.contains(OutputModes::OPOST)
}

/// Flies interactively in a pty, sends `signal` (a `kill -s` name) after about a
/// second and checks the exit status, the terminal and the CSV.
fn signal_restores_and_flushes(signal: &str, number: i32) {
    let pty = open_pty();
    let before = tcgetattr(&pty.slave).expect("tcgetattr");
    assert!(cooked(&before), "a new pty starts cooked: {before:?}");

    let fg = UdpSocket::bind("127.0.0.1:0").expect("bind the FlightGear stand-in");
    let fg_addr = fg.local_addr().unwrap().to_string();
    let dir = scratch(&format!("sig-{signal}"));
    let csv = dir.join("flight.csv");
    let slave_io = || Stdio::from(pty.slave.try_clone().expect("dup slave"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["palmer", "--fg", &fg_addr, "--csv", csv.to_str().unwrap()])
        .stdin(slave_io())
        .stdout(slave_io())
        .stderr(slave_io())
        .spawn()
        .expect("spawn sim-cli");
    let (seen, stop, reader) = drain(pty.master.try_clone().expect("dup master"));

    // Wait for the HUD, then let it fly for about a second.
    let start = Instant::now();
    while find_last(&seen.lock().unwrap(), ENTER_ALT).is_none() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "no alternate screen after 30 s: {:?}",
            String::from_utf8_lossy(&seen.lock().unwrap())
        );
        assert!(child.try_wait().unwrap().is_none(), "sim-cli exited early");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(1000));
    let during = tcgetattr(&pty.slave).expect("tcgetattr");
    assert!(
        !cooked(&during),
        "sim-cli should be in raw mode: {during:?}"
    );

    let kill = Command::new("kill")
        .args(["-s", signal, &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(kill.success());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            panic!("sim-cli still running 20 s after SIG{signal}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    // Let the reader collect the last bytes.
    std::thread::sleep(Duration::from_millis(200));
    stop.store(true, Ordering::SeqCst);
    reader.join().unwrap();
    let screen = seen.lock().unwrap().clone();
    let shown = String::from_utf8_lossy(&screen);
    let tail = &shown[shown.len().saturating_sub(400)..];

    assert_eq!(
        status.code(),
        Some(128 + number),
        "SIG{signal}: {status:?}; terminal tail {tail:?}"
    );
    let after = tcgetattr(&pty.slave).expect("tcgetattr");
    assert!(
        cooked(&after),
        "SIG{signal} left the terminal raw: {after:?}"
    );
    assert_eq!(after.local_modes, before.local_modes, "SIG{signal}");
    assert_eq!(after.output_modes, before.output_modes, "SIG{signal}");
    assert!(
        find_last(&screen, LEAVE_ALT) > find_last(&screen, ENTER_ALT),
        "SIG{signal} left the alternate screen on: {tail:?}"
    );
    assert!(
        find_last(&screen, SHOW_CURSOR) > find_last(&screen, HIDE_CURSOR),
        "SIG{signal} left the cursor hidden: {tail:?}"
    );
    assert!(
        shown.contains(&format!("sim-cli: stopped by SIG{signal}")),
        "{tail:?}"
    );

    let text = std::fs::read_to_string(&csv).expect("read the CSV");
    assert!(
        text.ends_with('\n'),
        "SIG{signal}: last CSV row cut: {text:.200}"
    );
    let mut lines = csv_body(&text, "palmer").lines();
    let header = lines.next().expect("a header");
    let columns = header.split(',').count();
    let frames: Vec<u64> = lines
        .map(|line| {
            assert_eq!(line.split(',').count(), columns, "row {line:?}");
            line.split(',')
                .next()
                .unwrap()
                .parse()
                .expect("frame number")
        })
        .collect();
    // About a second at 30 fps; at least a few frames even on a loaded machine.
    assert!(frames.len() >= 5, "SIG{signal}: only {} rows", frames.len());
    let expected: Vec<u64> = (0..frames.len() as u64).collect();
    assert_eq!(frames, expected, "SIG{signal}: frames not 0, 1, 2, ...");
}

#[test]
fn sigterm_restores_the_terminal_and_flushes_the_csv() {
    signal_restores_and_flushes("TERM", 15);
}

#[test]
fn sighup_restores_the_terminal_and_flushes_the_csv() {
    signal_restores_and_flushes("HUP", 1);
}

#[test]
fn sigint_restores_the_terminal_and_flushes_the_csv() {
    signal_restores_and_flushes("INT", 2);
}

#[test]
fn sigquit_restores_the_terminal_and_flushes_the_csv() {
    signal_restores_and_flushes("QUIT", 3);
}
