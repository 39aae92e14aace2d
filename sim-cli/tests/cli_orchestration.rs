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
use support::{csv_body, scratch, text};

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
    let written = std::fs::read_to_string(&csv).unwrap();
    let rows = csv_body(&written, "palmer").lines().count();
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

/// Two runs writing the same `--csv` once both exited 0 with Palmer's and
/// Bourg's rows spliced into one file. The second is refused before it
/// changes a byte, naming the process that holds the file.
#[test]
fn a_second_run_writing_the_same_csv_is_refused() {
    let dir = scratch("orchestration-lock");
    let csv = dir.join("shared.csv");
    let csv_arg = csv.to_str().unwrap();
    let mut first = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args([
            "palmer",
            "--headless",
            "--realtime",
            "--duration",
            "10",
            "--csv",
            csv_arg,
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // The first run creates and locks the file before it flies (its rows stay
    // in its buffer for a while, so the file's size says nothing yet); the
    // lock follows the creation within microseconds.
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    while !csv.exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "the first run never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    let second = Command::new(env!("CARGO_BIN_EXE_sim-cli"))
        .args(["bourg", "--headless", "--frames", "30", "--csv", csv_arg])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stderr = text(&second.stderr);
    assert_eq!(second.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "is being written by another process (pid {})",
            first.id()
        )),
        "{stderr}"
    );
    assert!(first.wait().unwrap().success());
    let written = std::fs::read_to_string(&csv).unwrap();
    let written = csv_body(&written, "palmer");
    let header = written.lines().next().unwrap();
    assert!(header.contains(",airspeed,"), "Palmer's columns: {header}");
    assert!(!header.contains(",speed,"));
    let columns = header.split(',').count();
    assert!(written.lines().all(|row| row.split(',').count() == columns));
    assert_eq!(
        written.lines().count(),
        1 + 301,
        "10 s at 30 fps and frame 0"
    );
}
