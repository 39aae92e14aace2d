//! A model from outside `fdm-core` with the provided `LaneModel::run_blocks`
//! body: the glider `sim-cli glider` flies (its one model file, included here
//! as the fdm-ecs example `third_model.rs` includes it), whose kernel is the
//! provided one. Palmer and Bourg override it (to compile their kernels in
//! `fdm-core`), so only such a model runs the provided body.
//!
//! Its fleet must do what the fleet's docs say of any model: every stepping
//! method (on this thread, on rayon's pool, on the SSE2 baseline) gives each
//! aircraft [`Model::step`]'s bits, every flying method
//! [`fdm_core::model::fly`]'s state and status, flying piece by piece is
//! flying whole, and a fast step of a model without fast maths is refused
//! with nothing flown.

#[path = "../../sim-cli/src/models/glider/model.rs"]
mod glider;

use fdm_core::model::{fly, FlightStatus, Model};
use fdm_fleet::{Fleet, FleetError, Precision};
use glider::{Glider, GliderControls, GliderState};

/// Eleven gliders (a full block of eight and three in a partial one), each
/// with its own lift, bank and start; the last two start 0.3 m above the
/// ground sinking at 4 and 8 m/s, so that flying them lands or crashes them.
fn members() -> Vec<(GliderControls, GliderState)> {
    (0..11)
        .map(|i| {
            let k = f64::from(u8::try_from(i).unwrap());
            let mut c = Glider::initial_controls();
            c.lift_coefficient = 0.3 + 0.07 * k;
            c.bank_deg = -30.0 + 6.0 * k;
            let mut s = Glider::initial_state();
            s.position_m.x += 50.0 * k;
            s.velocity_mps.y = k - 5.0;
            if i >= 9 {
                s.position_m.z = 0.3;
                s.velocity_mps.z = -4.0 - 4.0 * (k - 9.0);
            }
            (c, s)
        })
        .collect()
}

fn fleet_of(members: &[(GliderControls, GliderState)]) -> Fleet<Glider> {
    Fleet::<Glider>::from_states(
        Glider::default_aircraft(),
        members.iter().map(|&(c, s)| (s, c)),
    )
    .unwrap()
}

/// The fleet's states and statuses, printed (so that the sign of a zero
/// counts: the bits, not `==`).
fn printed(fleet: &Fleet<Glider>) -> Vec<String> {
    fleet
        .states()
        .zip(fleet.statuses())
        .map(|(s, status)| format!("{s:?} {status:?}"))
        .collect()
}

type Method = fn(&mut Fleet<Glider>, f64, Precision) -> Result<(), FleetError>;

/// The fleet's stepping methods (its statuses neither read nor changed).
const STEPS: [(&str, Method); 3] = [
    ("step_with", Fleet::step_with),
    ("par_step_with", Fleet::par_step_with),
    ("step_baseline_with", Fleet::step_baseline_with),
];

/// The fleet's flying methods (whole frames with the flight statuses).
const FLIGHTS: [(&str, Method); 3] = [
    ("fly_with", Fleet::fly_with),
    ("par_fly_with", Fleet::par_fly_with),
    ("fly_baseline_with", Fleet::fly_baseline_with),
];

#[test]
fn the_provided_kernel_steps_each_aircraft_as_its_model() {
    let members = members();
    let aircraft = Glider::default_aircraft();
    let dt = Glider::time_step(30.0);
    for (name, step) in STEPS {
        let mut fleet = fleet_of(&members);
        let mut alone = members.clone();
        for frame in 0..45 {
            step(&mut fleet, dt, Precision::Exact).unwrap();
            for (c, s) in &mut alone {
                *s = Glider::step(&aircraft, c, s, dt);
            }
            for (i, (_, s)) in alone.iter().enumerate() {
                assert_eq!(
                    format!("{:?}", fleet.state(i).unwrap()),
                    format!("{s:?}"),
                    "{name}, frame {frame}, glider {i}"
                );
            }
        }
        // A step changes no status (the docs: "not read or changed").
        let initial: Vec<FlightStatus> = members
            .iter()
            .map(|(_, s)| FlightStatus::initial(s.position_m.z))
            .collect();
        assert_eq!(fleet.statuses().collect::<Vec<_>>(), initial, "{name}");
    }
}

#[test]
fn the_provided_kernel_flies_each_aircraft_as_fly_does() {
    let members = members();
    let aircraft = Glider::default_aircraft();
    let dt = Glider::time_step(30.0);
    for (name, flight) in FLIGHTS {
        let mut fleet = fleet_of(&members);
        let mut alone: Vec<_> = members
            .iter()
            .map(|&(c, s)| (c, s, FlightStatus::initial(s.position_m.z)))
            .collect();
        for frame in 0..45 {
            flight(&mut fleet, dt, Precision::Exact).unwrap();
            for (c, s, status) in &mut alone {
                (*s, *status) = fly::<Glider>(&aircraft, c, *status, s, dt);
            }
            for (i, (_, s, status)) in alone.iter().enumerate() {
                assert_eq!(
                    format!(
                        "{:?} {:?}",
                        fleet.state(i).unwrap(),
                        fleet.status(i).unwrap()
                    ),
                    format!("{s:?} {status:?}"),
                    "{name}, frame {frame}, glider {i}"
                );
            }
        }
        // The low gliders came down: the flight statuses were run too.
        assert!(
            alone[9..]
                .iter()
                .all(|(_, _, status)| *status != FlightStatus::Airborne),
            "{name}: {:?}",
            alone[9..].iter().map(|m| m.2).collect::<Vec<_>>()
        );
    }
}

#[test]
fn the_provided_piece_kernel_flies_pieces_as_the_whole_fleet() {
    let members = members();
    let dt = Glider::time_step(30.0);
    for blocks in [1, 2] {
        let mut whole = fleet_of(&members);
        let mut in_pieces = fleet_of(&members);
        for frame in 0..45 {
            whole.fly_with(dt, Precision::Exact).unwrap();
            for mut piece in in_pieces.pieces_mut(blocks) {
                piece.fly_with(dt, Precision::Exact).unwrap();
            }
            assert_eq!(
                printed(&in_pieces),
                printed(&whole),
                "{blocks} blocks a piece, frame {frame}"
            );
        }
        assert_ne!(printed(&whole), printed(&fleet_of(&members)));
    }
}

#[test]
fn a_fast_step_of_a_model_without_fast_maths_is_refused_with_nothing_flown() {
    const { assert!(!<Glider as fdm_core::real::LaneModel>::HAS_FAST) };
    let members = members();
    let dt = Glider::time_step(30.0);
    let before = printed(&fleet_of(&members));
    let unavailable = FleetError::PrecisionUnavailable {
        model: Glider::NAME,
        precision: Precision::Fast,
    };
    for (name, method) in STEPS.into_iter().chain(FLIGHTS) {
        let mut fleet = fleet_of(&members);
        let refused = method(&mut fleet, dt, Precision::Fast).unwrap_err();
        assert_eq!(refused, unavailable, "{name}");
        assert_eq!(printed(&fleet), before, "{name}");
    }
    let mut fleet = fleet_of(&members);
    for mut piece in fleet.pieces_mut(1) {
        assert_eq!(
            piece.fly_with(dt, Precision::Fast).unwrap_err(),
            unavailable
        );
    }
    assert_eq!(printed(&fleet), before);
}
