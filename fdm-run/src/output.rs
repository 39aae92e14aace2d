//! Outputs as plugins: one interface for everything a run writes or sends
//! as it flies.
//!
//! An [`Output`] is attached to a [`Run`](crate::Run) with
//! [`Run::attach`](crate::Run::attach). The run calls [`Output::frame`] with
//! the start (frame 0, at attach time), after every flown frame and after every
//! reset, and [`Output::finish`] once at the end. Each call carries a
//! [`Frame`]: the frame's actions, the model's controls, state and
//! [`FlightView`], the flight status, and the aircraft's [`Placement`] on
//! WGS-84, computed once per frame by the ECS (its Place system) and shared
//! by every output. Network outputs count their sends in a [`LinkStats`].
//!
//! A new protocol is one type implementing [`Output`]; the run loop does not
//! change.

use fdm_core::geodesy::{Attitude, Geodetic, GeodeticOrigin};
use fdm_core::model::{FlightStatus, FlightView, Model};

/// What an output's failure carries (any error; its message should be one
/// line).
pub type OutputError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// `error`'s message followed by those of its sources, `: `-separated, as
/// `sim-cli` prints an error ("writing CSV file out.csv: No space left on
/// device (os error 28)"): the reason is often only in a source. A source
/// whose message already ends the text is not repeated (an error that prints
/// its source and also returns it, as [`crate::acmi::AcmiError`] does, would
/// otherwise show the reason twice).
///
/// ```
/// use fdm_run::output::error_text;
///
/// let full = std::io::Error::other("No space left on device");
/// let acmi = fdm_run::acmi::AcmiError::Io(full);
/// assert_eq!(error_text(&acmi), "writing the ACMI file: No space left on device");
/// ```
#[must_use]
pub fn error_text(error: &(dyn std::error::Error + 'static)) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let message = cause.to_string();
        if !text.ends_with(&message) {
            text.push_str(": ");
            text.push_str(&message);
        }
        source = cause.source();
    }
    text
}

/// Why the run calls an output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// Frame 0, when the output is attached.
    Start,
    /// A frame was flown (its actions applied, then one model step).
    Step,
    /// The aircraft went back to its start (frame 0 again).
    Reset,
}

/// An aircraft's place on WGS-84: position and attitude relative to the
/// local north-east-down frame at the aircraft.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// WGS-84 position.
    pub geodetic: Geodetic,
    /// Roll (right wing down +), pitch (nose up +) and heading (clockwise
    /// from true north, `[0, 360)`), degrees.
    pub attitude: Attitude,
}

impl Placement {
    /// `view` placed at `origin`, for aircraft flown outside the ECS (the
    /// fleet kernels): what the ECS's Place system computes every frame
    /// (`fdm_ecs::systems::placement`), the numbers the FlightGear datagram,
    /// the DIS PDUs and the ACMI tracks carry.
    #[must_use]
    pub fn of(view: &FlightView, origin: &GeodeticOrigin) -> Self {
        let (geodetic, attitude) = fdm_ecs::systems::placement(view, origin);
        Self { geodetic, attitude }
    }

    /// [`Self::of`] when it can be shown: `None` unless the view and every
    /// number of the placement are finite (the ECS's Place system's rule,
    /// `fdm_ecs::systems::finite_placement`).
    #[must_use]
    pub fn of_finite(view: &FlightView, origin: &GeodeticOrigin) -> Option<Self> {
        fdm_ecs::systems::finite_placement(view, origin)
            .map(|(geodetic, attitude)| Self { geodetic, attitude })
    }
}

/// The counters of a network output (the FlightGear link, a DIS sender):
/// the one link-counter type of the run library, and `sim-cli`'s JSON
/// report's `fg` object (`{"sent": n, "failed": n}`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct LinkStats {
    /// Datagrams the operating system accepted (UDP: not a delivery).
    pub sent: u64,
    /// Datagrams that were not sent (any error, a full buffer, a short
    /// write); never fatal.
    pub failed: u64,
}

/// One frame as the outputs see it.
#[derive(Debug)]
pub struct Frame<'a, M: Model> {
    /// Why this call.
    pub event: Event,
    /// The frame number since the start or the last reset (0 at both).
    pub number: u64,
    /// Frames flown since the run began, across resets: the run's clock in
    /// frames ([`Self::clock_s`]).
    pub flown: u64,
    /// Frames per second.
    pub fps: u32,
    /// The actions the frame applied, in order (empty for start and reset).
    pub actions: &'a [M::Action],
    /// The model's controls after the frame.
    pub controls: &'a M::Controls,
    /// The model's state after the frame (for a diverged step: the last
    /// finite state).
    pub state: &'a M::State,
    /// The model's common view of the state.
    pub view: &'a FlightView,
    /// The aircraft on WGS-84.
    pub placement: &'a Placement,
    /// The flight status after the frame.
    pub status: FlightStatus,
}

impl<M: Model> Frame<'_, M> {
    /// The run's clock, seconds: [`Self::flown`] / [`Self::fps`]. It only
    /// goes forward (a reset does not turn it back), unlike the model's
    /// own `time_s`.
    #[must_use]
    pub fn clock_s(&self) -> f64 {
        // Exact for any frame count below 2^53.
        #[allow(clippy::cast_precision_loss)]
        let flown = self.flown as f64;
        flown / f64::from(self.fps)
    }
}

/// Something a run writes or sends as it flies: a file, a network link, a
/// counter.
pub trait Output<M: Model> {
    /// Takes one frame (see [`Event`] for when).
    ///
    /// # Errors
    /// Whatever makes the output unusable; the run stops with it.
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError>;

    /// Completes the output when the run ends (flushes, writes trailers).
    /// The default does nothing.
    ///
    /// # Errors
    /// As [`Self::frame`].
    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{error_text, Event, Frame, Output, OutputError};
    use crate::{Run, Scenario, SharedOutput, Start};
    use fdm_core::model::Model as _;
    use fdm_core::palmer::Palmer;

    /// Each frame's clock, as an output sees it.
    #[derive(Default)]
    struct Clocks(Vec<(Event, u64, f64)>);

    impl Output<Palmer> for Clocks {
        fn frame(&mut self, frame: &Frame<'_, Palmer>) -> Result<(), OutputError> {
            self.0.push((frame.event, frame.number, frame.clock_s()));
            Ok(())
        }
    }

    /// A frame's clock is the frames flown over the frame rate, and it goes
    /// on across a reset (the model's `time_s` starts again there).
    #[test]
    fn the_clock_is_the_frames_flown_over_the_rate() {
        let mut run = Run::new(Scenario::<Palmer>::new(Start::thesis(), 20, 0).unwrap()).unwrap();
        let clocks = SharedOutput::new(Clocks::default());
        run.attach(clocks.clone()).unwrap();
        for _ in 0..3 {
            run.step_frame(&[]).unwrap();
        }
        run.reset().unwrap();
        run.step_frame(&[]).unwrap();
        let seen = clocks.take().unwrap().0;
        assert_eq!(
            seen,
            [
                (Event::Start, 0, 0.0),
                (Event::Step, 1, 0.05),
                (Event::Step, 2, 0.1),
                (Event::Step, 3, 0.15),
                (Event::Reset, 0, 0.15),
                (Event::Step, 1, 0.2),
            ]
        );
        assert_eq!(run.view().time_s, Palmer::time_step(20.0));
    }

    /// An error with a message and, maybe, a source.
    #[derive(Debug)]
    struct Caused(&'static str, Option<Box<Caused>>);

    impl std::fmt::Display for Caused {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(self.0)
        }
    }

    impl std::error::Error for Caused {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            self.1.as_deref().map(|e| e as _)
        }
    }

    #[test]
    fn an_errors_text_is_its_chain_without_repeats() {
        let root = Caused("disk full", None);
        assert_eq!(error_text(&root), "disk full");
        let middle = Caused("writing out.csv", Some(Box::new(root)));
        assert_eq!(error_text(&middle), "writing out.csv: disk full");
        // A source whose message already ends the text is not repeated.
        let printed = Caused(
            "writing: disk full",
            Some(Box::new(Caused("disk full", None))),
        );
        assert_eq!(error_text(&printed), "writing: disk full");
        let top = Caused("run stopped", Some(Box::new(middle)));
        assert_eq!(error_text(&top), "run stopped: writing out.csv: disk full");
    }
}
