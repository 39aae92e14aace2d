//! [`Simulation`]: a world, its resources and the thesis's schedule behind a
//! small builder API (what `fdm_run::Run` flies one aircraft in, and what
//! `sim-cli`'s fleets use).

use std::sync::Arc;

use fdm_core::model::{FlightStatus, FlightView, Model};
use fdm_core::script::Script;
use hecs::{Component, Entity, EntityBuilder, QueryOneError, World};

use crate::components::{Attitude, FrameInput, Geodetic, Params, ScriptInput, ScriptReplay};
use crate::resources::Resources;
use crate::schedule::Schedule;
use crate::systems::placement;
use crate::EcsError;

/// What the aircraft of a fleet spawned by [`Simulation::spawn_fleet`] carry
/// besides the model's own components.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FleetOutputs {
    /// Geodetic position and attitude (the placement every output reads),
    /// rebuilt by Place every frame.
    Placement,
    /// Nothing more: a fleet that only flies (Place skips it).
    None,
}

/// A world of aircraft of any number of models, its [`Resources`] and the
/// [`Schedule`] run by [`run_frame`](Self::run_frame).
///
/// ```
/// use std::sync::Arc;
/// use fdm_core::bourg::{Bourg, BourgAction, BourgControls, BourgState};
/// use fdm_core::model::Model;
/// use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
/// use fdm_ecs::{Resources, Simulation};
///
/// let mut sim = Simulation::new(Resources::new(30.0)?);
/// let cessna = sim.spawn::<Palmer>(
///     Arc::new(Palmer::default_aircraft()),
///     PalmerControls { throttle: 1.0, alpha_deg: 4.0, ..PalmerControls::default() },
///     PalmerState::initial(),
/// );
/// let bourg = sim.spawn::<Bourg>(
///     Arc::new(Bourg::default_aircraft()),
///     BourgControls::initial(),
///     BourgState::initial(),
/// );
/// for _ in 0..30 {
///     sim.push_input(bourg, BourgAction::PitchUp)?; // as if the key were held
///     sim.run_frame();
/// }
/// assert_eq!(sim.frame(), 30);
/// let palmer = sim.state::<Palmer>(cessna).unwrap();
/// assert!((palmer.time_s - 1.0).abs() < 1e-9 && palmer.velocity_mps.x > 0.0);
/// let here = sim.geodetic(bourg).unwrap();
/// assert!(here.lat_deg < 39.8264); // Bourg starts 5000 ft south of the origin
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Simulation {
    world: World,
    resources: Resources,
    schedule: Schedule,
}

/// Maps a failed single-entity query needing model component `T`.
/// The status of an aircraft starting at `state`: [`FlightStatus::initial`]
/// of its height, or [`FlightStatus::Diverged`] for a non-finite state (so it
/// is never stepped nor sent).
fn start_status<M: Model>(state: &M::State) -> FlightStatus {
    if M::is_finite(state) {
        FlightStatus::initial(M::height_m(state))
    } else {
        FlightStatus::Diverged
    }
}

fn query_error<T>(error: QueryOneError) -> EcsError {
    match error {
        QueryOneError::NoSuchEntity => EcsError::NoSuchEntity,
        QueryOneError::Unsatisfied => EcsError::missing::<T>(),
    }
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("entities", &self.world.len())
            .field("resources", &self.resources)
            .field("schedule", &self.schedule)
            .finish()
    }
}

impl Simulation {
    /// An empty world with these resources and a schedule without models
    /// ([`Schedule::for_no_model`]): each model's systems join it with the
    /// model's first aircraft ([`Simulation::spawn`]).
    #[must_use]
    pub fn new(resources: Resources) -> Self {
        Self {
            world: World::new(),
            resources,
            schedule: Schedule::for_no_model(),
        }
    }

    /// Spawns an aircraft of model `M` with its shared parameters, initial
    /// controls and state; adds `M`'s systems to the schedule if they are
    /// not there yet. Its flight status, geodetic position and attitude are
    /// computed right away, so they are valid before the first frame.
    pub fn spawn<M: Model>(
        &mut self,
        aircraft: Arc<M::Aircraft>,
        controls: M::Controls,
        state: M::State,
    ) -> Entity {
        self.schedule.add_model::<M>();
        let (geodetic, attitude) = placement(
            &M::view(&aircraft, &controls, &state),
            &self.resources.origin,
        );
        let status = start_status::<M>(&state);
        let mut builder = EntityBuilder::new();
        builder.add_bundle((
            Params::<M>::new(aircraft),
            controls,
            state,
            FrameInput::<M::Action>::new(),
            status,
            geodetic,
            attitude,
        ));
        self.world.spawn(builder.build())
    }

    /// Spawns members `members` (e.g. `0..n`) of model `M`'s demonstration
    /// fleet ([`Model::fleet_member`]), all sharing `aircraft`, in order
    /// (which is also the order of the world's queries over them). With
    /// [`FleetOutputs::None`] they carry only the model's components and
    /// their flight status (no geodetic position or attitude, which Place
    /// then skips); with [`FleetOutputs::Placement`] they are full aircraft
    /// as [`spawn`](Self::spawn) makes them.
    pub fn spawn_fleet<M: Model>(
        &mut self,
        aircraft: &Arc<M::Aircraft>,
        members: std::ops::Range<usize>,
        outputs: FleetOutputs,
    ) {
        for i in members {
            let (controls, state) = M::fleet_member(i);
            self.spawn_member::<M>(aircraft, controls, state, outputs);
        }
    }

    /// Spawns one fleet aircraft of model `M` at `controls` and `state`,
    /// sharing `aircraft`, with the components
    /// `outputs` says (see [`spawn_fleet`](Self::spawn_fleet)).
    pub fn spawn_member<M: Model>(
        &mut self,
        aircraft: &Arc<M::Aircraft>,
        controls: M::Controls,
        state: M::State,
        outputs: FleetOutputs,
    ) -> Entity {
        self.schedule.add_model::<M>();
        match outputs {
            FleetOutputs::Placement => self.spawn::<M>(Arc::clone(aircraft), controls, state),
            FleetOutputs::None => {
                let status = start_status::<M>(&state);
                self.world.spawn((
                    Params::<M>::new(Arc::clone(aircraft)),
                    controls,
                    state,
                    FrameInput::<M::Action>::new(),
                    status,
                ))
            }
        }
    }

    /// Makes `script` drive `entity` from the next frame on (replacing any
    /// earlier script): on frame `n` its rules covering `n` are applied
    /// before the frame's queued input. `A` is the entity's model's action type.
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`], or [`EcsError::MissingComponent`] when the
    /// entity is not an aircraft of the script's model.
    pub fn set_script<A: Component>(
        &mut self,
        entity: Entity,
        script: Arc<Script<A>>,
    ) -> Result<(), EcsError> {
        if let Err(e) = self.world.get::<&FrameInput<A>>(entity) {
            return Err(EcsError::component::<FrameInput<A>>(&e));
        }
        self.world
            .insert(entity, (ScriptInput(script), ScriptReplay::default()))
            .map_err(|_| EcsError::NoSuchEntity)
    }

    /// Queues `action` (a key press) for `entity`'s next frame. `A` is the
    /// entity's model's action type.
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`], or [`EcsError::MissingComponent`] when the
    /// entity is not an aircraft of the action's model.
    pub fn push_input<A: Component>(&mut self, entity: Entity, action: A) -> Result<(), EcsError> {
        self.world
            .get::<&mut FrameInput<A>>(entity)
            .map_err(|e| EcsError::component::<FrameInput<A>>(&e))?
            .push(action);
        Ok(())
    }

    /// Puts an `M` aircraft back to `controls` and `state` (e.g. the
    /// interactive reset key): drops its queued input, restarts its flight
    /// status and recomputes its geodetic position and attitude at once, as
    /// at spawn. Its parameters and script stay.
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`], or [`EcsError::MissingComponent`] for an
    /// aircraft of another model.
    pub fn reset<M: Model>(
        &mut self,
        entity: Entity,
        controls: M::Controls,
        state: M::State,
    ) -> Result<(), EcsError> {
        let origin = self.resources.origin;
        let (params, c, s, input, status, geodetic, attitude) = self
            .world
            .query_one_mut::<(
                &Params<M>,
                &mut M::Controls,
                &mut M::State,
                &mut FrameInput<M::Action>,
                &mut FlightStatus,
                &mut Geodetic,
                &mut Attitude,
            )>(entity)
            .map_err(query_error::<Params<M>>)?;
        let (g, a) = placement(&M::view(params, &controls, &state), &origin);
        *status = start_status::<M>(&state);
        (*c, *s) = (controls, state);
        input.drain();
        (*geodetic, *attitude) = (g, a);
        Ok(())
    }

    /// Runs one frame of the schedule (FlightControl → EquationsOfMotion →
    /// FlightStatus → Place).
    pub fn run_frame(&mut self) {
        self.schedule.run(&mut self.world, &mut self.resources);
    }

    /// [`run_frame`](Self::run_frame), calling `observer` with each system's
    /// name and the world right after that system has run (tracing, tests).
    pub fn run_frame_observed(&mut self, observer: impl FnMut(&'static str, &World)) {
        self.schedule
            .run_observed(&mut self.world, &mut self.resources, observer);
    }

    /// Runs `frames` frames.
    pub fn run_frames(&mut self, frames: u64) {
        for _ in 0..frames {
            self.run_frame();
        }
    }

    /// Frames run so far.
    #[must_use]
    pub const fn frame(&self) -> u64 {
        self.resources.frame
    }

    /// A copy of `entity`'s component `T`, if it exists and has one.
    #[must_use]
    pub fn get<T: Component + Clone>(&self, entity: Entity) -> Option<T> {
        self.world.get::<&T>(entity).ok().map(|c| (*c).clone())
    }

    /// An `M` aircraft's state (`None` for another model or no entity).
    #[must_use]
    pub fn state<M: Model>(&self, entity: Entity) -> Option<M::State> {
        self.model_component::<M, M::State>(entity)
    }

    /// An `M` aircraft's controls (`None` for another model or no entity).
    #[must_use]
    pub fn controls<M: Model>(&self, entity: Entity) -> Option<M::Controls> {
        self.model_component::<M, M::Controls>(entity)
    }

    /// An `M` aircraft's shared parameters.
    #[must_use]
    pub fn aircraft<M: Model>(&self, entity: Entity) -> Option<Arc<M::Aircraft>> {
        self.model_component::<M, Params<M>>(entity).map(|p| p.0)
    }

    /// The common view of an `M` aircraft now ([`Model::view`]).
    #[must_use]
    pub fn view<M: Model>(&self, entity: Entity) -> Option<FlightView> {
        let mut query = self
            .world
            .query_one::<(&Params<M>, &M::Controls, &M::State)>(entity);
        query
            .get()
            .ok()
            .map(|(params, controls, state)| M::view(params, controls, state))
    }

    /// Component `T` of `entity` if it is an aircraft of model `M`.
    fn model_component<M: Model, T: Component + Clone>(&self, entity: Entity) -> Option<T> {
        let mut query = self.world.query_one::<(&Params<M>, &T)>(entity);
        query.get().ok().map(|(_, t)| t.clone())
    }

    /// How many aircraft (of any model) have diverged
    /// ([`FlightStatus::Diverged`]): they are no longer stepped nor placed.
    #[must_use]
    pub fn diverged_count(&self) -> usize {
        self.world
            .query::<&FlightStatus>()
            .iter()
            .filter(|s| **s == FlightStatus::Diverged)
            .count()
    }

    /// The aircraft's flight status as of the last frame (any model).
    #[must_use]
    pub fn status(&self, entity: Entity) -> Option<FlightStatus> {
        self.get(entity)
    }

    /// The aircraft's WGS-84 position as of the last Place.
    #[must_use]
    pub fn geodetic(&self, entity: Entity) -> Option<Geodetic> {
        self.get(entity)
    }

    /// The aircraft's attitude relative to the local north-east-down frame
    /// as of the last Place (degrees; roll right wing down +, pitch nose up
    /// +, heading clockwise from true north in `[0, 360)`).
    #[must_use]
    pub fn attitude(&self, entity: Entity) -> Option<Attitude> {
        self.get(entity)
    }

    /// Removes an aircraft.
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`] if it does not exist.
    pub fn despawn(&mut self, entity: Entity) -> Result<(), EcsError> {
        self.world
            .despawn(entity)
            .map_err(|_| EcsError::NoSuchEntity)
    }

    /// The resources.
    #[must_use]
    pub const fn resources(&self) -> &Resources {
        &self.resources
    }

    /// The resources, to change the origin or the execution mode between
    /// frames.
    pub fn resources_mut(&mut self) -> &mut Resources {
        &mut self.resources
    }

    /// The world, for queries of your own.
    #[must_use]
    pub const fn world(&self) -> &World {
        &self.world
    }

    /// The world, to add components or entities of your own.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// The schedule.
    #[must_use]
    pub const fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// The schedule, to add systems of your own (e.g.
    /// [`Schedule::insert_after`]).
    pub fn schedule_mut(&mut self) -> &mut Schedule {
        &mut self.schedule
    }
}
