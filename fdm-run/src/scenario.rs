//! A scenario: what a run starts from and how long it lasts.

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::script::Script;

/// Highest frame rate a run accepts, frames per second. Far above any useful
/// real-time rate; it only keeps dt = 1/N away from values where `f32`
/// (Bourg) loses all meaning. `sim-cli --fps` reads its limit from here.
pub const MAX_FPS: u32 = 10_000;

/// Longest run in frames. About 1e9 frames is hours of CPU even for Palmer;
/// more is surely a typo. `sim-cli --frames` reads its limit from here.
pub const MAX_FRAMES: u64 = 1_000_000_000;

/// How an aircraft of model `M` starts (and restarts on a reset): its
/// parameters, controls and state at frame 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Start<M: Model> {
    /// The aircraft's parameters.
    pub aircraft: M::Aircraft,
    /// Controls at frame 0.
    pub controls: M::Controls,
    /// State at frame 0.
    pub state: M::State,
}

impl<M: Model> Start<M> {
    /// The thesis's start: the default aircraft, initial controls and state.
    #[must_use]
    pub fn thesis() -> Self {
        Self {
            aircraft: M::default_aircraft(),
            controls: M::initial_controls(),
            state: M::initial_state(),
        }
    }
}

/// Why a scenario was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScenarioError {
    /// A frame rate outside `1..=MAX_FPS`.
    #[error("frame rate {0} is not a whole number from 1 to {MAX_FPS}")]
    Fps(u32),
    /// More frames than [`MAX_FRAMES`].
    #[error("{0} frames, more than the {MAX_FRAMES} a run can have")]
    Frames(u64),
}

/// One flight of model `M`: its start, where on Earth, how fast frames go,
/// how many there are, and the scripted controls.
///
/// ```
/// use fdm_core::palmer::Palmer;
/// use fdm_run::{Run, Scenario, Start};
///
/// let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 90)?;
/// let mut run = Run::new(scenario)?;
/// let end = run.run_to_end()?;
/// assert_eq!(end.frames, 90);
/// assert!(run.view().time_s > 2.9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Scenario<M: Model> {
    /// The aircraft's start.
    pub start: Start<M>,
    /// The earth-frame origin (the model's `x, y, z = 0` on WGS-84).
    pub origin: GeodeticOrigin,
    /// Frames per second: every frame advances the model by dt = 1/fps
    /// ([`Model::time_step`]).
    pub fps: u32,
    /// Frames [`crate::Run::run_to_end`] flies.
    pub frames: u64,
    /// Scripted controls: the rules of frame N apply, in file order, before
    /// any other action of that frame.
    pub script: Script<M::Action>,
}

impl<M: Model> Scenario<M> {
    /// A scenario from `start` at `fps` for `frames` frames, at the default
    /// origin ([`GeodeticOrigin::default`]) without a script.
    ///
    /// # Errors
    /// A frame rate outside `1..=`[`MAX_FPS`] or more than [`MAX_FRAMES`] frames.
    pub fn new(start: Start<M>, fps: u32, frames: u64) -> Result<Self, ScenarioError> {
        if !(1..=MAX_FPS).contains(&fps) {
            return Err(ScenarioError::Fps(fps));
        }
        if frames > MAX_FRAMES {
            return Err(ScenarioError::Frames(frames));
        }
        Ok(Self {
            start,
            origin: GeodeticOrigin::default(),
            fps,
            frames,
            script: Script::default(),
        })
    }

    /// The same scenario at `origin`.
    #[must_use]
    pub fn with_origin(mut self, origin: GeodeticOrigin) -> Self {
        self.origin = origin;
        self
    }

    /// The same scenario with `script`.
    #[must_use]
    pub fn with_script(mut self, script: Script<M::Action>) -> Self {
        self.script = script;
        self
    }
}
