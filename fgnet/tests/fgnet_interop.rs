//! Interoperability with an independent FGNetFDM v24 implementation: the PyPI
//! package `flightgear-python` (module `flightgear_python.fdm_v24`, a
//! `construct` struct), over real UDP sockets on 127.0.0.1.
//!
//! * Rust → Python: our [`Sender`] sends datagrams to a port a Python script
//!   binds; `fdm_struct.parse` decodes them and every field comes back as
//!   JSON (floats as IEEE bit patterns) and is compared bit for bit.
//! * Python → Rust: `fdm_struct.build` builds datagrams from values this test
//!   gives and sends them to a socket this test binds; our `decode` must give
//!   back every value bit for bit, and the bytes must equal our `encode`.
//! * The library's angle handling: `fdm_v24.parse`/`build` are exact (no
//!   conversion at all). Its connection class `FDMConnection` however runs
//!   `fg_util.fix_fg_radian_parsing` on every datagram it *receives*, adding
//!   `math.degrees(x) * 1.09349403e-9` radians to the ten radian fields
//!   (lon, lat, phi, theta, psi, alpha, beta, phidot, thetadot, psidot), a
//!   relative +6.265e-8 meant to undo the shrink from FlightGear's float
//!   radian constant (docs/fgnetfdm.md §6). Nothing undoes it on `build`, so a datagram
//!   echoed through `FDMConnection` comes back with those ten fields grown.
//!   The third test echoes our datagrams through a real `FDMConnection` and
//!   predicts the result exactly: `x + x.to_degrees() * 1.09349403e-9` in
//!   `f64` (Rust's `to_degrees` multiplies by the same correctly rounded
//!   180/π as CPython's `math.degrees`), rounded to `f32` for the `f32`
//!   fields as construct's `struct.pack('>f')` does; every other field must
//!   come back unchanged.
//!
//! Python: `$FGNET_PYTHON` if set (it must import flightgear-python
//! `fdm_tests::python::FGPY`'s version); otherwise a virtualenv created once under
//! `$CARGO_TARGET_TMPDIR` with `python3 -m venv` and
//! `pip install flightgear-python==2.1.0 construct==2.10.70`. If that is not
//! possible the tests fail with the reason; they never skip.
//!
//! NaNs: quiet NaN payloads survive CPython's float conversions and are
//! tested; a *signalling* f32 NaN is quieted by CPython 3.11's
//! `struct.unpack('>f')` (an `f32` → `f64` conversion), which is Python's
//! behaviour, not the wire format's, so f32 values here are never signalling
//! NaNs. Signalling `f64` NaNs pass through Python unchanged and are tested.

use std::io::Write;
use std::net::UdpSocket;
use std::path::Path;

use fdm_tests::python::{PyScript, PythonEnv};
use std::time::Duration;

use fdm_tests::fgnet_fields::{assert_bitwise_eq, element_bits, fields, from_element_bits, Kind};
use fgnet::{DisplayState, EngineState, FgNetFdm, Sender};
use serde_json::{json, Map, Value};

/// flightgear-python's `offset_fg_radian` coefficient (fg_util.py).
const FGPY_RADIAN_COEFF: f64 = 1.09349403e-9;
/// The radian fields `fix_fg_radian_parsing` adjusts (our names).
const RADIAN_FIELDS: [&str; 10] = [
    "longitude",
    "latitude",
    "phi",
    "theta",
    "psi",
    "alpha",
    "beta",
    "phidot",
    "thetadot",
    "psidot",
];

const SCRIPT_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fgnet_interop");
const TIMEOUT: Duration = Duration::from_secs(20);

// ---------------------------------------------------------------- python setup

/// flightgear-python and its construct, pinned (shared with the Python
/// package's suite).
const ENV: PythonEnv = fdm_tests::python::FGPY;

/// A Python script of this test's directory, started with the pinned Python.
struct Script;

impl Script {
    fn start(name: &str, args: &[String]) -> PyScript {
        let python = ENV.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
        PyScript::start(&python, &Path::new(SCRIPT_DIR).join(name), args)
    }
}

// ------------------------------------------------------------------- values

/// SplitMix64, for reproducible pseudo-random field values.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

fn golden() -> FgNetFdm {
    let text = fdm_tests::read_reference("fgnetfdm_golden.json").expect("golden file");
    let json: Value = serde_json::from_str(&text).expect("golden JSON");
    serde_json::from_value(json["fields"].clone()).expect("golden fields")
}

/// Every element set from random bits: arbitrary f64 (any NaN included) and
/// f32 (signalling NaNs made quiet, see the module doc), valid counts.
fn random_fdm(rng: &mut Rng) -> FgNetFdm {
    let mut bits = Vec::new();
    for f in fields() {
        for _ in 0..f.len {
            let r = rng.next();
            bits.push(match (f.name, f.count_max(), f.kind) {
                ("version", _, _) => 24,
                (_, Some(max), _) => r % (max + 1),
                (_, _, Kind::F32) => {
                    let b = r as u32;
                    let b = if f32::from_bits(b).is_nan() {
                        b | 0x0040_0000
                    } else {
                        b
                    };
                    u64::from(b)
                }
                (_, _, Kind::F64) => r,
                (_, _, Kind::U32 | Kind::I32) => u64::from(r as u32),
            });
        }
    }
    from_element_bits(&bits)
}

/// Hand-picked awkward values.
fn edge_fdm() -> FgNetFdm {
    let mut f = FgNetFdm::new();
    f.padding = 0xdead_beef;
    f.longitude = f64::from_bits(0x7ff0_0000_0000_0001); // signalling NaN
    f.latitude = -0.0;
    f.altitude = f64::MAX;
    f.agl = f32::from_bits(0x7fc1_2345); // quiet NaN, payload
    f.phi = f32::from_bits(0xffc0_0001); // negative quiet NaN
    f.theta = f32::INFINITY;
    f.psi = f32::NEG_INFINITY;
    f.alpha = f32::from_bits(1); // smallest subnormal
    f.beta = -0.0;
    f.vcas = f32::MAX;
    f.num_engines = 4;
    f.eng_state = [0, 1, 2, 7]; // 7 is no Enum label in flightgear-python
    f.rpm = [1.0, -1.0, 0.5, 3.0e38];
    f.num_tanks = 4;
    f.num_wheels = 3;
    f.wow = [1, 0, u32::MAX];
    f.cur_time = u32::MAX;
    f.warp = i32::MIN;
    f.spoilers = f32::MIN_POSITIVE;
    f
}

fn display_fdm() -> FgNetFdm {
    FgNetFdm::from_display(&DisplayState {
        latitude_deg: 37.625,
        longitude_deg: -122.375,
        altitude_m: 123.25,
        roll_deg: 20.0,
        pitch_deg: 5.0,
        heading_deg: 280.0,
        alpha_deg: 4.0,
        beta_deg: -1.0,
        airspeed_kt: 95.0,
        climb_rate_fps: 6.5,
        engine_state: EngineState::Running,
        engine_rpm: 2350.0,
        flaps_norm: 0.25,
        ..DisplayState::default()
    })
}

fn test_set() -> Vec<FgNetFdm> {
    let mut rng = Rng(0x00f1_1e55_f9e7_0024);
    let mut v = vec![golden(), edge_fdm(), display_fdm(), FgNetFdm::new()];
    v.extend((0..16).map(|_| random_fdm(&mut rng)));
    v
}

/// The JSON value of one field in fgnet_py_common's encoding.
fn py_value(kind: Kind, bits: u64) -> Value {
    match kind {
        Kind::I32 => json!(bits as u32 as i32),
        _ => json!(bits),
    }
}

fn to_py_json(fdm: &FgNetFdm) -> Value {
    let mut m = Map::new();
    for f in fields() {
        let vals: Vec<Value> = (0..f.len)
            .map(|i| py_value(f.kind, (f.get)(fdm, i)))
            .collect();
        let v = if f.len == 1 {
            vals[0].clone()
        } else {
            Value::Array(vals)
        };
        m.insert(f.py.to_owned(), v);
    }
    Value::Object(m)
}

fn py_kind(f: &fdm_tests::fgnet_fields::Field) -> &'static str {
    if f.name == "padding" {
        "bytes4"
    } else {
        f.kind.py()
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

// -------------------------------------------------------------------- tests

#[test]
fn rust_sender_to_flightgear_python_parser() {
    let sent = test_set();
    let mut script = Script::start(
        "parse_udp.py",
        &[sent.len().to_string(), TIMEOUT.as_secs().to_string()],
    );
    let port = script.port();
    let mut tx = Sender::connect(&format!("127.0.0.1:{port}")).expect("sender");
    for (i, fdm) in sent.iter().enumerate() {
        assert!(tx.send(fdm).is_sent(), "datagram {i}");
    }
    let expected_layout: Vec<Value> = fields()
        .iter()
        .map(|f| {
            json!([
                f.py,
                py_kind(f),
                if f.len == 1 {
                    Value::Null
                } else {
                    json!(f.len)
                }
            ])
        })
        .collect();
    for (i, fdm) in sent.iter().enumerate() {
        let line = script.line();
        let got: Value = serde_json::from_str(&line).expect("JSON line");
        assert_eq!(got["len"], 408, "datagram {i}");
        assert_eq!(
            got["rebuild_equal"], true,
            "datagram {i}: build(parse(x)) != x"
        );
        assert_eq!(
            got["layout"],
            Value::Array(expected_layout.clone()),
            "flightgear-python's field order/types differ from the table of docs/fgnetfdm.md"
        );
        let py_fields = &got["fields"];
        let mut checked = 0;
        for f in fields() {
            let entry = &py_fields[f.py];
            assert_eq!(entry["kind"], py_kind(&f), "datagram {i}: kind of {}", f.py);
            for el in 0..f.len {
                let py = if f.len == 1 {
                    &entry["value"]
                } else {
                    &entry["value"][el]
                };
                let want = py_value(f.kind, (f.get)(fdm, el));
                assert_eq!(
                    py,
                    &want,
                    "datagram {i}: {} ({}) parsed by flightgear-python",
                    f.element_name(el),
                    f.py
                );
                checked += 1;
            }
        }
        assert_eq!(checked, 99);
    }
    script.finish();
}

#[test]
fn flightgear_python_builder_to_rust_decoder() {
    let expected = test_set();
    let rx = UdpSocket::bind("127.0.0.1:0").expect("bind");
    rx.set_read_timeout(Some(TIMEOUT)).unwrap();
    let port = rx.local_addr().unwrap().port();
    let mut script = Script::start("build_udp.py", &[port.to_string()]);
    {
        let stdin = script.stdin().expect("stdin");
        for fdm in &expected {
            writeln!(stdin, "{}", to_py_json(fdm)).expect("write to build_udp.py");
        }
    }
    script.close_stdin();
    let mut buf = [0u8; 4096];
    for (i, want) in expected.iter().enumerate() {
        let built_hex = script.line();
        let len = match rx.recv(&mut buf) {
            Ok(n) => n,
            Err(e) => {
                let err = script.stderr();
                panic!("datagram {i} from flightgear-python not received: {e}\n{err}");
            }
        };
        assert_eq!(len, 408, "datagram {i}");
        assert_eq!(hex(&buf[..len]), built_hex, "datagram {i} arrived as built");
        let got = FgNetFdm::decode(&buf[..len])
            .unwrap_or_else(|e| panic!("datagram {i} built by flightgear-python: {e}"));
        assert_bitwise_eq(
            &got,
            want,
            &format!("datagram {i} built by flightgear-python"),
        );
        assert_eq!(
            hex(&want.encode()),
            built_hex,
            "datagram {i}: flightgear-python and our encoder give different bytes"
        );
    }
    script.finish();
}

/// What `fix_fg_radian_parsing` makes of one radian value, computed the way
/// CPython does (`x + math.degrees(x) * 1.09349403e-9`, in `f64`).
fn fgpy_offset(x: f64) -> f64 {
    x + x.to_degrees() * FGPY_RADIAN_COEFF
}

#[test]
fn flightgear_python_fdm_connection_adds_its_radian_offset() {
    // Finite values only (NaN arithmetic in Python is not this test's topic).
    let mut sent = vec![golden(), display_fdm()];
    let mut rng = Rng(24);
    for _ in 0..8 {
        let mut f = display_fdm();
        let mut angle = || ((rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 6.5;
        f.longitude = angle();
        f.latitude = angle() / 2.0;
        (f.phi, f.theta, f.psi) = (angle() as f32, angle() as f32, angle() as f32);
        (f.alpha, f.beta) = (angle() as f32, angle() as f32);
        (f.phidot, f.thetadot, f.psidot) = (angle() as f32, angle() as f32, angle() as f32);
        f.rpm[1] = 1234.5;
        sent.push(f);
    }

    let back = UdpSocket::bind("127.0.0.1:0").expect("bind");
    back.set_read_timeout(Some(TIMEOUT)).unwrap();
    let back_port = back.local_addr().unwrap().port();
    let mut script = Script::start("fdm_connection_echo.py", &[back_port.to_string()]);
    let port = script.port();
    let mut tx = Sender::connect(&format!("127.0.0.1:{port}")).expect("sender");

    let mut buf = [0u8; 4096];
    let mut changed_f32 = 0;
    for (i, fdm) in sent.iter().enumerate() {
        assert!(tx.send(fdm).is_sent());
        let len = match back.recv(&mut buf) {
            Ok(n) => n,
            Err(e) => {
                let err = script.stderr();
                panic!("echo {i} from FDMConnection not received: {e}\n{err}");
            }
        };
        let got = FgNetFdm::decode(&buf[..len]).expect("echo decodes");

        let mut want = *fdm;
        want.longitude = fgpy_offset(fdm.longitude);
        want.latitude = fgpy_offset(fdm.latitude);
        for (w, x) in [
            (&mut want.phi, fdm.phi),
            (&mut want.theta, fdm.theta),
            (&mut want.psi, fdm.psi),
            (&mut want.alpha, fdm.alpha),
            (&mut want.beta, fdm.beta),
            (&mut want.phidot, fdm.phidot),
            (&mut want.thetadot, fdm.thetadot),
            (&mut want.psidot, fdm.psidot),
        ] {
            *w = fgpy_offset(f64::from(x)) as f32;
            if *w != x {
                changed_f32 += 1;
            }
        }
        assert_bitwise_eq(&got, &want, &format!("echo {i} through FDMConnection"));

        // The offset is real and only on the radian fields.
        assert_ne!(got.latitude, fdm.latitude, "echo {i}");
        let rel = (got.latitude - fdm.latitude) / fdm.latitude;
        assert!(
            (rel - 6.2653e-8).abs() < 1e-11,
            "echo {i}: relative offset {rel}"
        );
        for ((name, a), (_, b)) in element_bits(&got).into_iter().zip(element_bits(fdm)) {
            if !RADIAN_FIELDS.contains(&name.as_str()) {
                assert_eq!(a, b, "echo {i}: {name} must pass through unchanged");
            }
        }
    }
    // The f32 angles are often too coarse to move (half an f32 ulp is
    // 6e-8 relative), but some do.
    assert!(changed_f32 > 0, "no f32 angle moved");
    script.finish();
}

// ------------------------------------------- the bridge's fields, physically

/// WGS-84 semi-major axis, m, and first eccentricity squared (the defining
/// constants, written here independently of `fdm_core::geodesy`).
const WGS84_A: f64 = 6_378_137.0;
const WGS84_E2: f64 = 6.694_379_990_141_316e-3;
/// One international foot, m, and one knot, m/s (1852 m per hour): the
/// definitions, not the crate's constants.
const FOOT_M: f64 = 0.3048;
const KNOT_MPS: f64 = 1852.0 / 3600.0;

/// Reads a datagram back from flightgear-python's JSON (values as bits).
fn from_py_fields(py_fields: &Value) -> FgNetFdm {
    let mut fdm = FgNetFdm::new();
    for f in fields() {
        let entry = &py_fields[f.py]["value"];
        for el in 0..f.len {
            let v = if f.len == 1 { entry } else { &entry[el] };
            let bits = match f.kind {
                Kind::I32 => u64::from(v.as_i64().expect("i32") as i32 as u32),
                _ => v.as_u64().expect("bits"),
            };
            (f.set)(&mut fdm, el, bits);
        }
    }
    fdm
}

/// One frame of a scripted flight: the packet and what the test knows
/// independently of the bridge (the controls the script set).
struct Frame {
    packet: FgNetFdm,
    /// Palmer: the scripted angle of attack, degrees (None for Bourg).
    alpha_deg: Option<f64>,
    /// The flap setting the script made, 0..1 of full.
    flaps: f64,
    /// Whether the script left the throttle above zero.
    engine_on: bool,
    /// The engine speed the aircraft data gives while running, rev/min.
    rpm_on: f64,
}

/// Flies `M` for `frames` frames at `fps` with `script` (frame → actions),
/// from `state`, and returns the datagram of every frame from the bridge.
fn fly<M: fdm_core::model::Model>(
    state: M::State,
    fps: f64,
    frames: usize,
    script: impl Fn(usize) -> Vec<M::Action>,
    known: impl Fn(&M::Controls) -> (Option<f64>, f64, bool, f64),
) -> Vec<Frame> {
    let origin = fdm_core::geodesy::GeodeticOrigin::default();
    let aircraft = M::default_aircraft();
    let mut controls = M::initial_controls();
    let mut state = state;
    let dt = M::time_step(fps);
    let mut out = Vec::new();
    for frame in 1..=frames {
        controls = M::begin_frame(controls);
        for action in script(frame) {
            controls = M::apply(&aircraft, controls, action);
        }
        state = M::step(&aircraft, &controls, &state, dt);
        let view = M::view(&aircraft, &controls, &state);
        let (alpha_deg, flaps, engine_on, rpm_on) = known(&controls);
        out.push(Frame {
            packet: fgnet::bridge::display(&view, &origin).packet,
            alpha_deg,
            flaps,
            engine_on,
            rpm_on,
        });
    }
    out
}

/// Palmer: full power, alpha to 6° then down to 2°, a 15° right bank from
/// frame 30 (so the aircraft turns and v_east is not zero), flaps 20° at
/// frame 120 and 40° at 180, throttle back to zero from frame 240 on.
fn palmer_flight(fps: f64) -> Vec<Frame> {
    use fdm_core::palmer::{PalmerAction as A, PalmerState};
    let start = PalmerState {
        time_s: 0.0,
        position_m: nalgebra::Vector3::new(0.0, 0.0, 500.0),
        velocity_mps: nalgebra::Vector3::new(50.0, 0.0, 0.0),
    };
    fly::<fdm_core::palmer::Palmer>(
        start,
        fps,
        300,
        |f| {
            let mut a = Vec::new();
            if f <= 20 {
                a.push(A::ThrottleUp);
            }
            if f <= 6 {
                a.push(A::AlphaUp);
            }
            if (150..154).contains(&f) {
                a.push(A::AlphaDown);
            }
            if (30..45).contains(&f) {
                a.push(A::BankRight);
            }
            if f == 120 || f == 180 {
                a.push(A::FlapsDown);
            }
            if f >= 240 {
                a.push(A::ThrottleDown);
            }
            a
        },
        |c| {
            (
                Some(c.alpha_deg),
                c.flaps.degrees() / 40.0,
                c.throttle > 0.0,
                // The Cessna's propeller turns 40 rev/s (docs/palmer-model.md).
                40.0 * 60.0,
            )
        },
    )
}

/// Bourg: from the book's start (60 ft/s north at 2000 ft), thrust up to
/// 1500 lb, pulses of pitch, roll and yaw (so the body velocity has all
/// three components and the heading moves), landing flaps down from frame
/// 100, thrust to zero from frame 200.
fn bourg_flight(fps: f64) -> Vec<Frame> {
    use fdm_core::bourg::{BourgAction as A, BourgState};
    fly::<fdm_core::bourg::Bourg>(
        BourgState::initial(),
        fps,
        300,
        |f| {
            let mut a = Vec::new();
            if f <= 10 {
                a.push(A::ThrustUp);
            }
            if f % 7 == 0 {
                a.push(A::PitchUp);
            }
            if f % 11 == 0 {
                a.push(A::RollLeft);
            }
            if f % 13 == 0 {
                a.push(A::YawRight);
            }
            if f == 100 {
                a.push(A::FlapsDown);
            }
            if f >= 200 {
                a.push(A::ThrustDown);
            }
            a
        },
        |c| {
            (
                None,
                if c.landing_flaps { 1.0 } else { 0.0 },
                c.thrust_lb > 0.0,
                // Bourg's model has no engine speed.
                0.0,
            )
        },
    )
}

/// Body (forward, right, down) to north-east-down, from FlightGear's Euler
/// angles (roll φ, pitch θ, heading ψ; the aerospace z-y-x sequence).
fn body_to_ned(phi: f64, theta: f64, psi: f64, b: [f64; 3]) -> [f64; 3] {
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    let r = [
        [ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp],
        [ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp],
        [-st, sf * ct, cf * ct],
    ];
    [0, 1, 2].map(|i| r[i][0] * b[0] + r[i][1] * b[1] + r[i][2] * b[2])
}

/// The largest deviations of one flight's packets from the physics, for the
/// tolerances below: (finite-difference velocity, ft/s; body↔NED rotation,
/// ft/s; relative speed; angle, rad).
fn check_flight(name: &str, fps: f64, sent: &[Frame], got: &[FgNetFdm]) -> [f64; 4] {
    let dt = 1.0 / fps;
    let trapezoid = name == "palmer";
    // Palmer's positions are f64; Bourg's are f32 feet, whose ulp near
    // 5000 ft (4.9e-4 ft) divided by dt is 0.015 ft/s.
    let fd_tol = if trapezoid { 0.005 } else { 0.03 };
    let mut worst = [0.0_f64; 4];
    let mut seen = (0.0_f64, 0.0_f64, 0.0_f64, [false; 2], [0.0_f64; 3]);
    for (k, (frame, p)) in sent.iter().zip(got).enumerate() {
        let ctx = format!("{name} frame {}", k + 1);
        let f = |x: f32| f64::from(x);
        let (vn, ve, vd) = (f(p.v_north), f(p.v_east), f(p.v_down));
        let (u, v, w) = (f(p.v_body_u), f(p.v_body_v), f(p.v_body_w));
        let speed_fps = f(p.vcas) * KNOT_MPS / FOOT_M;

        // Finite differences of the geodetic position over the frame that
        // ended here: local north, east and down, ft/s. The controls are
        // constant within a step, so what the difference equals follows from
        // the integrator: Palmer's RK4 moves by the mean of the velocities
        // at the two ends (trapezoid, error O(dt³)); Bourg's semi-implicit
        // Euler moves by exactly the new velocity times dt.
        if k > 0 {
            let a = &got[k - 1];
            let lat = p.latitude;
            let s2 = lat.sin().powi(2);
            let m = WGS84_A * (1.0 - WGS84_E2) / (1.0 - WGS84_E2 * s2).powf(1.5) + p.altitude;
            let n = WGS84_A / (1.0 - WGS84_E2 * s2).sqrt() + p.altitude;
            let fd = [
                (p.latitude - a.latitude) / dt * m / FOOT_M,
                (p.longitude - a.longitude) / dt * n * lat.cos() / FOOT_M,
                -(p.altitude - a.altitude) / dt / FOOT_M,
            ];
            let prev = [f(a.v_north), f(a.v_east), f(a.v_down)];
            for (i, ((fd, pkt), prev)) in fd.iter().zip([vn, ve, vd]).zip(prev).enumerate() {
                let want = if trapezoid { (pkt + prev) / 2.0 } else { pkt };
                let e = (fd - want).abs();
                worst[0] = worst[0].max(e);
                assert!(
                    e < fd_tol,
                    "{ctx}: NED velocity {i}: packet {want}, from positions {fd}"
                );
            }
        }
        // The body velocity rotated by the packet's attitude is the NED one.
        let ned = body_to_ned(f(p.phi), f(p.theta), f(p.psi), [u, v, w]);
        for (i, (r, pkt)) in ned.iter().zip([vn, ve, vd]).enumerate() {
            let e = (r - pkt).abs();
            worst[1] = worst[1].max(e);
            assert!(
                e < 5e-4,
                "{ctx}: body velocity rotated, axis {i}: {r} vs {pkt}"
            );
        }
        // No wind: the airspeed is the speed, in both frames.
        let ned_speed = (vn * vn + ve * ve + vd * vd).sqrt();
        let body_speed = (u * u + v * v + w * w).sqrt();
        for s in [ned_speed, body_speed] {
            let e = (speed_fps - s).abs() / s;
            worst[2] = worst[2].max(e);
            assert!(e < 1e-6, "{ctx}: airspeed {speed_fps} ft/s vs |v| {s}");
        }
        // Alpha and beta from the body velocity (u = V cos α cos β,
        // v = V sin β, w = V sin α cos β).
        let alpha = w.atan2(u);
        let beta = (v / body_speed).asin();
        for (what, pkt, want) in [("alpha", f(p.alpha), alpha), ("beta", f(p.beta), beta)] {
            let e = (pkt - want).abs();
            worst[3] = worst[3].max(e);
            assert!(e < 1e-6, "{ctx}: {what} {pkt} rad, from u, v, w {want}");
        }
        if let Some(alpha_deg) = frame.alpha_deg {
            let e = (f(p.alpha) - alpha_deg.to_radians()).abs();
            assert!(
                e < 1e-6,
                "{ctx}: alpha {} vs the scripted {alpha_deg}°",
                p.alpha
            );
        }
        // Climb rate: up is minus down. The bridge takes it along the model
        // frame's vertical, v_down along the local one; the two verticals
        // part by the distance from the origin over the earth's radius
        // (Bourg starts 1.5 km south of it: 2.4e-4 rad), so the tolerance is
        // the speed times 1.5 × that angle, plus f32 rounding. A wrong sign
        // or unit is off by far more.
        let (lat0, lon0) = (39.8264_f64.to_radians(), (-84.0483_f64).to_radians());
        let d = WGS84_A * ((p.latitude - lat0).hypot((p.longitude - lon0) * lat0.cos()));
        let tilt = d / (WGS84_A * (1.0 - WGS84_E2));
        assert!(
            (f(p.climb_rate) + vd).abs() <= ned_speed * (1.5 * tilt + 1e-6),
            "{ctx}: climb rate {} vs v_down {vd}",
            p.climb_rate
        );
        // Flaps, engine.
        assert_eq!(f(p.left_flap), frame.flaps, "{ctx}: left flap");
        assert_eq!(f(p.right_flap), frame.flaps, "{ctx}: right flap");
        assert_eq!(p.num_engines, 1, "{ctx}");
        let (state, rpm) = if frame.engine_on {
            (EngineState::Running, frame.rpm_on)
        } else {
            (EngineState::Off, 0.0)
        };
        assert_eq!(p.eng_state[0], u32::from(state), "{ctx}: engine state");
        assert_eq!(f(p.rpm[0]), rpm, "{ctx}: rpm");

        seen.0 = seen.0.max(ve.abs());
        seen.1 = seen.1.max(vd.abs());
        seen.2 = seen.2.max(v.abs());
        seen.3[usize::from(frame.engine_on)] = true;
        seen.4[(frame.flaps * 2.0) as usize] = 1.0;
    }
    // The flight exercised what it checks: an eastward and a vertical
    // component, the engine both on and off, and more than one flap setting.
    assert!(
        seen.0 > 1.0 && seen.1 > 1.0,
        "{name}: |v_east| {} |v_down| {}",
        seen.0,
        seen.1
    );
    assert!(seen.3 == [true, true], "{name}: engine on and off");
    assert!(
        seen.4.iter().sum::<f64>() >= 2.0,
        "{name}: flap settings {:?}",
        seen.4
    );
    if name == "bourg" {
        assert!(seen.2 > 0.1, "bourg: sideslip velocity {}", seen.2);
    }
    worst
}

/// Every display field the bridge fills (velocities, body velocities,
/// airspeed, climb rate, alpha, beta, flaps, engine), decoded by
/// flightgear-python from the datagrams of two scripted flights, against
/// independent expectations:
///
/// * v_north/east/down against finite differences of the datagram's own
///   latitude, longitude and altitude over each frame (WGS-84 radii of
///   curvature, written here): Palmer's RK4 step moves by the mean of the
///   end velocities, Bourg's semi-implicit Euler by the new velocity.
///   Tolerance 0.005 ft/s for Palmer (measured worst 8.1e-4: the O(dt³)
///   trapezoid error), 0.03 ft/s for Bourg (measured 7.3e-3: its f32
///   positions, one ulp at 5000 ft / dt = 0.015 ft/s);
/// * the body velocity rotated by the datagram's roll, pitch, heading equals
///   the NED velocity: 5e-4 ft/s (f32 angles: an ulp of ψ ≈ 5e-7 rad on a
///   ~200 ft/s velocity), measured worst 6.1e-5;
/// * airspeed (knots, 1852 m/h) equals |v| in both frames: relative 1e-6
///   (f32 fields; measured 3.3e-7), alpha = atan2(w, u), beta = asin(v/|v|):
///   1e-6 rad (measured 1.3e-8);
///   Palmer's alpha equals the scripted one;
/// * climb rate = −v_down; flaps, engine state and rpm as the script set
///   the controls (Palmer's 40 rev/s propeller; Bourg has no rpm).
#[test]
fn bridge_fields_match_the_physics_through_flightgear_python() {
    let fps = 30.0;
    let flights = [("palmer", palmer_flight(fps)), ("bourg", bourg_flight(fps))];
    let total: usize = flights.iter().map(|(_, f)| f.len()).sum();
    let mut script = Script::start(
        "parse_udp.py",
        &[total.to_string(), TIMEOUT.as_secs().to_string()],
    );
    let port = script.port();
    let mut tx = Sender::connect(&format!("127.0.0.1:{port}")).expect("sender");
    for (name, frames) in &flights {
        let mut got = Vec::new();
        for (i, frame) in frames.iter().enumerate() {
            // One at a time, so no datagram waits in a full socket buffer.
            assert!(tx.send(&frame.packet).is_sent(), "{name} datagram {i}");
            let line: Value = serde_json::from_str(&script.line()).expect("JSON line");
            let parsed = from_py_fields(&line["fields"]);
            assert_bitwise_eq(&parsed, &frame.packet, &format!("{name} datagram {i}"));
            got.push(parsed);
        }
        let worst = check_flight(name, fps, frames, &got);
        eprintln!(
            "{name}: worst deviations (fd ft/s, rotation ft/s, speed rel, angle rad): {worst:?}"
        );
    }
    script.finish();
}
