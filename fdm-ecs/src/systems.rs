//! The four systems of the thesis's flight simulators (its figures 11 and 12),
//! as plain functions over the world and the [`Resources`], run every frame
//! in this order by [`Schedule::thesis`](crate::Schedule::thesis):
//!
//! 1. [`flight_control`]: the frame's input actions → controls;
//! 2. [`equations_of_motion`]: one step of each aircraft's model;
//! 3. [`make_packet`]: geodetic position, FlightGear attitude and datagram;
//! 4. [`send_packet`]: the datagram to FlightGear, for linked entities only.
//!
//! Each reads what the one before it wrote, so they cannot overlap; the
//! parallelism is inside EquationsOfMotion and MakePacket, across aircraft.

use fdm_core::bourg::{self, BourgAction, BourgControls, BourgState};
use fdm_core::palmer::{self, PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::ScriptAction;
use fgnet::{DisplayState, EngineState, FgNetFdm};
use hecs::{Query, World};
use nalgebra::{Matrix3, Vector3};
use rayon::iter::{ParallelBridge, ParallelIterator};

use crate::components::{
    BourgInput, BourgParams, FlightGearLink, FrameInput, PalmerInput, PalmerParams, ScriptInput,
};
use crate::geodesy::{
    bourg_attitude, ned_from_model, palmer_attitude, Attitude, Geodetic, GeodeticOrigin,
    METRES_PER_FOOT,
};
use crate::resources::{Execution, Resources};

/// Entities per batch handed to a worker thread by the parallel systems.
pub const PARALLEL_BATCH: u32 = 1024;

/// Knots per metre per second (1 kt = 1852 m / 3600 s, exact).
const KNOTS_PER_MPS: f64 = 3600.0 / 1852.0;

/// Palmer's full flap deflection, degrees: `flaps_norm` 1.
const PALMER_FULL_FLAPS_DEG: f64 = 40.0;

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

/// Applies one frame's input to `controls`: the script's actions for `frame`
/// in file order, then the queued actions in push order (emptying the queue).
fn apply_frame_input<A: ScriptAction, C>(
    mut controls: C,
    script: Option<&ScriptInput<A>>,
    input: Option<&mut FrameInput<A>>,
    frame: u64,
    apply: impl Fn(C, A) -> C,
) -> C {
    if let Some(ScriptInput(script)) = script {
        for action in script.actions_at(frame) {
            controls = apply(controls, action);
        }
    }
    if let Some(input) = input {
        for action in input.drain() {
            controls = apply(controls, action);
        }
    }
    controls
}

/// One Bourg action with the thrust limits of the resources: thrust up/down
/// by [`Resources::delta_thrust_lb`], clamped to
/// `0..=`[`Resources::max_thrust_lb`], in the same `f32` operations as
/// [`BourgControls::apply`] (so with the default resources the result is
/// bit-identical to it); every other action is [`BourgControls::apply`].
#[must_use]
pub fn apply_bourg_action(
    controls: BourgControls,
    action: BourgAction,
    res: &Resources,
) -> BourgControls {
    let mut c = controls;
    match action {
        BourgAction::ThrustUp => {
            c.thrust_lb += res.delta_thrust_lb;
            if c.thrust_lb > res.max_thrust_lb {
                c.thrust_lb = res.max_thrust_lb;
            }
        }
        BourgAction::ThrustDown => {
            c.thrust_lb -= res.delta_thrust_lb;
            if c.thrust_lb < 0.0 {
                c.thrust_lb = 0.0;
            }
        }
        other => c = c.apply(other),
    }
    c
}

/// **FlightControl**: applies each aircraft's input of this frame to its
/// controls (the thesis's FlightControl reading the keyboard, plus the part of
/// its EquationsOfMotion that acts on the keys).
///
/// * Palmer: the controls keep their values; each action is
///   [`PalmerControls::apply`].
/// * Bourg: rudder, ailerons and elevators first return to neutral
///   ([`BourgControls::neutralize_surfaces`]), every frame, input or not;
///   then each action is [`apply_bourg_action`] (thrust steps and limit from
///   the resources).
///
/// Order of the actions: the entity's script rules covering this frame
/// ([`Resources::frame`]) in file order, then its queued [`FrameInput`] in
/// push order.
///
/// | access | what |
/// |---|---|
/// | reads | [`ScriptInput`] (optional), `Resources::{frame, delta_thrust_lb, max_thrust_lb}` |
/// | writes | [`PalmerControls`], [`BourgControls`], [`FrameInput`] (emptied) |
pub fn flight_control(world: &mut World, res: &Resources) {
    let frame = res.frame;
    for (controls, input, script) in world.query_mut::<(
        &mut PalmerControls,
        Option<&mut PalmerInput>,
        Option<&ScriptInput<PalmerAction>>,
    )>() {
        *controls = apply_frame_input(*controls, script, input, frame, PalmerControls::apply);
    }
    for (controls, input, script) in world.query_mut::<(
        &mut BourgControls,
        Option<&mut BourgInput>,
        Option<&ScriptInput<BourgAction>>,
    )>() {
        *controls = apply_frame_input(
            controls.neutralize_surfaces(),
            script,
            input,
            frame,
            |c, a| apply_bourg_action(c, a, res),
        );
    }
}

/// The EquationsOfMotion query of Palmer aircraft.
type PalmerStep<'a> = (&'a PalmerParams, &'a PalmerControls, &'a mut PalmerState);
/// The EquationsOfMotion query of Bourg aircraft.
type BourgStep<'a> = (&'a BourgParams, &'a BourgControls, &'a mut BourgState);

/// **EquationsOfMotion**: advances every aircraft by one time step with its
/// model's pure step function (`fdm_core::palmer::step` with
/// [`Resources::dt_palmer_s`], `fdm_core::bourg::step` with
/// [`Resources::dt_bourg_s`]), sequentially or in parallel according to
/// [`Resources::execution`].
///
/// | access | what |
/// |---|---|
/// | reads | [`PalmerParams`], [`PalmerControls`], [`BourgParams`], [`BourgControls`], `Resources::{fps, execution}` |
/// | writes | [`PalmerState`], [`BourgState`] |
pub fn equations_of_motion(world: &mut World, res: &Resources) {
    match res.execution {
        Execution::Sequential => equations_of_motion_sequential(world, res),
        Execution::Parallel => equations_of_motion_parallel(world, res),
    }
}

/// [`equations_of_motion`] on the calling thread: one hecs query per model.
pub fn equations_of_motion_sequential(world: &mut World, res: &Resources) {
    step_all(world, res, Execution::Sequential);
}

/// [`equations_of_motion`] on rayon's global pool: each model's query is cut
/// into batches of [`PARALLEL_BATCH`] entities (`QueryMut::into_iter_batched`),
/// bridged to rayon with `par_bridge`. Every aircraft's step is a pure function
/// of its own components, so the result is bit-identical to
/// [`equations_of_motion_sequential`] whatever the thread count or order.
///
/// Alternatives measured at 100 000 aircraft on the project's 2-core machine
/// were no faster, within run-to-run noise: rayon's `par_chunks_mut` over the
/// archetypes' component columns (hecs `Archetype::get`), and batches of 256
/// or 4096 entities; so the plain batched query is used (it also serves
/// MakePacket's six-component query unchanged).
pub fn equations_of_motion_parallel(world: &mut World, res: &Resources) {
    step_all(world, res, Execution::Parallel);
}

fn step_all(world: &mut World, res: &Resources, execution: Execution) {
    let dt = res.dt_palmer_s();
    for_each_entity::<PalmerStep<'_>, _>(world, execution, |(params, controls, state)| {
        *state = palmer::step(params, controls, state, dt);
    });
    let dt = res.dt_bourg_s();
    for_each_entity::<BourgStep<'_>, _>(world, execution, |(params, controls, state)| {
        *state = bourg::step(params, controls, state, dt);
    });
}

/// What MakePacket derives from one aircraft: its geodetic position, its
/// attitude as sent to FlightGear, and the datagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Display {
    /// WGS-84 position of the aircraft.
    pub geodetic: Geodetic,
    /// Roll (right wing down +), pitch (nose up +) and heading (clockwise from
    /// true north, `[0, 360)`) relative to the local frame at the aircraft,
    /// degrees, before rounding to the datagram's `f32` radians.
    pub attitude: Attitude,
    /// The FGNetFDM datagram.
    pub packet: FgNetFdm,
}

/// Rotates a model-frame attitude into the local north-east-down frame at
/// the aircraft with `to_local` ([`GeodeticOrigin::model_ned_to_local_ned_at`]): what
/// [`GeodeticOrigin::attitude_at`] computes.
fn local_attitude(to_local: &Matrix3<f64>, attitude: Attitude) -> Attitude {
    Attitude::from_body_to_ned(&(to_local * attitude.body_to_ned()))
}

/// MakePacket for one Palmer aircraft.
///
/// * position: [`GeodeticOrigin::model_to_geodetic`] of `position_m`;
/// * attitude: [`palmer_attitude`] (wind axes, bank, then alpha) made local
///   as [`GeodeticOrigin::attitude_at`] does;
/// * velocities: local NED in ft/s; body `u = V cos α`, `w = V sin α`, no
///   sideslip; airspeed in knots; climb rate `vz` in ft/s;
/// * flaps `degrees / 40`; engine running with the model's propeller speed
///   (`engine_rps · 60` rev/min) while the throttle is above 0.
#[must_use]
pub fn palmer_display(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    state: &PalmerState,
    origin: &GeodeticOrigin,
) -> Display {
    let position_m = state.position_m;
    let geodetic = origin.model_to_geodetic(position_m);
    let to_local = origin.model_ned_to_local_ned_at(&geodetic);
    let attitude = local_attitude(
        &to_local,
        palmer_attitude(state.velocity_mps, controls.alpha_deg, controls.bank_deg),
    );
    let ned_fps = to_local * ned_from_model(state.velocity_mps) / METRES_PER_FOOT;
    let airspeed_mps = state.airspeed_mps();
    let alpha_rad = controls.alpha_deg.to_radians();
    let running = controls.throttle > 0.0;
    let display = DisplayState {
        latitude_deg: geodetic.lat_deg,
        longitude_deg: geodetic.lon_deg,
        altitude_m: geodetic.alt_m,
        roll_deg: attitude.roll_deg,
        pitch_deg: attitude.pitch_deg,
        heading_deg: attitude.heading_deg,
        alpha_deg: controls.alpha_deg,
        beta_deg: 0.0,
        v_north_fps: ned_fps.x,
        v_east_fps: ned_fps.y,
        v_down_fps: ned_fps.z,
        u_body_fps: airspeed_mps * alpha_rad.cos() / METRES_PER_FOOT,
        v_body_fps: 0.0,
        w_body_fps: airspeed_mps * alpha_rad.sin() / METRES_PER_FOOT,
        airspeed_kt: airspeed_mps * KNOTS_PER_MPS,
        climb_rate_fps: state.velocity_mps.z / METRES_PER_FOOT,
        flaps_norm: controls.flaps.degrees() / PALMER_FULL_FLAPS_DEG,
        engine_state: if running {
            EngineState::Running
        } else {
            EngineState::Off
        },
        engine_rpm: if running {
            aircraft.engine_rps * 60.0
        } else {
            0.0
        },
        ..DisplayState::default()
    };
    Display {
        geodetic,
        attitude,
        packet: FgNetFdm::from_display(&display),
    }
}

/// MakePacket for one Bourg aircraft (feet converted to metres with
/// [`METRES_PER_FOOT`]).
///
/// * position: [`GeodeticOrigin::model_to_geodetic`];
/// * attitude: [`bourg_attitude`] of the model's Euler angles made local as
///   [`GeodeticOrigin::attitude_at`] does;
/// * velocities: local NED and body (forward, right, down), ft/s; alpha
///   `atan2(w, u)` and sideslip `asin(v / |v|)` from the body velocity;
///   airspeed `speed` in knots; climb rate `velocity.z`;
/// * flaps 1 when the landing flaps are down; engine running while thrust is
///   above 0 (the model has no engine speed: rpm 0). Control surfaces are
///   not sent.
#[must_use]
pub fn bourg_display(
    controls: &BourgControls,
    state: &BourgState,
    origin: &GeodeticOrigin,
) -> Display {
    let widen = |v: Vector3<f32>| v.map(f64::from);
    let position_m = widen(state.position) * METRES_PER_FOOT;
    let geodetic = origin.model_to_geodetic(position_m);
    let to_local = origin.model_ned_to_local_ned_at(&geodetic);
    let attitude = local_attitude(&to_local, bourg_attitude(state.euler_angles_deg));
    let ned_fps = to_local * ned_from_model(widen(state.velocity));
    // Body frame x forward, y left, z up → forward, right, down.
    let body = ned_from_model(widen(state.velocity_body));
    let body_speed = body.norm();
    let display = DisplayState {
        latitude_deg: geodetic.lat_deg,
        longitude_deg: geodetic.lon_deg,
        altitude_m: geodetic.alt_m,
        roll_deg: attitude.roll_deg,
        pitch_deg: attitude.pitch_deg,
        heading_deg: attitude.heading_deg,
        alpha_deg: body.z.atan2(body.x).to_degrees(),
        beta_deg: if body_speed > 0.0 {
            (body.y / body_speed).asin().to_degrees()
        } else {
            0.0
        },
        v_north_fps: ned_fps.x,
        v_east_fps: ned_fps.y,
        v_down_fps: ned_fps.z,
        u_body_fps: body.x,
        v_body_fps: body.y,
        w_body_fps: body.z,
        airspeed_kt: f64::from(state.speed) * METRES_PER_FOOT * KNOTS_PER_MPS,
        climb_rate_fps: f64::from(state.velocity.z),
        flaps_norm: if controls.landing_flaps { 1.0 } else { 0.0 },
        engine_state: if controls.thrust_lb > 0.0 {
            EngineState::Running
        } else {
            EngineState::Off
        },
        ..DisplayState::default()
    };
    Display {
        geodetic,
        attitude,
        packet: FgNetFdm::from_display(&display),
    }
}

/// The MakePacket query of Palmer aircraft.
type PalmerPacket<'a> = (
    &'a PalmerParams,
    &'a PalmerControls,
    &'a PalmerState,
    &'a mut Geodetic,
    &'a mut Attitude,
    &'a mut FgNetFdm,
);
/// The MakePacket query of Bourg aircraft.
type BourgPacket<'a> = (
    &'a BourgControls,
    &'a BourgState,
    &'a mut Geodetic,
    &'a mut Attitude,
    &'a mut FgNetFdm,
);

/// **MakePacket**: converts each aircraft's new state into its geodetic
/// position, its FlightGear attitude and its FGNetFDM datagram
/// ([`palmer_display`], [`bourg_display`]), sequentially or in parallel
/// according to [`Resources::execution`]. Entities without the three output
/// components are skipped.
///
/// | access | what |
/// |---|---|
/// | reads | [`PalmerParams`], [`PalmerControls`], [`PalmerState`], [`BourgControls`], [`BourgState`], `Resources::{origin, execution}` |
/// | writes | [`Geodetic`], [`Attitude`], [`FgNetFdm`] |
pub fn make_packet(world: &mut World, res: &Resources) {
    let origin = &res.origin;
    for_each_entity::<PalmerPacket<'_>, _>(
        world,
        res.execution,
        |(params, controls, state, geodetic, attitude, packet)| {
            let display = palmer_display(params, controls, state, origin);
            (*geodetic, *attitude, *packet) = (display.geodetic, display.attitude, display.packet);
        },
    );
    for_each_entity::<BourgPacket<'_>, _>(
        world,
        res.execution,
        |(controls, state, geodetic, attitude, packet)| {
            let display = bourg_display(controls, state, origin);
            (*geodetic, *attitude, *packet) = (display.geodetic, display.attitude, display.packet);
        },
    );
}

/// **SendPacket**: sends each linked entity's datagram (one 408-byte UDP
/// datagram per entity per frame) through its [`FlightGearLink`]. Entities
/// without a link send nothing. Failures never stop the simulation; they are
/// counted in the link (see [`FlightGearLink::stats`]).
///
/// | access | what |
/// |---|---|
/// | reads | [`FgNetFdm`] |
/// | writes | [`FlightGearLink`] (its socket and counters) |
pub fn send_packet(world: &mut World, _res: &Resources) {
    for (packet, link) in world.query_mut::<(&FgNetFdm, &mut FlightGearLink)>() {
        link.send(packet);
    }
}
