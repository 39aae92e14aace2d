//! Tacview ACMI files read back by an independent reader: pyacmi (PyPI
//! `pyacmi` 1.2.4, pinned: `fdm_tests::python::PYACMI`, a venv built once
//! like the other interop tests'), through `tests/acmi_interop/read_acmi.py`.
//!
//! Every aircraft's track as pyacmi reads it matches the placements the run
//! computed, frame by frame, within 1e-7 degrees of longitude and latitude,
//! 0.01 m of altitude and 0.01 degrees of attitude; removed objects are
//! removed at the frame they crashed.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use fdm_core::bourg::Bourg;
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::Palmer;
use fdm_core::script::Script;
use fdm_ecs::{FleetOutputs, Resources, Simulation};
use fdm_run::acmi::{AcmiHeader, AcmiOutput, AcmiWriter, ObjectInfo, ReferenceTime};
use fdm_run::{
    Frame, Output, OutputError, Placement, Run, RunModel, Scenario, SharedOutput, Start,
};
use fdm_tests::python::{PyScript, PYACMI, PYACMI_SCRIPT};

fn script_path() -> PathBuf {
    PathBuf::from(PYACMI_SCRIPT)
}

fn python() -> PathBuf {
    PYACMI.ready(Path::new(env!("CARGO_TARGET_TMPDIR")))
}

fn temp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("acmi_pyacmi");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The truth: every placement the run handed its outputs, by frame.
#[derive(Default)]
struct Truth {
    frames: Vec<(u64, Placement, FlightStatus)>,
}

impl<M: Model> Output<M> for Truth {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        self.frames
            .push((frame.flown, *frame.placement, frame.status));
        Ok(())
    }
}

/// What pyacmi read: per frame time, each live object's six values.
#[derive(Debug, Default)]
struct Read {
    header: HashMap<String, String>,
    objects: HashMap<String, Vec<String>>,
    removed: HashMap<String, f64>,
}

/// Reads `path` with pyacmi; calls `frame(t, id, [lon, lat, alt, roll, pitch, yaw])`
/// for every live object of every frame.
fn read(path: &Path, mut frame: impl FnMut(f64, &str, [f64; 6])) -> Read {
    let mut py = PyScript::start(&python(), &script_path(), &[path.display().to_string()]);
    let mut read = Read::default();
    let mut t = f64::NAN;
    loop {
        let line = py.line();
        let mut words = line.split(' ');
        match words.next() {
            Some("H") => {
                let key = words.next().unwrap().to_owned();
                read.header.insert(key, words.collect::<Vec<_>>().join(" "));
            }
            Some("O") => {
                let id = words.next().unwrap().to_owned();
                let rest = words.collect::<Vec<_>>().join(" ");
                read.objects
                    .insert(id, rest.split('\t').map(str::to_owned).collect());
            }
            Some("F") => t = words.next().unwrap().parse().unwrap(),
            Some("P") => {
                let id = words.next().unwrap();
                let v: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                frame(t, id, v.try_into().unwrap());
            }
            Some("R") => {
                let id = words.next().unwrap().to_owned();
                read.removed
                    .insert(id, words.next().unwrap().parse().unwrap());
            }
            Some("E") => break,
            other => panic!("unexpected line from read_acmi.py: {other:?} {line:?}"),
        }
    }
    py.finish();
    read
}

/// The largest differences seen: degrees (lon/lat), metres, degrees (attitude).
#[derive(Debug, Default, Clone, Copy)]
struct MaxError {
    deg: f64,
    m: f64,
    attitude_deg: f64,
    samples: u64,
}

impl MaxError {
    fn add(&mut self, got: [f64; 6], want: &Placement) {
        let g = &want.geodetic;
        let a = &want.attitude;
        self.deg = self
            .deg
            .max((got[0] - g.lon_deg).abs())
            .max((got[1] - g.lat_deg).abs());
        self.m = self.m.max((got[2] - g.alt_m).abs());
        let yaw = (got[5] - a.heading_deg + 180.0).rem_euclid(360.0) - 180.0;
        self.attitude_deg = self
            .attitude_deg
            .max((got[3] - a.roll_deg).abs())
            .max((got[4] - a.pitch_deg).abs())
            .max(yaw.abs());
        self.samples += 1;
    }

    fn check(&self) {
        assert!(self.samples > 0);
        assert!(self.deg <= 1e-7, "{self:?}");
        assert!(self.m <= 0.01, "{self:?}");
        assert!(self.attitude_deg <= 0.01, "{self:?}");
    }
}

fn header(title: &str, origin: &GeodeticOrigin) -> AcmiHeader {
    AcmiHeader {
        reference_time: ReferenceTime::default(),
        title: title.to_owned(),
        origin: origin.geodetic(),
    }
}

/// Flies `scenario` for its frames with an ACMI file at `path` and the
/// truth; checks pyacmi's reading of the file against the truth.
fn single<M: RunModel>(scenario: Scenario<M>, path: &Path) -> (MaxError, Read, u64) {
    let fps = scenario.fps;
    let writer = AcmiWriter::create(path, &header(M::NAME, &scenario.origin), fps).unwrap();
    let mut run = Run::new(scenario).unwrap();
    let truth = SharedOutput::new(Truth::default());
    run.attach(truth.clone()).unwrap();
    run.attach(AcmiOutput::<M>::new(writer)).unwrap();
    run.run_to_end().unwrap();
    run.finish().unwrap();
    let truth = truth.take().unwrap();
    let by_time: HashMap<u64, Placement> = truth
        .frames
        .iter()
        .map(|&(flown, p, _)| (micros(flown, fps), p))
        .collect();
    let mut error = MaxError::default();
    let read = read(path, |t, id, v| {
        assert_eq!(id, "1");
        let key = (t * 1e6).round() as u64;
        // A frame whose line was left out (nothing changed) has no time of
        // its own; every time pyacmi lists is one the run flew.
        let want = by_time
            .get(&key)
            .unwrap_or_else(|| panic!("no frame at {t}"));
        error.add(v, want);
    });
    (error, read, truth.frames.len() as u64)
}

fn micros(flown: u64, fps: u32) -> u64 {
    (flown * 2_000_000 + u64::from(fps)) / (2 * u64::from(fps))
}

#[test]
fn a_palmer_flight_reads_back_within_1e_7_degrees_and_a_centimetre() {
    let script =
        Script::parse("1-20 throttle-up\n1-6 alpha-up\n600-640 bank-right\n1200-1240 bank-left\n")
            .unwrap();
    let origin: GeodeticOrigin = "21.3187,-157.9225,4".parse().unwrap();
    let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 1800)
        .unwrap()
        .with_origin(origin)
        .with_script(script);
    for name in ["palmer.txt.acmi", "palmer.zip.acmi"] {
        let path = temp(name);
        let (error, read, frames) = single(scenario.clone(), &path);
        error.check();
        assert_eq!(frames, 1801);
        assert!(error.samples > 1000, "{error:?}");
        assert_eq!(read.header["FileType"], "text/acmi/tacview");
        assert_eq!(read.header["FileVersion"], "2.2");
        assert_eq!(read.header["ReferenceTime"], "2000-01-01T00:00:00Z");
        assert_eq!(read.header["ReferenceLongitude"], "-158.0");
        assert_eq!(read.header["ReferenceLatitude"], "21.0");
        assert_eq!(read.objects["1"], ["C172", "Air+FixedWing", "C172-1"]);
        assert!(read.removed.is_empty());
        eprintln!(
            "{name}: {} bytes for 1 aircraft-minute, max errors {error:?}",
            std::fs::metadata(&path).unwrap().len()
        );
    }
}

#[test]
fn a_bourg_dive_is_removed_when_it_crashes() {
    // Nose down from the thesis start (2000 ft): Bourg hits the ground fast.
    let script = Script::parse("1-200 pitch-down\n").unwrap();
    let scenario = Scenario::<Bourg>::new(Start::thesis(), 30, 900)
        .unwrap()
        .with_script(script);
    let path = temp("bourg.txt.acmi");
    let (error, read, _) = single(scenario.clone(), &path);
    error.check();
    let mut run = Run::new(scenario).unwrap();
    let mut crash = None;
    while run.frame() < 900 {
        run.step_frame(&[]).unwrap();
        if matches!(run.status(), FlightStatus::Landed(_)) && crash.is_none() {
            crash = Some(run.frame());
        }
    }
    let crash = crash.expect("the dive ends on the ground");
    assert_eq!(
        run.status(),
        FlightStatus::Landed(fdm_core::model::LandingState::Crash)
    );
    assert_eq!(read.removed["1"], micros(crash, 30) as f64 / 1e6);
    assert_eq!(read.objects["1"], ["Bourg 6-DoF", "Air+FixedWing", "BRG-1"]);
}

/// A fleet of `n` Palmer aircraft (the demonstration fleet: distinct flying
/// states) through the ECS for `frames` frames at 30 fps, every aircraft's
/// placement written by the same writer the CLI uses; pyacmi's reading is
/// checked against the ECS's placements frame by frame (kept for two frames
/// at a time, so that 10,000 aircraft over a minute fit in memory).
fn fleet(n: usize, frames: u64, path: &Path) -> MaxError {
    let origin = GeodeticOrigin::default();
    let mut sim = Simulation::new(Resources::new(30.0).unwrap().with_origin(origin));
    sim.spawn_fleet::<Palmer>(
        &Arc::new(Palmer::default_aircraft()),
        0..n,
        FleetOutputs::Placement,
    );
    let entities: Vec<_> = sim.world_mut().iter().map(|e| e.entity()).collect();
    let mut writer = AcmiWriter::create(path, &header("fleet", &origin), 30).unwrap();
    let place = |sim: &Simulation, e| Placement {
        geodetic: sim.geodetic(e).unwrap(),
        attitude: sim.attitude(e).unwrap(),
    };
    let mut truth: Vec<Vec<Placement>> = Vec::with_capacity(frames as usize + 1);
    for (i, _) in entities.iter().enumerate() {
        writer.declare(i, ObjectInfo::of::<Palmer>(i)).unwrap();
    }
    for flown in 0..=frames {
        if flown > 0 {
            sim.run_frame();
        }
        writer.begin_frame(flown);
        let placements: Vec<Placement> = entities.iter().map(|&e| place(&sim, e)).collect();
        for (i, p) in placements.iter().enumerate() {
            writer.sample(i, p).unwrap();
        }
        truth.push(placements);
    }
    writer.finish().unwrap();
    assert_eq!(sim.diverged_count(), 0);
    let mut error = MaxError::default();
    let mut seen = 0_u64;
    let read = read(path, |t, id, v| {
        let flown = (t * 30.0).round() as usize;
        let i = usize::from_str_radix(id, 16).unwrap() - 1;
        error.add(v, &truth[flown][i]);
        seen += 1;
    });
    assert_eq!(read.objects.len(), n);
    assert_eq!(read.objects[&format!("{:x}", n)][2], format!("C172-{n}"));
    assert!(seen >= n as u64, "{seen}");
    eprintln!(
        "fleet of {n} over {} s: {} bytes, {:.0} bytes per aircraft-minute, max errors {error:?}",
        frames / 30,
        std::fs::metadata(path).unwrap().len(),
        std::fs::metadata(path).unwrap().len() as f64 / n as f64 / (frames as f64 / 1800.0)
    );
    error
}

#[test]
fn a_fleet_of_100_reads_back_every_track() {
    fleet(100, 1800, &temp("fleet100.zip.acmi")).check();
}

/// The size: 10,000 aircraft over 60 s (18 million object lines, a
/// 331 MB `.zip.acmi`, 836 MB of text; pyacmi got through about 0.2 MB of
/// the zip per second of CPU here, so about half an hour of Python on an
/// idle core).
/// `cargo test --release -p fdm-run --test acmi_pyacmi -- --ignored`.
#[test]
#[ignore = "tens of minutes of Python: run with --release -- --ignored"]
fn a_fleet_of_10000_over_60_s_reads_back_every_track() {
    fleet(10_000, 1800, &temp("fleet10000.zip.acmi")).check();
}

/// What a flight with resets looks like to pyacmi: Palmer flies 60 frames,
/// is reset while flying and flies 45 more; Bourg dives until it crashes
/// (and is removed), is reset and flies 30 more. Each flight is its own
/// object (ids `1`, `100000001`, `200000001`: the flight's number above bit
/// 32), each read back against the run's placements of its own frames; the
/// flight a reset ends is removed at the reset's time, so no track joins
/// one flight's last place to the next one's start, and a flight after a
/// crash is not lost to a reader that keeps an id's removal (pyacmi does:
/// a removed id stays removed when it is written again).
#[test]
fn each_flight_after_a_reset_is_an_object_of_its_own() {
    fn flights<M: RunModel>(
        scenario: Scenario<M>,
        path: &Path,
        legs: &[Option<u64>],
    ) -> (Vec<MaxError>, Read, Vec<u64>) {
        let fps = scenario.fps;
        let writer = AcmiWriter::create(path, &header(M::NAME, &scenario.origin), fps).unwrap();
        let mut run = Run::new(scenario).unwrap();
        let truth = SharedOutput::new(Truth::default());
        run.attach(truth.clone()).unwrap();
        run.attach(AcmiOutput::<M>::new(writer)).unwrap();
        // Each leg: a number of frames, or (None) until it lands.
        let mut resets = Vec::new();
        for (k, leg) in legs.iter().enumerate() {
            if k > 0 {
                run.reset().unwrap();
                resets.push(run.flown());
            }
            match *leg {
                Some(frames) => (0..frames).for_each(|_| run.step_frame(&[]).unwrap()),
                None => {
                    while !matches!(run.status(), FlightStatus::Landed(_)) {
                        run.step_frame(&[]).unwrap();
                    }
                }
            }
        }
        run.finish().unwrap();
        // The truth of flight f: its frames, by time (a reset's frame shares
        // its time with the frame before it, which belongs to the flight
        // before).
        let truth = truth.take().unwrap();
        let mut by_flight: Vec<HashMap<u64, Placement>> = vec![HashMap::new(); legs.len()];
        let mut flight = 0;
        for (k, &(flown, p, _)) in truth.frames.iter().enumerate() {
            if k > 0 && truth.frames[k - 1].0 == flown {
                flight += 1;
            }
            by_flight[flight].insert(micros(flown, fps), p);
        }
        let mut errors = vec![MaxError::default(); legs.len()];
        let read = read(path, |t, id, v| {
            let id = u64::from_str_radix(id, 16).unwrap();
            let flight = usize::try_from(id >> 32).unwrap();
            assert_eq!(id & 0xffff_ffff, 1, "{id:x}");
            let want = by_flight[flight]
                .get(&((t * 1e6).round() as u64))
                .unwrap_or_else(|| panic!("flight {flight} has no frame at {t}"));
            errors[flight].add(v, want);
        });
        (errors, read, resets)
    }

    let script = Script::parse("1-20 throttle-up\n1-6 alpha-up\n").unwrap();
    let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 1800)
        .unwrap()
        .with_script(script);
    let (errors, read, resets) = flights(
        scenario,
        &temp("palmer_reset.txt.acmi"),
        &[Some(60), Some(45)],
    );
    errors.iter().for_each(MaxError::check);
    assert_eq!(resets, [60]);
    let call = ["C172", "Air+FixedWing", "C172-1"];
    assert_eq!(read.objects["1"], call);
    assert_eq!(read.objects["100000001"], call);
    assert_eq!(read.removed.len(), 1, "{:?}", read.removed);
    assert_eq!(read.removed["1"], 2.0);

    let script = Script::parse("1-200 pitch-down\n").unwrap();
    let scenario = Scenario::<Bourg>::new(Start::thesis(), 30, 900)
        .unwrap()
        .with_script(script);
    let (errors, read, resets) = flights(
        scenario,
        &temp("bourg_reset.txt.acmi"),
        &[None, Some(30), Some(10)],
    );
    errors.iter().for_each(MaxError::check);
    let crash = resets[0];
    assert!(crash > 30, "{resets:?}");
    // The crash removes the first; the second reset the second; the third
    // flies on.
    assert_eq!(read.objects.len(), 3, "{:?}", read.objects);
    assert_eq!(read.removed.len(), 2, "{:?}", read.removed);
    assert_eq!(read.removed["1"], micros(crash, 30) as f64 / 1e6);
    assert_eq!(
        read.removed["100000001"],
        micros(crash + 30, 30) as f64 / 1e6
    );
    assert!(errors[2].samples >= 10, "{errors:?}");
}

#[test]
fn files_are_reproducible() {
    let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 300).unwrap();
    let bytes = |dir: &str, name: &str| {
        let path = temp(dir);
        std::fs::create_dir_all(&path).unwrap();
        let path = path.join(name);
        let writer = AcmiWriter::create(&path, &header("palmer", &scenario.origin), 30).unwrap();
        let mut run = Run::new(scenario.clone()).unwrap();
        run.attach(AcmiOutput::<Palmer>::new(writer)).unwrap();
        run.run_to_end().unwrap();
        run.finish().unwrap();
        std::fs::read(path).unwrap()
    };
    assert_eq!(bytes("a", "f.zip.acmi"), bytes("b", "f.zip.acmi"));
    assert_eq!(bytes("a", "f.txt.acmi"), bytes("b", "f.txt.acmi"));
}
