//! Each model's lane step ([`LaneModel::step_lanes`] with [`Exact`] maths,
//! what a fleet flies) against its scalar step ([`Model::step`]), lane by
//! lane, bit for bit: the contract `LaneModel` documents ("bit-identical to
//! `Model::step` lane by lane with `Exact`"). Both come from one source
//! (`palmer/dynamics.rs`'s `rk4`, `bourg/generic.rs`'s `step`), so what this
//! checks is the lanes' own part: moving each aircraft's state and control
//! terms into its lane and out again (`set_state`, `set_controls`, `state`,
//! `idle`), the blends of the scalar `if`s when neighbouring lanes take
//! different branches (on the ground and in the air, brakes on and off, low
//! and high, stalled and not), and Bourg's table look-ups in lanes.
//!
//! Every lane holds a different aircraft, so a lane that read its
//! neighbour's terms, or a block that ignored the terms set for it, gives
//! other numbers. No tolerance: the same operations on the same numbers.
//! The clock is the fleet's, not the step's, so it is not compared.

use fdm_core::bourg::{
    ops::quat_from_euler_deg, Bourg, BourgControls, BourgState, Flap, Vector3 as V3f,
};
use fdm_core::model::Model;
use fdm_core::palmer::{Flaps, Palmer, PalmerControls, PalmerState};
use fdm_core::real::{Exact, LaneModel};
use nalgebra::Vector3;

/// `members` (at most a block's worth) flown `steps` steps of `dt` in one
/// block of lanes, starting from [`LaneModel::idle`]; with `set_controls`
/// false the lanes keep `idle`'s control terms. Returns every lane's state
/// after each step (clock 0).
fn fly_lanes<M: LaneModel>(
    aircraft: &M::Aircraft,
    members: &[(M::Controls, M::State)],
    set_controls: bool,
    dt: M::TimeStep,
    steps: usize,
) -> Vec<Vec<M::State>> {
    let shared = M::shared(aircraft);
    let (mut vars, mut terms) = M::idle(aircraft);
    for (lane, (controls, state)) in members.iter().enumerate() {
        M::set_state(&mut vars, lane, state);
        if set_controls {
            M::set_controls(&mut terms, lane, aircraft, &shared, controls);
        }
    }
    (0..steps)
        .map(|_| {
            vars = M::step_lanes::<Exact>(aircraft, &shared, &terms, &vars, dt);
            (0..members.len())
                .map(|lane| M::state(&vars, 0.0, lane))
                .collect()
        })
        .collect()
}

/// The same members flown one by one with the scalar step.
fn fly_scalar<M: Model>(
    aircraft: &M::Aircraft,
    members: &[(M::Controls, M::State)],
    dt: M::TimeStep,
    steps: usize,
) -> Vec<Vec<M::State>> {
    let mut states: Vec<M::State> = members.iter().map(|(_, s)| *s).collect();
    (0..steps)
        .map(|_| {
            for (state, (controls, _)) in states.iter_mut().zip(members) {
                *state = M::step(aircraft, controls, state, dt);
            }
            states.clone()
        })
        .collect()
}

/// Palmer's state without its clock, as bits (`-0.0` and `0.0` differ).
fn palmer_bits(s: &PalmerState) -> [u64; 6] {
    let (p, v) = (&s.position_m, &s.velocity_mps);
    [p.x, p.y, p.z, v.x, v.y, v.z].map(f64::to_bits)
}

/// Bourg's state without its clock, as bits, and the stall flag.
fn bourg_bits(s: &BourgState) -> ([u32; 16], bool) {
    let (p, v, b, w) = (
        &s.position_ft,
        &s.velocity_ftps,
        &s.velocity_body_ftps,
        &s.angular_velocity_radps,
    );
    let q = &s.orientation.coords;
    let numbers = [
        p.x, p.y, p.z, v.x, v.y, v.z, b.x, b.y, b.z, w.x, w.y, w.z, q.w, q.x, q.y, q.z,
    ];
    (numbers.map(f32::to_bits), s.stalling)
}

fn palmer_state(position_m: [f64; 3], velocity_mps: [f64; 3]) -> PalmerState {
    PalmerState {
        time_s: 0.0,
        position_m: Vector3::from(position_m),
        velocity_mps: Vector3::from(velocity_mps),
    }
}

fn palmer_controls(throttle: f64, alpha_deg: f64, bank_deg: f64, flaps: Flaps) -> PalmerControls {
    PalmerControls {
        throttle,
        alpha_deg,
        bank_deg,
        flaps,
        brakes: false,
    }
}

/// Eight Palmer aircraft, one per lane, each in another branch of the
/// right-hand side (docs/palmer-model.md steps 7, 10 and 12, and the wheel
/// brakes).
fn palmer_members() -> Vec<(PalmerControls, PalmerState)> {
    let braked = |c: PalmerControls| PalmerControls { brakes: true, ..c };
    vec![
        // The take-off roll from rest (the reference scenarios' start).
        (
            palmer_controls(1.0, 0.0, 0.0, Flaps::Up),
            PalmerState::at_rest(),
        ),
        // Held at rest by the brakes against full throttle.
        (
            braked(palmer_controls(1.0, 0.0, 0.0, Flaps::Up)),
            PalmerState::at_rest(),
        ),
        // Braking a roll at 20 m/s, flaps 40.
        (
            braked(palmer_controls(0.2, 2.0, 0.0, Flaps::Deg40)),
            palmer_state([100.0, 3.0, 0.0], [20.0, 1.0, 0.0]),
        ),
        // In ground effect (below 5 m), climbing out.
        (
            palmer_controls(0.7, 8.0, 3.0, Flaps::Deg20),
            palmer_state([300.0, 0.0, 2.0], [40.0, 0.0, 1.0]),
        ),
        // Climbing turn, flaps 20.
        (
            palmer_controls(1.0, 4.0, 15.0, Flaps::Deg20),
            palmer_state([500.0, -20.0, 500.0], [45.0, -3.0, 2.0]),
        ),
        // Past the stall (alpha 18 > 16), banked left, descending.
        (
            palmer_controls(0.5, 18.0, -20.0, Flaps::Up),
            palmer_state([0.0, 0.0, 1200.0], [30.0, 5.0, -4.0]),
        ),
        // Sinking through the ground plane, brakes set (no ground reaction
        // while sinking fast enough that lift and weight push down).
        (
            braked(palmer_controls(0.0, -5.0, 0.0, Flaps::Up)),
            palmer_state([50.0, 0.0, -0.5], [30.0, 0.0, -3.0]),
        ),
        // Straight up: no horizontal speed (step 10's `vh == 0`).
        (
            palmer_controls(0.3, 0.0, 10.0, Flaps::Up),
            palmer_state([0.0, 0.0, 100.0], [0.0, 0.0, 10.0]),
        ),
    ]
}

fn assert_palmer_lanes_match(lanes: &[Vec<PalmerState>], scalar: &[Vec<PalmerState>], what: &str) {
    for (n, (l, s)) in lanes.iter().zip(scalar).enumerate() {
        for (lane, (a, b)) in l.iter().zip(s).enumerate() {
            assert_eq!(
                palmer_bits(a),
                palmer_bits(b),
                "{what}: lane {lane} after step {}: lanes {a:?}, scalar {b:?}",
                n + 1
            );
        }
    }
}

#[test]
fn palmers_lanes_step_each_aircraft_as_the_scalar_step_does() {
    let aircraft = Palmer::default_aircraft();
    let members = palmer_members();
    assert_eq!(members.len(), fdm_core::palmer::LANES);
    // 30 steps of 0.1 s: the braked roll stops, the sinking one keeps
    // sinking (the bare step has no ground contact), the others fly on.
    let lanes = fly_lanes::<Palmer>(&aircraft, &members, true, 0.1, 30);
    let scalar = fly_scalar::<Palmer>(&aircraft, &members, 0.1, 30);
    assert_palmer_lanes_match(&lanes, &scalar, "palmer");
    // The lanes really differ (a block stepping one lane's aircraft in
    // every lane would not).
    let last = &scalar[29];
    for i in 0..last.len() {
        for j in 0..i {
            assert_ne!(palmer_bits(&last[i]), palmer_bits(&last[j]), "{i} {j}");
        }
    }
}

#[test]
fn palmers_idle_lanes_fly_with_the_initial_controls() {
    // `idle`: every lane's terms are those of `Model::initial_controls`
    // (throttle 0, alpha 0, bank 0, flaps up): set only the states.
    let aircraft = Palmer::default_aircraft();
    let members: Vec<_> = palmer_members()
        .into_iter()
        .map(|(_, state)| (Palmer::initial_controls(), state))
        .collect();
    let lanes = fly_lanes::<Palmer>(&aircraft, &members, false, 0.1, 10);
    let scalar = fly_scalar::<Palmer>(&aircraft, &members, 0.1, 10);
    assert_palmer_lanes_match(&lanes, &scalar, "palmer idle");
}

/// Sixteen Bourg aircraft, one per lane: the demonstration fleet's members
/// with every control surface and the pitch trim set in some lanes, rotated
/// and turning states, a slow one (local speeds at or below 1 ft/s: the drag
/// direction carried), and the original's first frame (no body velocity).
fn bourg_members() -> Vec<(BourgControls, BourgState)> {
    let flaps = [Flap::Neutral, Flap::TrailingEdgeDown, Flap::TrailingEdgeUp];
    (0..16)
        .map(|i| {
            let (mut c, mut s) = Bourg::fleet_member(i);
            c.port_aileron = flaps[i % 3];
            c.starboard_aileron = flaps[(i + 1) % 3];
            // Elevators neutral in lanes 0, 3, 6, ...: there the pitch trim
            // blends them (trim set in half of those).
            c.elevators = flaps[(i / 2) % 3];
            c.pitch_trim = [0.0, 0.5, -0.75, 1.0][i % 4];
            c.rudder_deg = [0.0, 16.0, -16.0][i % 3];
            let euler = V3f::new(
                [0.0, 30.0, -60.0][i % 3],
                [0.0, -10.0, 20.0, 85.0][i % 4],
                [0.0, 45.0, 170.0, -90.0, 10.0][i % 5],
            );
            s.orientation = quat_from_euler_deg(&euler);
            #[allow(clippy::cast_precision_loss)] // i < 16
            let spin = i as f32 * 0.05;
            s.angular_velocity_radps = V3f::new(spin, -0.5 * spin, 0.25 * spin);
            match i {
                // The original's first frame: no body velocity yet.
                14 => s = BourgState::initial(),
                // Slow: every element's local speed at or below 1 ft/s.
                15 => {
                    s.velocity_ftps = V3f::new(0.5, 0.0, -0.2);
                    s.velocity_body_ftps = V3f::new(0.5, 0.0, -0.2);
                    s.angular_velocity_radps = V3f::new(0.0, 0.0, 0.0);
                }
                _ => {}
            }
            (c, s)
        })
        .collect()
}

fn assert_bourg_lanes_match(lanes: &[Vec<BourgState>], scalar: &[Vec<BourgState>], what: &str) {
    for (n, (l, s)) in lanes.iter().zip(scalar).enumerate() {
        for (lane, (a, b)) in l.iter().zip(s).enumerate() {
            assert_eq!(
                bourg_bits(a),
                bourg_bits(b),
                "{what}: lane {lane} after step {}: lanes {a:?}, scalar {b:?}",
                n + 1
            );
        }
    }
}

#[test]
fn bourgs_lanes_step_each_aircraft_as_the_scalar_step_does() {
    let aircraft = Bourg::default_aircraft();
    let members = bourg_members();
    assert_eq!(members.len(), fdm_core::bourg::LANES);
    let dt = Bourg::time_step(30.0);
    // 60 steps: two seconds of tumbling through every table interval some
    // lane reaches.
    let lanes = fly_lanes::<Bourg>(&aircraft, &members, true, dt, 60);
    let scalar = fly_scalar::<Bourg>(&aircraft, &members, dt, 60);
    assert_bourg_lanes_match(&lanes, &scalar, "bourg");
    // Some lanes stall and some do not, on the same step, so the stall flag
    // is a per-lane blend here.
    assert!(
        scalar
            .iter()
            .any(|step| step.iter().any(|s| s.stalling) && step.iter().any(|s| !s.stalling)),
        "no step with stalled and unstalled lanes together"
    );
    let last = &scalar[59];
    for i in 0..last.len() {
        for j in 0..i {
            assert_ne!(bourg_bits(&last[i]), bourg_bits(&last[j]), "{i} {j}");
        }
    }
}

#[test]
fn bourgs_idle_lanes_fly_with_the_initial_controls() {
    // `idle`: every lane's terms are those of `Model::initial_controls`
    // (thrust 500 lb, surfaces neutral, no trim): set only the states.
    let aircraft = Bourg::default_aircraft();
    let members: Vec<_> = bourg_members()
        .into_iter()
        .map(|(_, state)| (Bourg::initial_controls(), state))
        .collect();
    let dt = Bourg::time_step(30.0);
    let lanes = fly_lanes::<Bourg>(&aircraft, &members, false, dt, 10);
    let scalar = fly_scalar::<Bourg>(&aircraft, &members, dt, 10);
    assert_bourg_lanes_match(&lanes, &scalar, "bourg idle");
}

#[test]
fn a_palmer_fleet_refuses_the_aircraft_the_scalar_checks_refuse() {
    // `LaneModel::check_aircraft`: why the aircraft cannot be flown, the
    // same answer as `PalmerAircraft::validate` (what `try_step` checks).
    let good = Palmer::default_aircraft();
    assert_eq!(<Palmer as LaneModel>::check_aircraft(&good), Ok(()));
    let mut heavy = good;
    heavy.mass_kg = -1.0;
    let err = <Palmer as LaneModel>::check_aircraft(&heavy).unwrap_err();
    assert_eq!(Err(err), heavy.validate());
    let mut no_wing = good;
    no_wing.wing_area_m2 = f64::NAN;
    assert!(<Palmer as LaneModel>::check_aircraft(&no_wing).is_err());
}

#[test]
fn every_component_of_a_block_reaches_the_finiteness_check() {
    // `LaneModel::for_each_component` hands every lane vector of the state
    // to the fleet's finiteness check: a NaN in any one of Palmer's six
    // numbers, in any lane, must reach it.
    let aircraft = Palmer::default_aircraft();
    let (vars, _) = <Palmer as LaneModel>::idle(&aircraft);
    let mut count = 0;
    <Palmer as LaneModel>::for_each_component(&vars, |_| count += 1);
    assert_eq!(count, 6);
    for component in 0..6 {
        // `[vx, x, vy, y, vz, z]`, the model's order.
        let mut q = [40.0, 10.0, 1.0, 20.0, 2.0, 30.0];
        q[component] = f64::NAN;
        let state = palmer_state([q[1], q[3], q[5]], [q[0], q[2], q[4]]);
        let mut vars = vars;
        <Palmer as LaneModel>::set_state(&mut vars, 5, &state);
        let mut nan_lanes = Vec::new();
        <Palmer as LaneModel>::for_each_component(&vars, |v| {
            nan_lanes.extend((0..fdm_core::palmer::LANES).filter(|&l| v.0[l].is_nan()));
        });
        assert_eq!(nan_lanes, [5], "component {component}");
    }
}

#[test]
fn one_aircrafts_terms_splat_into_one_lane_are_themselves() {
    // `splat` ("every lane `t`") and `set_lane` with the scalar number type,
    // one lane: the terms themselves. Bourg's with every surface and the trim
    // set (the tables are a hook of the number type: `Flap` for `f32`).
    use fdm_core::bourg::BourgTerms;
    use fdm_core::palmer::{AircraftTerms, ControlTerms};
    let aircraft = Bourg::default_aircraft();
    for (controls, _) in bourg_members() {
        let t = BourgTerms::new(&aircraft, &controls);
        assert_eq!(BourgTerms::<f32>::splat(&t), t, "{controls:?}");
        let mut other = BourgTerms::new(&aircraft, &Bourg::initial_controls());
        other.set_lane(0, &t);
        assert_eq!(other, t, "{controls:?}");
    }
    let palmer = Palmer::default_aircraft();
    let at = AircraftTerms::new(&palmer);
    for (controls, _) in palmer_members() {
        let t = ControlTerms::new(&palmer, &at, &controls);
        assert_eq!(ControlTerms::<f64>::splat(&t), t, "{controls:?}");
        let mut other = ControlTerms::new(&palmer, &at, &PalmerControls::default());
        other.set_lane(0, &t);
        assert_eq!(other, t, "{controls:?}");
    }
}

#[test]
fn bourgs_lane_moves_keep_the_clock_the_position_and_the_height_sign() {
    // `LaneModel` (fdm_core::real) for Bourg, method by method as the trait
    // documents it: `set_state` "returns its clock"; `state` gives the lane
    // "with its clock `time_s`"; `above_ground` is "height `> 0` ... false
    // for NaN" in the model's own unit (feet); `position_m` is "the
    // `position_m` of `Model::view`, bit for bit". No tolerance: these move
    // numbers, they do not compute with them (`position_m` is the same
    // widening and product as the view's).
    let aircraft = Bourg::default_aircraft();
    let controls = Bourg::initial_controls();
    let (mut vars, _) = <Bourg as LaneModel>::idle(&aircraft);
    let heights = [
        2000.0,
        1.0e-30,
        0.0,
        -0.0,
        -1.0e-30,
        -3.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.5,
        12_345.678,
        -12_345.678,
        f32::MIN_POSITIVE,
        -f32::MIN_POSITIVE,
        7.0,
        1.0e30,
    ];
    let members = bourg_members();
    for (lane, &z) in heights.iter().enumerate() {
        let mut s = members[lane].1;
        #[allow(clippy::cast_precision_loss)] // lane < 16
        let (x, clock) = (-5000.0 + 37.5 * lane as f32, 1.5 + lane as f64 * 0.25);
        s.position_ft = V3f::new(x, 0.125, z);
        s.time_s = clock;
        assert_eq!(
            <Bourg as LaneModel>::set_state(&mut vars, lane, &s).to_bits(),
            clock.to_bits(),
            "set_state's clock, lane {lane}"
        );
        let back = <Bourg as LaneModel>::state(&vars, 42.0, lane);
        assert_eq!(back.time_s.to_bits(), 42.0_f64.to_bits(), "lane {lane}");
        assert_eq!(bourg_bits(&back), bourg_bits(&s), "lane {lane}");
        let view = Bourg::view(&aircraft, &controls, &s);
        let p = <Bourg as LaneModel>::position_m(&s);
        for k in 0..3 {
            assert_eq!(
                p[k].to_bits(),
                view.position_m[k].to_bits(),
                "position_m[{k}], lane {lane}"
            );
        }
    }
    let above = <Bourg as LaneModel>::above_ground(&vars);
    for (lane, &z) in heights.iter().enumerate() {
        assert_eq!(above.0[lane], z > 0.0, "above_ground, lane {lane}, z {z}");
    }
}

#[test]
fn every_component_of_a_bourg_block_reaches_the_finiteness_check() {
    // `LaneModel::for_each_component` for Bourg: each of the sixteen numbers
    // of a lane's state (position, velocity, body velocity, angular velocity,
    // orientation) made NaN alone, in one lane, reaches the fleet's
    // finiteness check in that lane only.
    let aircraft = Bourg::default_aircraft();
    let (vars, _) = <Bourg as LaneModel>::idle(&aircraft);
    let mut count = 0;
    <Bourg as LaneModel>::for_each_component(&vars, |_| count += 1);
    assert_eq!(count, 16);
    for component in 0..16 {
        let mut s = BourgState::initial();
        let mut n = [
            -5000.0, 0.0, 2000.0, 60.0, 0.0, 0.0, 60.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        ];
        n[component] = f32::NAN;
        s.position_ft = V3f::new(n[0], n[1], n[2]);
        s.velocity_ftps = V3f::new(n[3], n[4], n[5]);
        s.velocity_body_ftps = V3f::new(n[6], n[7], n[8]);
        s.angular_velocity_radps = V3f::new(n[9], n[10], n[11]);
        s.orientation = fdm_core::bourg::Quaternion::new(n[12], n[13], n[14], n[15]);
        let mut vars = vars;
        <Bourg as LaneModel>::set_state(&mut vars, 9, &s);
        let mut nan_lanes = Vec::new();
        <Bourg as LaneModel>::for_each_component(&vars, |v| {
            nan_lanes.extend((0..fdm_core::bourg::LANES).filter(|&l| v.0[l].is_nan()));
        });
        assert_eq!(nan_lanes, [9], "component {component}");
    }
}

#[test]
fn bourg_terms_splat_into_every_lane_fly_as_the_scalar_step() {
    // `BourgTerms::splat`: "Every lane `t`" — with the lanes' number type, a
    // block whose terms are one aircraft's controls splat into all sixteen
    // lanes flies every lane with those controls (the airfoil tables of the
    // ailerons, landing flaps and elevators, the rudder, and the pitch
    // trim's tables and blend), bit for bit as the scalar step, whatever the
    // lane's state.
    use fdm_core::bourg::{BourgLanes, BourgTerms};
    let aircraft = Bourg::default_aircraft();
    let members = bourg_members();
    let dt = Bourg::time_step(30.0);
    for (controls, _) in &members {
        let terms = BourgTerms::<BourgLanes>::splat(&BourgTerms::new(&aircraft, controls));
        let (mut vars, _) = <Bourg as LaneModel>::idle(&aircraft);
        for (lane, (_, state)) in members.iter().enumerate() {
            <Bourg as LaneModel>::set_state(&mut vars, lane, state);
        }
        let mut scalar: Vec<BourgState> = members.iter().map(|(_, s)| *s).collect();
        for n in 1..=20 {
            vars = <Bourg as LaneModel>::step_lanes::<Exact>(&aircraft, &(), &terms, &vars, dt);
            for (lane, s) in scalar.iter_mut().enumerate() {
                *s = Bourg::step(&aircraft, controls, s, dt);
                let l = <Bourg as LaneModel>::state(&vars, 0.0, lane);
                assert_eq!(
                    bourg_bits(&l),
                    bourg_bits(s),
                    "{controls:?}: lane {lane} after step {n}"
                );
            }
        }
    }
}

/// `LaneModel::set_controls_lanes`'s contract, for a model of each width:
/// the terms of `controls[lane]` in each of the first `count` lanes, as
/// `set_controls` writes them one by one (Bourg keeps the trait's provided
/// body; Palmer computes the lanes together), and the other lanes'
/// untouched. Shown by flying both blocks from the same states.
fn check_set_controls_lanes<M: LaneModel, B: PartialEq + std::fmt::Debug>(
    members: &[(M::Controls, M::State)],
    bits: fn(&M::State) -> B,
) {
    use fdm_core::real::{Lanes, Real};
    let aircraft = M::default_aircraft();
    let shared = M::shared(&aircraft);
    let dt = M::time_step(30.0);
    let width = <M::Lanes as Real>::LANES;
    assert_eq!(members.len(), width);
    let controls = <M::Lanes as Lanes>::array(|lane| members[lane].0);
    for count in [width, width / 2 + 1, 1, 0] {
        let (mut vars, mut together) = M::idle(&aircraft);
        let mut one_by_one = together;
        M::set_controls_lanes(&mut together, count, &aircraft, &shared, &controls);
        for (lane, (c, s)) in members.iter().enumerate() {
            M::set_state(&mut vars, lane, s);
            if lane < count {
                M::set_controls(&mut one_by_one, lane, &aircraft, &shared, c);
            }
        }
        let (mut a, mut b) = (vars, vars);
        for n in 1..=10 {
            a = M::step_lanes::<Exact>(&aircraft, &shared, &together, &a, dt);
            b = M::step_lanes::<Exact>(&aircraft, &shared, &one_by_one, &b, dt);
            for lane in 0..width {
                assert_eq!(
                    bits(&M::state(&a, 0.0, lane)),
                    bits(&M::state(&b, 0.0, lane)),
                    "{}: {count} lanes set, lane {lane} after step {n}",
                    M::NAME
                );
            }
        }
    }
}

#[test]
fn set_controls_lanes_sets_the_first_count_lanes_as_set_controls_does() {
    check_set_controls_lanes::<Palmer, _>(&palmer_members(), palmer_bits);
    check_set_controls_lanes::<Bourg, _>(&bourg_members(), bourg_bits);
    // The members' controls are not all the idle ones, so an unset lane
    // would show: the idle block flies differently in some lane.
    let aircraft = Bourg::default_aircraft();
    let members = bourg_members();
    let dt = Bourg::time_step(30.0);
    let set = fly_lanes::<Bourg>(&aircraft, &members, true, dt, 10);
    let idle = fly_lanes::<Bourg>(&aircraft, &members, false, dt, 10);
    assert_ne!(
        set[9].iter().map(bourg_bits).collect::<Vec<_>>(),
        idle[9].iter().map(bourg_bits).collect::<Vec<_>>()
    );
}
