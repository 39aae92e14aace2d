//! The run loops, written once for every model against the [`Flight`] trait.
//!
//! `crate::flight::ModelFlight` implements [`Flight`] for any
//! `CliModel` (one aircraft entity in an `fdm_ecs::Simulation`);
//! `crate::flight::run_model` builds it from the validated configuration
//! and hands it to [`fly`]. The flight flies its script (the run library's
//! `Run::step_frame`: the script's rules for the frame, then the keys).
//! Everything here (JSON report, progress bar, terminal, keys, pacing, HUD)
//! is model-agnostic and tested with a fake model.

use std::net::SocketAddrV4;

use anyhow::Context as _;

use crate::config::Mode;
use crate::error::CliError;
use crate::keys::KeyAction;
use crate::models::Details;
use crate::progress::StderrProgress;
use crate::report::Report;
use crate::snapshot::Snapshot;

pub mod headless;
pub mod interactive;

pub use headless::run_headless;
pub use interactive::{run_interactive, Flow, InteractiveSummary, Session};

/// One aircraft the loops can fly: the seam between the CLI and the ECS.
pub trait Flight {
    /// The model's control vocabulary (keys and script actions).
    type Action: KeyAction;
    /// The model's own report fields.
    type Details: Details;

    /// The model's title for the HUD.
    const TITLE: &'static str;

    /// Advances one frame of fixed dt: apply the flight's script's rules for
    /// the frame (in file order; frames count from the start or the last
    /// reset), then `keys` in order as key presses (for Bourg after returning
    /// the rudder, ailerons and elevators to neutral), step the model, and hand the frame to the run's outputs (the FlightGear
    /// link, DIS, ...). A failed send must not be an error: the output counts
    /// it ([`Self::links`]).
    ///
    /// # Errors
    /// Anything that makes continuing pointless; the run stops with exit status 1.
    fn step(&mut self, keys: &[Self::Action]) -> anyhow::Result<()>;

    /// Puts the model back to its initial state and controls, the script back
    /// to its first frame (interactive R key).
    ///
    /// # Errors
    /// As [`Self::step`].
    fn reset(&mut self) -> anyhow::Result<()>;

    /// The current state, for the report, the CSV rows and the HUD.
    fn snapshot(&self) -> Snapshot<Self::Details>;

    /// The network outputs attached to the flight (handles to them: their
    /// counters and first failures). The default: none.
    fn links(&self) -> Links {
        Links::default()
    }

    /// Called once when the run ends normally, before the report: completes
    /// anything written alongside the flight (the `--record` file). The default
    /// does nothing.
    ///
    /// # Errors
    /// Writing fails; the run ends with exit status 1.
    fn finish(&mut self) -> anyhow::Result<()> {
        Ok(())
    }
}

/// The network outputs of a flight, as the loops read them: the run
/// library's handles to the outputs attached to its run (`--fg`: the
/// FlightGear link, `--dis`: DIS), their counters and first failures.
pub use fdm_run::links::Links;

/// The stderr line for a link failure (see [`Links::take_failure`]).
pub(crate) fn link_warning(message: &str) -> String {
    format!("sim-cli: warning: {}", crate::error::one_line(message))
}

/// Finishes `flight`'s outputs (the CSV rows written so far flushed, the
/// recording ended) also when the run stopped early (e.g. the model
/// diverged on the next frame), and completes its `report` with the links'
/// counters (the FlightGear link's when `fg`, a target was given).
///
/// # Errors
/// The run's error first, else finishing's.
pub(crate) fn finish_report<F: Flight>(
    flight: &mut F,
    report: Result<Report<F::Details>, CliError>,
    fg: bool,
) -> Result<Report<F::Details>, CliError> {
    let finished = flight.finish();
    let mut report = report?;
    finished?;
    let links = flight.links();
    if fg {
        report.fg = links.fg_stats();
    }
    report.dis = links.dis_report();
    Ok(report)
}

/// Flies `flight` at `fps` in `mode` (`fg`: the FlightGear link's target,
/// whose counters the report shows): headless (report on stdout: JSON with `--json`,
/// else a short summary, on stderr when an output writes the standard
/// output) or interactive (a one-line summary on stderr at the end).
///
/// # Errors
/// Whatever the loop or the output reports.
pub fn fly<F: Flight>(
    mut flight: F,
    mode: Mode,
    fps: u32,
    fg: Option<SocketAddrV4>,
) -> Result<(), CliError> {
    match mode {
        Mode::Headless {
            frames,
            json,
            realtime,
            summary_on_stderr,
        } => {
            let mut progress = StderrProgress::new(frames);
            let report = run_headless(&mut flight, fps, frames, realtime, &mut progress);
            // The outputs are finished (the CSV rows written so far flushed,
            // the recording ended) even when the run stopped early (e.g. the
            // model diverged on the next frame).
            let report = finish_report(&mut flight, report, fg.is_some())?;
            let text = if json {
                report.to_json().context("encoding the JSON report")?
            } else {
                report.human_summary()
            };
            crate::print_report(&text, summary_on_stderr)
        }
        Mode::Interactive => {
            let summary = run_interactive(&mut flight, fps, fg);
            let finished = flight.finish();
            let summary = summary?;
            finished?;
            if let Some(message) = &summary.link_failure {
                eprintln!("{}", link_warning(message));
            }
            let link = summary.link.map_or_else(String::new, |l| {
                format!(", {} packets sent, {} failed", l.sent, l.failed)
            });
            let dis = flight.links().dis_report().map_or_else(String::new, |d| {
                format!(", {} DIS PDUs sent, {} failed", d.pdus, d.failed)
            });
            eprintln!(
                "sim-cli: flew {} frames, {} overruns{link}{dis}",
                summary.frames, summary.overruns
            );
            Ok(())
        }
    }
}

/// Lets the loops fly a borrowed flight, so the caller keeps it afterwards.
impl<F: Flight> Flight for &mut F {
    type Action = F::Action;
    type Details = F::Details;

    const TITLE: &'static str = F::TITLE;

    fn step(&mut self, keys: &[Self::Action]) -> anyhow::Result<()> {
        (**self).step(keys)
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        (**self).reset()
    }

    fn snapshot(&self) -> Snapshot<Self::Details> {
        (**self).snapshot()
    }

    fn links(&self) -> Links {
        (**self).links()
    }

    fn finish(&mut self) -> anyhow::Result<()> {
        (**self).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keys::{AppCommand, Input};
    use fdm_core::palmer::PalmerAction;
    use fdm_core::script::Script;
    use fdm_run::model::palmer::PalmerDetails;

    /// A stand-in model: records the actions of every step (its script's
    /// rules for the frame since the last reset, then the keys, as
    /// [`Flight::step`] has them; `flight::tests::the_script_comes_first_and_starts_over_on_a_reset`
    /// checks the real flight); position x counts steps.
    #[derive(Default)]
    struct Fake {
        script: Script<PalmerAction>,
        steps: Vec<Vec<PalmerAction>>,
        resets: u32,
        fail_at: Option<usize>,
    }

    impl Flight for Fake {
        type Action = PalmerAction;
        type Details = PalmerDetails;

        const TITLE: &'static str = "Fake";

        fn step(&mut self, keys: &[PalmerAction]) -> anyhow::Result<()> {
            let frame = self.steps.len() + 1;
            if self.fail_at == Some(frame) {
                anyhow::bail!("model diverged");
            }
            let mut actions: Vec<_> = self.script.actions_at(frame as u64).collect();
            actions.extend_from_slice(keys);
            self.steps.push(actions);
            Ok(())
        }

        fn reset(&mut self) -> anyhow::Result<()> {
            self.steps.clear();
            self.resets += 1;
            Ok(())
        }

        fn snapshot(&self) -> Snapshot<PalmerDetails> {
            let mut s = PalmerDetails::sample_snapshot();
            s.common.time_s = self.steps.len() as f64 * 0.1;
            s.common.position = [self.steps.len() as f64, 0.0, 0.0];
            s.details.controls.throttle = self.steps.iter().flatten().count() as f64;
            s
        }
    }

    fn script(text: &str) -> Script<PalmerAction> {
        Script::parse(text).unwrap()
    }

    #[test]
    fn headless_applies_script_rules_on_their_frames() {
        use PalmerAction::*;
        let mut flight = Fake {
            script: script("2-3 throttle-up\n3-3 flaps-down\n5-9 alpha-up\n"),
            ..Fake::default()
        };
        let mut progress = StderrProgress::with_enabled(4, false);
        let report = run_headless(&mut flight, 10, 4, false, &mut progress).unwrap();
        assert_eq!(
            flight.steps,
            [
                vec![],
                vec![ThrottleUp],
                vec![ThrottleUp, FlapsDown],
                vec![]
            ]
        );
        assert_eq!(report.frames, 4);
        assert_eq!(report.fps, 10);
        assert_eq!(report.common.position[0], 4.0);
    }

    #[test]
    fn headless_zero_frames_reports_the_initial_state() {
        let mut flight = Fake::default();
        let mut progress = StderrProgress::with_enabled(0, false);
        let report = run_headless(&mut flight, 30, 0, false, &mut progress).unwrap();
        assert_eq!((report.frames, report.common.time_s), (0, 0.0));
        assert!(flight.steps.is_empty());
    }

    #[test]
    fn step_errors_name_the_frame_and_exit_1() {
        let mut flight = Fake {
            fail_at: Some(3),
            ..Fake::default()
        };
        let mut progress = StderrProgress::with_enabled(5, false);
        let err = run_headless(&mut flight, 10, 5, false, &mut progress).unwrap_err();
        assert_eq!(err.exit_code(), 1);
        assert_eq!(err.one_line(), "frame 3: model diverged");
    }

    #[test]
    fn session_keys_pause_reset_quit() {
        use PalmerAction::*;
        let mut flight = Fake {
            script: script("1-1 flaps-down\n"),
            ..Fake::default()
        };
        let mut s = Session::new();
        fn handle(s: &mut Session<PalmerAction>, f: &mut Fake, input: Input<PalmerAction>) -> Flow {
            s.handle(input, f).unwrap()
        }

        // Frame 1: script first, then keys in the order pressed.
        handle(&mut s, &mut flight, Input::Action(ThrottleUp));
        handle(&mut s, &mut flight, Input::Action(ThrottleUp));
        s.advance(&mut flight).unwrap();
        assert_eq!(flight.steps, [vec![FlapsDown, ThrottleUp, ThrottleUp]]);

        // Paused: no steps, keys ignored.
        handle(&mut s, &mut flight, Input::App(AppCommand::Pause));
        handle(&mut s, &mut flight, Input::Action(AlphaUp));
        s.advance(&mut flight).unwrap();
        assert_eq!((s.frame(), flight.steps.len(), s.paused()), (1, 1, true));
        handle(&mut s, &mut flight, Input::App(AppCommand::Pause));
        s.advance(&mut flight).unwrap();
        assert_eq!(flight.steps[1], []);

        // Reset: model reset, frame 0, the script starts over.
        handle(&mut s, &mut flight, Input::App(AppCommand::Reset));
        assert_eq!((s.frame(), flight.resets), (0, 1));
        s.advance(&mut flight).unwrap();
        assert_eq!(flight.steps, [vec![FlapsDown]]);
        assert_eq!(s.total_frames(), 3);

        assert_eq!(
            handle(&mut s, &mut flight, Input::App(AppCommand::Quit)),
            Flow::Quit
        );
    }

    /// The warning line is one line whatever the failure's message (the
    /// failures themselves: `flight::tests::a_failing_link_is_reported_once_and_counted`).
    #[test]
    fn link_warnings_are_one_line() {
        assert!(Fake::default().links().take_failure().is_none());
        assert_eq!(
            link_warning("sending to 127.0.0.1:5500 failed\non frame 1"),
            "sim-cli: warning: sending to 127.0.0.1:5500 failed on frame 1"
        );
    }
}
