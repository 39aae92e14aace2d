//! The world-wide data every system reads: the thesis's resource `DeltaTime`
//! (as the frame rate each model derives its own time step from), the
//! geodetic origin, the frame counter and the execution mode. (The thesis's
//! `MaxThrust` and `DeltaThrust` are parameters of Bourg's aircraft now.)

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;

use crate::EcsError;

/// How the per-aircraft systems (EquationsOfMotion, Place) visit the
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
/// The frame rate is stored once and every model derives its time step from
/// it with [`Model::time_step`] (Palmer `1.0 / fps` in `f64`, Bourg
/// `1.0f32 / fps as f32`), so they can never disagree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resources {
    fps: f64,
    /// Where the models' earth-frame origin (x north, y west, z up) sits on
    /// WGS-84; Place converts positions with it.
    pub origin: GeodeticOrigin,
    /// Frames run so far. [`Schedule::run`](crate::Schedule::run) increments it
    /// before the systems run, so during a frame it is that frame's 1-based
    /// number (the numbering of script rules), and 0 before the first frame.
    pub frame: u64,
    /// Sequential or parallel per-aircraft systems.
    pub execution: Execution,
}

impl Resources {
    /// Resources for `fps` frames per second, with the default origin (Wright-Patterson AFB runway), frame 0
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

    /// Model `M`'s time step (`DeltaTime`) at this frame rate:
    /// [`Model::time_step`].
    #[must_use]
    pub fn time_step<M: Model>(&self) -> M::TimeStep {
        M::time_step(self.fps)
    }
}
