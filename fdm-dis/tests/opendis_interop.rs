//! Interoperability with an independent DIS implementation: Open-DIS for
//! Python (PyPI package `opendis`), over real UDP on 127.0.0.1.
//!
//! * Rust → Python: our [`EntityPublisher`] output goes through a
//!   [`UdpSender`] to `decode_udp.py`, which parses it with
//!   `opendis.PduFactory.createPdu` and converts it back with opendis's own
//!   `RangeCoordinates.GPS`: `ecef2lla` for the position and `ecef2llarpy`
//!   for roll/pitch/yaw relative to local NED. Every field must be what we
//!   sent (exactly: opendis reads the same `f32`/`f64`), and the geodetic
//!   read-back must match our input:
//!   - latitude/longitude within 1e-6°, height within 0.01 m. opendis is
//!     not exact: it uses a rounded semi-minor axis (6 356 752.3142 m,
//!     4.5e-5 m short of WGS-84's) and an iteration that stops once the
//!     latitude moves by less than 1e-9 rad; the test prints the largest
//!     differences seen;
//!   - heading/pitch/roll within 1e-4°: the wire's `f32` Euler angles are
//!     rounded by up to 1.2e-7 rad each, which moves heading and roll by at
//!     most 7.2e-7 rad (4.1e-5°) for |pitch| ≤ 60° (derivation in
//!     `tests/frames.rs`), so the states here keep |pitch| ≤ 60°.
//! * Python → Rust: `build_udp.py` builds DIS 7 Entity State PDUs with
//!   opendis (ECEF location and Euler angles from its `llarpy2ecef`) and
//!   sends them to a socket this test binds; our [`Listener`] decodes them
//!   and must give back the geodetic position and attitude opendis started
//!   from, with the same tolerances.
//!
//! Python: `$DIS_PYTHON` if set (it must import the opendis version `fdm_tests::python::OPENDIS` pins);
//! otherwise a virtualenv made once under `$CARGO_TARGET_TMPDIR` with
//! `python3 -m venv` and `pip install opendis==1.0 numpy==1.26.4`. If that is
//! not possible the tests fail with the reason; they never skip.

use std::io::Write;
use std::net::UdpSocket;
use std::path::Path;

use fdm_tests::python::{PyScript, PythonEnv};
use std::time::Duration;

use fdm_dis::geodesy::{Attitude, Geodetic};
use fdm_dis::{
    AircraftKind, AircraftState, DisVersion, DrAlgorithm, DrThresholds, EntityConfig,
    EntityIdentity, EntityPublisher, Listener, Marking, UdpSender,
};
use nalgebra::Vector3;
use serde_json::Value;

const SCRIPT_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/opendis_interop");
const TIMEOUT: Duration = Duration::from_secs(20);

const LATLON_TOL_DEG: f64 = 1e-6;
const HEIGHT_TOL_M: f64 = 0.01;
const ANGLE_TOL_DEG: f64 = 1e-4;

// ---------------------------------------------------------------- python setup

/// opendis and the numpy it works with, pinned (shared with sim-cli's
/// interop test through `fdm_tests::python`).
const ENV: PythonEnv = fdm_tests::python::OPENDIS;

/// A Python script of this test's directory, started with the pinned Python.
struct Script;

impl Script {
    fn start(name: &str, args: &[String]) -> PyScript {
        let python = ENV.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
        PyScript::start(&python, &Path::new(SCRIPT_DIR).join(name), args)
    }
}

// ------------------------------------------------------------------- values

/// SplitMix64, for reproducible pseudo-random states.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn state(lat: f64, lon: f64, alt: f64, heading: f64, pitch: f64, roll: f64) -> AircraftState {
    let mut s = AircraftState::new(
        12.5,
        Geodetic {
            lat_deg: lat,
            lon_deg: lon,
            alt_m: alt,
        },
        Attitude {
            heading_deg: heading,
            pitch_deg: pitch,
            roll_deg: roll,
        },
        Vector3::new(55.0, -12.0, 1.5),
    );
    s.angular_velocity_body_rad_s = Some(Vector3::new(0.05, -0.01, 0.08));
    s.acceleration_ned_m_s2 = Some(Vector3::new(0.3, 1.1, -0.2));
    s
}

/// Hand-picked places and attitudes (equator/prime meridian, where DIS's θ is
/// ±90° for a level aircraft heading north or south; date line; high
/// latitudes; below the ellipsoid) and random ones.
fn test_states() -> Vec<AircraftState> {
    let mut v = vec![
        state(0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        state(0.0, 0.0, 100.0, 180.0, 0.0, 0.0),
        state(0.0, 0.0, 100.0, 90.0, 0.0, 45.0),
        state(0.0, 90.0, 1000.0, 90.0, 10.0, -30.0),
        state(39.8264, -84.0483, 251.0, 280.0, 5.0, 20.0),
        state(-33.9461, 151.1772, 6.0, 157.0, -3.0, -15.0),
        state(51.4775, -0.4614, 25.0, 270.0, 12.0, 0.0),
        state(89.5, 45.0, 3000.0, 10.0, 0.0, 0.0),
        state(-89.0, -179.999, 2800.0, 300.0, -45.0, 170.0),
        state(10.0, 179.9999, -50.0, 359.999, 60.0, -179.0),
    ];
    let mut rng = Rng(0xD15_1278);
    for _ in 0..30 {
        v.push(state(
            rng.range(-89.0, 89.0),
            rng.range(-180.0, 180.0),
            rng.range(-400.0, 15_000.0),
            rng.range(0.0, 360.0),
            rng.range(-60.0, 60.0),
            rng.range(-179.0, 179.0),
        ));
    }
    v
}

fn angle_diff_deg(a: f64, b: f64) -> f64 {
    ((a - b + 180.0).rem_euclid(360.0) - 180.0).abs()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("not a number: {x}")))
        .collect()
}

fn u64s(v: &Value) -> Vec<u64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_u64().unwrap_or_else(|| panic!("not an integer: {x}")))
        .collect()
}

#[derive(Default)]
struct MaxErr {
    latlon_deg: f64,
    height_m: f64,
    angle_deg: f64,
}

impl MaxErr {
    fn check(&mut self, what: &str, lla: [f64; 3], att: [f64; 3], want: &AircraftState) {
        let dlat = (lla[0] - want.position.lat_deg).abs();
        let dlon = angle_diff_deg(lla[1], want.position.lon_deg);
        let dh = (lla[2] - want.position.alt_m).abs();
        assert!(dlat < LATLON_TOL_DEG, "{what}: latitude off by {dlat:e}°");
        assert!(dlon < LATLON_TOL_DEG, "{what}: longitude off by {dlon:e}°");
        assert!(dh < HEIGHT_TOL_M, "{what}: height off by {dh:e} m");
        let [roll, pitch, heading] = att;
        let a = &want.attitude;
        let dr = angle_diff_deg(roll, a.roll_deg);
        let dp = (pitch - a.pitch_deg).abs();
        let dy = angle_diff_deg(heading, a.heading_deg);
        for (n, d) in [("roll", dr), ("pitch", dp), ("heading", dy)] {
            assert!(d < ANGLE_TOL_DEG, "{what}: {n} off by {d:e}°");
        }
        self.latlon_deg = self.latlon_deg.max(dlat).max(dlon);
        self.height_m = self.height_m.max(dh);
        self.angle_deg = self.angle_deg.max(dr).max(dp).max(dy);
    }
}

// -------------------------------------------------------------------- tests

#[test]
fn our_pdus_decoded_by_opendis() {
    let states = test_states();
    let variants = [
        (
            AircraftKind::CESSNA_172_SKYHAWK,
            DisVersion::V7,
            DrAlgorithm::Rvw,
        ),
        (
            AircraftKind::SMALL_CIVIL_FIXED_WING,
            DisVersion::V6,
            DrAlgorithm::Fpw,
        ),
    ];
    let total = states.len() * variants.len();
    let mut script = Script::start(
        "decode_udp.py",
        &[total.to_string(), TIMEOUT.as_secs().to_string()],
    );
    let port = script.port();
    let tx = UdpSender::new(("127.0.0.1", port), false).expect("sender");
    let mut max = MaxErr::default();
    let mut checked = 0;
    for (kind, version, alg) in variants {
        for (i, s) in states.iter().enumerate() {
            let entity = u16::try_from(i + 1).unwrap();
            let mut cfg = EntityConfig::new(
                EntityIdentity::new(17, 4, entity).unwrap(),
                kind,
                Marking::new(&format!("AC{i}")).unwrap(),
            );
            cfg.version = version;
            cfg.dr_algorithm = alg;
            // A fresh publisher: its first update always sends.
            let mut p = EntityPublisher::new(cfg.clone(), DrThresholds::default()).unwrap();
            let due = p.update(s).unwrap().expect("first PDU");
            tx.send(due.bytes).unwrap();
            let wire = *p.reckoner().last_sent().unwrap();

            let line = script.line();
            let got: Value = serde_json::from_str(&line).expect("JSON line");
            let what = format!("{kind:?} {version:?} state {i}");
            assert_eq!(got["class"], "EntityStatePdu", "{what}");
            assert_eq!(got["len"], 144, "{what}");
            let v = if version == DisVersion::V7 { 7 } else { 6 };
            let stamp = u64::from(fdm_dis::dis_timestamp(s.time_s).to_u32());
            assert_eq!(u64s(&got["header"]), [v, 1, 1, 1, stamp, 144], "{what}");
            assert_eq!(u64s(&got["id"]), [17, 4, u64::from(entity)], "{what}");
            assert_eq!(got["force"], 1, "{what}: Friendly");
            let t = kind.entity_type();
            assert_eq!(
                u64s(&got["type"]),
                [
                    1,
                    2,
                    u64::from(u16::from(t.country)),
                    u64::from(t.category),
                    u64::from(t.subcategory),
                    u64::from(t.specific),
                    0
                ],
                "{what}"
            );
            let code = u64::from(u8::from(alg.to_dis()));
            assert_eq!(got["dr_algorithm"], code, "{what}");
            let as64 = |a: [f32; 3]| a.map(f64::from).to_vec();
            assert_eq!(f64s(&got["velocity"]), as64(wire.velocity_m_s), "{what}");
            assert_eq!(
                f64s(&got["acceleration"]),
                as64(wire.acceleration_m_s2),
                "{what}"
            );
            assert_eq!(
                f64s(&got["angular_velocity"]),
                as64(wire.angular_velocity_rad_s),
                "{what}"
            );
            assert_eq!(
                f64s(&got["orientation"]),
                as64(wire.orientation_rad),
                "{what}"
            );
            assert_eq!(f64s(&got["location"]), wire.location_m.as_slice(), "{what}");
            assert_eq!(got["marking_set"], 1, "{what}: ASCII");
            // dis-rs pads with spaces; opendis strips only NULs.
            assert_eq!(
                got["marking"].as_str().unwrap().trim_end(),
                format!("AC{i}")
            );

            let lla = f64s(&got["lla"]);
            let rpy = f64s(&got["rpy_deg"]);
            max.check(&what, [lla[0], lla[1], lla[2]], [rpy[0], rpy[1], rpy[2]], s);
            checked += 1;
        }
    }
    assert_eq!(checked, total);
    script.finish();
    println!(
        "opendis decoded {checked} PDUs; largest differences from our input: \
         lat/lon {:.2e}°, height {:.2e} m, roll/pitch/heading {:.2e}°",
        max.latlon_deg, max.height_m, max.angle_deg
    );
}

#[test]
fn opendis_pdus_decoded_by_our_listener() {
    let states = test_states();
    let rx = UdpSocket::bind("127.0.0.1:0").expect("bind");
    rx.set_read_timeout(Some(TIMEOUT)).unwrap();
    let port = rx.local_addr().unwrap().port();
    let mut script = Script::start("build_udp.py", &[port.to_string()]);
    {
        let stdin = script.stdin().expect("stdin");
        for (i, s) in states.iter().enumerate() {
            let req = serde_json::json!({
                "lla": [s.position.lat_deg, s.position.lon_deg, s.position.alt_m],
                "rpy_deg": [s.attitude.roll_deg, s.attitude.pitch_deg, s.attitude.heading_deg],
                "id": [5, 6, i + 1],
                "marking": format!("OD{i}"),
            });
            writeln!(stdin, "{req}").expect("write to build_udp.py");
        }
    }
    script.close_stdin();
    let mut listener = Listener::new();
    let mut max = MaxErr::default();
    let mut buf = [0u8; 8192];
    for (i, s) in states.iter().enumerate() {
        let built_hex = script.line();
        let n = match rx.recv(&mut buf) {
            Ok(n) => n,
            Err(e) => {
                let err = script.stderr();
                panic!("datagram {i} from opendis not received: {e}\n{err}");
            }
        };
        let hex: String = buf[..n].iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(hex, built_hex, "datagram {i} arrived as built");
        assert_eq!(listener.ingest(&buf[..n]), Ok(1), "datagram {i}");
        let id = EntityIdentity::new(5, 6, u16::try_from(i + 1).unwrap()).unwrap();
        let rec = listener.entity(&id).expect("entity recorded");
        assert_eq!(rec.marking, format!("OD{i}"));
        assert_eq!(
            rec.entity_type,
            AircraftKind::CESSNA_172_SKYHAWK.entity_type()
        );
        assert_eq!(rec.dr_algorithm, Some(DrAlgorithm::Fpw));
        let p = rec.position;
        let a = rec.attitude;
        max.check(
            &format!("opendis state {i}"),
            [p.lat_deg, p.lon_deg, p.alt_m],
            [a.roll_deg, a.pitch_deg, a.heading_deg],
            s,
        );
    }
    script.finish();
    let st = listener.stats();
    assert_eq!((st.pdus, st.malformed_datagrams), (states.len() as u64, 0));
    assert_eq!(listener.entity_count(), states.len());
    println!(
        "our listener decoded {} opendis PDUs; largest differences from opendis's input: \
         lat/lon {:.2e}°, height {:.2e} m, roll/pitch/heading {:.2e}°",
        st.pdus, max.latlon_deg, max.height_m, max.angle_deg
    );
}
