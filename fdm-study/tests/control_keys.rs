//! The controls a study sets by name beyond the thrust and attitude:
//! Palmer's flaps and brakes, Bourg's landing flaps and pitch trim. A
//! study's run with them is the single flight with them, bit for bit; the
//! flaps are in place when the trim runs (the trim flies with them); a
//! control the trim solves for is the trim's, whatever the study gives; a
//! drawn value the model does not take makes that run `start_refused`
//! without stopping the others.

use fdm_core::bourg::{Bourg, BourgControls};
use fdm_core::model::Model;
use fdm_core::palmer::{Flaps, Palmer, PalmerControls};
use fdm_core::script::Script;
use fdm_run::scenario::{Scenario, Start, StartOptions};
use fdm_run::{Run, SharedOutput};
use fdm_study::{MeasureOutput, RunTable, Study, StudyError, StudyModel};

mod support;
use support::{bits, options};

/// A landing with full flaps: trimmed at 500 ft and 60 kt, power off from
/// the first frame, to touchdown.
const PALMER_FLAPS_40: &str = r#"
model = "palmer"
runs = 2
seed = 3
fps = 30
duration_s = 90.0
stop = "touchdown"
script = "1-60 throttle-down\n"
measures = ["touchdown_x_m", "touchdown_sink_rate_mps", "touchdown_time_s",
            "min_height_m", "max_height_m", "final_time_s"]
[initial]
altitude_ft = 500.0
speed_kt = 60.0
trim = true
[controls]
flaps_deg = 40
"#;

/// The study's start conditions as `sim-cli palmer --altitude-ft 500
/// --speed-kt 60 --trim` gives them.
const PALMER_START: StartOptions = StartOptions {
    altitude_ft: Some(500.0),
    speed_kt: Some(60.0),
    heading_deg: None,
    trim: true,
};

/// Run `run` of `study` flown alone through `fdm_run::Run` from `start`
/// (built by the caller, not by the study) with the study's script, for
/// the frames the batch flew: its row, and the fingerprint of the state it
/// ends in.
fn fly_alone<M: StudyModel>(
    study: &Study,
    run: u64,
    start: Start<M>,
    script: &str,
    frames: u64,
) -> (RunTable, u64) {
    let scenario = Scenario::new(start, study.fps(), frames)
        .unwrap()
        .with_origin(study.origin())
        .with_script(Script::<M::Action>::parse(script).unwrap());
    let output = SharedOutput::new(MeasureOutput::<M>::new(
        study,
        run,
        scenario.start.aircraft.clone(),
    ));
    let mut run = Run::new(scenario).unwrap();
    run.attach(output.clone()).unwrap();
    run.run_to_end().unwrap();
    let fingerprint = M::state_fingerprint(&run.state().unwrap());
    (output.take().unwrap().table(), fingerprint)
}

/// `[controls] flaps_deg = 40` with the trim: the start `sim-cli study
/// --run I` flies (`Study::scenario`) is the single flight's with `--flaps
/// 40` (the trim's throttle and angle for flaps 40, the flaps kept), and
/// the batch's row is that single flight's, bit for bit (measures,
/// fingerprint). The trim saw the flaps: flaps 40 add lift, so it trims
/// at a lower angle of attack than with the flaps up, and the flight lands
/// with the flaps down.
#[test]
fn palmer_flaps_40_flies_as_the_single_flight_with_flaps_40() {
    let study = Study::from_toml_str(PALMER_FLAPS_40).unwrap();
    let all = study.fly_runs(0..2, &options(2)).unwrap();
    assert!(
        all.status.iter().all(|s| s.code().starts_with("landed")),
        "{:?}",
        all.status.iter().map(|s| s.code()).collect::<Vec<_>>()
    );
    let controls = PalmerControls {
        flaps: Flaps::Deg40,
        ..Palmer::initial_controls()
    };
    let (start, _) = PALMER_START
        .start::<Palmer>(Palmer::default_aircraft(), controls)
        .unwrap();
    let (flaps_up, _) = PALMER_START
        .start::<Palmer>(Palmer::default_aircraft(), Palmer::initial_controls())
        .unwrap();
    assert_eq!(start.controls.flaps, Flaps::Deg40);
    assert!(
        start.controls.alpha_deg < flaps_up.controls.alpha_deg - 1.0,
        "{} {}",
        start.controls.alpha_deg,
        flaps_up.controls.alpha_deg
    );
    for run in 0..2 {
        let row = usize::try_from(run).unwrap();
        let scenario = study.scenario::<Palmer>(run, all.frames[row]).unwrap();
        assert_eq!(scenario.start, start);
        let (alone, fingerprint) = fly_alone::<Palmer>(
            &study,
            run,
            start.clone(),
            "1-60 throttle-down\n",
            all.frames[row],
        );
        assert_eq!(bits(&alone)[0], bits(&all)[row], "run {run}");
        assert_eq!(Some(fingerprint), all.fingerprint[row], "run {run}");
    }
    // Trimmed, flaps 0 and 40 land alike (here with the same measures, bit
    // for bit): in this model the flaps only add lift, and the trim's lower
    // angle of attack makes up the same lift coefficient. At a set angle (no
    // trim) the flaps make another flight.
    let untrimmed = |flaps: &str| {
        let text = PALMER_FLAPS_40
            .replace("trim = true", "trim = false")
            .replace(
                "flaps_deg = 40",
                &format!("flaps_deg = {flaps}\nalpha_deg = 4.0\nthrottle = 0.5"),
            );
        let table = Study::from_toml_str(&text)
            .unwrap()
            .fly_runs(0..1, &options(1))
            .unwrap();
        (table.status[0].code(), table.fingerprint[0].unwrap())
    };
    let (up, down) = (untrimmed("0"), untrimmed("40"));
    assert_ne!(up.1, down.1, "{up:?} {down:?}");
}

/// A control the trim solves for (Palmer's throttle and angle of attack,
/// and its bank, levelled; Bourg's thrust and pitch trim) is the trim's: the value the study gives
/// is set first and then replaced, so the run is the same as without it,
/// bit for bit; the other controls (flaps, brakes, landing flaps) are kept
/// and the trim flies with them.
#[test]
fn the_trim_replaces_the_controls_it_solves_for_and_keeps_the_flaps() {
    let with = |extra: &str| {
        let text = PALMER_FLAPS_40.replace("flaps_deg = 40", &format!("flaps_deg = 40\n{extra}"));
        let study = Study::from_toml_str(&text).unwrap();
        study.scenario::<Palmer>(0, 1).unwrap().start
    };
    let plain = with("");
    for extra in [
        "throttle = 0.1",
        "alpha_deg = 15.0",
        "throttle = 1.0\nalpha_deg = -10.0",
        // The trim flies wings level: the bank is set to 0 too.
        "bank_deg = 10.0",
    ] {
        assert_eq!(with(extra), plain, "{extra}");
    }
    // The brakes are kept too (in the air they do nothing).
    let braked = with("brakes = 1");
    assert!(braked.controls.brakes);
    assert_eq!(
        braked.controls,
        PalmerControls {
            brakes: true,
            ..plain.controls
        }
    );

    let bourg = |controls: &str| {
        let text = format!(
            "model = \"bourg\"\nruns = 1\nduration_s = 1.0\nmeasures = [\"max_height_m\"]\n\
             [initial]\naltitude_ft = 2000.0\nspeed_kt = 100.0\ntrim = true\n\
             [controls]\n{controls}\n"
        );
        Study::from_toml_str(&text)
            .unwrap()
            .scenario::<Bourg>(0, 1)
            .unwrap()
            .start
    };
    let down = bourg("landing_flaps = 1");
    assert!(down.controls.landing_flaps);
    for extra in ["pitch_trim = 0.9", "pitch_trim = -1.0", "thrust_lb = 0.0"] {
        assert_eq!(
            bourg(&format!("landing_flaps = 1\n{extra}")),
            down,
            "{extra}"
        );
    }
    // The trim flew with the flaps down: flaps up trims otherwise.
    let up = bourg("landing_flaps = 0");
    assert!(!up.controls.landing_flaps);
    assert_ne!(
        (up.controls.thrust_lb, up.controls.pitch_trim),
        (down.controls.thrust_lb, down.controls.pitch_trim)
    );
    assert_eq!(bourg("pitch_trim = 0.5"), up);
}

/// A `choice` over the three notches: each run flies the flaps it drew
/// (its `input.controls.flaps_deg`), all three are drawn, and each row is
/// that run's single flight, bit for bit.
#[test]
fn dispersed_flaps_are_drawn_among_the_notches_and_flown() {
    let text = PALMER_FLAPS_40.replace("runs = 2", "runs = 12")
        + "[[dispersion]]\nkey = \"controls.flaps_deg\"\ndistribution = \"choice\"\n\
           values = [0.0, 20.0, 40.0]\n";
    let study = Study::from_toml_str(&text).unwrap();
    let all = study.fly_runs(0..12, &options(2)).unwrap();
    assert_eq!(all.inputs[0].0, "input.controls.flaps_deg");
    let mut drawn = std::collections::BTreeSet::new();
    for run in 0..12 {
        let row = usize::try_from(run).unwrap();
        let degrees = all.inputs[0].1[row];
        assert!([0.0, 20.0, 40.0].contains(&degrees), "{degrees}");
        drawn.insert(degrees.to_bits());
        assert!(all.status[row].code().starts_with("landed"), "run {run}");
        let controls = PalmerControls {
            flaps: Flaps::from_degrees(degrees as u8).unwrap(),
            ..Palmer::initial_controls()
        };
        let (start, _) = PALMER_START
            .start::<Palmer>(Palmer::default_aircraft(), controls)
            .unwrap();
        assert_eq!(start.controls.flaps.degrees(), degrees);
        let (alone, fingerprint) =
            fly_alone::<Palmer>(&study, run, start, "1-60 throttle-down\n", all.frames[row]);
        assert_eq!(bits(&alone)[0], bits(&all)[row], "run {run}");
        assert_eq!(Some(fingerprint), all.fingerprint[row], "run {run}");
    }
    assert_eq!(drawn.len(), 3, "{drawn:?}");
}

/// A dispersion drawing flaps the model does not take (a `uniform` over
/// 0..40 never gives exactly a notch; a `choice` with 10) refuses those
/// runs' starts, naming the value, and flies the others: the study does not
/// stop. Bourg's landing flaps the same (0.5 is neither up nor down).
#[test]
fn drawn_controls_the_model_does_not_take_refuse_that_run_only() {
    let uniform = PALMER_FLAPS_40.replace("runs = 2", "runs = 6")
        + "[[dispersion]]\nkey = \"controls.flaps_deg\"\ndistribution = \"uniform\"\n\
           low = 0.0\nhigh = 40.0\n";
    let study = Study::from_toml_str(&uniform).unwrap();
    let all = study.fly_runs(0..6, &options(2)).unwrap();
    assert_eq!(all.len(), 6);
    for row in 0..6 {
        assert_eq!(all.status[row].code(), "start_refused", "row {row}");
        assert!(all.measures.iter().all(|(_, c)| c[row].is_none()));
    }
    let degrees = all.inputs[0].1[2];
    match study.scenario::<Palmer>(2, 1) {
        Err(StudyError::StartRefused { run: 2, reason }) => assert_eq!(
            reason,
            format!(
                "controls: flaps_deg = {}: expected 0, 20 or 40",
                fdm_core::message::ShortNumber(degrees)
            )
        ),
        other => panic!("{other:?}"),
    }

    let mixed = PALMER_FLAPS_40.replace("runs = 2", "runs = 12")
        + "[[dispersion]]\nkey = \"controls.flaps_deg\"\ndistribution = \"choice\"\n\
           values = [0.0, 10.0, 40.0]\n";
    let all = Study::from_toml_str(&mixed)
        .unwrap()
        .fly_runs(0..12, &options(2))
        .unwrap();
    let codes: Vec<(f64, &str)> = (0..12)
        .map(|row| (all.inputs[0].1[row], all.status[row].code()))
        .collect();
    for &(degrees, code) in &codes {
        if degrees == 10.0 {
            assert_eq!(code, "start_refused", "{codes:?}");
        } else {
            assert!(code.starts_with("landed"), "{codes:?}");
        }
    }
    assert!(codes.iter().any(|&(d, _)| d == 10.0), "{codes:?}");
    assert!(codes.iter().any(|&(d, _)| d != 10.0), "{codes:?}");

    let bourg = Study::from_toml_str(
        BOURG_FLAPS
            .replace("[0.0, 1.0]", "[0.0, 0.5, 1.0]")
            .as_str(),
    )
    .unwrap();
    let all = bourg.fly_runs(0..8, &options(1)).unwrap();
    let codes: Vec<(f64, &str)> = (0..8)
        .map(|row| (all.inputs[0].1[row], all.status[row].code()))
        .collect();
    for &(down, code) in &codes {
        assert_eq!(code == "start_refused", down == 0.5, "{codes:?}");
    }
    assert!(codes.iter().any(|&(d, _)| d == 0.5), "{codes:?}");
    assert!(codes.iter().any(|&(d, _)| d != 0.5), "{codes:?}");
}

/// Bourg for 3 s with a pitch trim and the landing flaps drawn up or down.
const BOURG_FLAPS: &str = r#"
model = "bourg"
runs = 8
seed = 11
duration_s = 3.0
measures = ["max_height_m", "final_x_m", "max_load_factor"]
[controls]
pitch_trim = 0.25
[[dispersion]]
key = "controls.landing_flaps"
distribution = "choice"
values = [0.0, 1.0]
"#;

/// Bourg's landing flaps drawn 0 or 1, with `[controls] pitch_trim`: each
/// run flies the flaps it drew and the trim, and its row is the single
/// flight from the model's start with those controls, bit for bit.
#[test]
fn bourg_dispersed_landing_flaps_fly_as_the_single_flight() {
    let study = Study::from_toml_str(BOURG_FLAPS).unwrap();
    let all = study.fly_runs(0..8, &options(2)).unwrap();
    let mut drawn = std::collections::BTreeSet::new();
    for run in 0..8 {
        let row = usize::try_from(run).unwrap();
        let down = all.inputs[0].1[row];
        assert!(down == 0.0 || down == 1.0, "{down}");
        drawn.insert(down.to_bits());
        let start = Start::<Bourg> {
            aircraft: Bourg::default_aircraft(),
            controls: BourgControls {
                landing_flaps: down == 1.0,
                pitch_trim: 0.25,
                ..Bourg::initial_controls()
            },
            state: Bourg::initial_state(),
        };
        assert_eq!(study.scenario::<Bourg>(run, 1).unwrap().start, start);
        let (alone, fingerprint) = fly_alone::<Bourg>(&study, run, start, "", all.frames[row]);
        assert_eq!(bits(&alone)[0], bits(&all)[row], "run {run}");
        assert_eq!(Some(fingerprint), all.fingerprint[row], "run {run}");
    }
    assert_eq!(drawn.len(), 2, "{drawn:?}");
    // Flaps down and up end in different states.
    let end = |down: f64| {
        (0..8)
            .find(|&row| all.inputs[0].1[row] == down)
            .map(|row| all.fingerprint[row].unwrap())
            .unwrap()
    };
    assert_ne!(end(0.0), end(1.0));
}
