//! The built `sim-cli` at the edges of the models' envelopes: the ground holds,
//! the status is reported everywhere, a crash is a result (exit 0), and a
//! divergence stops the run cleanly (exit 1, one line, nothing non-finite
//! written or sent). Comparisons are exact: the ground is an exact clamp and
//! the outputs are the numbers the run produced.

mod support;

use std::net::UdpSocket;
use std::time::Duration;

use fgnet::FgNetFdm;
use support::{csv_body, num, report, scratch, sim, text, triple, write_file};

#[test]
fn palmer_crash_at_10_fps_stays_on_the_ground_and_exits_0() {
    // The script: it used to sink through the ground and diverge at
    // frame 12655; now it crashes around frame 674 and stays there.
    let dir = scratch("edges-crash");
    let script = write_file(
        &dir,
        "s.txt",
        "1-600 alpha-up\n601-630 alpha-down\n601-620 throttle-down\n",
    );
    let csv = dir.join("run.csv");
    let csv = csv.to_str().unwrap();
    let args = [
        "palmer",
        "--headless",
        "--json",
        "--fps",
        "10",
        "--frames",
        "36000",
        "--throttle",
        "1",
        "--alpha",
        "10",
        "--script",
        &script,
        "--csv",
        csv,
    ];
    let r = report(&args);
    assert_eq!(r["status"], "crashed", "{r}");
    assert_eq!(triple(&r["position"])[2], 0.0);
    assert_eq!(triple(&r["velocity"]), [0.0; 3]);
    let rows = std::fs::read_to_string(csv).unwrap();
    let rows = csv_body(&rows, "palmer");
    let header: Vec<&str> = rows.lines().next().unwrap().split(',').collect();
    let z = header.iter().position(|c| *c == "z").unwrap();
    let status = header.iter().position(|c| *c == "status").unwrap();
    let mut statuses = Vec::new();
    for line in rows.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(v.iter().all(|x| x.is_finite()), "{line}");
        assert!(v[z] >= 0.0, "{line}");
        if statuses.last() != Some(&v[status]) {
            statuses.push(v[status]);
        }
    }
    // on ground, airborne, crashed.
    assert_eq!(statuses, [0.0, 1.0, 4.0]);
    // The human summary says it too.
    let out = sim(&args[..args.len() - 2]
        .iter()
        .filter(|a| **a != "--json")
        .copied()
        .collect::<Vec<_>>());
    assert_eq!(out.status.code(), Some(0));
    assert!(
        text(&out.stdout).contains("status    crashed"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn bourg_without_input_lands_instead_of_sinking() {
    // 60 s hands off: it used to be 841 ft below the ground plane, "flying".
    let r = report(&["bourg", "--headless", "--json", "--frames", "1800"]);
    assert_eq!(r["status"], "crashed", "{r}");
    assert_eq!(triple(&r["position"])[2], 0.0);
    assert_eq!(triple(&r["velocity"]), [0.0; 3]);
}

#[test]
fn a_divergence_stops_the_run_with_one_line_and_nothing_non_finite() {
    // Bourg's explicit Euler at 1 frame per second with more thrust: its
    // rotation blows up in the air (measured: within 30 frames).
    let dir = scratch("edges-diverge");
    let script = write_file(&dir, "s.txt", "1-20 thrust-up\n");
    let csv = dir.join("run.csv");
    let csv = csv.to_str().unwrap();
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    let target = socket.local_addr().unwrap().to_string();
    let out = sim(&[
        "bourg",
        "--headless",
        "--json",
        "--fps",
        "1",
        "--frames",
        "3600",
        "--script",
        &script,
        "--csv",
        csv,
        "--fg",
        &target,
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(out.stdout.is_empty(), "no report: {}", text(&out.stdout));
    let stderr = text(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let line = stderr.trim_end();
    let rest = line
        .strip_prefix("sim-cli: error: frame ")
        .unwrap_or_else(|| panic!("{line}"));
    let (frame, message) = rest.split_once(": ").unwrap();
    let frame: u64 = frame.parse().unwrap();
    assert_eq!(
        message,
        "the bourg model diverged (non-finite state) at dt = 1.0 s; try a higher --fps"
    );
    // CSV: the model line, the header and frames 0..frame-1, all finite, flushed.
    let rows = std::fs::read_to_string(csv).unwrap();
    let rows = csv_body(&rows, "bourg");
    let frames: Vec<u64> = rows
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            assert!(v.iter().all(|x| x.is_finite()), "{l}");
            l.split(',').next().unwrap().parse().unwrap()
        })
        .collect();
    assert_eq!(frames, (0..frame).collect::<Vec<_>>());
    // One datagram per frame stepped before the divergence, none with a NaN.
    let mut buf = [0_u8; 2048];
    let mut datagrams = 0;
    while let Ok(n) = socket.recv(&mut buf) {
        let p = FgNetFdm::decode(&buf[..n]).unwrap();
        for x in [p.latitude, p.longitude, p.altitude] {
            assert!(x.is_finite(), "{p:?}");
        }
        for x in [p.phi, p.theta, p.psi, p.vcas, p.v_north, p.v_east, p.v_down] {
            assert!(x.is_finite(), "{p:?}");
        }
        datagrams += 1;
    }
    assert_eq!(datagrams, frame - 1);
}

#[test]
fn status_of_a_run_on_the_runway_and_in_the_air() {
    let r = report(&["palmer", "--headless", "--json", "--frames", "3"]);
    assert_eq!(r["status"], "on_ground");
    let r = report(&["bourg", "--headless", "--json", "--frames", "3"]);
    assert_eq!(r["status"], "airborne");
    assert!(num(&r["position"][2]) > 0.0);
}

#[test]
fn starting_in_cruise_and_trimmed() {
    // Palmer at 2000 ft, 100 kt, heading east, trimmed, five minutes at 30 fps
    // hands off: within ±10 ft and ±1 kt (the target).
    let out = sim(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "9000",
        "--altitude-ft",
        "2000",
        "--speed-kt",
        "100",
        "--heading-deg",
        "90",
        "--trim",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with("sim-cli: palmer trimmed: throttle "),
        "{stderr}"
    );
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["status"], "airborne");
    let z_ft = triple(&r["position"])[2] / 0.3048;
    assert!((z_ft - 2000.0).abs() <= 10.0, "{z_ft}");
    let kt = num(&r["airspeed"]) * 3600.0 / 1852.0;
    assert!((kt - 100.0).abs() <= 1.0, "{kt}");
    // East along the flat earth's −y: FlightGear's heading, from the local
    // north 15 km further east, differs by the meridians' convergence
    // (measured 0.115°).
    assert!(
        (num(&r["attitude_deg"]["heading"]) - 90.0).abs() < 0.2,
        "{}",
        r["attitude_deg"]
    );
    // Bourg: ±100 ft, ±5 kt for 60 s.
    let out = sim(&[
        "bourg",
        "--headless",
        "--json",
        "--frames",
        "1800",
        "--altitude-ft",
        "2000",
        "--speed-kt",
        "100",
        "--trim",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stderr).starts_with("sim-cli: bourg trimmed: thrust "));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let z_ft = triple(&r["position"])[2];
    assert!((z_ft - 2000.0).abs() <= 100.0, "{z_ft}");
    let kt = num(&r["speed"]) * 0.3048 * 3600.0 / 1852.0;
    assert!((kt - 100.0).abs() <= 5.0, "{kt}");
}

#[test]
fn untrimmable_speeds_exit_2_with_a_message() {
    for (model, kt, why) in [
        ("palmer", "30", "below the stall speed"),
        ("palmer", "300", "above the speed full power can hold"),
        ("bourg", "30", "below the stall speed"),
        ("bourg", "300", "above the speed full power can hold"),
    ] {
        let out = sim(&[
            model,
            "--headless",
            "--frames",
            "1",
            "--altitude-ft",
            "2000",
            "--speed-kt",
            kt,
            "--trim",
        ]);
        assert_eq!(out.status.code(), Some(2), "{model} {kt}");
        let stderr = text(&out.stderr);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(why), "{model} {kt}: {stderr}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn defaults_are_the_thesis_starts_and_options_move_them() {
    // No option: exactly the thesis's start (frame 0 of the CSV).
    let plain = report(&["bourg", "--headless", "--json", "--frames", "0"]);
    assert_eq!(triple(&plain["position"]), [-5000.0, 0.0, 2000.0]);
    let r = report(&[
        "bourg",
        "--headless",
        "--json",
        "--frames",
        "0",
        "--altitude-ft",
        "3000",
        "--thrust-lb",
        "1200",
    ]);
    assert_eq!(triple(&r["position"]), [-5000.0, 0.0, 3000.0]);
    assert_eq!(r["thrust_lb"], 1200.0);
    // The speed stays the model's own start (60 ft/s) when not given.
    assert!((num(&r["speed"]) - 60.0).abs() < 1e-4);
    let r = report(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "0",
        "--altitude-ft",
        "1000",
        "--speed-kt",
        "90",
    ]);
    assert_eq!(triple(&r["position"])[2], 304.8);
    // fgfs-command starts FlightGear where the aircraft starts.
    let line = |extra: &[&str]| {
        let mut args = vec!["fgfs-command", "bourg"];
        args.extend_from_slice(extra);
        let out = sim(&args);
        assert_eq!(out.status.code(), Some(0));
        text(&out.stdout)
    };
    let default = line(&[]);
    let moved = line(&["--altitude-ft", "5000", "--heading-deg", "270"]);
    assert!(default.contains("--heading=0 "), "{default}");
    assert!(moved.contains("--heading=270 "), "{moved}");
    assert_ne!(default, moved);
    let alt = |l: &str| -> f64 {
        l.split(' ')
            .find_map(|w| w.strip_prefix("--altitude="))
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(
        (alt(&moved) - alt(&default) - 3000.0).abs() < 0.2,
        "{default} {moved}"
    );
}
