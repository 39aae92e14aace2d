//! The object-oriented baseline the thesis argues against: a fleet is a
//! `Vec<Box<dyn Aircraft>>` of objects that each own all their data, stepped
//! one after the other through a virtual call.
//!
//! This is the design of Bourg's C++ original and of the "plane objects" of
//! a typical game loop, ported idiomatically over the same
//! [`Model`] interface the ECS uses:
//!
//! * every aircraft is its own heap object (`Box<dyn Aircraft>`), reached
//!   through the fleet's vector of pointers;
//! * every object owns a private copy of its parameters, in a heap allocation
//!   of its own ([`Object::aircraft`]), as an object holding its elements in a
//!   `Vec` would;
//! * the object also owns its controls and state, and advances itself with
//!   [`Aircraft::step`], a dynamically dispatched call.
//!
//! The arithmetic is the same [`Model::step`] that fdm-ecs's
//! EquationsOfMotion calls, so a fleet flown this way and the same fleet flown
//! through the ECS end in bit-identical states (`tests/oop_ecs_parity.rs`),
//! and the benchmark `fleet.rs` measures only what the data layout and the
//! dispatch cost. The objects of a fleet are allocated in one loop, so the
//! heap is as orderly as it ever gets; in a long-running program they would
//! be scattered further.
//!
//! ```
//! use fdm_core::model::Model;
//! use fdm_core::palmer::{Palmer, PalmerControls};
//! use fdm_benches::oop::{Fleet, Object};
//!
//! let mut fleet = Fleet::new();
//! let full_power = PalmerControls { throttle: 1.0, ..PalmerControls::default() };
//! fleet.push(Box::new(Object::<Palmer>::new(
//!     &Palmer::default_aircraft(),
//!     full_power,
//!     Palmer::initial_state(),
//! )));
//! fleet.step_sequential(30.0);
//! let state = fleet.state::<Palmer>(0).unwrap();
//! assert!(state.velocity_mps.x > 0.0);
//! ```

use std::any::Any;

use fdm_core::model::Model;
use fdm_ecs::components::Params;
use fdm_ecs::World;
use rayon::prelude::*;

/// An aircraft object: owns its parameters, controls and state and advances
/// itself. Fleets hold `Box<dyn Aircraft>`, so every call is virtual.
pub trait Aircraft: Send + Sync {
    /// Advances the object by one frame at `fps` frames per second with its
    /// model's step (the time step computed as the ECS does,
    /// [`Model::time_step`]).
    fn step(&mut self, fps: f64);

    /// The model's name, e.g. `"palmer"`.
    fn model(&self) -> &'static str;

    /// The object, for downcasting to its [`Object<M>`].
    fn as_any(&self) -> &dyn Any;

    /// The object, for downcasting to its [`Object<M>`].
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// An aircraft of model `M` as an object.
#[derive(Debug, Clone)]
pub struct Object<M: Model> {
    /// The object's own copy of its parameters, in a heap allocation of its own.
    pub aircraft: Box<M::Aircraft>,
    /// Its controls.
    pub controls: M::Controls,
    /// Its state.
    pub state: M::State,
}

impl<M: Model> Object<M> {
    /// An object with its own copy of `aircraft`.
    #[must_use]
    pub fn new(aircraft: &M::Aircraft, controls: M::Controls, state: M::State) -> Self {
        Self {
            aircraft: Box::new(aircraft.clone()),
            controls,
            state,
        }
    }
}

impl<M: Model> Aircraft for Object<M> {
    fn step(&mut self, fps: f64) {
        self.state = M::step(
            &self.aircraft,
            &self.controls,
            &self.state,
            M::time_step(fps),
        );
    }

    fn model(&self) -> &'static str {
        M::NAME
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// A fleet of aircraft objects, stepped one after the other (or on rayon's
/// pool), each through a virtual call.
#[derive(Default)]
pub struct Fleet {
    aircraft: Vec<Box<dyn Aircraft>>,
}

impl std::fmt::Debug for Fleet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fleet")
            .field("aircraft", &self.aircraft.len())
            .finish()
    }
}

impl Fleet {
    /// An empty fleet.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            aircraft: Vec::new(),
        }
    }

    /// A fleet of `M` aircraft, one object per `(controls, state)`, each with
    /// its own copy of `aircraft`.
    #[must_use]
    pub fn of<M: Model>(aircraft: &M::Aircraft, members: &[(M::Controls, M::State)]) -> Self {
        let mut fleet = Self::new();
        for (controls, state) in members {
            fleet.push(Box::new(Object::<M>::new(aircraft, *controls, *state)));
        }
        fleet
    }

    /// Adds an object.
    pub fn push(&mut self, aircraft: Box<dyn Aircraft>) {
        self.aircraft.push(aircraft);
    }

    /// The objects, in insertion order.
    #[must_use]
    pub fn aircraft(&self) -> &[Box<dyn Aircraft>] {
        &self.aircraft
    }

    /// Object `i`'s state, if it is an `M` aircraft.
    #[must_use]
    pub fn state<M: Model>(&self, i: usize) -> Option<M::State> {
        self.aircraft
            .get(i)?
            .as_any()
            .downcast_ref::<Object<M>>()
            .map(|o| o.state)
    }

    /// The states of every `M` aircraft, in insertion order.
    #[must_use]
    pub fn states<M: Model>(&self) -> Vec<M::State> {
        (0..self.len()).filter_map(|i| self.state::<M>(i)).collect()
    }

    /// Replaces the states of the `M` aircraft, in insertion order (to reset
    /// a fleet between benchmark runs).
    pub fn set_states<M: Model>(&mut self, states: &[M::State]) {
        let objects = self
            .aircraft
            .iter_mut()
            .filter_map(|a| a.as_any_mut().downcast_mut::<Object<M>>());
        for (object, state) in objects.zip(states) {
            object.state = *state;
        }
    }

    /// Number of objects.
    #[must_use]
    pub fn len(&self) -> usize {
        self.aircraft.len()
    }

    /// Whether the fleet is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.aircraft.is_empty()
    }

    /// Steps every object once, in order, on this thread.
    pub fn step_sequential(&mut self, fps: f64) {
        for aircraft in &mut self.aircraft {
            aircraft.step(fps);
        }
    }

    /// Steps every object once on rayon's pool.
    pub fn step_parallel(&mut self, fps: f64) {
        self.aircraft
            .par_iter_mut()
            .for_each(|aircraft| aircraft.step(fps));
    }
}

/// The states of every `M` aircraft of an fdm-ecs world, in query order (for
/// a world spawned from one fleet, the spawn order, so the order of
/// [`Fleet::of`] over the same members).
#[must_use]
pub fn world_states<M: Model>(world: &World) -> Vec<M::State> {
    world
        .query::<(&Params<M>, &M::State)>()
        .iter()
        .map(|(_, s)| *s)
        .collect()
}

/// Writes `states` (as [`world_states`] returned them) back into the world's
/// `M` aircraft, in the same order.
pub fn set_world_states<M: Model>(world: &mut World, states: &[M::State]) {
    for ((_, state), new) in world
        .query_mut::<(&Params<M>, &mut M::State)>()
        .into_iter()
        .zip(states)
    {
        *state = *new;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;

    fn objects_step_like_the_model<M: Model>() {
        let aircraft = M::default_aircraft();
        let members: Vec<_> = (0..7).map(M::fleet_member).collect();
        let mut fleet = Fleet::of::<M>(&aircraft, &members);
        for _ in 0..5 {
            fleet.step_sequential(30.0);
        }
        for (i, (controls, state)) in members.iter().enumerate() {
            let mut want = *state;
            for _ in 0..5 {
                want = M::step(&aircraft, controls, &want, M::time_step(30.0));
            }
            assert_eq!(fleet.state::<M>(i), Some(want), "{} {i}", M::NAME);
        }
    }

    #[test]
    fn objects_step_like_the_pure_functions() {
        objects_step_like_the_model::<Palmer>();
        objects_step_like_the_model::<Bourg>();
    }

    #[test]
    fn mixed_fleets_keep_their_models_apart() {
        let mut fleet =
            Fleet::of::<Palmer>(&Palmer::default_aircraft(), &[Palmer::fleet_member(0)]);
        fleet.push(Box::new(Object::<Bourg>::new(
            &Bourg::default_aircraft(),
            Bourg::initial_controls(),
            Bourg::initial_state(),
        )));
        assert_eq!(fleet.state::<Bourg>(0), None);
        assert_eq!(fleet.state::<Bourg>(1), Some(Bourg::initial_state()));
        assert_eq!(fleet.states::<Palmer>().len(), 1);
        assert_eq!(fleet.aircraft()[1].model(), "bourg");
        fleet.set_states::<Palmer>(&[Palmer::initial_state()]);
        assert_eq!(fleet.state::<Palmer>(0), Some(Palmer::initial_state()));
    }
}
