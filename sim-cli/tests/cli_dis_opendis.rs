//! Interop through the binary: what `sim-cli palmer --headless --dis
//! 127.0.0.1:PORT` sends over real UDP is decoded by Open-DIS for Python
//! (PyPI `opendis`, independent of dis-rs), and opendis's own conversions
//! give back the report's numbers:
//!
//! * `RangeCoordinates.GPS().ecef2lla` of the PDU's ECEF location agrees with
//!   the `geodetic` of the same frame (the CSV row of that frame, and for the
//!   last frame the JSON report) within 1e-6° in latitude/longitude and
//!   0.01 m in height. opendis is not exact (a semi-minor axis rounded to
//!   0.1 mm, an iteration stopped at 1e-9 rad; fdm-dis's interop test
//!   measured at most 4e-10° and 2.4e-5 m), and the PDU's location is the
//!   `f64` ECEF of exactly that geodetic position;
//! * `ecef2llarpy` of the PDU's ψ/θ/φ agrees with the frame's
//!   `attitude_deg` heading/pitch/roll within 1e-4°: the wire rounds each
//!   angle to `f32` (≤ 1.2e-7 rad), which moves heading and roll by at most
//!   4.1e-5° for |pitch| ≤ 60° (derived in fdm-dis's `tests/frames.rs`);
//!   Palmer's pitch stays far below that here.
//!
//! The frame of a PDU is read from its timestamp (simulation time within the
//! hour in units of 3600 s / 2³¹, bit 0 the relative/absolute flag): at most
//! 1.7 µs off, far from the 33 ms between frames.
//!
//! Python: the shared Open-DIS virtualenv of `fdm_tests::python::OPENDIS`
//! (or `$DIS_PYTHON`); the test fails, never skips, without it. Loopback only.

mod support;

use std::path::Path;

use fdm_tests::python::PyScript;

use serde_json::Value;
use support::{csv_body, num, report, scratch};

const LATLON_TOL_DEG: f64 = 1e-6;
const HEIGHT_TOL_M: f64 = 0.01;
const ANGLE_TOL_DEG: f64 = 1e-4;
const FPS: f64 = 30.0;

/// `decode_udp.py COUNT TIMEOUT` with the shared Open-DIS Python; returns
/// the script and the port it bound on 127.0.0.1.
fn start_decoder(count: u64) -> (PyScript, u16) {
    let python = fdm_tests::python::OPENDIS.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
    let script = Path::new(fdm_tests::python::OPENDIS_SCRIPT_DIR).join("decode_udp.py");
    let mut decoder = PyScript::start(&python, &script, &[count.to_string(), "20".to_owned()]);
    let port = decoder.port();
    (decoder, port)
}

/// `count` decoded PDUs, then the script's successful exit.
fn finish(mut decoder: PyScript, count: u64) -> Vec<Value> {
    let pdus = (0..count)
        .map(|_| serde_json::from_str(&decoder.line()).unwrap())
        .collect();
    decoder.finish();
    pdus
}

/// The CSV rows by frame, after Palmer's model line: `{column: value}`.
fn csv_rows(path: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = csv_body(&text, "palmer").lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| ((*h).to_owned(), v.parse::<f64>().unwrap()))
                .collect()
        })
        .collect()
}

fn angle_diff_deg(a: f64, b: f64) -> f64 {
    ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(num).collect()
}

/// The frame a PDU belongs to, from its header timestamp.
fn frame_of(pdu: &Value) -> usize {
    let ts = pdu["header"][4].as_u64().unwrap();
    assert_eq!(ts & 1, 0, "relative timestamp expected");
    let t = (ts >> 1) as f64 * 3600.0 / 2f64.powi(31);
    (t * FPS).round() as usize
}

/// Checks one decoded PDU against the geodetic position and attitude of
/// its frame; returns the largest differences (lat/lon °, height m, angle °).
fn check(pdu: &Value, geo: [f64; 3], att: [f64; 3]) -> [f64; 3] {
    let lla = f64s(&pdu["lla"]);
    let rpy = f64s(&pdu["rpy_deg"]);
    let d_latlon = (lla[0] - geo[0]).abs().max(angle_diff_deg(lla[1], geo[1]));
    let d_h = (lla[2] - geo[2]).abs();
    let d_ang = angle_diff_deg(rpy[0], att[0])
        .max((rpy[1] - att[1]).abs())
        .max(angle_diff_deg(rpy[2], att[2]));
    assert!(d_latlon < LATLON_TOL_DEG, "{pdu}: lla {lla:?} vs {geo:?}");
    assert!(d_h < HEIGHT_TOL_M, "{pdu}: lla {lla:?} vs {geo:?}");
    assert!(d_ang < ANGLE_TOL_DEG, "{pdu}: rpy {rpy:?} vs {att:?}");
    [d_latlon, d_h, d_ang]
}

/// Runs `palmer` with `args` twice: once to learn how many PDUs it sends (the
/// run is deterministic), once to opendis. Returns the report, the CSV rows
/// and the decoded PDUs.
fn fly_to_opendis(
    args: &[&str],
) -> (
    Value,
    Vec<std::collections::HashMap<String, f64>>,
    Vec<Value>,
) {
    let dir = scratch("dis-opendis");
    let csv = dir.join("run.csv");
    let csv_arg = csv.to_str().unwrap();
    let sink = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let sink_addr = sink.local_addr().unwrap().to_string();
    let mut full: Vec<&str> = vec!["palmer", "--headless", "--json", "--csv", csv_arg];
    full.extend_from_slice(args);
    let dry = report(&[&full[..], &["--dis", &sink_addr]].concat());
    let count = dry["dis"]["pdus"].as_u64().unwrap();

    let (decoder, port) = start_decoder(count);
    let target = format!("127.0.0.1:{port}");
    let r = report(&[&full[..], &["--dis", &target]].concat());
    assert_eq!(r["dis"]["pdus"], dry["dis"]["pdus"]);
    assert_eq!(r["geodetic"], dry["geodetic"]);
    let pdus = finish(decoder, count);
    (r, csv_rows(&csv), pdus)
}

fn row_geo_att(row: &std::collections::HashMap<String, f64>) -> ([f64; 3], [f64; 3]) {
    (
        [row["lat_deg"], row["lon_deg"], row["alt_m"]],
        [row["roll_deg"], row["pitch_deg"], row["fg_heading_deg"]],
    )
}

#[test]
fn opendis_decodes_every_frame_to_the_reports_geodetic_and_attitude() {
    let (r, rows, pdus) = fly_to_opendis(&[
        "--frames",
        "90",
        "--throttle",
        "1",
        "--alpha",
        "6",
        "--bank",
        "-15",
        "--dis-every-frame",
        "--dis-version",
        "6",
        "--dis-site",
        "7",
        "--dis-application",
        "8",
        "--dis-entity",
        "9",
    ]);
    assert_eq!(pdus.len(), 90);
    let mut worst = [0.0f64; 3];
    for (i, pdu) in pdus.iter().enumerate() {
        assert_eq!(pdu["class"], "EntityStatePdu");
        assert_eq!(pdu["header"][0], 6);
        assert_eq!(pdu["id"], serde_json::json!([7, 8, 9]));
        assert_eq!(pdu["type"], serde_json::json!([1, 2, 225, 85, 11, 1, 0]));
        // Sent padded with spaces to 11 characters; opendis keeps the padding.
        assert_eq!(pdu["marking"], "C172-9     ");
        assert_eq!(pdu["dr_algorithm"], 4);
        let frame = frame_of(pdu);
        assert_eq!(frame, i + 1);
        let (geo, att) = row_geo_att(&rows[frame]);
        let d = check(pdu, geo, att);
        for k in 0..3 {
            worst[k] = worst[k].max(d[k]);
        }
    }
    // The last PDU is the last frame: the JSON report's own numbers.
    let g = &r["geodetic"];
    let a = &r["attitude_deg"];
    check(
        pdus.last().unwrap(),
        [num(&g["lat_deg"]), num(&g["lon_deg"]), num(&g["alt_m"])],
        [num(&a["roll"]), num(&a["pitch"]), num(&a["heading"])],
    );
    eprintln!(
        "largest differences: {:.1e} deg lat/lon, {:.1e} m height, {:.1e} deg attitude",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn opendis_decodes_the_dead_reckoned_pdus_at_their_frames() {
    let (_r, rows, pdus) = fly_to_opendis(&[
        "--duration",
        "60",
        "--throttle",
        "1",
        "--alpha",
        "4",
        "--bank",
        "10",
    ]);
    // A minute of a 10° turn with DRM(R,V,W): the first PDU, then some.
    assert!(pdus.len() > 12 && pdus.len() < 200, "{}", pdus.len());
    let mut last = 0;
    for pdu in &pdus {
        assert_eq!(pdu["header"][0], 7);
        assert_eq!(pdu["dr_algorithm"], 4);
        let frame = frame_of(pdu);
        assert!(frame > last, "frames in order: {frame} after {last}");
        last = frame;
        let (geo, att) = row_geo_att(&rows[frame]);
        check(pdu, geo, att);
        // DRM(R,V,W) sends its rates: a turning aircraft has an angular velocity.
        if frame > 1 {
            let w = f64s(&pdu["angular_velocity"]);
            assert!(w.iter().any(|c| c.abs() > 1e-3), "{pdu}");
        }
    }
    assert_eq!(frame_of(&pdus[0]), 1);
}
