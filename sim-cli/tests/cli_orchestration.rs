//! Another program starting `sim-cli` is a first-class user: started the way
//! Python's `subprocess.run(..., stdout=subprocess.DEVNULL)`, Node's
//! `stdio: 'ignore'` or systemd's `StandardOutput=null` start it (descriptor 1
//! is `/dev/null` opened read-write), it runs exactly as from a shell: same
//! exit status, same files, same datagrams (docs/cli.md, "A discarded stdout").
//! Loopback only.

mod support;

use std::fs::{File, OpenOptions};
use std::net::UdpSocket;
use std::process::{Command, Stdio};
use std::time::Duration;

use fdm_dis::Listener;
use support::{scratch, text};

/// `/dev/null` opened read-write, as `subprocess.DEVNULL` opens it (Rust's own
/// `Stdio::null()` opens it write-only for a stdout, which sim-cli always took).
fn devnull_read_write() -> File {
    OpenOptions::new()
        .read(true)
        .write(true)
        .open("/dev/null")
        .expect("open /dev/null read-write")
}

/// Runs sim-cli with stdin from /dev/null and stdout on a read-write /dev/null.
fn sim_discarding_stdout(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::from(devnull_read_write()))
        .stderr(Stdio::piped())
        .output()
        .expect("run sim-cli");
    (out.status.code(), text(&out.stderr))
}

#[test]
fn a_read_write_dev_null_stdout_runs_and_writes_its_files() {
    let dir = scratch("orchestration-files");
    let csv = dir.join("f.csv");
    let rec = dir.join("f.rec");
    let (status, stderr) = sim_discarding_stdout(&[
        "palmer",
        "--headless",
        "--frames",
        "90",
        "--json",
        "--csv",
        csv.to_str().unwrap(),
        "--record",
        rec.to_str().unwrap(),
    ]);
    assert_eq!(status, Some(0), "{stderr}");
    assert_eq!(stderr, "");
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
    assert_eq!(
        rows,
        1 + 91,
        "header and one row per frame, frame 0 included"
    );
    assert!(std::fs::metadata(&rec).unwrap().len() > 0);
    // The recording replays (its own stdout discarded the same way).
    let (status, stderr) = sim_discarding_stdout(&["replay", rec.to_str().unwrap(), "--json"]);
    assert_eq!(status, Some(0), "{stderr}");
}

/// The reported failure: two DIS fleet shards started from Python with their
/// stdout discarded sent nothing. Each shard now sends its aircraft.
#[test]
fn fleet_shards_with_a_discarded_stdout_send_their_pdus() {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    let addr = socket.local_addr().unwrap().to_string();
    for application in ["1", "2"] {
        let (status, stderr) = sim_discarding_stdout(&[
            "fleet",
            "--model",
            "palmer",
            "--aircraft",
            "20",
            "--frames",
            "3",
            "--dis",
            &addr,
            "--dis-application",
            application,
        ]);
        assert_eq!(status, Some(0), "shard {application}: {stderr}");
    }
    let mut listener = Listener::new();
    let mut buf = [0u8; 2048];
    while let Ok((n, _)) = socket.recv_from(&mut buf) {
        listener.ingest(&buf[..n]).expect("a well-formed PDU");
    }
    assert_eq!(listener.entity_count(), 40, "20 aircraft from each shard");
}
