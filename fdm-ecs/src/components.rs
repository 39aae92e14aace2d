//! The components of an aircraft entity, generic over its [`Model`].
//!
//! The thesis's single `DataFDM` component (parameters, mass properties, state
//! and controls in one struct, copied into every entity) is split, as its
//! future-work section suggests, into pieces each system takes only what it
//! needs of. For an aircraft of model `M`:
//!
//! | component | type | written by |
//! |---|---|---|
//! | shared parameters (marks the entity as an `M` aircraft) | [`Params<M>`] | spawn only |
//! | controls | `M::Controls` | FlightControl |
//! | state | `M::State` | EquationsOfMotion |
//! | this frame's input | [`FrameInput<M::Action>`](FrameInput) | the caller (keyboard), emptied by FlightControl |
//! | scripted input (optional) | [`ScriptInput<M::Action>`](ScriptInput), [`ScriptReplay`] | spawn / the caller; FlightControl moves the cursor |
//! | flight status | [`FlightStatus`] | FlightStatus |
//! | geodetic position (WGS-84) | [`Geodetic`] | Place |
//! | attitude relative to the local north-east-down frame | [`Attitude`] | Place |
//!
//! State, controls, position and attitude are the plain types of `fdm-core`,
//! used as components directly. The position and attitude are the aircraft's
//! placement, computed once per frame and read by every output (the
//! FlightGear link, DIS, ACMI: `fdm_run::Placement`); no wire format lives in
//! the ECS. Every system's query
//! includes [`Params<M>`], so two models never see each other's aircraft.
//!
//! # Shared parameters: `Arc`, not a copy and not a table index
//!
//! [`Params`] holds an [`Arc`] of the model's parameters, so every aircraft of
//! one type points at the same data: 8 bytes per entity instead of a copy (a
//! Bourg aircraft with its mass properties is about 690 bytes, a Palmer one
//! 128), and the one shared copy stays in the cache while a fleet is stepped.
//! An index into a per-type table in the resources would be as small, but
//! every system would then need the table, spawning would need to register
//! it, and the index could dangle; the `Arc` keeps each entity
//! self-contained and allows any number of aircraft types in one world. The
//! reference count is touched only at spawn and despawn, never per frame.

use std::ops::Deref;
use std::sync::Arc;

use fdm_core::model::Model;
use fdm_core::script::{Script, ScriptCursor};

pub use fdm_core::geodesy::{Attitude, Geodetic};
pub use fdm_core::model::FlightStatus;

/// The parameters of an entity's aircraft type, shared by every aircraft of
/// that type. Its presence makes an entity an aircraft of model `M`.
pub struct Params<M: Model>(pub Arc<M::Aircraft>);

impl<M: Model> Params<M> {
    /// Shares `aircraft`.
    #[must_use]
    pub fn new(aircraft: Arc<M::Aircraft>) -> Self {
        Self(aircraft)
    }
}

impl<M: Model> Clone for Params<M> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<M: Model> std::fmt::Debug for Params<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Params")
            .field(&M::NAME)
            .field(&self.0)
            .finish()
    }
}

impl<M: Model> PartialEq for Params<M> {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl<M: Model> Deref for Params<M> {
    type Target = M::Aircraft;

    fn deref(&self) -> &M::Aircraft {
        &self.0
    }
}

/// The control actions of one frame (the thesis's `KeyboardState`): what the
/// keyboard or another caller pushed since the last frame, in order.
///
/// FlightControl applies the frame's script actions (if the entity has a
/// [`ScriptInput`]) and then these, as if each key had been pressed once, and
/// empties the list. Pushing the same action twice presses it twice.
///
/// An empty `FrameInput` does not allocate; once used, it keeps its capacity.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameInput<A> {
    actions: Vec<A>,
}

impl<A> FrameInput<A> {
    /// An empty input.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            actions: Vec::new(),
        }
    }

    /// Queues `action` for the next frame, after those already queued.
    pub fn push(&mut self, action: A) {
        self.actions.push(action);
    }

    /// The queued actions, in the order they will be applied.
    #[must_use]
    pub fn actions(&self) -> &[A] {
        &self.actions
    }

    /// Whether nothing is queued.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.actions.is_empty()
    }

    /// Removes and returns the queued actions in order, keeping the capacity.
    pub fn drain(&mut self) -> std::vec::Drain<'_, A> {
        self.actions.drain(..)
    }
}

impl<A> Default for FrameInput<A> {
    fn default() -> Self {
        Self::new()
    }
}

/// A control script driving an entity: on frame `n` (1-based,
/// [`Resources::frame`](crate::Resources::frame)) FlightControl applies
/// [`Script::actions_at`]`(n)` before the frame's [`FrameInput`] (through the
/// entity's [`ScriptReplay`] cursor when it has one, which
/// [`Simulation::set_script`](crate::Simulation::set_script) adds).
///
/// The script is shared (`Arc`), so a fleet can fly one script without copies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptInput<A>(pub Arc<Script<A>>);

/// The entity's position in its [`ScriptInput`]: a [`ScriptCursor`] sweeping
/// the rules, so a frame costs only the rules that start or end on it, not a
/// scan of every rule. Kept apart from [`ScriptInput`] because the script is
/// shared (`Arc`) and the cursor is per entity.
#[derive(Debug, Clone, Default)]
pub struct ScriptReplay(pub ScriptCursor);
