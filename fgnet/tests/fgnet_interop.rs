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
//! [`FGPY_VERSION`]); otherwise a virtualenv created once under
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
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use fdm_tests::python::{PyScript, PythonEnv};
use std::time::Duration;

use fdm_tests::fgnet_fields::{assert_bitwise_eq, element_bits, fields, from_element_bits, Kind};
use fgnet::{DisplayState, EngineState, FgNetFdm, Sender};
use serde_json::{json, Map, Value};

/// The flightgear-python release these tests pin.
const FGPY_VERSION: &str = "2.1.0";
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

/// flightgear-python and its construct, pinned.
const ENV: PythonEnv = PythonEnv {
    name: "fgpy-2.1.0",
    override_var: "FGNET_PYTHON",
    packages: &["flightgear-python==2.1.0", "construct==2.10.70"],
    distribution: "flightgear-python",
    version: FGPY_VERSION,
    imports: &["flightgear_python.fdm_v24", "flightgear_python.fg_if"],
};

fn python() -> &'static Path {
    static PYTHON: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match PYTHON.get_or_init(|| ENV.python(Path::new(env!("CARGO_TARGET_TMPDIR")))) {
        Ok(p) => p,
        Err(e) => panic!(
            "fgnet interop tests need Python with flightgear-python=={FGPY_VERSION}:\n{e}\n\
             Install python3 (with the venv module and access to PyPI), or set FGNET_PYTHON \
             to a Python that has it."
        ),
    }
}

/// A Python script of this test's directory, started with the pinned Python.
struct Script;

impl Script {
    fn start(name: &str, args: &[String]) -> PyScript {
        PyScript::start(python(), &Path::new(SCRIPT_DIR).join(name), args)
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
