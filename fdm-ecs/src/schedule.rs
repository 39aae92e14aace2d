//! The deterministic per-frame order of the systems (the thesis's figure 12).
//!
//! The thesis found that its dispatcher, left to itself, could run the
//! systems in a different order from frame to frame; here the order is a list
//! run front to back, every frame. Each model in the world adds its
//! instantiation of the generic systems to their phase
//! ([`Schedule::with_model`], which
//! [`Simulation::spawn`](crate::Simulation::spawn) calls on a model's first
//! aircraft); a caller's own systems go anywhere in the list
//! ([`Schedule::insert_after`], [`Schedule::push`]). The crate names no
//! model: a schedule starts empty ([`Schedule::for_no_model`]).
//!
//! Within a phase the models' systems run in the order the models joined.
//! That order cannot change a result: every system of model `M` queries only
//! entities with `M`'s parameters ([`Params<M>`](crate::components::Params),
//! which `spawn::<M>` gives an aircraft of `M` alone), so the systems of two
//! models touch disjoint entities, and every system reads the resources
//! without writing them.

use std::any::TypeId;

use fdm_core::model::Model;
use hecs::World;

use crate::resources::Resources;
use crate::systems::{equations_of_motion, flight_control, flight_status, place};

/// A system: a named function over the world and the resources.
#[derive(Debug, Clone, Copy)]
pub struct System {
    /// The system's name, e.g. `"EquationsOfMotion"`; the instantiations of a
    /// generic system for several models share their phase's name.
    pub name: &'static str,
    /// The function run once per frame.
    pub run: fn(&mut World, &Resources),
}

/// Systems run one after the other, in a fixed order, once per frame.
#[derive(Debug, Clone)]
pub struct Schedule {
    systems: Vec<System>,
    models: Vec<TypeId>,
}

impl Schedule {
    /// The name of [`flight_control`].
    pub const FLIGHT_CONTROL: &'static str = "FlightControl";
    /// The name of [`equations_of_motion`].
    pub const EQUATIONS_OF_MOTION: &'static str = "EquationsOfMotion";
    /// The name of [`flight_status`].
    pub const FLIGHT_STATUS: &'static str = "FlightStatus";
    /// The name of [`place`].
    pub const PLACE: &'static str = "Place";

    /// The phases every model takes part in, in order.
    const MODEL_PHASES: [&'static str; 4] = [
        Self::FLIGHT_CONTROL,
        Self::EQUATIONS_OF_MOTION,
        Self::FLIGHT_STATUS,
        Self::PLACE,
    ];

    /// The thesis's phases with no model yet: no system (every phase is
    /// per model). Models join with [`with_model`](Self::with_model), each
    /// adding its FlightControl → EquationsOfMotion → FlightStatus → Place
    /// (the thesis's order; its MakePacket and SendPacket are outputs of the
    /// run library now: `fdm_run::flightgear`).
    #[must_use]
    pub fn for_no_model() -> Self {
        Self {
            systems: Vec::new(),
            models: Vec::new(),
        }
    }

    /// Adds model `M`'s FlightControl, EquationsOfMotion, FlightStatus and
    /// Place, each after the last system of its phase (or, for a phase not
    /// present yet, before the first system of a later phase, else at the
    /// end). Adding a model twice changes nothing.
    #[must_use]
    pub fn with_model<M: Model>(mut self) -> Self {
        self.add_model::<M>();
        self
    }

    /// [`with_model`](Self::with_model) in place; returns whether `M` was new.
    pub fn add_model<M: Model>(&mut self) -> bool {
        let id = TypeId::of::<M>();
        if self.models.contains(&id) {
            return false;
        }
        self.models.push(id);
        let runs: [fn(&mut World, &Resources); 4] = [
            flight_control::<M>,
            equations_of_motion::<M>,
            flight_status::<M>,
            place::<M>,
        ];
        for (phase, (name, run)) in Self::MODEL_PHASES.iter().zip(runs).enumerate() {
            let at = self.end_of_phase(phase);
            self.systems.insert(at, System { name, run });
        }
        true
    }

    /// Whether model `M`'s systems are in the schedule.
    #[must_use]
    pub fn has_model<M: Model>(&self) -> bool {
        self.models.contains(&TypeId::of::<M>())
    }

    /// Where a new system of model phase `phase` goes: after the last system
    /// of that phase or of an earlier one, else before the first system of a
    /// later phase, else at the end.
    fn end_of_phase(&self, phase: usize) -> usize {
        let rank = |name: &str| Self::MODEL_PHASES.iter().position(|p| *p == name);
        let mut at = None;
        for (i, system) in self.systems.iter().enumerate() {
            match rank(system.name) {
                Some(r) if r <= phase => at = Some(i + 1),
                _ => {}
            }
        }
        at.unwrap_or_else(|| {
            self.systems
                .iter()
                .position(|s| rank(s.name).is_some())
                .unwrap_or(self.systems.len())
        })
    }

    /// A schedule running exactly `systems` in the given order (no model
    /// phases are managed: [`with_model`](Self::with_model) then places a
    /// model's systems by their names).
    #[must_use]
    pub const fn new(systems: Vec<System>) -> Self {
        Self {
            systems,
            models: Vec::new(),
        }
    }

    /// Appends `system` at the end of the frame.
    pub fn push(&mut self, system: System) {
        self.systems.push(system);
    }

    /// Inserts `system` right after the last system named `after`; returns
    /// `false` (and inserts nothing) when there is none.
    pub fn insert_after(&mut self, after: &str, system: System) -> bool {
        match self.systems.iter().rposition(|s| s.name == after) {
            Some(i) => {
                self.systems.insert(i + 1, system);
                true
            }
            None => false,
        }
    }

    /// The systems, in the order they run.
    #[must_use]
    pub fn systems(&self) -> &[System] {
        &self.systems
    }

    /// Runs one frame: increments [`Resources::frame`], then runs every system
    /// in order.
    pub fn run(&self, world: &mut World, res: &mut Resources) {
        self.run_observed(world, res, |_, _| {});
    }

    /// [`Schedule::run`], calling `observer` with each system's name and the
    /// world right after that system has run (for tracing and tests).
    pub fn run_observed(
        &self,
        world: &mut World,
        res: &mut Resources,
        mut observer: impl FnMut(&'static str, &World),
    ) {
        res.frame += 1;
        for system in &self.systems {
            (system.run)(world, res);
            observer(system.name, world);
        }
    }
}

impl Default for Schedule {
    /// [`Schedule::for_no_model`].
    fn default() -> Self {
        Self::for_no_model()
    }
}
