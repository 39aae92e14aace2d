//! The run library's public API as another program uses it: a scenario flown
//! frame by frame or to the end gives the core's own bits; outputs see every
//! frame and reset; a recording made through the `Output` interface replays
//! to the same bits; pacing takes the scenario's wall-clock time.

use std::time::{Duration, Instant};

use fdm_core::bourg::{self, Bourg, BourgAction};
use fdm_core::fingerprint::Fingerprint;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::{self, Palmer, PalmerAction, PalmerControls};
use fdm_core::script::Script;
use fdm_run::recording::{parse_recording, RecordWriter, Recording, Replayed};
use fdm_run::{Event, Frame, Output, OutputError, Run, RunModel, Scenario, SharedOutput, Start};

const PALMER_SCRIPT: &str =
    "1-20 throttle-up\n1-5 alpha-up\n300-310 bank-right\n500-501 flaps-down\n";

fn palmer_scenario(frames: u64) -> Scenario<Palmer> {
    let start = Start {
        controls: PalmerControls {
            throttle: 0.5,
            alpha_deg: 2.0,
            ..PalmerControls::default()
        },
        ..Start::thesis()
    };
    Scenario::new(start, 30, frames)
        .unwrap()
        .with_script(Script::parse(PALMER_SCRIPT).unwrap())
}

#[test]
fn run_to_end_is_the_cores_step_bit_for_bit() {
    let scenario = palmer_scenario(900);
    let mut run = Run::new(scenario.clone()).unwrap();
    let end = run.run_to_end().unwrap();
    assert_eq!((end.frames, end.overruns), (900, None));
    let aircraft = Palmer::default_aircraft();
    let mut controls = scenario.start.controls;
    let mut state = scenario.start.state;
    for frame in 1..=900 {
        for a in scenario.script.actions_at(frame) {
            controls = controls.apply(a);
        }
        state = palmer::step(&aircraft, &controls, &state, 1.0 / 30.0);
    }
    assert_eq!(run.state().unwrap(), state);
    assert_eq!(run.controls().unwrap(), controls);
    assert_eq!(run.frame(), 900);
    assert_eq!(run.status(), FlightStatus::Airborne);
}

#[test]
fn frame_by_frame_with_keys_is_the_cores_step_for_bourg() {
    let scenario = Scenario::<Bourg>::new(Start::thesis(), 60, 0).unwrap();
    let mut run = Run::new(scenario).unwrap();
    let aircraft = Bourg::default_aircraft();
    let mut controls = Bourg::initial_controls();
    let mut state = Bourg::initial_state();
    for frame in 1..=120_u32 {
        let keys: &[BourgAction] = if frame % 4 == 0 {
            &[BourgAction::RollRight, BourgAction::ThrustUp]
        } else {
            &[]
        };
        run.step_frame(keys).unwrap();
        controls = controls.neutralize_surfaces();
        for &a in keys {
            controls = controls.apply(a);
        }
        state = bourg::step(&aircraft, &controls, &state, 1.0f32 / 60.0);
    }
    assert_eq!(run.state().unwrap(), state);
}

/// Counts what an output sees.
#[derive(Default)]
struct Log {
    events: Vec<(Event, u64, u64, usize)>,
    finished: u32,
}

impl<M: Model> Output<M> for Log {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        assert!(frame.placement.geodetic.lat_deg.is_finite());
        self.events
            .push((frame.event, frame.number, frame.flown, frame.actions.len()));
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        self.finished += 1;
        Ok(())
    }
}

#[test]
fn outputs_see_the_start_every_frame_and_every_reset() {
    let mut run = Run::new(palmer_scenario(3)).unwrap();
    let log = SharedOutput::new(Log::default());
    run.attach(log.clone()).unwrap();
    run.step_frame(&[PalmerAction::BankLeft]).unwrap();
    run.reset().unwrap();
    run.run_to_end().unwrap();
    run.finish().unwrap();
    let log = log.take().unwrap();
    assert_eq!(
        log.events,
        [
            (Event::Start, 0, 0, 0),
            // Frame 1: the script's two actions, then the key.
            (Event::Step, 1, 1, 3),
            (Event::Reset, 0, 1, 0),
            (Event::Step, 1, 2, 2),
            (Event::Step, 2, 3, 2),
            (Event::Step, 3, 4, 2),
        ]
    );
    assert_eq!(log.finished, 1);
}

#[test]
fn a_recording_made_through_the_output_interface_replays_bit_for_bit() {
    let scenario = palmer_scenario(600);
    let mut run = Run::new(scenario.clone()).unwrap();
    let writer = RecordWriter::new(Vec::new(), 30, &scenario.origin, &scenario.start).unwrap();
    let recorder = SharedOutput::new(writer);
    run.attach(recorder.clone()).unwrap();
    run.run_to_end().unwrap();
    run.step_frame(&[PalmerAction::ThrottleDown]).unwrap();
    run.reset().unwrap();
    for _ in 0..50 {
        run.step_frame(&[PalmerAction::AlphaUp]).unwrap();
    }
    run.finish().unwrap();
    let bytes = recorder.take().unwrap().into_inner();
    let info = parse_recording(&bytes).unwrap();
    assert_eq!(
        (info.model, info.fps, info.frames, info.resets),
        ("palmer", 30, 651, 1)
    );

    let recording = Recording::<Palmer>::parse(&bytes).unwrap();
    let mut replay =
        Run::new(Scenario::new(recording.start.clone(), recording.fps, 0).unwrap()).unwrap();
    for event in recording.events() {
        match event.unwrap() {
            Replayed::Frames { count, actions } => {
                for _ in 0..count {
                    replay.step_actions(&actions).unwrap();
                }
            }
            Replayed::Reset => replay.reset().unwrap(),
        }
    }
    assert_eq!(replay.state().unwrap(), run.state().unwrap());
    assert_eq!(replay.flown(), run.flown());
    // The end marker carries the flight's fingerprint: the final state's
    // (after the 50 frames since the reset) and the maths'.
    assert_eq!(
        recording.fingerprint,
        Some(Fingerprint::of_palmer(&run.state().unwrap()))
    );
    assert_eq!(
        recording.fingerprint.unwrap().state,
        Palmer::state_fingerprint(&replay.state().unwrap())
    );
}

#[test]
fn a_bourg_recording_carries_its_final_states_fingerprint() {
    let scenario = Scenario::<Bourg>::new(Start::thesis(), 30, 95).unwrap();
    let mut run = Run::new(scenario.clone()).unwrap();
    let writer = RecordWriter::new(Vec::new(), 30, &scenario.origin, &scenario.start).unwrap();
    let recorder = SharedOutput::new(writer);
    run.attach(recorder.clone()).unwrap();
    run.run_to_end().unwrap();
    run.finish().unwrap();
    let bytes = recorder.take().unwrap().into_inner();
    let recording = Recording::<Bourg>::parse(&bytes).unwrap();
    let end = run.state().unwrap();
    assert_eq!(recording.fingerprint, Some(Fingerprint::of_bourg(&end)));
    assert_ne!(
        recording.fingerprint.unwrap().state,
        fdm_core::fingerprint::bourg_state(&scenario.start.state),
        "the fingerprint is the final state's, not the start's"
    );
}

#[test]
fn a_writer_driven_by_hand_without_a_state_writes_no_fingerprint() {
    let scenario = palmer_scenario(3);
    let mut writer = RecordWriter::new(Vec::new(), 30, &scenario.origin, &scenario.start).unwrap();
    writer.frame(&[PalmerAction::AlphaUp]).unwrap();
    writer.finish().unwrap();
    let bytes = writer.into_inner();
    let recording = Recording::<Palmer>::parse(&bytes).unwrap();
    assert_eq!((recording.frames, recording.fingerprint), (1, None));
}

#[test]
fn a_paced_run_takes_its_wall_clock_time() {
    let scenario = Scenario::<Palmer>::new(Start::thesis(), 100, 20).unwrap();
    let mut run = Run::new(scenario).unwrap().with_realtime(true);
    let started = Instant::now();
    let end = run.run_to_end().unwrap();
    assert!(
        started.elapsed() >= Duration::from_millis(190),
        "{:?}",
        started.elapsed()
    );
    assert_eq!(end.frames, 20);
    assert!(end.overruns.is_some());
}

#[test]
fn bad_scenarios_are_refused() {
    assert!(Scenario::<Palmer>::new(Start::thesis(), 0, 1).is_err());
    assert!(Scenario::<Palmer>::new(Start::thesis(), 10_001, 1).is_err());
    assert!(Scenario::<Palmer>::new(Start::thesis(), 30, fdm_run::MAX_FRAMES + 1).is_err());
    let mut scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 1).unwrap();
    scenario.fps = 0;
    assert!(Run::new(scenario).is_err());
}

/// An output whose failure has a cause: the CSV writer over a full disk.
struct FullDisk;

impl std::io::Write for FullDisk {
    fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
        Err(std::io::Error::other("disk full"))
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A failing output's error keeps its cause: `RunError::Output` shows the
/// output's own message and its `source()` is the output's cause, so the
/// chain reads `writing CSV file out.csv: disk full` (it used to stop at
/// `writing CSV file out.csv`).
#[test]
fn an_output_failure_keeps_its_cause() {
    use fdm_run::csv::{CsvOutput, CsvWriter};
    struct Row(f64);
    impl fdm_run::csv::CsvRecord for Row {
        fn csv_columns(&self) -> Vec<&'static str> {
            vec![]
        }
        fn time_s(&self) -> f64 {
            self.0
        }
        fn csv_values(&self, _: &mut Vec<f64>) {}
    }
    let mut run = Run::new(palmer_scenario(10)).unwrap();
    let csv = CsvOutput::new(
        CsvWriter::new(FullDisk, "out.csv"),
        |f: &Frame<'_, Palmer>| Row(f.view.time_s),
    );
    let err = run.attach(csv).unwrap_err();
    assert!(matches!(err, fdm_run::RunError::Output(_)), "{err:?}");
    assert_eq!(err.to_string(), "writing CSV file out.csv");
    let mut chain = vec![err.to_string()];
    let mut source = std::error::Error::source(&err);
    while let Some(s) = source {
        chain.push(s.to_string());
        source = s.source();
    }
    assert_eq!(chain.join(": "), "writing CSV file out.csv: disk full");
}
