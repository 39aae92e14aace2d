//! The systems of the thesis's flight simulators (its figures 11 and 12), as
//! plain functions over the world and the [`Resources`], generic over the
//! [`Model`]. [`Schedule::thesis`](crate::Schedule::thesis) runs them every
//! frame in this order, each phase once per model in the world:
//!
//! 1. [`flight_control`]: the frame's input actions → controls;
//! 2. [`equations_of_motion`]: one step of each aircraft's model;
//! 3. [`flight_status`]: on the ground, airborne, landed (how);
//! 4. [`make_packet`]: geodetic position, FlightGear attitude and datagram;
//! 5. [`send_packet`]: the datagram to FlightGear, for linked entities only.
//!
//! Each reads what the one before it wrote, so they cannot overlap; the
//! parallelism is inside EquationsOfMotion and MakePacket, across aircraft.
//! Nothing here names a model: what differs between models is behind
//! [`Model`] (the step, the frame's start, the actions) and behind
//! [`fgnet::bridge`] (the mapping of any model's view to FlightGear).

use fdm_core::model::{advance, settle, FlightStatus, Model};
use fgnet::FgNetFdm;
use hecs::{Query, World};
use rayon::iter::{ParallelBridge, ParallelIterator};

use crate::components::{
    Attitude, FlightGearLink, FrameInput, Geodetic, Params, ScriptInput, ScriptReplay,
};
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

/// The MakePacket query of `M` aircraft.
type PacketQuery<'a, M> = (
    &'a Params<M>,
    &'a <M as Model>::Controls,
    &'a <M as Model>::State,
    &'a mut FlightStatus,
    &'a mut Geodetic,
    &'a mut Attitude,
    &'a mut FgNetFdm,
);

/// **MakePacket** for model `M`: converts each aircraft's new state into its
/// geodetic position, its FlightGear attitude and its FGNetFDM datagram
/// ([`Model::view`], then [`fgnet::bridge::display`]), sequentially or in
/// parallel according to [`Resources::execution`]. Entities without the
/// three output components are skipped, and so are diverged ones
/// ([`FlightStatus::Diverged`]): their last packet stays as it was, built
/// from their last finite state. A finite state whose view, geodetic
/// position or attitude is not finite (e.g. a position far beyond the
/// earth) is marked diverged here and gets no new packet either, so no
/// datagram ever carries a NaN or an infinity.
///
/// | access | what |
/// |---|---|
/// | reads | [`Params<M>`], `M::Controls`, `M::State`, `Resources::{origin, execution}` |
/// | writes | [`Geodetic`], [`Attitude`], [`FgNetFdm`], [`FlightStatus`] (diverged only) |
pub fn make_packet<M: Model>(world: &mut World, res: &Resources) {
    let origin = &res.origin;
    for_each_entity::<PacketQuery<'_, M>, _>(
        world,
        res.execution,
        |(params, controls, state, status, geodetic, attitude, packet)| {
            if *status == FlightStatus::Diverged {
                return;
            }
            let view = M::view(params, controls, state);
            let display = fgnet::bridge::display(&view, origin);
            let (g, a) = (&display.geodetic, &display.attitude);
            let placed = [g.lat_deg, g.lon_deg, g.alt_m]
                .into_iter()
                .chain([a.roll_deg, a.pitch_deg, a.heading_deg])
                .all(f64::is_finite);
            if !(placed && view.is_finite()) {
                // A finite state too far out to be shown (e.g. a position
                // of 1e300 m): diverged as well; the old packet stays.
                *status = FlightStatus::Diverged;
                return;
            }
            (*geodetic, *attitude, *packet) = (display.geodetic, display.attitude, display.packet);
        },
    );
}

/// **SendPacket**: sends each linked entity's datagram (one 408-byte UDP
/// datagram per entity per frame) through its [`FlightGearLink`], whatever
/// its model. Entities without a link send nothing, and diverged ones
/// ([`FlightStatus::Diverged`]) send nothing more. Failures never stop the
/// simulation; they are counted in the link (see [`FlightGearLink::stats`]).
///
/// | access | what |
/// |---|---|
/// | reads | [`FgNetFdm`], [`FlightStatus`] |
/// | writes | [`FlightGearLink`] (its socket and counters) |
pub fn send_packet(world: &mut World, _res: &Resources) {
    for (packet, status, link) in
        world.query_mut::<(&FgNetFdm, &FlightStatus, &mut FlightGearLink)>()
    {
        if *status != FlightStatus::Diverged {
            link.send(packet);
        }
    }
}
