//! Golden recordings (docs/recording.md, "Golden recordings"): one committed
//! recording per model for every format version this `sim-cli` reads
//! (versions 1, 2 and 3), with the output of its replay, so that any change of the
//! format, of its byte order or of what a replay prints is a deliberate,
//! visible change of the files in `tests/golden/`:
//!
//! * replaying each committed recording prints exactly the committed JSON
//!   report and CSV (the reader and the replay; the human summary is checked
//!   by `replay.rs`);
//! * flying the recorded flight again writes exactly the committed bytes (the
//!   writer);
//! * the committed bytes follow the documented layout: magic, the version as
//!   a little-endian `u16`, the model name, the fps and the origin's latitude
//!   as IEEE bits in little-endian order;
//! * the same recording with any other version number (older, newer, or the
//!   version's bytes swapped) is refused naming the version;
//! * a Palmer recording from before the wheel brakes (8 actions in its
//!   header) replays as today's.
//!
//! Tolerance 0 everywhere (bytes). To change the format on purpose, bump
//! `FORMAT_VERSION`, keep the old files as the older version's goldens if it
//! is still read, and write the new ones with `SIM_CLI_BLESS_GOLDEN=1 cargo
//! test -p afit-fdm-cli --test golden golden_recordings_replay` (then
//! review the diff).

mod support;

use std::path::PathBuf;

use support::{scratch, sim, text};

/// The directory of the committed files.
fn golden(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden")).join(name)
}

/// One golden flight: the model, its fps, origin and the command line that
/// flies and records it (without `--record` and `--csv`).
struct Flight {
    model: &'static str,
    fps: u8,
    origin: [f64; 3],
    args: &'static [&'static str],
}

const VERSIONS: [u16; 3] = [1, 2, 3];

const FLIGHTS: [Flight; 2] = [
    Flight {
        model: "palmer",
        fps: 60,
        origin: [37.6, -122.4, 4.0],
        args: &[
            "--altitude-ft",
            "2000",
            "--speed-kt",
            "100",
            "--trim",
            "--frames",
            "150",
        ],
    },
    Flight {
        model: "bourg",
        fps: 30,
        origin: [47.5, 11.2, 700.0],
        args: &["--frames", "150"],
    },
];

impl Flight {
    fn name(&self, version: u16, what: &str) -> String {
        format!("{}_v{version}.{what}", self.model)
    }

    /// Flies the flight, recording it and writing its CSV into `dir`; returns
    /// the JSON report, the recording and the CSV.
    fn fly(&self, dir: &std::path::Path) -> (String, Vec<u8>, Vec<u8>) {
        let rec = dir.join(format!("{}.rec", self.model));
        let csv = dir.join(format!("{}.csv", self.model));
        let script = golden(&format!("{}.txt", self.model));
        let fps = self.fps.to_string();
        let origin = format!("{},{},{}", self.origin[0], self.origin[1], self.origin[2]);
        let mut args = vec![
            self.model,
            "--headless",
            "--json",
            "--fps",
            &fps,
            "--origin",
            &origin,
            "--script",
            script.to_str().unwrap(),
            "--record",
            rec.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
        ];
        args.extend_from_slice(self.args);
        let out = sim(&args);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            text(&out.stderr)
        );
        (
            text(&out.stdout),
            std::fs::read(rec).unwrap(),
            std::fs::read(csv).unwrap(),
        )
    }
}

/// Replays `rec`: the `--json` report and the CSV.
fn replay(rec: &std::path::Path, dir: &std::path::Path) -> (String, Vec<u8>) {
    let csv = dir.join("replay.csv");
    let out = sim(&[
        "replay",
        rec.to_str().unwrap(),
        "--json",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{rec:?}: {}", text(&out.stderr));
    (text(&out.stdout), std::fs::read(csv).unwrap())
}

fn read(name: &str) -> Vec<u8> {
    std::fs::read(golden(name)).unwrap_or_else(|e| {
        panic!("{name}: {e} (write the goldens with SIM_CLI_BLESS_GOLDEN=1, see the module docs)")
    })
}

/// With `SIM_CLI_BLESS_GOLDEN=1`: (re)writes the goldens of the current
/// version from today's binary.
fn bless() -> bool {
    if std::env::var_os("SIM_CLI_BLESS_GOLDEN").is_none() {
        return false;
    }
    let dir = scratch("golden-bless");
    let version = *VERSIONS.last().unwrap();
    for flight in &FLIGHTS {
        let (_, rec, _) = flight.fly(&dir);
        std::fs::write(golden(&flight.name(version, "rec")), &rec).unwrap();
        let (json, csv) = replay(&golden(&flight.name(version, "rec")), &dir);
        std::fs::write(golden(&flight.name(version, "replay.json")), json).unwrap();
        std::fs::write(golden(&flight.name(version, "replay.csv")), csv).unwrap();
    }
    true
}

#[test]
fn golden_recordings_replay_to_their_committed_output() {
    let blessed = bless();
    let dir = scratch("golden-replay");
    for version in VERSIONS {
        for flight in &FLIGHTS {
            let rec = golden(&flight.name(version, "rec"));
            let (json, csv) = replay(&rec, &dir);
            let name = flight.name(version, "replay");
            assert_eq!(
                json.as_bytes(),
                read(&format!("{name}.json")),
                "{name}.json"
            );
            assert!(csv == read(&format!("{name}.csv")), "{name}.csv differs");
        }
    }
    assert!(
        !blessed,
        "goldens written: review the diff, then run without SIM_CLI_BLESS_GOLDEN"
    );
}

/// The writer: the current version's goldens are what flying them writes
/// today, and the replay prints what the flight printed.
#[test]
fn flying_the_golden_flights_writes_the_committed_bytes() {
    let dir = scratch("golden-fly");
    let version = *VERSIONS.last().unwrap();
    for flight in &FLIGHTS {
        let (json, rec, csv) = flight.fly(&dir);
        let name = flight.name(version, "rec");
        let committed = read(&name);
        if rec != committed {
            let at = rec.iter().zip(&committed).position(|(a, b)| a != b);
            panic!(
                "{name}: today's recording differs from the committed one (first at byte {at:?}, \
                 lengths {} and {}): a format change needs a new FORMAT_VERSION",
                rec.len(),
                committed.len()
            );
        }
        let replay = flight.name(version, "replay");
        assert_eq!(json.as_bytes(), read(&format!("{replay}.json")), "{name}");
        assert!(
            csv == read(&format!("{replay}.csv")),
            "{name}: the CSV differs"
        );
    }
}

/// docs/recording.md, "Format (version 1)": magic, version (u16,
/// little-endian), then the bincode header whose first fields are the model
/// name (a one-byte varint length and the bytes), the fps (a varint: one byte
/// up to 250) and the origin's latitude, longitude and altitude (`f64`, IEEE
/// bits, little-endian).
#[test]
fn golden_recordings_follow_the_documented_layout() {
    for version in VERSIONS {
        for flight in &FLIGHTS {
            let bytes = read(&flight.name(version, "rec"));
            assert_eq!(&bytes[..8], b"SIMCLIRC");
            assert_eq!(bytes[8..10], version.to_le_bytes());
            let name = flight.model.as_bytes();
            assert_eq!(usize::from(bytes[10]), name.len());
            let mut at = 11 + name.len();
            assert_eq!(&bytes[11..at], name);
            assert_eq!(bytes[at], flight.fps);
            at += 1;
            for value in flight.origin {
                assert_eq!(
                    bytes[at..at + 8],
                    value.to_le_bytes(),
                    "{}: origin {value}",
                    flight.model
                );
                at += 8;
            }
        }
    }
}

/// Every other version number is refused with the documented message, older
/// ones included, and so is the current version with its two bytes swapped
/// (as a big-endian writer would put them).
#[test]
fn other_format_versions_of_the_goldens_are_refused() {
    let dir = scratch("golden-versions");
    let current = *VERSIONS.last().unwrap();
    for flight in &FLIGHTS {
        let good = read(&flight.name(current, "rec"));
        let mut others: Vec<u16> = vec![0, current + 1, u16::MAX, current.swap_bytes()];
        others.extend((0..current).filter(|v| !VERSIONS.contains(v)));
        for version in others {
            let mut bytes = good.clone();
            bytes[8..10].copy_from_slice(&version.to_le_bytes());
            let path = dir.join(format!("{}-{version}.rec", flight.model));
            std::fs::write(&path, &bytes).unwrap();
            let out = sim(&["replay", path.to_str().unwrap(), "--json"]);
            let stderr = text(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "version {version}: {stderr}");
            assert!(out.stdout.is_empty());
            assert_eq!(
                stderr.trim_end(),
                format!(
                    "sim-cli: error: {}: recording format version {version}; this sim-cli reads \
                     versions 1, 2 and 3",
                    path.display()
                ),
            );
        }
    }
}

/// A Palmer recording written before the wheel brakes existed (the version 2
/// golden: its header lists 8 actions; today's, version 3, 10) replays to
/// exactly the flight today's does: adding actions to a model keeps its older
/// recordings readable.
#[test]
fn a_palmer_recording_from_before_the_brakes_replays_as_today() {
    let dir = scratch("golden-before-brakes");
    let before = read("palmer_v2.rec");
    let today = read("palmer_v3.rec");
    let names = |bytes: &[u8], name: &[u8]| bytes.windows(name.len()).any(|w| w == name);
    assert!(!names(&before, b"brakes-on") && names(&today, b"brakes-on"));
    let (json, csv) = replay(&golden("palmer_v2.rec"), &dir);
    assert_eq!(json.as_bytes(), read("palmer_v3.replay.json"));
    assert!(csv == read("palmer_v3.replay.csv"), "the CSV differs");
}
