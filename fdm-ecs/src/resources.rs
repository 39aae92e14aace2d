//! The world-wide data every system reads: the thesis's resources `DeltaTime`,
//! `MaxThrust` and `DeltaThrust`, plus the geodetic origin, the frame counter
//! and the execution mode.

use fdm_core::bourg::{DELTA_THRUST_LB, MAX_THRUST_LB};

use crate::geodesy::GeodeticOrigin;
use crate::EcsError;

/// How the per-aircraft systems (EquationsOfMotion, MakePacket) visit the
/// entities. Both give bit-identical results; see
/// [`equations_of_motion_parallel`](crate::systems::equations_of_motion_parallel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Execution {
    /// One thread, one query after the other. Best for a handful of aircraft.
    #[default]
    Sequential,
    /// Rayon's global thread pool over batches of entities. Worth it from a
    /// few hundred aircraft on.
    Parallel,
}

/// The resources passed to every system (`&Resources`).
///
/// The frame rate is stored once and both models' time steps are derived from
/// it as `shared/spec/cli.md` states: Palmer `1.0 / fps` in `f64`, Bourg
/// `1.0f32 / fps as f32`, so they can never disagree. For a whole number of
/// frames per second `N` (below 2^24) `fps as f32` is exactly `N as f32`, the
/// original C++'s `1.0f / N`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resources {
    fps: f64,
    /// Bourg's `MaxThrust`: the thrust a thrust-up action cannot exceed, lb
    /// (default [`MAX_THRUST_LB`], 3000). FlightControl honours it.
    pub max_thrust_lb: f32,
    /// Bourg's `DeltaThrust`: the change per thrust-up/down action, lb
    /// (default [`DELTA_THRUST_LB`], 100). FlightControl honours it.
    pub delta_thrust_lb: f32,
    /// Where the models' earth-frame origin (x north, y west, z up) sits on
    /// WGS-84; MakePacket converts positions with it.
    pub origin: GeodeticOrigin,
    /// Frames run so far. [`Schedule::run`](crate::Schedule::run) increments it
    /// before the systems run, so during a frame it is that frame's 1-based
    /// number (the numbering of script rules), and 0 before the first frame.
    pub frame: u64,
    /// Sequential or parallel per-aircraft systems.
    pub execution: Execution,
}

impl Resources {
    /// Resources for `fps` frames per second, with the original programs'
    /// thrust limits, the default origin (Wright-Patterson AFB runway), frame 0
    /// and sequential execution.
    ///
    /// # Errors
    /// [`EcsError::InvalidFps`] unless `fps` is finite and above 0.
    pub fn new(fps: f64) -> Result<Self, EcsError> {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(EcsError::InvalidFps { fps });
        }
        Ok(Self {
            fps,
            max_thrust_lb: MAX_THRUST_LB,
            delta_thrust_lb: DELTA_THRUST_LB,
            origin: GeodeticOrigin::default(),
            frame: 0,
            execution: Execution::Sequential,
        })
    }

    /// These resources with another geodetic origin.
    #[must_use]
    pub fn with_origin(self, origin: GeodeticOrigin) -> Self {
        Self { origin, ..self }
    }

    /// These resources with another execution mode.
    #[must_use]
    pub fn with_execution(self, execution: Execution) -> Self {
        Self { execution, ..self }
    }

    /// Frames per second.
    #[must_use]
    pub const fn fps(&self) -> f64 {
        self.fps
    }

    /// Palmer's time step (`DeltaTime`), seconds: `1.0 / fps` in `f64`.
    #[must_use]
    pub fn dt_palmer_s(&self) -> f64 {
        1.0 / self.fps
    }

    /// Bourg's time step (`DeltaTime`), seconds: `1.0f32 / fps as f32`, as the
    /// original C++ computes it.
    #[must_use]
    #[allow(clippy::cast_possible_truncation)] // the original's own f32 time step
    pub fn dt_bourg_s(&self) -> f32 {
        1.0f32 / self.fps as f32
    }
}
