//! The object-oriented baseline the thesis argues against: a fleet is a
//! `Vec<Box<dyn Aircraft>>` of objects that each own all their data, stepped
//! one after the other through a virtual call.
//!
//! This is the design of Bourg's C++ original and of the "plane objects" of
//! a typical game loop, ported idiomatically:
//!
//! * every aircraft is its own heap object (`Box<dyn Aircraft>`), reached
//!   through the fleet's vector of pointers;
//! * every object owns a private copy of its parameters: [`PalmerObject`]
//!   holds its [`PalmerAircraft`] (128 bytes) inline, [`BourgObject`] its
//!   [`bourg::Aircraft`] (the eight elements with the mass properties, 680
//!   bytes) in a second heap allocation of its own, as an object holding its
//!   elements in a `Vec` would;
//! * the object also owns its controls and state, and advances itself with
//!   [`Aircraft::step`], a dynamically dispatched call.
//!
//! The arithmetic is the same pure step function of `fdm-core` that
//! fdm-ecs's EquationsOfMotion calls, so a fleet flown this way and the same
//! fleet flown through the ECS end in bit-identical states
//! (`tests/oop_ecs_parity.rs`), and the benchmark `benches/fleet.rs` measures
//! only what the data layout and the dispatch cost. The objects of a fleet are
//! allocated in one loop, so the heap is as orderly as it ever gets; in a
//! long-running program they would be scattered further.
//!
//! ```
//! use fdm_suite::fdm_core::palmer::{PalmerControls, PalmerState};
//! use fdm_suite::oop::{Fleet, FleetState, PalmerObject, TimeSteps};
//!
//! let mut fleet = Fleet::new();
//! let full_power = PalmerControls { throttle: 1.0, ..PalmerControls::default() };
//! fleet.push(Box::new(PalmerObject::cessna_172(full_power, PalmerState::at_rest())));
//! fleet.step_sequential(&TimeSteps::at_fps(30));
//! let FleetState::Palmer(state) = fleet.aircraft()[0].state() else { unreachable!() };
//! assert!(state.velocity_mps.x > 0.0);
//! ```

use fdm_core::bourg::{self, BourgControls, BourgState};
use fdm_core::palmer::{self, PalmerAircraft, PalmerControls, PalmerState};
use fdm_ecs::World;
use rayon::prelude::*;

/// The time steps of one frame rate, computed once per frame as the original
/// programs do: Palmer `1.0 / fps` (f64), Bourg `1.0f32 / fps as f32`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSteps {
    /// Palmer's step, s.
    pub palmer_s: f64,
    /// Bourg's step, s.
    pub bourg_s: f32,
}

impl TimeSteps {
    /// The steps for `fps` frames per second (`fps` > 0; 0 gives infinite steps).
    #[must_use]
    #[allow(clippy::cast_precision_loss)] // the original's own conversion
    pub fn at_fps(fps: u32) -> Self {
        Self {
            palmer_s: 1.0 / f64::from(fps),
            bourg_s: 1.0f32 / fps as f32,
        }
    }
}

/// An object's state, whichever its model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FleetState {
    /// A Palmer aircraft's state.
    Palmer(PalmerState),
    /// A Bourg aircraft's state.
    Bourg(BourgState),
}

impl FleetState {
    /// The states of every aircraft of an fdm-ecs world, in query order:
    /// the Palmer aircraft, then the Bourg aircraft (for a world spawned from
    /// one fleet, the spawn order, so the order of [`Fleet::palmer`] or
    /// [`Fleet::bourg`] over the same slice).
    #[must_use]
    pub fn of_world(world: &World) -> Vec<Self> {
        let mut states: Vec<Self> = world
            .query::<&PalmerState>()
            .iter()
            .map(|s| Self::Palmer(*s))
            .collect();
        states.extend(world.query::<&BourgState>().iter().map(|s| Self::Bourg(*s)));
        states
    }

    /// Writes `states` (as [`of_world`](Self::of_world) returned them) back
    /// into the world's aircraft, in the same order; a state of the other
    /// model at an aircraft's place is skipped.
    pub fn write_to_world(world: &mut World, states: &[Self]) {
        let palmer = world.query_mut::<&mut PalmerState>().into_iter().count();
        let (palmer_states, bourg_states) = states.split_at(palmer.min(states.len()));
        for (state, new) in world
            .query_mut::<&mut PalmerState>()
            .into_iter()
            .zip(palmer_states)
        {
            if let Self::Palmer(new) = new {
                *state = *new;
            }
        }
        for (state, new) in world
            .query_mut::<&mut BourgState>()
            .into_iter()
            .zip(bourg_states)
        {
            if let Self::Bourg(new) = new {
                *state = *new;
            }
        }
    }
}

/// An aircraft object: owns its parameters, controls and state and advances
/// itself. Fleets hold `Box<dyn Aircraft>`, so every call is virtual.
pub trait Aircraft: Send + Sync {
    /// Advances the object by one frame with its model's step.
    fn step(&mut self, dt: &TimeSteps);

    /// The model's name, `"palmer"` or `"bourg"`.
    fn model(&self) -> &'static str;

    /// A copy of the object's current state.
    fn state(&self) -> FleetState;

    /// Replaces the object's state; `false` (and no change) when `state` is
    /// of another model.
    fn set_state(&mut self, state: FleetState) -> bool;
}

/// A Palmer Cessna 172 as an object: its own parameter copy, controls and state.
#[derive(Debug, Clone, PartialEq)]
pub struct PalmerObject {
    aircraft: PalmerAircraft,
    controls: PalmerControls,
    state: PalmerState,
}

impl PalmerObject {
    /// An object with these parameters, controls and initial state.
    #[must_use]
    pub const fn new(
        aircraft: PalmerAircraft,
        controls: PalmerControls,
        state: PalmerState,
    ) -> Self {
        Self {
            aircraft,
            controls,
            state,
        }
    }

    /// A Cessna 172 ([`PalmerAircraft::cessna_172`]) with these controls and state.
    #[must_use]
    pub const fn cessna_172(controls: PalmerControls, state: PalmerState) -> Self {
        Self::new(PalmerAircraft::cessna_172(), controls, state)
    }
}

impl Aircraft for PalmerObject {
    fn step(&mut self, dt: &TimeSteps) {
        self.state = palmer::step(&self.aircraft, &self.controls, &self.state, dt.palmer_s);
    }

    fn model(&self) -> &'static str {
        "palmer"
    }

    fn state(&self) -> FleetState {
        FleetState::Palmer(self.state)
    }

    fn set_state(&mut self, state: FleetState) -> bool {
        match state {
            FleetState::Palmer(state) => {
                self.state = state;
                true
            }
            FleetState::Bourg(_) => false,
        }
    }
}

/// A Bourg aircraft as an object: its own airframe and mass properties (on
/// the heap, as the elements of an object-oriented port would be), controls
/// and state.
#[derive(Debug, Clone, PartialEq)]
pub struct BourgObject {
    aircraft: Box<bourg::Aircraft>,
    controls: BourgControls,
    state: BourgState,
}

impl BourgObject {
    /// An object with a copy of `aircraft`, these controls and initial state.
    #[must_use]
    pub fn new(aircraft: &bourg::Aircraft, controls: BourgControls, state: BourgState) -> Self {
        Self {
            aircraft: Box::new(*aircraft),
            controls,
            state,
        }
    }

    /// Bourg's airplane ([`bourg::Aircraft::bourg_default`]) with these
    /// controls and state.
    #[must_use]
    pub fn bourg_default(controls: BourgControls, state: BourgState) -> Self {
        Self::new(&bourg::Aircraft::bourg_default(), controls, state)
    }
}

impl Aircraft for BourgObject {
    fn step(&mut self, dt: &TimeSteps) {
        self.state = bourg::step(&self.aircraft, &self.controls, &self.state, dt.bourg_s);
    }

    fn model(&self) -> &'static str {
        "bourg"
    }

    fn state(&self) -> FleetState {
        FleetState::Bourg(self.state)
    }

    fn set_state(&mut self, state: FleetState) -> bool {
        match state {
            FleetState::Bourg(state) => {
                self.state = state;
                true
            }
            FleetState::Palmer(_) => false,
        }
    }
}

/// A fleet of aircraft objects (any mix of models).
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

    /// Palmer Cessnas, one object per `(controls, state)`.
    #[must_use]
    pub fn palmer(fleet: &[(PalmerControls, PalmerState)]) -> Self {
        Self {
            aircraft: fleet
                .iter()
                .map(|&(c, s)| Box::new(PalmerObject::cessna_172(c, s)) as Box<dyn Aircraft>)
                .collect(),
        }
    }

    /// Bourg airplanes, one object (with its own airframe copy) per
    /// `(controls, state)`.
    #[must_use]
    pub fn bourg(fleet: &[(BourgControls, BourgState)]) -> Self {
        let aircraft = bourg::Aircraft::bourg_default();
        Self {
            aircraft: fleet
                .iter()
                .map(|&(c, s)| Box::new(BourgObject::new(&aircraft, c, s)) as Box<dyn Aircraft>)
                .collect(),
        }
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

    /// The objects, in insertion order, mutably.
    pub fn aircraft_mut(&mut self) -> &mut [Box<dyn Aircraft>] {
        &mut self.aircraft
    }

    /// Copies of every object's state, in insertion order.
    #[must_use]
    pub fn states(&self) -> Vec<FleetState> {
        self.aircraft.iter().map(|a| a.state()).collect()
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

    /// One frame: every object's [`Aircraft::step`], in order, on this thread.
    pub fn step_sequential(&mut self, dt: &TimeSteps) {
        for aircraft in &mut self.aircraft {
            aircraft.step(dt);
        }
    }

    /// One frame on rayon's current pool (`par_iter_mut` over the objects).
    /// Each object only touches itself, so the result is the same as
    /// [`step_sequential`](Self::step_sequential).
    pub fn step_parallel(&mut self, dt: &TimeSteps) {
        self.aircraft
            .par_iter_mut()
            .for_each(|aircraft| aircraft.step(dt));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_step_like_the_pure_functions() {
        let dt = TimeSteps::at_fps(30);
        let pc = PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        };
        let mut fleet = Fleet::new();
        fleet.push(Box::new(PalmerObject::cessna_172(
            pc,
            PalmerState::at_rest(),
        )));
        fleet.push(Box::new(BourgObject::bourg_default(
            BourgControls::initial(),
            BourgState::initial(),
        )));
        let cessna = PalmerAircraft::cessna_172();
        let plane = bourg::Aircraft::bourg_default();
        let (mut ps, mut bs) = (PalmerState::at_rest(), BourgState::initial());
        for frame in 0..60 {
            if frame % 2 == 0 {
                fleet.step_sequential(&dt);
            } else {
                fleet.step_parallel(&dt);
            }
            ps = palmer::step(&cessna, &pc, &ps, dt.palmer_s);
            bs = bourg::step(&plane, &BourgControls::initial(), &bs, dt.bourg_s);
        }
        assert_eq!(fleet.len(), 2);
        assert!(!fleet.is_empty());
        assert_eq!(fleet.aircraft()[0].model(), "palmer");
        assert_eq!(fleet.aircraft()[1].model(), "bourg");
        assert_eq!(
            fleet.states(),
            [FleetState::Palmer(ps), FleetState::Bourg(bs)]
        );
        let palmer = &mut fleet.aircraft_mut()[0];
        assert!(!palmer.set_state(FleetState::Bourg(bs)));
        assert!(palmer.set_state(FleetState::Palmer(PalmerState::at_rest())));
        assert_eq!(palmer.state(), FleetState::Palmer(PalmerState::at_rest()));
        assert!(!fleet.aircraft_mut()[1].set_state(FleetState::Palmer(ps)));
    }

    #[test]
    fn world_states_read_and_write_in_query_order() {
        use std::sync::Arc;

        let mut sim = fdm_ecs::Simulation::new(fdm_ecs::Resources::new(30.0).unwrap());
        sim.spawn_bourg(
            Arc::new(bourg::Aircraft::bourg_default()),
            BourgControls::initial(),
            BourgState::initial(),
            None,
        );
        sim.spawn_palmer(
            Arc::new(PalmerAircraft::cessna_172()),
            PalmerControls::default(),
            PalmerState::at_rest(),
            None,
        );
        let states = FleetState::of_world(sim.world());
        assert_eq!(
            states,
            [
                FleetState::Palmer(PalmerState::at_rest()),
                FleetState::Bourg(BourgState::initial())
            ]
        );
        let mut moved = PalmerState::at_rest();
        moved.position_m.x = 12.0;
        let mut turned = BourgState::initial();
        turned.speed = 99.0;
        let new = [FleetState::Palmer(moved), FleetState::Bourg(turned)];
        FleetState::write_to_world(sim.world_mut(), &new);
        assert_eq!(FleetState::of_world(sim.world()), new);
        // A state of the wrong model is skipped.
        FleetState::write_to_world(sim.world_mut(), &[FleetState::Bourg(BourgState::initial())]);
        assert_eq!(FleetState::of_world(sim.world()), new);
    }

    #[test]
    fn time_steps_follow_the_originals() {
        let dt = TimeSteps::at_fps(30);
        assert_eq!(dt.palmer_s, 1.0 / 30.0);
        assert_eq!(dt.bourg_s, 1.0f32 / 30.0);
    }
}
