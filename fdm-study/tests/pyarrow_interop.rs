//! `runs.arrow` read back by an independent reader: pyarrow (PyPI `pyarrow`
//! 21.0.0, pinned, in a venv under the test's target tmp dir, as the other
//! interop tests make theirs; `$ARROW_PYTHON` can name a ready Python). The
//! comparison is exact: every float as its bits (`float.hex()`), every null
//! where the table has `None`, the drawn inputs and the fingerprints as text.

use std::path::Path;
use std::process::Command;

use fdm_core::model::{FlightStatus, LandingState};
use fdm_study::arrow::ArrowWriter;
use fdm_study::table::fingerprint_text;
use fdm_study::{FlyOptions, RunStatus, RunTable, Study};
use fdm_tests::python::PythonEnv;

const PYARROW: PythonEnv = PythonEnv {
    name: "pyarrow-21.0.0",
    override_var: "ARROW_PYTHON",
    packages: &["pyarrow==21.0.0"],
    distribution: "pyarrow",
    version: "21.0.0",
    imports: &["pyarrow", "pyarrow.ipc"],
};

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/arrow_interop/read_arrow.py"
);

/// Python's `float.hex()` of `v`, to compare bits.
fn hex(v: f64) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() {
            "-0x0.0p+0"
        } else {
            "0x0.0p+0"
        }
        .to_owned();
    }
    let bits = v.to_bits();
    let sign = if v < 0.0 { "-" } else { "" };
    let exp = i64::try_from((bits >> 52) & 0x7ff).unwrap();
    let mantissa = bits & ((1 << 52) - 1);
    let (lead, exp) = if exp == 0 {
        (0, -1022)
    } else {
        (1, exp - 1023)
    };
    format!("{sign}0x{lead}.{mantissa:013x}p{exp:+}")
}

fn read_back(path: &Path) -> serde_json::Value {
    let python = PYARROW.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
    let out = Command::new(python).arg(SCRIPT).arg(path).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn check(tables: &[RunTable], path: &Path) {
    let names: Vec<String> = tables[0].measures.iter().map(|(n, _)| n.clone()).collect();
    let inputs: Vec<String> = tables[0].inputs.iter().map(|(n, _)| n.clone()).collect();
    let mut all = RunTable::empty(&[]);
    all.measures = names.iter().map(|n| (n.clone(), Vec::new())).collect();
    all.inputs = inputs.iter().map(|n| (n.clone(), Vec::new())).collect();
    let file = std::fs::File::create(path).unwrap();
    let mut writer = ArrowWriter::new(std::io::BufWriter::new(file), &all).unwrap();
    for t in tables {
        writer.write(t).unwrap();
    }
    writer.finish().unwrap();
    for t in tables {
        all.append(t.clone()).unwrap();
    }
    let back = read_back(path);
    assert_eq!(back["batches"], tables.len());
    let mut schema = vec![
        serde_json::json!(["run", "uint64", false]),
        serde_json::json!(["status", "string", false]),
    ];
    for n in &names {
        schema.push(serde_json::json!([n, "double", true]));
    }
    for n in &inputs {
        schema.push(serde_json::json!([n, "double", false]));
    }
    schema.push(serde_json::json!(["fingerprint", "string", true]));
    assert_eq!(back["schema"], serde_json::Value::Array(schema));
    let cols = &back["columns"];
    assert_eq!(cols["run"], serde_json::json!(all.run));
    let codes: Vec<&str> = all.status.iter().map(|s| s.code()).collect();
    assert_eq!(cols["status"], serde_json::json!(codes));
    for (name, values) in &all.measures {
        let expected: Vec<Option<String>> = values.iter().map(|v| v.map(hex)).collect();
        assert_eq!(cols[name.as_str()], serde_json::json!(expected), "{name}");
    }
    for (name, values) in &all.inputs {
        let expected: Vec<String> = values.iter().map(|v| hex(*v)).collect();
        assert_eq!(cols[name.as_str()], serde_json::json!(expected), "{name}");
    }
    let expected: Vec<Option<String>> = all
        .fingerprint
        .iter()
        .map(|f| f.map(fingerprint_text))
        .collect();
    assert_eq!(cols["fingerprint"], serde_json::json!(expected));
}

#[test]
fn hex_matches_python() {
    // As Python prints them: (1.0).hex(), (0.1).hex(), (-2.5).hex(), (5e-324).hex().
    assert_eq!(hex(1.0), "0x1.0000000000000p+0");
    assert_eq!(hex(0.1), "0x1.999999999999ap-4");
    assert_eq!(hex(-2.5), "-0x1.4000000000000p+1");
    assert_eq!(hex(5e-324), "0x0.0000000000001p-1022");
}

#[test]
fn pyarrow_reads_a_handmade_table_exactly() {
    let dir = std::env::temp_dir().join(format!("fdm-study-arrow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let a = RunTable {
        run: vec![0, 1, 2, 3, 4, 5, 6, 7, 8],
        status: vec![
            RunStatus::Flown(FlightStatus::Landed(LandingState::Safe)),
            RunStatus::StartRefused,
            RunStatus::Flown(FlightStatus::Airborne),
            RunStatus::Flown(FlightStatus::Diverged),
            RunStatus::Flown(FlightStatus::Landed(LandingState::Crash)),
            RunStatus::Flown(FlightStatus::OnGround),
            RunStatus::Flown(FlightStatus::Landed(LandingState::Rough)),
            RunStatus::Flown(FlightStatus::Airborne),
            RunStatus::Flown(FlightStatus::Airborne),
        ],
        frames: vec![0; 9],
        measures: vec![
            (
                "x_m".into(),
                vec![
                    Some(0.1),
                    None,
                    Some(-0.0),
                    Some(1e300),
                    None,
                    Some(5e-324),
                    Some(3.0),
                    None,
                    Some(-7.25),
                ],
            ),
            (
                "full".into(),
                (0..9).map(|i| Some(f64::from(i) / 3.0)).collect(),
            ),
        ],
        inputs: vec![(
            "input.aircraft.mass_kg".into(),
            vec![1114.0, 0.1, -0.0, 1e-300, 5e-324, 7.0, 1e300, 2.5, 3.0],
        )],
        // A refused start has none; the rest as flown (0 and u64::MAX too).
        fingerprint: vec![
            Some(0),
            None,
            Some(u64::MAX),
            Some(0x0123_4567_89ab_cdef),
            Some(1),
            Some(2),
            Some(3),
            Some(4),
            Some(5),
        ],
    };
    let mut b = a.clone();
    b.run = (9..18).collect();
    b.measures[0].1.reverse();
    check(&[a, b], &dir.join("handmade.arrow"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pyarrow_reads_a_flown_study_exactly() {
    let dir = std::env::temp_dir().join(format!("fdm-study-arrow-flown-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study = Study::from_toml_str(
        r#"
model = "palmer"
runs = 20
seed = 4
duration_s = 3.0
# Starts at 100 ft = 30.48 m: some angles of attack climb 1.5 m in 3 s.
target_height_m = 32.0
measures = ["max_height_m", "time_to_height_s", "final_x_m"]
[initial]
altitude_ft = 100.0
speed_kt = 70.0
[controls]
throttle = 1.0
alpha_deg = 6.0
[[dispersion]]
key = "controls.alpha_deg"
distribution = "uniform"
low = 0.0
high = 12.0
"#,
    )
    .unwrap();
    let options = FlyOptions {
        threads: 1,
        ..FlyOptions::default()
    };
    let first = study.fly_runs(0..13, &options).unwrap();
    let second = study.fly_runs(13..20, &options).unwrap();
    // Some runs reach 32 m in 3 s and some do not: nulls and values.
    let reached = first.measures[1]
        .1
        .iter()
        .chain(&second.measures[1].1)
        .filter(|v| v.is_some())
        .count();
    assert!(reached > 0 && reached < 20, "{reached}");
    check(&[first, second], &dir.join("flown.arrow"));
    let _ = std::fs::remove_dir_all(&dir);
}
