//! Bourg's loads and step against docs/bourg-model.md's pseudo-code, written
//! here the way the page writes it: one loop over the elements 0..=7 with the
//! drag direction declared once before it ("Loads: `CalcAirplaneLoads`"),
//! then the semi-implicit Euler step ("The step: `StepSimulation`"), with the
//! page's constants (`g = −32.174`, `rho = 0.0023769`) and its operations:
//! `fdm_core::bourg::ops` (each checked against the C++'s own rows by
//! `bourg_math.rs`), the airfoil and rudder look-ups, `asinf`, and for the
//! elevators `BourgControls::elevator_coefficients`, the documented pitch
//! trim blend ("Pitch trim": `c = c_neutral + (c_deflected − c_neutral)·|trim|`
//! while the elevators are neutral, |trim| clamped to 1).
//!
//! The model's step is one generic source (`bourg/generic.rs`) evaluated
//! phase by phase for all eight elements; the page says "every value comes
//! from the same expression on the same inputs, and the sums still run in
//! element order, so the results are identical". So the comparison is bit for
//! bit, no tolerance, on what the five reference scenarios never reach: the
//! pitch trim (positive, negative, fractional, past 1, with and without a
//! pitch key), a rudder, ailerons and landing flaps together, slow elements
//! (the carried drag direction), a spinning aircraft, the first frame, and a
//! zero orientation (the renormalisation skipped).

use fdm_core::bourg::ops::{
    conjugate, cross, dot, magnitude, mat_mul_vec, normalize, quat_add, quat_div, quat_magnitude,
    quat_mul_vec, quat_scale, qv_rotate, radians_to_degrees,
};
use fdm_core::bourg::{
    loads, ops::quat_from_euler_deg, rudder_drag_coefficient, rudder_lift_coefficient, step,
    Airframe, BourgAircraft, BourgControls, BourgState, Flap, Quaternion, Vector3,
};
use fdm_core::math::asinf;

/// docs/bourg-model.md, "Constants": `g = −32.174` ft/s², `rho = 0.0023769`
/// slug/ft³ (`f32`).
const G: f32 = -32.174;
#[allow(clippy::excessive_precision)]
const RHO: f32 = 0.0023769;

/// "Loads", line by line: (earth-frame force, body-frame moment, stalling).
fn oracle_loads(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    state: &BourgState,
) -> (Vector3<f32>, Vector3<f32>, bool) {
    let mass = aircraft.mass_properties();
    let elements = &aircraft.airframe().elements;
    let zero = Vector3::new(0.0_f32, 0.0, 0.0);
    let mut drag_dir = zero; // declared once, before the loop
    let (mut fb, mut mb, mut stalling) = (zero, zero, false);
    for i in 0..8 {
        let normal = if i == 6 {
            aircraft.rudder_normal(controls.rudder_incidence_deg(&elements[6]))
        } else {
            mass.normals[i]
        };
        let c = mass.cg_offsets_ft[i];
        let v_local = state.velocity_body_ftps + cross(&state.angular_velocity_radps, &c);
        let speed = magnitude(&v_local);
        if speed > 1.0 {
            drag_dir = -v_local / speed;
        }
        let lift_dir = normalize(&cross(&cross(&drag_dir, &normal), &drag_dir));
        // "clamped to [−1, 1]" (NaN stays NaN, as with the original's `if`s).
        let s = dot(&drag_dir, &normal).clamp(-1.0, 1.0);
        let attack = radians_to_degrees(asinf(s));
        let q_area = 0.5 * RHO * speed * speed * elements[i].area_ft2;
        let force = match i {
            6 => {
                let (cl, cd) = (
                    rudder_lift_coefficient(attack),
                    rudder_drag_coefficient(attack),
                );
                (lift_dir * cl + drag_dir * cd) * q_area
            }
            7 => drag_dir * 0.5 * q_area,
            _ => {
                let (cl, cd) = controls.elevator_coefficients(i, &elements[i], attack);
                if i <= 3 && cl == 0.0 {
                    stalling = true;
                }
                (lift_dir * cl + drag_dir * cd) * q_area
            }
        };
        fb += force;
        mb += cross(&c, &force);
    }
    fb += Vector3::new(controls.thrust_lb, 0.0, 0.0);
    let mut force = qv_rotate(&state.orientation, &fb);
    force.z += G * mass.mass_slug;
    (force, mb, stalling)
}

/// "The step", line by line (the clock is `time_s + dt` widened).
fn oracle_step(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    state: &BourgState,
    dt: f32,
) -> BourgState {
    let mass = aircraft.mass_properties();
    let (force, moment, stalling) = oracle_loads(aircraft, controls, state);
    let velocity = state.velocity_ftps + (force / mass.mass_slug) * dt;
    let position = state.position_ft + velocity * dt;
    let w = state.angular_velocity_radps;
    let gyro = cross(&w, &mat_mul_vec(&mass.inertia, &w));
    let angular_velocity = w + mat_mul_vec(&mass.inertia_inverse, &(moment - gyro)) * dt;
    let q = state.orientation;
    let mut orientation = quat_add(
        &q,
        &quat_scale(&quat_mul_vec(&q, &angular_velocity), 0.5 * dt),
    );
    let m = quat_magnitude(&orientation);
    if m != 0.0 {
        orientation = quat_div(&orientation, m);
    }
    BourgState {
        time_s: state.time_s + f64::from(dt),
        position_ft: position,
        velocity_ftps: velocity,
        velocity_body_ftps: qv_rotate(&conjugate(&orientation), &velocity),
        angular_velocity_radps: angular_velocity,
        orientation,
        stalling,
    }
}

fn bits3(v: &Vector3<f32>) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

fn state_bits(s: &BourgState) -> ([u32; 16], bool, u64) {
    let q = &s.orientation.coords;
    let mut n = [0; 16];
    n[..3].copy_from_slice(&bits3(&s.position_ft));
    n[3..6].copy_from_slice(&bits3(&s.velocity_ftps));
    n[6..9].copy_from_slice(&bits3(&s.velocity_body_ftps));
    n[9..12].copy_from_slice(&bits3(&s.angular_velocity_radps));
    n[12..].copy_from_slice(&[q.w, q.x, q.y, q.z].map(f32::to_bits));
    (n, s.stalling, s.time_s.to_bits())
}

/// Flies `frames` steps of the model from `start` with `controls`, and checks
/// every step's loads and result against the oracle's from the same state.
/// Returns how many steps stalled.
fn check(what: &str, controls: &BourgControls, start: BourgState, frames: usize) -> usize {
    check_on(
        &BourgAircraft::bourg_default(),
        what,
        controls,
        start,
        frames,
    )
}

/// [`check`] on another airframe.
fn check_on(
    aircraft: &BourgAircraft,
    what: &str,
    controls: &BourgControls,
    start: BourgState,
    frames: usize,
) -> usize {
    let dt = 1.0_f32 / 30.0;
    let mut state = start;
    let mut stalled = 0;
    for frame in 1..=frames {
        let got = loads(aircraft, controls, &state);
        let (force, moment, stalling) = oracle_loads(aircraft, controls, &state);
        assert_eq!(
            (
                bits3(&got.force_earth),
                bits3(&got.moment_body),
                got.stalling
            ),
            (bits3(&force), bits3(&moment), stalling),
            "{what}, frame {frame}: loads {got:?}, documented {force:?} {moment:?} {stalling}"
        );
        let next = step(aircraft, controls, &state, dt);
        let want = oracle_step(aircraft, controls, &state, dt);
        assert_eq!(
            state_bits(&next),
            state_bits(&want),
            "{what}, frame {frame}: step {next:?}, documented {want:?}"
        );
        stalled += usize::from(next.stalling);
        state = next;
    }
    stalled
}

/// Level flight north at `speed` ft/s, the body velocity already set.
fn flying(speed: f32, euler_deg: [f32; 3], omega: [f32; 3]) -> BourgState {
    let mut s = BourgState::initial();
    s.orientation = quat_from_euler_deg(&Vector3::from(euler_deg));
    s.velocity_ftps = Vector3::new(speed, 0.0, 0.0);
    s.velocity_body_ftps = qv_rotate(&conjugate(&s.orientation), &s.velocity_ftps);
    s.angular_velocity_radps = Vector3::from(omega);
    s
}

#[test]
fn the_pitch_trim_blends_the_elevators_as_documented() {
    // Trims both ways, fractional (the blend is neither table), at 1 and
    // past it (clamped to 1: the deflected table itself). Cruise, and a
    // banked, pitching aircraft whose elevators' angle of attack changes
    // from frame to frame.
    let states = [
        ("cruise", flying(170.0, [0.0, 3.0, 0.0], [0.0, 0.0, 0.0])),
        (
            "pitching",
            flying(140.0, [5.0, -8.0, 20.0], [0.05, -0.4, 0.02]),
        ),
    ];
    for trim in [0.37, -0.62, 0.01, 1.0, -1.0, 1.75, -3.0] {
        for (name, start) in states {
            let mut c = BourgControls::initial();
            c.pitch_trim = trim;
            c.thrust_lb = 900.0;
            check(&format!("{name}, trim {trim}"), &c, start, 60);
            // A pitch key selects its full table: no blend on that frame.
            for elevators in [Flap::TrailingEdgeUp, Flap::TrailingEdgeDown] {
                let mut keyed = c;
                keyed.elevators = elevators;
                check(
                    &format!("{name}, trim {trim}, elevators {elevators:?}"),
                    &keyed,
                    start,
                    20,
                );
            }
        }
    }
}

#[test]
fn every_surface_together_and_the_edges_of_the_loads() {
    let mut all = BourgControls::initial();
    all.thrust_lb = 2300.0;
    all.rudder_deg = -16.0;
    all.port_aileron = Flap::TrailingEdgeUp;
    all.starboard_aileron = Flap::TrailingEdgeDown;
    all.elevators = Flap::TrailingEdgeDown;
    all.landing_flaps = true;
    all.pitch_trim = 0.25;
    let mut odd_rudder = all;
    odd_rudder.rudder_deg = 7.5; // an incidence outside the precomputed normals
    odd_rudder.elevators = Flap::Neutral;

    // Slow: every element's local speed at or below 1 ft/s (the drag
    // direction stays zero), then some above and some below (a slow roll:
    // the wing tips move, the centre does not).
    let mut slow = flying(0.5, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
    slow.velocity_body_ftps = Vector3::new(0.5, 0.0, -0.2);
    let mut tips = flying(0.0, [0.0, 0.0, 0.0], [0.12, 0.0, 0.0]);
    tips.velocity_body_ftps = Vector3::new(0.3, 0.0, 0.0);
    // A zero orientation: the renormalisation is skipped.
    let mut no_attitude = flying(120.0, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
    no_attitude.orientation = Quaternion::new(0.0, 0.0, 0.0, 0.0);

    let cases = [
        ("first frame", BourgState::initial(), 30),
        (
            "tumbling",
            flying(150.0, [30.0, 60.0, 170.0], [1.5, -0.8, 2.0]),
            90,
        ),
        (
            "sideslip",
            flying(120.0, [-20.0, 10.0, -90.0], [0.0, 0.3, -1.2]),
            60,
        ),
        (
            "high alpha",
            flying(90.0, [0.0, -35.0, 0.0], [0.0, 0.0, 0.0]),
            60,
        ),
        ("slow", slow, 5),
        ("slow roll", tips, 5),
        ("no attitude", no_attitude, 1),
    ];
    let mut stalled = 0;
    for controls in [BourgControls::initial(), all, odd_rudder] {
        for (name, start, frames) in cases {
            stalled += check(&format!("{name}, {controls:?}"), &controls, start, frames);
        }
    }
    // The stall flag is compared too, and these flights do stall.
    assert!(stalled > 0);
}

#[test]
fn an_asymmetric_airframe_steps_with_its_whole_inertia_tensor() {
    // Bourg's airframe is symmetric about its x-z plane, so its inertia's
    // products Ixy and Iyz are zero ("Mass properties"): the step's
    // `I · ω` and `I⁻¹ · (M − ω × Iω)` (row-wise dot products, "Matrix ×
    // vector") never add a nonzero term for them. A validated airframe may
    // be asymmetric (`Airframe`'s elements are data): a heavier port wing tip
    // and a fin moved 0.8 ft to the left give all six products, and a 4°
    // dihedral on the wings normals with a y component.
    let mut airframe = Airframe::bourg_default();
    airframe.elements[0].mass_slug = 9.5;
    airframe.elements[6].design_position_ft.y = 0.8;
    for element in &mut airframe.elements[..4] {
        element.dihedral_deg = 4.0;
    }
    let aircraft = BourgAircraft::new(airframe).unwrap();
    let i = &aircraft.mass_properties().inertia;
    assert!(i.m12 != 0.0 && i.m13 != 0.0 && i.m23 != 0.0, "{i}");
    let mut c = BourgControls::initial();
    c.thrust_lb = 1500.0;
    c.rudder_deg = 16.0;
    for (name, start) in [
        (
            "tumbling",
            flying(150.0, [30.0, 60.0, 170.0], [1.5, -0.8, 2.0]),
        ),
        ("cruise", flying(170.0, [0.0, 3.0, 0.0], [0.0, 0.0, 0.0])),
    ] {
        check_on(&aircraft, name, &c, start, 60);
    }
}
