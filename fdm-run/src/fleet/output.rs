//! A fleet's outputs as plugins: [`FleetOutput`], attached to a
//! [`FleetRun`](super::FleetRun) with [`FleetRun::attach`](super::FleetRun::attach).
//!
//! The run calls [`FleetOutput::frame`] when the output is attached (the
//! frame flown so far, 0 at the start) and after every flown frame, with a
//! [`FleetFrame`]: the run's clock, the fleet's origin and every aircraft's
//! [`FlightView`] and [`FlightStatus`] in the fleet's order (for either
//! kernel); [`FleetOutput::finish`] once at the end. The Tacview ACMI writer
//! ([`AcmiWriter`]) is one. A new protocol for fleets is one type
//! implementing it; the fleet's run loop does not change.

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, FlightView, Model};

use crate::acmi::AcmiWriter;
use crate::model::RunModel;
use crate::output::OutputError;

/// Every aircraft's view and status, in the fleet's order (`None`: not
/// known this frame).
pub type Views<'a> = Box<dyn Iterator<Item = Option<(FlightView, FlightStatus)>> + 'a>;

/// Where a [`FleetFrame`] reads the aircraft from (either kernel).
pub(super) trait ViewSource {
    /// The aircraft now.
    fn views(&self) -> Views<'_>;
}

/// One frame of a fleet as its outputs see it.
pub struct FleetFrame<'a> {
    /// Frames flown since the run began (the run's clock in frames).
    pub flown: u64,
    /// Frames per second.
    pub fps: u32,
    /// Where the fleet's earth frame is on WGS-84 (for
    /// [`Placement::of`](crate::Placement::of)).
    pub origin: &'a GeodeticOrigin,
    pub(super) source: &'a dyn ViewSource,
}

impl FleetFrame<'_> {
    /// Every aircraft's view and status now, aircraft 0 first.
    #[must_use]
    pub fn views(&self) -> Views<'_> {
        self.source.views()
    }

    /// The run's clock, seconds: [`Self::flown`] / [`Self::fps`].
    #[must_use]
    pub fn clock_s(&self) -> f64 {
        // Exact for any frame count below 2^53.
        #[allow(clippy::cast_precision_loss)]
        let flown = self.flown as f64;
        flown / f64::from(self.fps)
    }
}

impl std::fmt::Debug for FleetFrame<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FleetFrame")
            .field("flown", &self.flown)
            .field("fps", &self.fps)
            .field("origin", &self.origin)
            .finish_non_exhaustive()
    }
}

/// Something a fleet run writes or sends as it flies.
pub trait FleetOutput<M: Model> {
    /// Takes one frame (when attached, then after every flown frame).
    ///
    /// # Errors
    /// Whatever makes the output unusable; the run stops with it
    /// ([`FleetError::Output`](super::FleetError::Output)).
    fn frame(&mut self, frame: &FleetFrame<'_>) -> Result<(), OutputError>;

    /// Completes the output when the run ends (flushes, writes trailers).
    /// The default does nothing.
    ///
    /// # Errors
    /// As [`Self::frame`].
    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(())
    }
}

/// Every aircraft's track ([`AcmiWriter::fleet_frame`]): declared on its
/// first frame, removed when it crashes or diverges; the errors are
/// [`AcmiError`](crate::acmi::AcmiError)s.
impl<M: RunModel> FleetOutput<M> for AcmiWriter {
    fn frame(&mut self, frame: &FleetFrame<'_>) -> Result<(), OutputError> {
        Ok(self.fleet_frame::<M>(frame.flown, frame.origin, frame.views())?)
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(AcmiWriter::finish(self)?)
    }
}
