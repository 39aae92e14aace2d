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

use std::io::{BufRead, BufReader, Read, Write};
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

use fdm_tests::fgnet_fields::{assert_bitwise_eq, element_bits, fields, from_element_bits, Kind};
use fgnet::{DisplayState, EngineState, FgNetFdm, Sender};
use serde_json::{json, Map, Value};

/// The flightgear-python release these tests pin.
const FGPY_VERSION: &str = "2.1.0";
/// The `construct` release pinned with it (flightgear-python requires >=2.10,<3).
const CONSTRUCT_VERSION: &str = "2.10.70";
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

fn python() -> &'static Path {
    static PYTHON: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match PYTHON.get_or_init(setup_python) {
        Ok(p) => p,
        Err(e) => panic!(
            "fgnet interop tests need Python with flightgear-python=={FGPY_VERSION}:\n{e}\n\
             Install python3 (with the venv module and access to PyPI), or set FGNET_PYTHON \
             to a Python that has flightgear-python=={FGPY_VERSION}."
        ),
    }
}

/// Checks that `python` imports the pinned flightgear-python.
fn check_python(python: &Path) -> Result<(), String> {
    let out = Command::new(python)
        .args([
            "-c",
            "import importlib.metadata as m, flightgear_python.fdm_v24, flightgear_python.fg_if; \
             print(m.version('flightgear-python'))",
        ])
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} cannot import flightgear_python: {}",
            python.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let version = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    if version != FGPY_VERSION {
        return Err(format!(
            "{} has flightgear-python {version}, these tests pin {FGPY_VERSION}",
            python.display()
        ));
    }
    Ok(())
}

fn run(cmd: &mut Command, what: &str) -> Result<(), String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot start {cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{what} failed ({}):\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn setup_python() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("FGNET_PYTHON") {
        let p = PathBuf::from(p);
        check_python(&p).map_err(|e| format!("FGNET_PYTHON={}: {e}", p.display()))?;
        return Ok(p);
    }
    let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let venv = base.join(format!("fgpy-venv-{FGPY_VERSION}"));
    let ready = |dir: &Path| dir.join(".fgnet-ready").exists();
    let venv_python = venv.join("bin").join("python");
    if ready(&venv) && check_python(&venv_python).is_ok() {
        return Ok(venv_python);
    }
    // Build in a private directory and rename it into place, so an
    // interrupted or concurrent setup never leaves a half-made venv in use.
    std::fs::create_dir_all(base).map_err(|e| format!("{}: {e}", base.display()))?;
    let tmp = base.join(format!(
        "fgpy-venv-{FGPY_VERSION}.tmp-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&tmp);
    run(
        Command::new("python3").arg("-m").arg("venv").arg(&tmp),
        "python3 -m venv",
    )?;
    let tmp_python = tmp.join("bin").join("python");
    run(
        Command::new(&tmp_python).args([
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--no-input",
            "--quiet",
            &format!("flightgear-python=={FGPY_VERSION}"),
            &format!("construct=={CONSTRUCT_VERSION}"),
        ]),
        "pip install flightgear-python",
    )?;
    check_python(&tmp_python)?;
    std::fs::write(tmp.join(".fgnet-ready"), FGPY_VERSION).map_err(|e| e.to_string())?;
    if !ready(&venv) {
        let _ = std::fs::remove_dir_all(&venv);
    }
    if std::fs::rename(&tmp, &venv).is_err() {
        // Another process finished first; use its venv.
        let _ = std::fs::remove_dir_all(&tmp);
    }
    check_python(&venv_python)?;
    Ok(venv_python)
}

// ------------------------------------------------------------ child process

/// A Python script we started; killed (by its own handle) if the test fails.
struct Script {
    child: Child,
    stdout: BufReader<ChildStdout>,
    name: String,
}

impl Script {
    fn start(name: &str, args: &[String]) -> Self {
        let mut child = Command::new(python())
            .arg(Path::new(SCRIPT_DIR).join(name))
            .args(args)
            .env("PYTHONDONTWRITEBYTECODE", "1")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {name}: {e}"));
        let stdout = BufReader::new(child.stdout.take().expect("stdout"));
        Self {
            child,
            stdout,
            name: name.to_owned(),
        }
    }

    fn stderr(&mut self) -> String {
        let _ = self.child.kill();
        let mut s = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut s);
        }
        s
    }

    fn line(&mut self) -> String {
        let mut line = String::new();
        match self.stdout.read_line(&mut line) {
            Ok(n) if n > 0 => line.trim_end().to_owned(),
            _ => {
                let err = self.stderr();
                panic!("{} ended early; stderr:\n{err}", self.name)
            }
        }
    }

    fn port(&mut self) -> u16 {
        let line = self.line();
        line.strip_prefix("PORT ")
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("{}: expected 'PORT n', got {line:?}", self.name))
    }

    fn close_stdin(&mut self) {
        drop(self.child.stdin.take());
    }

    fn finish(mut self) {
        self.close_stdin();
        let status = self.child.wait().expect("wait");
        if !status.success() {
            let err = self.stderr();
            panic!("{} exited with {status}; stderr:\n{err}", self.name);
        }
    }
}

impl Drop for Script {
    fn drop(&mut self) {
        if std::thread::panicking() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
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
        let stdin = script.child.stdin.as_mut().expect("stdin");
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
