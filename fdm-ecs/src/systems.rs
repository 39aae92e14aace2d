//! The systems of the thesis's flight simulators (its figures 11 and 12), as
//! plain functions over the world and the [`Resources`], generic over the
//! [`Model`]. The [`Schedule`](crate::Schedule) runs them every
//! frame in this order, each phase once per model in the world:
//!
//! 1. [`flight_control`]: the frame's input actions → controls;
//! 2. [`equations_of_motion`]: one step of each aircraft's model;
//! 3. [`flight_status`]: on the ground, airborne, landed (how);
//! 4. [`place`]: the aircraft's placement on WGS-84 (geodetic position and
//!    attitude relative to the local north-east-down frame), read by every
//!    output.
//!
//! Each reads what the one before it wrote, so they cannot overlap; the
//! parallelism is inside EquationsOfMotion and Place, across aircraft.
//! Nothing here names a model (what differs between models is behind
//! [`Model`]: the step, the frame's start, the actions, the view) nor a
//! wire format: the thesis's MakePacket and SendPacket are the FlightGear
//! output of the run library (`fdm_run::flightgear`), which builds the
//! datagram from the placement computed here.

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{advance, settle, FlightStatus, FlightView, Model};
use hecs::{Query, World};
use rayon::iter::{ParallelBridge, ParallelIterator};

use crate::components::{Attitude, FrameInput, Geodetic, Params, ScriptInput, ScriptReplay};
use crate::resources::{Execution, Resources};

/// Entities per batch handed to a worker thread by the parallel systems.
pub const PARALLEL_BATCH: u32 = 1024;

/// Runs `f` on every entity matching `Q`, on this thread or on rayon's pool in
/// batches of [`PARALLEL_BATCH`]. `f` sees each entity once; the order of
/// visits differs between the modes, so `f` must only touch its own entity.
fn for_each_entity<Q, F>(world: &mut World, execution: Execution, f: F)
where
    Q: Query,
    for<'a> Q::Item<'a>: Send,
    F: for<'a> Fn(Q::Item<'a>) + Send + Sync,
{
    let query = world.query_mut::<Q>();
    match execution {
        Execution::Sequential => query.into_iter().for_each(f),
        Execution::Parallel => query
            .into_iter_batched(PARALLEL_BATCH)
            .par_bridge()
            .for_each(|batch| batch.for_each(&f)),
    }
}

/// One frame's input applied to `controls` of an `M` aircraft:
/// [`Model::begin_frame`], then the script's actions for `frame` in file
/// order (swept by `replay` when given, else looked up), then the queued
/// actions in push order (emptying the queue).
#[must_use]
pub fn apply_frame_input<M: Model>(
    aircraft: &M::Aircraft,
    controls: M::Controls,
    script: Option<(&ScriptInput<M::Action>, Option<&mut ScriptReplay>)>,
    input: Option<&mut FrameInput<M::Action>>,
    frame: u64,
) -> M::Controls {
    let mut controls = M::begin_frame(controls);
    match script {
        Some((ScriptInput(script), Some(ScriptReplay(cursor)))) => {
            for action in cursor.actions(script, frame) {
                controls = M::apply(aircraft, controls, action);
            }
        }
        Some((ScriptInput(script), None)) => {
            for action in script.actions_at(frame) {
                controls = M::apply(aircraft, controls, action);
            }
        }
        None => {}
    }
    if let Some(input) = input {
        for action in input.drain() {
            controls = M::apply(aircraft, controls, action);
        }
    }
    controls
}

/// The FlightControl query of `M` aircraft.
type ControlQuery<'a, M> = (
    &'a Params<M>,
    &'a mut <M as Model>::Controls,
    Option<&'a mut FrameInput<<M as Model>::Action>>,
    Option<&'a ScriptInput<<M as Model>::Action>>,
    Option<&'a mut ScriptReplay>,
);

/// **FlightControl** for model `M`: applies each aircraft's input of this
/// frame to its controls (the thesis's FlightControl reading the keyboard,
/// plus the part of its EquationsOfMotion that acts on the keys), with
/// [`apply_frame_input`]: [`Model::begin_frame`] every frame, input or not
/// (Bourg's rudder, ailerons and elevators return to neutral), then the
/// script rules covering this frame ([`Resources::frame`]) in file order,
/// then the queued [`FrameInput`] in push order, each with [`Model::apply`]
/// (Bourg's thrust limits are its aircraft's).
///
/// | access | what |
/// |---|---|
/// | reads | [`Params<M>`], [`ScriptInput`] (optional), `Resources::frame` |
/// | writes | `M::Controls`, [`FrameInput`] (emptied), [`ScriptReplay`] (its cursor) |
pub fn flight_control<M: Model>(world: &mut World, res: &Resources) {
    let frame = res.frame;
    for (params, controls, input, script, replay) in world.query_mut::<ControlQuery<'_, M>>() {
        let script = script.map(|script| (script, replay));
        *controls = apply_frame_input::<M>(params, *controls, script, input, frame);
    }
}

/// The EquationsOfMotion query of `M` aircraft.
type StepQuery<'a, M> = (
    &'a Params<M>,
    &'a <M as Model>::Controls,
    &'a mut <M as Model>::State,
    &'a mut FlightStatus,
);

/// **EquationsOfMotion** for model `M`: advances every aircraft by one time
/// step with [`Model::step`] at [`Resources::time_step`] (through
/// [`fdm_core::model::advance`]: a crashed aircraft stays at rest, a diverged
/// one is no longer stepped, and a step whose result is not finite is not
/// kept: the state stays the last finite one and the status becomes
/// [`FlightStatus::Diverged`]), sequentially or in parallel according to
/// [`Resources::execution`].
///
/// | access | what |
/// |---|---|
/// | reads | [`Params<M>`], `M::Controls`, `Resources::{fps, execution}` |
/// | writes | `M::State`, [`FlightStatus`] (diverged only) |
pub fn equations_of_motion<M: Model>(world: &mut World, res: &Resources) {
    step_all::<M>(world, res, res.execution);
}

/// [`equations_of_motion`] on the calling thread.
pub fn equations_of_motion_sequential<M: Model>(world: &mut World, res: &Resources) {
    step_all::<M>(world, res, Execution::Sequential);
}

/// [`equations_of_motion`] on rayon's global pool: the query is cut into
/// batches of [`PARALLEL_BATCH`] entities (`QueryMut::into_iter_batched`),
/// bridged to rayon with `par_bridge`. Every aircraft's step is a pure
/// function of its own components, so the result is bit-identical to
/// [`equations_of_motion_sequential`] whatever the thread count or order.
///
/// Alternatives measured at 100 000 aircraft on the project's 2-core machine
/// were no faster, within run-to-run noise: rayon's `par_chunks_mut` over the
/// archetypes' component columns (hecs `Archetype::get`), and batches of 256
/// or 4096 entities; so the plain batched query is used.
pub fn equations_of_motion_parallel<M: Model>(world: &mut World, res: &Resources) {
    step_all::<M>(world, res, Execution::Parallel);
}

fn step_all<M: Model>(world: &mut World, res: &Resources, execution: Execution) {
    let dt = res.time_step::<M>();
    for_each_entity::<StepQuery<'_, M>, _>(
        world,
        execution,
        |(params, controls, state, status)| {
            (*state, *status) = advance::<M>(params, controls, *status, state, dt);
        },
    );
}

/// **FlightStatus** for model `M`: each aircraft's [`FlightStatus`] after the
/// step, from [`Model::height_m`] and [`Model::climb_rate_mps`] (takeoff,
/// touchdown and its classification; the landing tracking of the book's GUI
/// versions, for every model), and the ground's reaction
/// ([`Model::ground_contact`]) to a step that ended at or below the ground
/// plane, both through [`fdm_core::model::settle`].
///
/// | access | what |
/// |---|---|
/// | reads | [`Params<M>`] |
/// | writes | `M::State` (at or below the ground plane only), [`FlightStatus`] |
pub fn flight_status<M: Model>(world: &mut World, _res: &Resources) {
    for (params, state, status) in
        world.query_mut::<(&Params<M>, &mut M::State, &mut FlightStatus)>()
    {
        (*state, *status) = settle::<M>(params, *status, state);
    }
}

/// `view` placed on WGS-84 with its model frame at `origin`: the geodetic
/// position of `position_m` ([`GeodeticOrigin::model_to_geodetic`]) and the
/// view's attitude made local (true north and the local horizontal at the
/// aircraft), as [`GeodeticOrigin::attitude_at`] computes it but from the
/// position already converted (one conversion instead of two). These are the
/// numbers the FlightGear datagram, the DIS PDUs and the ACMI tracks carry
/// (`fgnet::bridge::display` computes them the same way, bit for bit).
#[must_use]
pub fn placement(view: &FlightView, origin: &GeodeticOrigin) -> (Geodetic, Attitude) {
    let geodetic = origin.model_to_geodetic(view.position_m);
    let to_local = origin.model_ned_to_local_ned_at(&geodetic);
    let attitude = Attitude::from_body_to_ned(&(to_local * view.attitude.body_to_ned()));
    (geodetic, attitude)
}

/// [`placement`] of `view` when it can be shown: `None` unless the view and
/// every number of the placement are finite (the rule of [`place`], which
/// marks such an aircraft diverged and keeps its last placement).
#[must_use]
pub fn finite_placement(
    view: &FlightView,
    origin: &GeodeticOrigin,
) -> Option<(Geodetic, Attitude)> {
    let (g, a) = placement(view, origin);
    let placed = [g.lat_deg, g.lon_deg, g.alt_m]
        .into_iter()
        .chain([a.roll_deg, a.pitch_deg, a.heading_deg])
        .all(f64::is_finite);
    (placed && view.is_finite()).then_some((g, a))
}

/// The Place query of `M` aircraft.
type PlaceQuery<'a, M> = (
    &'a Params<M>,
    &'a <M as Model>::Controls,
    &'a <M as Model>::State,
    &'a mut FlightStatus,
    &'a mut Geodetic,
    &'a mut Attitude,
);

/// **Place** for model `M` (the placement half of the thesis's MakePacket):
/// converts each aircraft's new state into its geodetic position and its
/// attitude relative to the local north-east-down frame ([`Model::view`],
/// then [`placement`]), sequentially or in parallel according to
/// [`Resources::execution`]. Entities without the two placement components
/// are skipped, and so are diverged ones ([`FlightStatus::Diverged`]): their
/// last placement stays as it was, made from their last finite state. A
/// finite state whose view, geodetic position or attitude is not finite
/// (e.g. a position far beyond the earth) is marked diverged here and keeps
/// its old placement too, so no output is ever handed a NaN or an infinity
/// for an aircraft still flying.
///
/// | access | what |
/// |---|---|
/// | reads | [`Params<M>`], `M::Controls`, `M::State`, `Resources::{origin, execution}` |
/// | writes | [`Geodetic`], [`Attitude`], [`FlightStatus`] (diverged only) |
pub fn place<M: Model>(world: &mut World, res: &Resources) {
    let origin = &res.origin;
    for_each_entity::<PlaceQuery<'_, M>, _>(
        world,
        res.execution,
        |(params, controls, state, status, geodetic, attitude)| {
            if *status == FlightStatus::Diverged {
                return;
            }
            let view = M::view(params, controls, state);
            let Some(placed) = finite_placement(&view, origin) else {
                // A finite state too far out to be shown (e.g. a position
                // of 1.7e308 m): diverged as well; the old placement stays.
                *status = FlightStatus::Diverged;
                return;
            };
            (*geodetic, *attitude) = placed;
        },
    );
}
