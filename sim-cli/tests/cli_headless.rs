//! Headless runs of the built `sim-cli` (docs/cli.md): the JSON report's fields and
//! units, `--csv`, `--duration`, scripts, and the FlightGear datagrams sent with
//! `--fg` to a UDP socket the test binds.

mod support;

use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use fgnet::FgNetFdm;
use serde_json::Value;
use support::{csv_body, num, report, scratch, sim, text, triple, write_file};

#[test]
fn json_report_has_the_contract_fields() {
    let common = [
        "model",
        "fps",
        "frames",
        "time_s",
        "position",
        "velocity",
        "geodetic",
        "attitude_deg",
    ];
    let r = report(&["palmer", "--headless", "--json", "--frames", "3"]);
    for key in common.iter().chain(&[
        "airspeed",
        "controls",
        "climb_angle_deg",
        "climb_rate",
        "heading_deg",
    ]) {
        assert!(r.get(key).is_some(), "palmer report lacks {key}: {r}");
    }
    for key in ["throttle", "alpha_deg", "bank_deg", "flaps_deg"] {
        assert!(r["controls"].get(key).is_some(), "{key}");
    }
    // --fps is a whole number, and so is the report's.
    assert!(r["fps"].is_u64() && r["fps"] == 30, "{}", r["fps"]);
    assert_eq!(r["frames"], 3);
    // Throttle 0 by default: the Cessna stays at rest on the runway.
    assert_eq!(triple(&r["position"]), [0.0; 3]);

    let r = report(&["bourg", "--headless", "--json", "--frames", "3"]);
    for key in common
        .iter()
        .chain(&["speed", "euler_deg", "thrust_lb", "flaps", "stalling"])
    {
        assert!(r.get(key).is_some(), "bourg report lacks {key}: {r}");
    }
    for key in ["lat_deg", "lon_deg", "alt_m"] {
        assert!(r["geodetic"][key].is_f64(), "{key}");
    }
    for key in ["roll", "pitch", "heading"] {
        assert!(r["attitude_deg"][key].is_f64(), "{key}");
    }
    assert_eq!(r["thrust_lb"], 500.0);
    assert_eq!(
        (&r["flaps"], &r["stalling"]),
        (&false.into(), &false.into())
    );
    // Bourg's clock is the model's: 3 steps of the f32 time step 1/30,
    // widened and summed in f64 (not 3/30: the f32 step is 1/30 rounded).
    let dt = f64::from(1.0f32 / 30.0);
    assert_eq!(num(&r["time_s"]), dt + dt + dt);
    // Bourg's f32 values are widened exactly: narrowing gives them back unchanged.
    for v in triple(&r["position"])
        .into_iter()
        .chain(triple(&r["euler_deg"]))
    {
        assert_eq!(f64::from(v as f32), v);
    }
    // Bourg starts 5000 ft south of the origin: south of 39.8264 N, on its meridian.
    let lat = num(&r["geodetic"]["lat_deg"]);
    assert!((39.80..39.8264).contains(&lat), "{lat}");
}

#[test]
fn attitude_and_geodetic_follow_the_model() {
    // Palmer banked right at 5 deg with power: turning right (east), climbing, so
    // roll > 0, pitch > 0, and the compass heading moves from north towards east.
    let r = report(&[
        "palmer",
        "--headless",
        "--json",
        "--fps",
        "10",
        "--frames",
        "300",
        "--throttle",
        "1",
        "--alpha",
        "4",
        "--bank",
        "5",
    ]);
    let a = &r["attitude_deg"];
    assert!(num(&a["roll"]) > 4.0 && num(&a["roll"]) < 6.0, "{a}");
    assert!(num(&a["pitch"]) > 0.0, "{a}");
    let heading = num(&a["heading"]);
    assert!(heading > 0.0 && heading < 180.0, "{a}");
    // The model's own heading angle is measured towards the west: 360 - compass.
    assert!(
        (num(&r["heading_deg"]) - (360.0 - heading)).abs() < 1.0,
        "{r}"
    );
    // Moved north (x) and east (y < 0): latitude up, longitude up (less negative).
    let g = &r["geodetic"];
    assert!(
        num(&g["lat_deg"]) > 39.8264 && num(&g["lon_deg"]) > -84.0483,
        "{g}"
    );
    let z = triple(&r["position"])[2];
    assert!((num(&g["alt_m"]) - (251.0 + z)).abs() < 1.0, "{g} z {z}");
}

#[test]
fn origin_moves_the_aircraft() {
    let r = report(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "1",
        "--origin",
        "-33.9461,151.1772,6",
    ]);
    let g = &r["geodetic"];
    assert!((num(&g["lat_deg"]) + 33.9461).abs() < 1e-9, "{g}");
    assert!((num(&g["lon_deg"]) - 151.1772).abs() < 1e-9, "{g}");
    assert!((num(&g["alt_m"]) - 6.0).abs() < 1e-6, "{g}");
}

#[test]
fn duration_rounds_to_frames() {
    for (fps, duration, frames) in [("10", "1.26", 13), ("30", "0.05", 2), ("30", "0", 0)] {
        let r = report(&[
            "bourg",
            "--headless",
            "--json",
            "--fps",
            fps,
            "--duration",
            duration,
        ]);
        assert_eq!(r["frames"], frames, "--fps {fps} --duration {duration}");
    }
    let r = report(&[
        "palmer",
        "--headless",
        "--json",
        "--fps",
        "10",
        "--duration",
        "1.26",
    ]);
    assert_eq!(r["frames"], 13);
    // Palmer's clock is the model's: 13 f64 additions of 0.1.
    assert!((num(&r["time_s"]) - 1.3).abs() < 1e-12);
}

#[test]
fn csv_has_a_header_and_one_row_per_frame() {
    let dir = scratch("csv");
    for (model, frames) in [("palmer", 25_u64), ("bourg", 40)] {
        let csv = dir.join(format!("{model}.csv"));
        let frames_arg = frames.to_string();
        let mut args = vec![
            model,
            "--headless",
            "--json",
            "--frames",
            &frames_arg,
            "--csv",
            csv.to_str().unwrap(),
        ];
        if model == "palmer" {
            args.extend(["--throttle", "1", "--alpha", "4"]);
        }
        let r = report(&args);
        let content = std::fs::read_to_string(&csv).unwrap();
        let mut lines = csv_body(&content, model).lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(&header[..5], ["frame", "time_s", "x", "y", "z"], "{model}");
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
            .collect();
        // The initial state as frame 0, then one row per frame.
        assert_eq!(rows.len() as u64, frames + 1, "{model}");
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), header.len(), "{model} row {i}");
            assert_eq!(row[0], i as f64, "{model} row {i}");
        }
        // The last row is the reported final state, to the bit.
        let last = rows.last().unwrap();
        assert_eq!(last[1], num(&r["time_s"]), "{model}");
        assert_eq!(&last[2..5], triple(&r["position"]), "{model}");
        assert_eq!(&last[5..8], triple(&r["velocity"]), "{model}");
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        assert_eq!(last[col("lat_deg")], num(&r["geodetic"]["lat_deg"]));
        assert_eq!(
            last[col("fg_heading_deg")],
            num(&r["attitude_deg"]["heading"])
        );
    }
}

#[test]
fn scripts_apply_on_their_frames() {
    let dir = scratch("script");
    // Three throttle presses on frame 2, a flap notch on frames 3 and 4 (0 -> 20 -> 40),
    // two alpha presses on 5..6.
    let script = write_file(
        &dir,
        "palmer.txt",
        "# sample\n2-2 throttle-up\n2-2 throttle-up\n2-2 throttle-up\n3-4 flaps-down\n\n5-6 alpha-up\n",
    );
    let controls = |frames: &str| {
        let r = report(&[
            "palmer",
            "--headless",
            "--json",
            "--frames",
            frames,
            "--script",
            &script,
        ]);
        let c = &r["controls"];
        [
            num(&c["throttle"]),
            num(&c["flaps_deg"]),
            num(&c["alpha_deg"]),
        ]
    };
    assert_eq!(controls("1"), [0.0, 0.0, 0.0]);
    assert_eq!(controls("2"), [0.15, 0.0, 0.0]);
    assert_eq!(controls("3"), [0.15, 20.0, 0.0]);
    assert_eq!(controls("10"), [0.15, 40.0, 2.0]);

    // Bourg: thrust holds, but a pitch-up only deflects the elevators on its frames,
    // so a one-frame pulse differs from a two-frame one.
    let one = write_file(&dir, "one.txt", "1-2 thrust-up\n10-10 pitch-up\n");
    let two = write_file(&dir, "two.txt", "1-2 thrust-up\n10-11 pitch-up\n");
    let euler = |script: &str| {
        let r = report(&[
            "bourg",
            "--headless",
            "--json",
            "--frames",
            "30",
            "--script",
            script,
        ]);
        assert_eq!(r["thrust_lb"], 700.0);
        triple(&r["euler_deg"])
    };
    assert_ne!(euler(&one), euler(&two));
}

#[test]
fn human_summary_without_json() {
    let out = sim(&["bourg", "--headless", "--frames", "30"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.starts_with("bourg: 30 frames at 30 fps"), "{stdout}");
    assert!(stdout.contains("ft/s"), "{stdout}");
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
}

/// An output written to the standard output (`--csv /dev/stdout`, piped to
/// the test as to another program; `--record /dev/stdout`): the pipe gets
/// the output's bytes alone, the same bytes as a file, and the summary goes
/// to stderr; `sim-cli replay --csv` and `sim-cli fleet --acmi` too. The CSV
/// and the recording used to fail at once with "Invalid argument" (a pipe
/// cannot be emptied or synced). `--json` (its report is stdout's) and an
/// interactive run (its display is) are refused with such an output, but
/// not when stdout and the output are both `/dev/null`.
#[test]
fn an_output_on_the_standard_output_gets_it_alone() {
    let dir = scratch("stdout");
    let csv = dir.join("palmer.csv");
    let csv_arg = csv.to_str().unwrap();
    let flight = ["palmer", "--headless", "--frames", "40", "--throttle", "1"];
    let to_file = sim(&[&flight[..], &["--csv", csv_arg]].concat());
    assert_eq!(to_file.status.code(), Some(0), "{}", text(&to_file.stderr));
    let piped = sim(&[&flight[..], &["--csv", "/dev/stdout"]].concat());
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
    assert_eq!(piped.stdout, std::fs::read(&csv).unwrap());
    // The summary the file run printed on stdout, now on stderr.
    assert_eq!(piped.stderr, to_file.stdout);
    assert!(text(&piped.stderr).starts_with("palmer: 40 frames at 30 fps"));

    let rec = dir.join("bourg.rec");
    let flight = ["bourg", "--headless", "--frames", "75"];
    let to_file = sim(&[&flight[..], &["--record", rec.to_str().unwrap()]].concat());
    assert_eq!(to_file.status.code(), Some(0), "{}", text(&to_file.stderr));
    let piped = sim(&[&flight[..], &["--record", "/dev/stdout"]].concat());
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
    assert_eq!(piped.stdout, std::fs::read(&rec).unwrap());
    assert_eq!(piped.stderr, to_file.stdout);
    // `sim-cli replay` and `sim-cli fleet` alike.
    let replay_csv = dir.join("replay.csv");
    let replay = ["replay", rec.to_str().unwrap(), "--csv"];
    let to_file = sim(&[&replay[..], &[replay_csv.to_str().unwrap()]].concat());
    assert_eq!(to_file.status.code(), Some(0), "{}", text(&to_file.stderr));
    let piped = sim(&[&replay[..], &["/dev/stdout"]].concat());
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
    assert_eq!(piped.stdout, std::fs::read(&replay_csv).unwrap());
    assert_eq!(piped.stderr, to_file.stdout);
    let fleet = [
        "fleet",
        "--model",
        "palmer",
        "--aircraft",
        "3",
        "--frames",
        "5",
    ];
    let piped = sim(&[&fleet[..], &["--acmi", "/dev/stdout"]].concat());
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
    assert!(text(&piped.stdout).starts_with("FileType=text/acmi/tacview"));
    assert!(
        text(&piped.stderr).contains("aircraft"),
        "{}",
        text(&piped.stderr)
    );

    // A caller that discards stdout and names `/dev/null` as an output
    // gets the run it always got: `--json` taken, nothing on stderr. Outputs
    // all on `/dev/null` do not clash (nothing there is overwritten).
    let all = [
        "--acmi",
        "/dev/null",
        "--csv",
        "/dev/null",
        "--record",
        "/dev/null",
    ];
    for outputs in [&all[..2], &all[2..4], &all[4..], &all[..]] {
        let discarded = std::process::Command::new(env!("CARGO_BIN_EXE_sim-cli"))
            .args(["palmer", "--headless", "--frames", "3", "--json"])
            .args(outputs)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .output()
            .unwrap();
        assert_eq!(
            discarded.status.code(),
            Some(0),
            "{outputs:?}: {}",
            text(&discarded.stderr)
        );
        assert!(
            discarded.stderr.is_empty(),
            "{outputs:?}: {}",
            text(&discarded.stderr)
        );
    }
    let json = "--json prints its report there";
    for (run, why) in [
        (
            &["palmer", "--headless", "--frames", "3", "--json"][..],
            json,
        ),
        (
            &["palmer"][..],
            "the interactive display draws there (use --headless)",
        ),
        (&["replay", rec.to_str().unwrap(), "--json"][..], json),
    ] {
        let out = sim(&[run, &["--csv", "/dev/stdout"][..]].concat());
        assert_eq!(out.status.code(), Some(2), "{run:?}");
        assert_eq!(
            text(&out.stderr),
            format!("sim-cli: error: --csv /dev/stdout is the standard output, and {why}\n")
        );
        assert!(out.stdout.is_empty());
    }
}

/// Collects every datagram arriving on `socket` in a thread until `done` is set
/// and the socket has been quiet for a moment.
fn collect(socket: UdpSocket, done: Arc<AtomicBool>) -> std::thread::JoinHandle<Vec<Vec<u8>>> {
    socket
        .set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    std::thread::spawn(move || {
        let mut datagrams = Vec::new();
        let mut buf = [0_u8; 2048];
        loop {
            match socket.recv(&mut buf) {
                Ok(n) => datagrams.push(buf[..n].to_vec()),
                Err(_) if done.load(Ordering::SeqCst) => break,
                Err(_) => {}
            }
        }
        datagrams
    })
}

#[test]
fn fg_gets_one_datagram_per_frame_matching_the_report() {
    const FRAMES: usize = 50;
    for (model, extra) in [
        (
            "palmer",
            &["--throttle", "1", "--alpha", "4", "--bank", "5"][..],
        ),
        ("bourg", &[][..]),
    ] {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        let target = socket.local_addr().unwrap().to_string();
        let done = Arc::new(AtomicBool::new(false));
        let reader = collect(socket, Arc::clone(&done));
        let frames = FRAMES.to_string();
        let mut args = vec![
            model,
            "--headless",
            "--json",
            "--fps",
            "10",
            "--frames",
            &frames,
            "--fg",
            &target,
        ];
        args.extend_from_slice(extra);
        let out = sim(&args);
        done.store(true, Ordering::SeqCst);
        let datagrams = reader.join().unwrap();
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        // Somebody listens, so no send fails and nothing is said on stderr.
        assert!(out.stderr.is_empty(), "{model}: {}", text(&out.stderr));
        let r: Value = serde_json::from_slice(&out.stdout).unwrap();

        assert_eq!(datagrams.len(), FRAMES, "{model}: one datagram per frame");
        assert!(datagrams.iter().all(|d| d.len() == 408), "{model}");
        let last = FgNetFdm::decode(datagrams.last().unwrap()).unwrap();
        let first = FgNetFdm::decode(&datagrams[0]).unwrap();
        assert_eq!(last.version, 24);

        // Position: exactly the reported geodetic position, in radians and metres.
        let g = &r["geodetic"];
        let (lat, lon, alt) = (num(&g["lat_deg"]), num(&g["lon_deg"]), num(&g["alt_m"]));
        assert_eq!(last.latitude, lat.to_radians(), "{model}");
        assert_eq!(last.longitude, lon.to_radians(), "{model}");
        assert_eq!(last.altitude, alt, "{model}");
        assert!((last.latitude.to_degrees() - lat).abs() <= 1e-12, "{model}");
        assert!(
            (last.longitude.to_degrees() - lon).abs() <= 1e-12,
            "{model}"
        );
        // The aircraft moved between the first and the last frame.
        assert_ne!(first.latitude, last.latitude, "{model}");

        // Attitude: the reported degrees rounded to f32 radians.
        let a = &r["attitude_deg"];
        for (sent, key) in [
            (last.phi, "roll"),
            (last.theta, "pitch"),
            (last.psi, "heading"),
        ] {
            let deg = num(&a[key]);
            assert_eq!(sent, deg.to_radians() as f32, "{model} {key}");
            let back = f64::from(sent).to_degrees();
            assert!(
                (back - deg).abs() <= f64::from(f32::EPSILON) * deg.abs().max(1e-6),
                "{model} {key}: sent {back} deg, reported {deg} deg"
            );
        }
    }
}

#[test]
fn an_unreachable_fg_target_warns_once_and_does_not_fail() {
    // A port that was just free: nobody listens, the kernel refuses the datagrams.
    let port = UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let target = format!("127.0.0.1:{port}");
    let out = sim(&[
        "palmer",
        "--headless",
        "--json",
        "--frames",
        "40",
        "--fg",
        &target,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["frames"], 40);
    let stderr = text(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("sim-cli: warning: sending to "),
        "{stderr}"
    );
    assert!(stderr.contains(&target), "{stderr}");
}

/// `--realtime` paces a headless run at the frame rate, as a FlightGear that
/// reads its socket once per frame needs: the datagrams arrive spread over the
/// run's simulated time, not in one burst, and the report counts them.
#[test]
fn realtime_headless_runs_pace_frames_and_report_the_link() {
    const FRAMES: usize = 20;
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    let target = socket.local_addr().unwrap().to_string();
    socket
        .set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let done = Arc::new(AtomicBool::new(false));
    let reader = {
        let done = Arc::clone(&done);
        std::thread::spawn(move || {
            let mut arrivals = Vec::new();
            let mut buf = [0_u8; 2048];
            loop {
                match socket.recv(&mut buf) {
                    Ok(n) => arrivals.push((std::time::Instant::now(), buf[..n].to_vec())),
                    Err(_) if done.load(Ordering::SeqCst) => break,
                    Err(_) => {}
                }
            }
            arrivals
        })
    };
    let frames = FRAMES.to_string();
    let out = sim(&[
        "palmer",
        "--headless",
        "--json",
        "--realtime",
        "--fps",
        "20",
        "--frames",
        &frames,
        "--throttle",
        "1",
        "--fg",
        &target,
    ]);
    done.store(true, Ordering::SeqCst);
    let arrivals = reader.join().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["fg"]["sent"], FRAMES as u64);
    assert_eq!(r["fg"]["failed"], 0);
    assert!(r["realtime"]["overruns"].is_u64(), "{r}");
    assert_eq!(arrivals.len(), FRAMES);
    // 20 frames at 20 fps: the last datagram leaves 19 periods (0.95 s) after
    // the first; a burst would take milliseconds. Lower bound only (a loaded
    // machine can only make it later).
    let span = arrivals.last().unwrap().0 - arrivals[0].0;
    assert!(span >= Duration::from_millis(900), "{span:?}");
    // What FlightGear shows last is the report's final state.
    let last = FgNetFdm::decode(&arrivals.last().unwrap().1).unwrap();
    assert_eq!(last.latitude, num(&r["geodetic"]["lat_deg"]).to_radians());
    assert_eq!(last.altitude, num(&r["geodetic"]["alt_m"]));

    // Without --realtime and --fg the report has neither object.
    let r = report(&["palmer", "--headless", "--json", "--frames", "2"]);
    assert!(r.get("fg").is_none() && r.get("realtime").is_none(), "{r}");
    // --realtime belongs to headless runs (interactive ones are always paced).
    let out = sim(&["palmer", "--realtime"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--realtime needs --headless"));
}
