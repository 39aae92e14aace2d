//! Real-time pacing through the binary, bounded on both sides: a pacer that
//! sends frames as fast as they are flown fails, and so does one that runs
//! too slowly (docs/cli.md: `--realtime` paces the frames at 1/fps of wall
//! clock; `fleet --dis --realtime` at 1/30 s).
//!
//! What is measured is the time between the first and the last datagram
//! received on 127.0.0.1 (a reader thread timestamps each on arrival), so the
//! process's start-up and exit do not count: N frames take N − 1 periods
//! between the first frame's datagram and the last's. The bounds are generous
//! for a loaded 2-core machine, where a frame can be late but never early:
//! at least 95 % of the ideal span (the first frame's deadline is measured
//! from just before it, so the span can fall short by part of one period),
//! and at most the ideal span plus one second (a pacer at half the rate
//! takes twice the span, at least 1.9 s more here).
//!
//! Checked by planting each bug in a local copy and reverting it: a pacer
//! that never sleeps (all three caught: a burst of a few milliseconds); a
//! period of 2/fps (all three caught: twice the span); `fleet` computing its
//! sleep but not sleeping (the fleet test caught it).

mod support;

use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use support::{scratch, sim, text};

/// A receiver on 127.0.0.1 whose thread records the arrival time of every
/// datagram until `done` is set.
struct Receiver {
    addr: String,
    done: Arc<AtomicBool>,
    thread: std::thread::JoinHandle<Vec<Instant>>,
}

impl Receiver {
    fn start() -> Self {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        rustix::net::sockopt::set_socket_recv_buffer_size(&socket, 4 << 20).unwrap();
        socket
            .set_read_timeout(Some(Duration::from_millis(50)))
            .unwrap();
        let addr = socket.local_addr().unwrap().to_string();
        let done = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&done);
        let thread = std::thread::spawn(move || {
            let mut arrivals = Vec::new();
            let mut buf = [0_u8; 4096];
            loop {
                match socket.recv(&mut buf) {
                    Ok(_) => arrivals.push(Instant::now()),
                    Err(_) if flag.load(Ordering::SeqCst) => break,
                    Err(_) => {}
                }
            }
            arrivals
        });
        Self { addr, done, thread }
    }

    /// Stops the reader (after the datagrams in flight) and returns the
    /// arrival times.
    fn finish(self) -> Vec<Instant> {
        self.done.store(true, Ordering::SeqCst);
        self.thread.join().unwrap()
    }
}

/// Asserts that `arrivals` span `frames − 1` periods of `1/fps` within the
/// module's bounds.
#[track_caller]
fn assert_paced(what: &str, arrivals: &[Instant], frames: u32, fps: f64) {
    assert!(arrivals.len() >= 2, "{what}: {} datagrams", arrivals.len());
    let span = (*arrivals.last().unwrap() - arrivals[0]).as_secs_f64();
    let ideal = f64::from(frames - 1) / fps;
    assert!(
        span >= 0.95 * ideal && span <= ideal + 1.0,
        "{what}: {frames} frames at {fps} fps took {span:.3} s between the first and the last \
         datagram; paced, that is {ideal:.3} s (bounds {:.3} to {:.3} s)",
        0.95 * ideal,
        ideal + 1.0
    );
}

#[test]
fn a_realtime_headless_flight_takes_its_simulated_time() {
    let rx = Receiver::start();
    let out = sim(&[
        "bourg",
        "--headless",
        "--json",
        "--realtime",
        "--fps",
        "50",
        "--frames",
        "100",
        "--fg",
        &rx.addr,
    ]);
    let arrivals = rx.finish();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(arrivals.len(), 100, "one FGNetFDM datagram per frame");
    assert_paced("bourg --headless --realtime", &arrivals, 100, 50.0);
}

#[test]
fn a_realtime_dis_fleet_sends_its_frames_at_30_hz() {
    for kernel in ["lanes", "ecs"] {
        let rx = Receiver::start();
        let out = sim(&[
            "fleet",
            "--model",
            "palmer",
            "--kernel",
            kernel,
            "--aircraft",
            "3",
            "--frames",
            "60",
            "--threads",
            "1",
            "--json",
            "--dis",
            &rx.addr,
            "--dis-every-frame",
            "--realtime",
        ]);
        let arrivals = rx.finish();
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(r["realtime"]["overruns"].is_u64(), "{r}");
        // One PDU per aircraft per frame.
        assert_eq!(arrivals.len(), 3 * 60, "{kernel}");
        assert_paced(&format!("fleet --kernel {kernel}"), &arrivals, 60, 30.0);
        // Not in bursts either: each frame's three PDUs come together, and the
        // frames are spread out: the middle frame arrives near the middle.
        let middle = (arrivals[3 * 30] - arrivals[0]).as_secs_f64();
        assert!(
            (0.9..=1.0 + 0.5).contains(&middle),
            "{kernel}: frame 31 arrived {middle:.3} s after frame 1 (paced: 1.0 s)"
        );
    }
}

#[test]
fn a_realtime_replay_takes_the_flights_time() {
    let dir = scratch("pacing-replay");
    let rec = dir.join("p.rec");
    let out = sim(&[
        "palmer",
        "--headless",
        "--frames",
        "80",
        "--fps",
        "40",
        "--throttle",
        "1",
        "--record",
        rec.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let rx = Receiver::start();
    let out = sim(&[
        "replay",
        rec.to_str().unwrap(),
        "--realtime",
        "--fg",
        &rx.addr,
    ]);
    let arrivals = rx.finish();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(arrivals.len(), 80);
    assert_paced("replay --realtime", &arrivals, 80, 40.0);
}
