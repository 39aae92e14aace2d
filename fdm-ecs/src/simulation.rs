//! [`Simulation`]: a world, its resources and the thesis's schedule behind a
//! small builder API (what `sim-cli` uses).

use std::io;
use std::sync::Arc;

use fdm_core::bourg::{Aircraft, BourgControls, BourgState};
use fdm_core::palmer::{PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use fgnet::{FgNetFdm, SenderStats};
use hecs::{Component, Entity, EntityBuilder, QueryOneError, World};

use crate::components::{
    BourgInput, BourgParams, FlightGearLink, FrameInput, PalmerInput, PalmerParams, ScriptInput,
};
use crate::geodesy::{Attitude, Geodetic};
use crate::resources::Resources;
use crate::schedule::Schedule;
use crate::systems::{bourg_display, palmer_display, Display};
use crate::EcsError;

/// A world of aircraft (both models can be mixed), its [`Resources`] and the
/// [`Schedule`] run by [`run_frame`](Self::run_frame).
///
/// ```
/// use std::sync::Arc;
/// use fdm_core::bourg::{Aircraft, BourgAction, BourgControls, BourgState};
/// use fdm_core::palmer::{PalmerAircraft, PalmerControls, PalmerState};
/// use fdm_ecs::{Resources, Simulation};
///
/// let mut sim = Simulation::new(Resources::new(30.0)?);
/// let cessna = sim.spawn_palmer(
///     Arc::new(PalmerAircraft::cessna_172()),
///     PalmerControls { throttle: 1.0, alpha_deg: 4.0, ..PalmerControls::default() },
///     PalmerState::at_rest(),
///     None, // no FlightGear link: nothing is sent
/// );
/// let bourg = sim.spawn_bourg(
///     Arc::new(Aircraft::bourg_default()),
///     BourgControls::initial(),
///     BourgState::initial(),
///     None,
/// );
/// for _ in 0..30 {
///     sim.push_input(bourg, BourgAction::PitchUp)?; // as if the key were held
///     sim.run_frame();
/// }
/// assert_eq!(sim.frame(), 30);
/// let palmer = sim.palmer_state(cessna).unwrap();
/// assert!((palmer.time_s - 1.0).abs() < 1e-9 && palmer.velocity_mps.x > 0.0);
/// let here = sim.geodetic(bourg).unwrap();
/// assert!(here.lat_deg < 39.8264); // Bourg starts 5000 ft south of the origin
/// assert_eq!(sim.packet(bourg).unwrap().version, 24);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Simulation {
    world: World,
    resources: Resources,
    schedule: Schedule,
}

/// Maps a failed single-entity query needing model component `T`.
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
    /// An empty world with these resources and [`Schedule::thesis`].
    #[must_use]
    pub fn new(resources: Resources) -> Self {
        Self {
            world: World::new(),
            resources,
            schedule: Schedule::thesis(),
        }
    }

    /// Spawns a Palmer aircraft with its shared parameters, initial controls
    /// and state, and optionally a FlightGear link. Its geodetic position,
    /// attitude and packet are computed right away, so they are valid before
    /// the first frame.
    pub fn spawn_palmer(
        &mut self,
        aircraft: Arc<PalmerAircraft>,
        controls: PalmerControls,
        state: PalmerState,
        link: Option<FlightGearLink>,
    ) -> Entity {
        let display = palmer_display(&aircraft, &controls, &state, &self.resources.origin);
        let mut builder = EntityBuilder::new();
        builder.add_bundle((PalmerParams(aircraft), controls, state, PalmerInput::new()));
        self.spawn(builder, display, link)
    }

    /// Spawns a Bourg aircraft; see [`spawn_palmer`](Self::spawn_palmer).
    pub fn spawn_bourg(
        &mut self,
        aircraft: Arc<Aircraft>,
        controls: BourgControls,
        state: BourgState,
        link: Option<FlightGearLink>,
    ) -> Entity {
        let display = bourg_display(&controls, &state, &self.resources.origin);
        let mut builder = EntityBuilder::new();
        builder.add_bundle((BourgParams(aircraft), controls, state, BourgInput::new()));
        self.spawn(builder, display, link)
    }

    fn spawn(
        &mut self,
        mut builder: EntityBuilder,
        display: Display,
        link: Option<FlightGearLink>,
    ) -> Entity {
        builder.add_bundle((display.geodetic, display.attitude, display.packet));
        if let Some(link) = link {
            builder.add(link);
        }
        self.world.spawn(builder.build())
    }

    /// Makes `script` drive `entity` from the next frame on (replacing any
    /// earlier script): on frame `n` its rules covering `n` are applied
    /// before the frame's queued input. `A` is `PalmerAction` or `BourgAction`
    /// and must match the entity's model.
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
            .insert_one(entity, ScriptInput(script))
            .map_err(|_| EcsError::NoSuchEntity)
    }

    /// Queues `action` (a key press) for `entity`'s next frame. `A` is
    /// `PalmerAction` or `BourgAction` and must match the entity's model.
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

    /// Puts a Palmer aircraft back to `controls` and `state` (e.g. the
    /// interactive reset key): drops its queued input and recomputes its
    /// geodetic position, attitude and packet at once, as at spawn. Its
    /// parameters, script and FlightGear link stay.
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`], or [`EcsError::MissingComponent`] for a
    /// Bourg aircraft.
    pub fn reset_palmer(
        &mut self,
        entity: Entity,
        controls: PalmerControls,
        state: PalmerState,
    ) -> Result<(), EcsError> {
        let origin = self.resources.origin;
        let (params, c, s, input, geodetic, attitude, packet) = self
            .world
            .query_one_mut::<(
                &PalmerParams,
                &mut PalmerControls,
                &mut PalmerState,
                &mut PalmerInput,
                &mut Geodetic,
                &mut Attitude,
                &mut FgNetFdm,
            )>(entity)
            .map_err(query_error::<PalmerParams>)?;
        let display = palmer_display(params, &controls, &state, &origin);
        (*c, *s) = (controls, state);
        input.drain();
        (*geodetic, *attitude, *packet) = (display.geodetic, display.attitude, display.packet);
        Ok(())
    }

    /// Puts a Bourg aircraft back to `controls` and `state`; see
    /// [`reset_palmer`](Self::reset_palmer).
    ///
    /// # Errors
    /// [`EcsError::NoSuchEntity`], or [`EcsError::MissingComponent`] for a
    /// Palmer aircraft.
    pub fn reset_bourg(
        &mut self,
        entity: Entity,
        controls: BourgControls,
        state: BourgState,
    ) -> Result<(), EcsError> {
        let origin = self.resources.origin;
        let (_, c, s, input, geodetic, attitude, packet) = self
            .world
            .query_one_mut::<(
                &BourgParams,
                &mut BourgControls,
                &mut BourgState,
                &mut BourgInput,
                &mut Geodetic,
                &mut Attitude,
                &mut FgNetFdm,
            )>(entity)
            .map_err(query_error::<BourgParams>)?;
        let display = bourg_display(&controls, &state, &origin);
        (*c, *s) = (controls, state);
        input.drain();
        (*geodetic, *attitude, *packet) = (display.geodetic, display.attitude, display.packet);
        Ok(())
    }

    /// Runs one frame of the schedule (FlightControl → EquationsOfMotion →
    /// MakePacket → SendPacket).
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

    /// A Palmer aircraft's state (`None` for another model or no entity).
    #[must_use]
    pub fn palmer_state(&self, entity: Entity) -> Option<PalmerState> {
        self.get(entity)
    }

    /// A Palmer aircraft's controls.
    #[must_use]
    pub fn palmer_controls(&self, entity: Entity) -> Option<PalmerControls> {
        self.get(entity)
    }

    /// A Bourg aircraft's state.
    #[must_use]
    pub fn bourg_state(&self, entity: Entity) -> Option<BourgState> {
        self.get(entity)
    }

    /// A Bourg aircraft's controls.
    #[must_use]
    pub fn bourg_controls(&self, entity: Entity) -> Option<BourgControls> {
        self.get(entity)
    }

    /// The aircraft's WGS-84 position as of the last MakePacket.
    #[must_use]
    pub fn geodetic(&self, entity: Entity) -> Option<Geodetic> {
        self.get(entity)
    }

    /// The attitude sent to FlightGear as of the last MakePacket (degrees;
    /// roll right wing down +, pitch nose up +, heading clockwise from true
    /// north in `[0, 360)`).
    #[must_use]
    pub fn attitude(&self, entity: Entity) -> Option<Attitude> {
        self.get(entity)
    }

    /// The datagram built by the last MakePacket.
    #[must_use]
    pub fn packet(&self, entity: Entity) -> Option<FgNetFdm> {
        self.get(entity)
    }

    /// Datagrams sent and failed through the entity's FlightGear link (`None`
    /// without a link).
    #[must_use]
    pub fn send_stats(&self, entity: Entity) -> Option<SenderStats> {
        self.world
            .get::<&FlightGearLink>(entity)
            .ok()
            .map(|link| link.stats())
    }

    /// The error of the link's first failed send, once (see
    /// [`FlightGearLink::take_first_failure`]).
    pub fn take_send_failure(&mut self, entity: Entity) -> Option<io::Error> {
        self.world
            .get::<&mut FlightGearLink>(entity)
            .ok()
            .and_then(|mut link| link.take_first_failure())
    }

    /// Removes an aircraft (closing its FlightGear link, if any).
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

    /// The resources, to change the origin, thrust limits or execution mode
    /// between frames.
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
}
