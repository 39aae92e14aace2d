//! Run i is the same bits whatever the range, the thread count, the block
//! layout or the number of runs, and the same bits again flown alone through
//! `fdm_run::Run` (exact precision), drawn inputs and final-state
//! fingerprints included. Every comparison is exact (f64 bits, u64
//! fingerprints): the guarantee is bit-identity, not closeness.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use fdm_run::{Run, SharedOutput};
use fdm_study::{FlyOptions, MeasureOutput, RunTable, Study, StudyModel};

mod support;
use support::{bits, options};

/// A short landing: trimmed at 120 ft, power off after a dispersed delay,
/// every kind of dispersion, stop at touchdown; measures of every kind.
const PALMER_LANDING: &str = r#"
model = "palmer"
runs = 12
seed = 99
fps = 30
duration_s = 40.0
stop = "touchdown"
target_height_m = 30.0
script = """
1-5 throttle-down
1-1 flaps-down
"""
measures = ["touchdown_x_m", "touchdown_y_m", "touchdown_sink_rate_mps",
            "touchdown_ground_speed_mps", "touchdown_time_s", "min_height_m",
            "max_height_m", "final_time_s", "max_bank_deg", "max_load_factor",
            "time_to_height_s"]
[initial]
altitude_ft = 120.0
speed_kt = 65.0
trim = true
[[dispersion]]
key = "initial.speed_kt"
distribution = "normal"
mean = 65.0
sd = 2.5
[[dispersion]]
key = "aircraft.mass_kg"
distribution = "truncated_normal"
mean = 1050.0
sd = 40.0
low = 950.0
high = 1114.0
[[dispersion]]
key = "script_delay_s"
distribution = "uniform"
low = 0.0
high = 2.0
[[dispersion]]
key = "initial.heading_deg"
distribution = "choice"
values = [-5.0, 0.0, 5.0]
"#;

/// Bourg climbing for 4 s with a dispersed mass and thrust.
const BOURG_CLIMB: &str = r#"
model = "bourg"
runs = 10
seed = 5
duration_s = 4.0
measures = ["max_height_m", "final_x_m", "final_y_m", "final_ground_speed_mps",
            "max_bank_deg", "max_load_factor"]
script = "1-30 pitch-up\n"
[controls]
thrust_lb = 2500.0
[[dispersion]]
key = "aircraft.mass_scale"
distribution = "uniform"
low = 0.9
high = 1.1
[[dispersion]]
key = "controls.thrust_lb"
distribution = "normal"
mean = 2500.0
sd = 100.0
"#;

fn check_layouts(study: &Study) -> RunTable {
    let n = study.runs();
    let all = study.fly_runs(0..n, &options(1)).unwrap();
    assert_eq!(
        bits(&all),
        bits(&study.fly_runs(0..n, &options(3)).unwrap())
    );
    let mut joined = study.fly_runs(0..5, &options(2)).unwrap();
    joined
        .append(study.fly_runs(5..n, &options(1)).unwrap())
        .unwrap();
    assert_eq!(bits(&all), bits(&joined));
    for i in 0..n {
        let one = study.fly_runs(i..i + 1, &options(1)).unwrap();
        assert_eq!(bits(&one)[0], bits(&all)[usize::try_from(i).unwrap()]);
    }
    // More runs, another block layout: the first n rows are unchanged.
    let more = study.clone().with_runs(n + 1500).unwrap();
    let head = more.fly_runs(0..n, &options(2)).unwrap();
    assert_eq!(bits(&all), bits(&head));
    let tail = more.fly_runs(n + 1020..n + 1030, &options(2)).unwrap();
    assert_eq!(tail.len(), 10);
    all
}

/// Run i flown alone through `fdm_run::Run` for the batch's frames, with
/// the measures as an output: the batch's row, bit for bit (measures,
/// inputs, fingerprint); and the fingerprint of the state the lone flight
/// ends in (`Run::state`, the model's scalar step) is the row's. Different
/// runs end in different states here (each draws other values), so their
/// fingerprints all differ.
fn check_alone<M: StudyModel>(study: &Study, all: &RunTable) {
    let distinct: std::collections::BTreeSet<u64> =
        all.fingerprint.iter().map(|f| f.unwrap()).collect();
    assert_eq!(distinct.len(), all.len(), "{:x?}", all.fingerprint);
    for i in 0..study.runs() {
        let row = usize::try_from(i).unwrap();
        let scenario = study.scenario::<M>(i, all.frames[row]).unwrap();
        let output = SharedOutput::new(MeasureOutput::<M>::new(
            study,
            i,
            scenario.start.aircraft.clone(),
        ));
        let mut run = Run::new(scenario).unwrap();
        run.attach(output.clone()).unwrap();
        run.run_to_end().unwrap();
        let alone = output.take().unwrap().table();
        assert_eq!(bits(&alone)[0], bits(all)[row], "run {i}");
        assert_eq!(
            Some(M::state_fingerprint(&run.state().unwrap())),
            all.fingerprint[row],
            "run {i}"
        );
    }
}

/// Each row's `input.*` columns are the run's drawn values
/// (`Study::dispersed_values`, same bits, in the file's order, named
/// `input.` and the key), and the very values the run flies with: the
/// scenario `sim-cli study --run I` flies has that mass, and its script
/// starts later by the drawn delay (rounded to frames).
#[test]
fn the_input_columns_are_the_values_each_run_flies_with() {
    let study = Study::from_toml_str(PALMER_LANDING).unwrap();
    let all = study.fly_runs(0..12, &options(2)).unwrap();
    let names: Vec<&str> = all.inputs.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "input.initial.speed_kt",
            "input.aircraft.mass_kg",
            "input.script_delay_s",
            "input.initial.heading_deg"
        ]
    );
    assert_eq!(study.input_names(), names);
    for i in [0u64, 5, 11] {
        let row = usize::try_from(i).unwrap();
        let drawn = study.dispersed_values(i);
        for ((key, value), (name, column)) in drawn.iter().zip(&all.inputs) {
            assert_eq!(name, &format!("input.{key}"));
            assert_eq!(value.to_bits(), column[row].to_bits(), "run {i} {key}");
        }
        let scenario = study.scenario::<Palmer>(i, all.frames[row]).unwrap();
        assert_eq!(
            scenario.start.aircraft.mass_kg.to_bits(),
            all.inputs[1].1[row].to_bits()
        );
        let delay = all.inputs[2].1[row];
        let first = scenario.script.rules()[0].first_frame;
        assert_eq!(first, 1 + (delay * 30.0).round() as u64, "run {i}");
    }
    // Bourg's thrust is an f32 control: the model flies the f64 drawn,
    // rounded to f32 once.
    let study = Study::from_toml_str(BOURG_CLIMB).unwrap();
    let all = study.fly_runs(0..10, &options(1)).unwrap();
    for i in [0u64, 9] {
        let row = usize::try_from(i).unwrap();
        let scenario = study.scenario::<Bourg>(i, 1).unwrap();
        assert_eq!(
            scenario.start.controls.thrust_lb,
            all.inputs[1].1[row] as f32
        );
        assert_eq!(study.dispersed_values(i)[1].1, all.inputs[1].1[row]);
    }
}

#[test]
fn palmer_runs_are_the_same_bits_in_any_layout_and_alone() {
    let study = Study::from_toml_str(PALMER_LANDING).unwrap();
    let all = check_layouts(&study);
    // The study exercises what it claims: touchdowns, dispersed stops.
    assert!(all.status.iter().all(|s| s.code().starts_with("landed")));
    let frames: std::collections::BTreeSet<u64> = all.frames.iter().copied().collect();
    assert!(frames.len() > 1, "{frames:?}");
    check_alone::<Palmer>(&study, &all);
}

#[test]
fn bourg_runs_are_the_same_bits_in_any_layout_and_alone() {
    let study = Study::from_toml_str(BOURG_CLIMB).unwrap();
    let all = check_layouts(&study);
    check_alone::<Bourg>(&study, &all);
}

#[test]
fn another_seed_gives_other_runs() {
    let study = Study::from_toml_str(BOURG_CLIMB).unwrap();
    let a = study.fly_runs(0..3, &options(1)).unwrap();
    let b = study.with_seed(6).fly_runs(0..3, &options(1)).unwrap();
    assert_ne!(bits(&a), bits(&b));
}

/// Fast precision (Palmer): the same bits in every layout too (each lane
/// is flown alone), within 1e-6 m of exact (fdm-fleet's bound is 1e-9 m
/// after 1,800 steps; touchdown positions of a 40 s flight differ by less
/// than 1e-6 m, the first frame of touchdown being the same).
#[test]
fn fast_precision_is_layout_independent_and_close_to_exact() {
    let study = Study::from_toml_str(PALMER_LANDING).unwrap();
    let fast = |threads| FlyOptions {
        threads,
        precision: fdm_fleet::Precision::Fast,
    };
    let a = study.fly_runs(0..12, &fast(1)).unwrap();
    let b = study.fly_runs(0..12, &fast(2)).unwrap();
    assert_eq!(bits(&a), bits(&b));
    let one = study.fly_runs(7..8, &fast(1)).unwrap();
    assert_eq!(bits(&one)[0], bits(&a)[7]);
    let exact = study.fly_runs(0..12, &options(1)).unwrap();
    for ((name, f), (_, e)) in a.measures.iter().zip(&exact.measures) {
        if name == "touchdown_x_m" {
            for (f, e) in f.iter().zip(e) {
                assert!((f.unwrap() - e.unwrap()).abs() < 1e-6, "{f:?} {e:?}");
            }
        }
    }
}

#[test]
fn bourg_refuses_fast() {
    let study = Study::from_toml_str(BOURG_CLIMB).unwrap();
    let err = study
        .fly_runs(
            0..1,
            &FlyOptions {
                threads: 1,
                precision: fdm_fleet::Precision::Fast,
            },
        )
        .unwrap_err();
    assert!(err.to_string().contains("fast"), "{err}");
}
