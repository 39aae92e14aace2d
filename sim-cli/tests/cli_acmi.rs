//! `--acmi FILE` through the built binary (docs/cli.md): the Tacview ACMI
//! file, read back by an independent reader (pyacmi 1.2.4, pinned:
//! `fdm_tests::python::PYACMI`), carries the flight the CSV shows within 1e-7
//! degrees, 0.01 m and 0.01 degrees of attitude; a replay writes the same
//! bytes as the recorded flight; a fleet's file has every aircraft, the same
//! from both kernels; bad options are refused with exit status 2.

mod support;

use std::collections::HashMap;
use std::path::Path;

use fdm_tests::python::{PyScript, PYACMI, PYACMI_SCRIPT};
use support::{csv_body, scratch, sim, sim_ok, text};

const EXAMPLES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/scripts/");

#[track_caller]
fn refused(args: &[&str], needle: &str) {
    let out = sim(args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: stderr {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
}

/// What pyacmi read.
#[derive(Debug, Default)]
struct Read {
    header: HashMap<String, String>,
    /// Object id → name, type, callsign.
    objects: HashMap<String, Vec<String>>,
    /// (time, object id, lon, lat, alt, roll, pitch, yaw) of every live object per frame.
    samples: Vec<(f64, String, [f64; 6])>,
}

fn read(path: &Path) -> Read {
    let python = PYACMI.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
    let mut py = PyScript::start(
        &python,
        Path::new(PYACMI_SCRIPT),
        &[path.display().to_string()],
    );
    let mut read = Read::default();
    let mut t = f64::NAN;
    loop {
        let line = py.line();
        let (kind, rest) = line.split_once(' ').unwrap_or((&line, ""));
        match kind {
            "H" => {
                let (k, v) = rest.split_once(' ').unwrap();
                read.header.insert(k.to_owned(), v.to_owned());
            }
            "O" => {
                let (id, info) = rest.split_once(' ').unwrap();
                read.objects
                    .insert(id.to_owned(), info.split('\t').map(str::to_owned).collect());
            }
            "F" => t = rest.parse().unwrap(),
            "P" => {
                let mut words = rest.split(' ');
                let id = words.next().unwrap().to_owned();
                let v: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                read.samples.push((t, id, v.try_into().unwrap()));
            }
            "R" => {}
            "E" => break,
            _ => panic!("unexpected line from read_acmi.py: {line:?}"),
        }
    }
    py.finish();
    read
}

/// The CSV's placement columns by frame number (the first row of each frame
/// number: a headless flight has one), of a CSV written by `model`.
fn csv_placements(path: &Path, model: &str) -> HashMap<u64, [f64; 6]> {
    let csv = std::fs::read_to_string(path).unwrap();
    let mut lines = csv_body(&csv, model).lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|&h| h == name).unwrap();
    let cols = [
        col("lon_deg"),
        col("lat_deg"),
        col("alt_m"),
        col("roll_deg"),
        col("pitch_deg"),
        col("fg_heading_deg"),
    ];
    let mut rows = HashMap::new();
    for line in lines {
        let v: Vec<&str> = line.split(',').collect();
        let frame: u64 = v[0].parse().unwrap();
        rows.entry(frame)
            .or_insert_with(|| cols.map(|c| v[c].parse::<f64>().unwrap()));
    }
    rows
}

#[test]
fn the_acmi_track_is_the_csvs_within_1e_7_degrees_and_a_centimetre() {
    let dir = scratch("acmi_csv");
    for (model, script, frames, file) in [
        ("palmer", "palmer_climb_turn.txt", "1800", "p.zip.acmi"),
        ("bourg", "bourg_roll.txt", "900", "b.acmi"),
    ] {
        let acmi = dir.join(file);
        let csv = dir.join(format!("{model}.csv"));
        let script = format!("{EXAMPLES}{script}");
        sim_ok(&[
            model,
            "--headless",
            "--frames",
            frames,
            "--script",
            &script,
            "--csv",
            csv.to_str().unwrap(),
            "--acmi",
            acmi.to_str().unwrap(),
            "--acmi-reference-time",
            "2024-05-01T12:00:00Z",
        ]);
        let rows = csv_placements(&csv, model);
        let read = read(&acmi);
        assert_eq!(read.header["ReferenceTime"], "2024-05-01T12:00:00Z");
        assert_eq!(read.header["FileVersion"], "2.2");
        assert_eq!(read.objects.len(), 1);
        assert_eq!(read.objects["1"][1], "Air+FixedWing");
        assert!(read.samples.len() > 100, "{}", read.samples.len());
        let (mut deg, mut m, mut att) = (0.0_f64, 0.0_f64, 0.0_f64);
        for (t, id, got) in &read.samples {
            assert_eq!(id, "1");
            let frame = (t * 30.0).round() as u64;
            let want = rows[&frame];
            deg = deg
                .max((got[0] - want[0]).abs())
                .max((got[1] - want[1]).abs());
            m = m.max((got[2] - want[2]).abs());
            let yaw = (got[5] - want[5] + 180.0).rem_euclid(360.0) - 180.0;
            att = att
                .max((got[3] - want[3]).abs())
                .max((got[4] - want[4]).abs())
                .max(yaw.abs());
        }
        assert!(
            deg <= 1e-7 && m <= 0.01 && att <= 0.01,
            "{model}: {deg} {m} {att}"
        );
    }
}

#[test]
fn a_replay_writes_the_flights_acmi_bytes() {
    let dir = scratch("acmi_replay");
    let p = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let script = format!("{EXAMPLES}bourg_roll.txt");
    sim_ok(&[
        "bourg",
        "--headless",
        "--frames",
        "600",
        "--script",
        &script,
        "--record",
        &p("b.rec"),
        "--acmi",
        &p("flight.acmi"),
    ]);
    sim_ok(&["replay", &p("b.rec"), "--acmi", &p("replay.acmi")]);
    let flight = std::fs::read(p("flight.acmi")).unwrap();
    assert!(flight.starts_with(
        b"FileType=text/acmi/tacview\nFileVersion=2.2\n0,ReferenceTime=2000-01-01T00:00:00Z\n"
    ));
    assert_eq!(flight, std::fs::read(p("replay.acmi")).unwrap());
}

#[test]
fn a_fleets_acmi_has_every_aircraft_the_same_from_both_kernels() {
    let dir = scratch("acmi_fleet");
    let p = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for kernel in ["lanes", "ecs"] {
        // One file name in two folders: the zip entry is named after the file.
        std::fs::create_dir_all(dir.join(kernel)).unwrap();
        sim_ok(&[
            "fleet",
            "--model",
            "palmer",
            "--aircraft",
            "20",
            "--frames",
            "60",
            "--kernel",
            kernel,
            "--threads",
            "1",
            "--acmi",
            &p(&format!("{kernel}/fleet.zip.acmi")),
        ]);
    }
    let lanes = std::fs::read(p("lanes/fleet.zip.acmi")).unwrap();
    assert!(lanes == std::fs::read(p("ecs/fleet.zip.acmi")).unwrap());
    let read = read(Path::new(&p("lanes/fleet.zip.acmi")));
    assert_eq!(read.objects.len(), 20);
    for i in 1..=20 {
        assert_eq!(read.objects[&format!("{i:x}")][2], format!("C172-{i}"));
    }
    // Every aircraft in the first frame (time 0).
    assert_eq!(read.samples.iter().filter(|s| s.0 == 0.0).count(), 20);
}

#[test]
fn bad_acmi_options_are_refused() {
    let dir = scratch("acmi_bad");
    let p = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    refused(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--acmi-reference-time",
            "2024-01-01T00:00:00Z",
        ],
        "--acmi <FILE>",
    );
    refused(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--acmi",
            &p("a.acmi"),
            "--acmi-reference-time",
            "yesterday",
        ],
        "is not a UTC time",
    );
    refused(
        &[
            "palmer",
            "--headless",
            "--frames",
            "1",
            "--acmi",
            &p("a.csv"),
            "--csv",
            &p("a.csv"),
        ],
        "is also the --csv file",
    );
    refused(
        &[
            "bourg",
            "--headless",
            "--frames",
            "1",
            "--acmi",
            &p("no/such/dir/a.acmi"),
        ],
        "cannot create ACMI file",
    );
}
