//! The equations of motion (docs/palmer-model.md "The right-hand side", steps 1–13) and the RK4 step.
//!
//! Every expression keeps the operation order of docs/palmer-model.md (C's left-to-right
//! evaluation, `grp^5.25` through `pow`), so with the `std` feature (glibc's
//! libm) the results are those of the original C program, bit for bit on the
//! four reference scenarios. Two readings of the formulas' notation matter for the
//! last bits and were settled against `reference/palmer.json`:
//!
//! * `x^2` is a multiplication in place, evaluated left to right with its
//!   neighbours: `0.5 * cl * density * vtotal^2 * wing_area` is
//!   `((((0.5 * cl) * density) * vtotal) * vtotal) * wing_area`. By the same
//!   reading `b * advance_ratio^2` is `(b * advance_ratio) * advance_ratio`
//!   (the reference scenarios do not tell the two groupings of this one apart).
//! * step 13's `ds*Fx/mass` is `ds * (Fx / mass)` (the force is divided by the
//!   mass first).
//!
//! Read the other way (`(vtotal * vtotal)` grouped, and/or `(ds * Fx) / mass`),
//! the final positions differ from the reference by 2.3e-13 to 4.5e-13 m.
//!
//! The only rearrangements leave every value's operations untouched, so the
//! bits are the same (`tests/palmer_step_oracle.rs` checks `step` against the
//! plain form on random inputs):
//!
//! * values that do not depend on the RK stage are hoisted out of the four
//!   stages: `cos`/`sin` of the bank, the aspect ratio, the pre-stall or
//!   post-stall lift coefficient with its flap increment, `0.5 * cl`, the
//!   drag coefficient `cdp + cl * cl / (pi * AR * e)` (and `0.5 * cd`) of that
//!   lift coefficient (recomputed in a stage below 5 m, where ground effect
//!   changes it), the propeller's `rps * diameter` and the weight `mass * G`;
//! * each stage's pressure (`pow`) is computed one stage early: a stage's
//!   altitude depends on the vertical force of the stage before the previous
//!   one, so the `pow` overlaps with the previous stage's forces.
//!
//! Measured with `benches/palmer_step.rs` (see `BENCHMARKS.md`).

use core::f64::consts::PI;
use core::fmt;

use nalgebra::Vector3;

use super::{AircraftError, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use crate::math::{cos, pow, sin, sqrt};

/// Gravitational acceleration along z, m/s² (`G` of docs/palmer-model.md).
pub const GRAVITY_MPS2: f64 = -9.81;

/// The model's state vector `[vx, x, vy, y, vz, z]` (the original's order).
type Q = [f64; 6];

/// Everything in the right-hand side that is the same in all four RK stages.
#[derive(Clone, Copy)]
struct StageInvariants {
    /// `cos(bank * pi / 180)`.
    cos_w: f64,
    /// `sin(bank * pi / 180)`.
    sin_w: f64,
    /// Lift coefficient from alpha and flaps (without ground effect).
    cl_without_ground_effect: f64,
    /// `0.5 * cl` of that lift coefficient (the first product of step 8's lift).
    half_cl_without_ground_effect: f64,
    /// Step 9's drag coefficient `cdp + cl * cl / (pi * aspect_ratio * eff)`
    /// of that lift coefficient, times 0.5 (the first product of the drag).
    half_cd_without_ground_effect: f64,
    /// `engine_rps * prop_diameter`.
    rps_times_diameter: f64,
    /// `pi * aspect_ratio * eff`.
    induced_drag_divisor: f64,
    /// `mass * G` (step 11's weight term).
    weight: f64,
    /// The throttle (step 6).
    throttle: f64,
}

impl StageInvariants {
    #[inline(always)]
    fn new(aircraft: &PalmerAircraft, controls: &PalmerControls) -> Self {
        // Step 1 (alpha stays in degrees).
        let bank_rad = controls.bank_deg * PI / 180.0;
        // Step 7, the part that does not depend on z.
        let alpha = controls.alpha_deg;
        let mut cl = if alpha < aircraft.alpha_cl_max_deg {
            aircraft.cl_slope0_per_deg * alpha + aircraft.cl0
        } else {
            aircraft.cl_slope1_per_deg * alpha + aircraft.cl1
        };
        match controls.flaps {
            Flaps::Up => {}
            Flaps::Deg20 => cl += 0.25,
            Flaps::Deg40 => cl += 0.5,
        }
        // Step 9, the aspect ratio.
        let aspect_ratio = aircraft.wing_span_m * aircraft.wing_span_m / aircraft.wing_area_m2;
        let induced_drag_divisor = PI * aspect_ratio * aircraft.eff;
        Self {
            // Step 10, bank.
            cos_w: cos(bank_rad),
            sin_w: sin(bank_rad),
            cl_without_ground_effect: cl,
            half_cl_without_ground_effect: 0.5 * cl,
            half_cd_without_ground_effect: 0.5 * (aircraft.cdp + cl * cl / induced_drag_divisor),
            rps_times_diameter: aircraft.engine_rps * aircraft.prop_diameter_m,
            induced_drag_divisor,
            weight: aircraft.mass_kg * GRAVITY_MPS2,
            throttle: controls.throttle,
        }
    }
}

/// Step 4's pressure at altitude `z`: `101325 * pow(1 - 0.0065 * z / 288.15, 5.25)`.
#[inline(always)]
fn pressure_at(z: f64) -> f64 {
    let grp = 1.0 - 0.0065 * z / 288.15;
    101_325.0 * pow(grp, 5.25)
}

/// The `rhs(` of docs/palmer-model.md: `rhs(q, delta_q, ds, q_scale)`: the change of `q` over `ds`
/// (already multiplied by `ds`) at the intermediate state `q + q_scale * delta_q`,
/// given [`pressure_at`] that state's altitude `q[5] + q_scale * delta_q[5]`.
#[inline(always)]
#[allow(clippy::similar_names)] // names follow the original C: cosW/cosP/cosT, sinW/...
fn rhs(
    aircraft: &PalmerAircraft,
    k: &StageInvariants,
    q: &Q,
    delta_q: &Q,
    ds: f64,
    q_scale: f64,
    pressure: f64,
) -> Q {
    // Step 2.
    let new_q: Q = core::array::from_fn(|i| q[i] + q_scale * delta_q[i]);
    // Step 3.
    let vx = new_q[0];
    let vy = new_q[2];
    let vz = new_q[4];
    let z = new_q[5];
    let vh = sqrt(vx * vx + vy * vy);
    let vtotal = sqrt(vx * vx + vy * vy + vz * vz);

    // Step 4: atmosphere (the pressure at this `z` comes from [`pressure_at`]).
    let temperature = 288.15 - 0.0065 * z;
    let density = 0.00348 * pressure / temperature;

    // Step 5: power drop-off.
    let omega = density / 1.225;
    let factor = (omega - 0.12) / 0.88;

    // Step 6: thrust.
    let advance_ratio = vtotal / k.rps_times_diameter;
    let thrust = k.throttle
        * factor
        * aircraft.engine_power_w
        * (aircraft.prop_a + aircraft.prop_b * advance_ratio * advance_ratio)
        / k.rps_times_diameter;

    // Step 7: lift coefficient; ground effect below 5 m. Step 9's drag
    // coefficient depends on nothing else, so away from the ground both come
    // precomputed (as `0.5 * cl` and `0.5 * cd`, the first products of steps
    // 8 and 9).
    let (half_cl, half_cd) = if z < 5.0 {
        let cl = k.cl_without_ground_effect + 0.25;
        (
            0.5 * cl,
            0.5 * (aircraft.cdp + cl * cl / k.induced_drag_divisor),
        )
    } else {
        (
            k.half_cl_without_ground_effect,
            k.half_cd_without_ground_effect,
        )
    };

    // Step 8 (`vtotal^2` multiplied in place, see the module docs).
    let lift = half_cl * density * vtotal * vtotal * aircraft.wing_area_m2;

    // Step 9.
    let drag = half_cd * density * vtotal * vtotal * aircraft.wing_area_m2;

    // Step 10.
    let (cos_w, sin_w) = (k.cos_w, k.sin_w);
    let (cos_p, sin_p) = if vtotal == 0.0 {
        (1.0, 0.0)
    } else {
        (vh / vtotal, vz / vtotal)
    };
    let (cos_t, sin_t) = if vh == 0.0 {
        (1.0, 0.0)
    } else {
        (vx / vh, vy / vh)
    };

    // Step 11.
    let fx = cos_t * cos_p * (thrust - drag) + (sin_t * sin_w - cos_t * sin_p * cos_w) * lift;
    let fy = sin_t * cos_p * (thrust - drag) + (-cos_t * sin_w - sin_t * sin_p * cos_w) * lift;
    let mut fz = sin_p * (thrust - drag) + cos_p * cos_w * lift;
    fz += k.weight; // `Fz = Fz + mass * G`

    // Step 12: the ground holds the aircraft up.
    if z <= 0.0 && fz <= 0.0 {
        fz = 0.0;
    }

    // Step 13 (force divided by the mass first, see the module docs).
    let mass = aircraft.mass_kg;
    [
        ds * (fx / mass),
        ds * vx,
        ds * (fy / mass),
        ds * vy,
        ds * (fz / mass),
        ds * vz,
    ]
}

#[inline(always)]
fn to_q(state: &PalmerState) -> Q {
    let (p, v) = (&state.position_m, &state.velocity_mps);
    [v.x, p.x, v.y, p.y, v.z, p.z]
}

/// Time derivative of the state: velocity and acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PalmerDerivative {
    /// `d(position)/dt`, m/s (the velocity itself).
    pub velocity_mps: Vector3<f64>,
    /// `d(velocity)/dt`, m/s²: the forces (thrust, drag, lift, gravity, ground
    /// reaction) divided by the mass.
    pub acceleration_mps2: Vector3<f64>,
}

/// The model's right-hand side at `state` (steps 1–13 of docs/palmer-model.md with `ds = 1`,
/// `q_scale = 0`): how fast the aircraft moves and accelerates, with the given
/// aircraft and controls. [`step`] integrates exactly this function (scaled by
/// `dt`). Pure; NaN in, NaN out.
///
/// ```
/// use fdm_core::palmer::{derivatives, PalmerAircraft, PalmerControls, PalmerState};
///
/// let full_power = PalmerControls { throttle: 1.0, ..PalmerControls::default() };
/// let d = derivatives(&PalmerAircraft::cessna_172(), &full_power, &PalmerState::at_rest());
/// assert!(d.acceleration_mps2.x > 2.5); // about 2.57 m/s²: the take-off roll starts
/// assert_eq!(d.acceleration_mps2.z, 0.0); // the runway holds the weight
/// ```
#[must_use]
#[inline]
pub fn derivatives(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    state: &PalmerState,
) -> PalmerDerivative {
    let k = StageInvariants::new(aircraft, controls);
    let q = to_q(state);
    let pressure = pressure_at(q[5] + 0.0 * q[5]);
    let dq = rhs(aircraft, &k, &q, &q, 1.0, 0.0, pressure);
    PalmerDerivative {
        velocity_mps: Vector3::new(dq[1], dq[3], dq[5]),
        acceleration_mps2: Vector3::new(dq[0], dq[2], dq[4]),
    }
}

/// Advances the state by `dt_s` seconds with one classical 4th-order Runge-Kutta
/// step (docs/palmer-model.md "The Runge-Kutta step"), keeping the original's operation order:
/// `q + (dq1 + 2·dq2 + 2·dq3 + dq4) / 6` and `time_s + dt_s`.
///
/// Pure: no I/O, no allocation, no global state, never panics. It does not
/// check its inputs: non-finite values (or a nonsensical aircraft) simply
/// propagate, typically as NaN, into the result. Use [`try_step`] to have them
/// rejected instead. A `dt_s` of 0 returns the state unchanged; a negative one
/// integrates backwards.
///
/// ```
/// use fdm_core::palmer::{step, Flaps, PalmerAircraft, PalmerControls, PalmerState};
///
/// let cessna = PalmerAircraft::cessna_172();
/// let controls = PalmerControls { throttle: 1.0, alpha_deg: 4.0, bank_deg: 0.0, flaps: Flaps::Up };
/// let mut state = PalmerState::at_rest();
/// for _ in 0..600 {
///     state = step(&cessna, &controls, &state, 0.1); // 60 s at 10 frames per second
/// }
/// assert!(state.position_m.z > 150.0, "climbed to {} m", state.position_m.z);
/// assert!(state.velocity_mps.z > 0.0);
/// assert_eq!(state.position_m.y, 0.0); // no bank, no turn
/// assert!((state.airspeed_mps() - 44.74).abs() < 0.01);
/// ```
#[must_use]
#[inline]
pub fn step(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    state: &PalmerState,
    dt_s: f64,
) -> PalmerState {
    let k = StageInvariants::new(aircraft, controls);
    let q = to_q(state);
    let ds = dt_s;
    // Stage k's altitude is `q[5] + q_scale_k * dq_(k-1)[5]` with
    // `dq_(k-1)[5] = ds * (q[4] + q_scale_(k-1) * dq_(k-2)[4])`: it depends on
    // the vertical force of stage k-2, not k-1. So each stage's pressure (the
    // `pow`, the slowest operation) is computed one stage early, from the same
    // operations on the same values as `rhs` would use, and overlaps with the
    // previous stage's forces instead of lengthening the chain.
    let p1 = pressure_at(q[5] + 0.0 * q[5]);
    let p2 = pressure_at(q[5] + 0.5 * (ds * (q[4] + 0.0 * q[4])));
    let dq1 = rhs(aircraft, &k, &q, &q, ds, 0.0, p1);
    let p3 = pressure_at(q[5] + 0.5 * (ds * (q[4] + 0.5 * dq1[4])));
    let dq2 = rhs(aircraft, &k, &q, &dq1, ds, 0.5, p2);
    let p4 = pressure_at(q[5] + 1.0 * (ds * (q[4] + 0.5 * dq2[4])));
    let dq3 = rhs(aircraft, &k, &q, &dq2, ds, 0.5, p3);
    let dq4 = rhs(aircraft, &k, &q, &dq3, ds, 1.0, p4);
    let next: Q =
        core::array::from_fn(|j| q[j] + (dq1[j] + 2.0 * dq2[j] + 2.0 * dq3[j] + dq4[j]) / 6.0);
    PalmerState {
        time_s: state.time_s + ds,
        position_m: Vector3::new(next[1], next[3], next[5]),
        velocity_mps: Vector3::new(next[0], next[2], next[4]),
    }
}

/// [`step`] with its inputs and output checked.
///
/// Checks, in this order: `dt_s` finite and `> 0`; the state finite; the
/// controls finite; the aircraft valid ([`PalmerAircraft::validate`]); then
/// steps and checks that the new state is finite (huge but finite inputs can
/// overflow). On success the result is bit-identical to [`step`].
///
/// # Errors
/// The first failed check, as a [`StepError`].
///
/// ```
/// use fdm_core::palmer::{try_step, PalmerAircraft, PalmerControls, PalmerState, StepError};
///
/// let cessna = PalmerAircraft::cessna_172();
/// let controls = PalmerControls::default();
/// let rest = PalmerState::at_rest();
/// assert_eq!(try_step(&cessna, &controls, &rest, 0.1).unwrap().time_s, 0.1);
/// assert_eq!(
///     try_step(&cessna, &controls, &rest, 0.0),
///     Err(StepError::InvalidTimeStep { dt_s: 0.0 })
/// );
/// ```
pub fn try_step(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    state: &PalmerState,
    dt_s: f64,
) -> Result<PalmerState, StepError> {
    if !dt_s.is_finite() || dt_s <= 0.0 {
        return Err(StepError::InvalidTimeStep { dt_s });
    }
    if !state.is_finite() {
        return Err(StepError::NonFiniteState);
    }
    if !controls.is_finite() {
        return Err(StepError::NonFiniteControls);
    }
    aircraft.validate().map_err(StepError::InvalidAircraft)?;
    let next = step(aircraft, controls, state, dt_s);
    if next.is_finite() {
        Ok(next)
    } else {
        Err(StepError::NonFiniteResult)
    }
}

/// Why [`try_step`] refused to step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepError {
    /// The time step is NaN, infinite, zero or negative.
    InvalidTimeStep {
        /// The rejected time step, s.
        dt_s: f64,
    },
    /// The state's time, position or velocity has a NaN or infinite component.
    NonFiniteState,
    /// Throttle, angle of attack or bank is NaN or infinite.
    NonFiniteControls,
    /// The aircraft parameters cannot be flown.
    InvalidAircraft(AircraftError),
    /// The inputs were finite but the step overflowed to a non-finite state.
    NonFiniteResult,
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidTimeStep { dt_s } => {
                write!(f, "time step must be finite and > 0 s, got {dt_s}")
            }
            Self::NonFiniteState => f.write_str("state has a NaN or infinite component"),
            Self::NonFiniteControls => f.write_str("controls have a NaN or infinite value"),
            Self::InvalidAircraft(err) => write!(f, "invalid aircraft: {err}"),
            Self::NonFiniteResult => f.write_str("the step overflowed to a non-finite state"),
        }
    }
}

impl core::error::Error for StepError {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Self::InvalidAircraft(err) => Some(err),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CESSNA: PalmerAircraft = PalmerAircraft::cessna_172();

    fn flying() -> PalmerState {
        PalmerState {
            time_s: 12.3,
            position_m: Vector3::new(500.0, -20.0, 80.0),
            velocity_mps: Vector3::new(40.0, -3.0, 2.0),
        }
    }

    fn climb() -> PalmerControls {
        PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            bank_deg: 5.0,
            flaps: Flaps::Deg20,
        }
    }

    #[test]
    fn at_rest_without_throttle_nothing_moves() {
        let d = derivatives(&CESSNA, &PalmerControls::default(), &PalmerState::at_rest());
        assert_eq!(d.velocity_mps, Vector3::zeros());
        assert_eq!(d.acceleration_mps2, Vector3::zeros());
    }

    #[test]
    fn in_flight_gravity_pulls_down() {
        // No throttle, no speed, 1000 m up: free fall at g.
        let state = PalmerState {
            position_m: Vector3::new(0.0, 0.0, 1000.0),
            ..PalmerState::at_rest()
        };
        let d = derivatives(&CESSNA, &PalmerControls::default(), &state);
        assert_eq!(d.acceleration_mps2, Vector3::new(0.0, 0.0, GRAVITY_MPS2));
    }

    #[test]
    fn derivatives_match_the_first_rk_stage() {
        let (state, controls, dt) = (flying(), climb(), 0.1);
        let d = derivatives(&CESSNA, &controls, &state);
        let k = StageInvariants::new(&CESSNA, &controls);
        let q = to_q(&state);
        let dq1 = rhs(&CESSNA, &k, &q, &q, dt, 0.0, pressure_at(q[5]));
        // `ds * (F / m)` with ds = 1 is exactly `F / m`: the stage is dt times it.
        assert_eq!(dq1[1], dt * d.velocity_mps.x);
        assert_eq!(dq1[3], dt * d.velocity_mps.y);
        assert_eq!(dq1[5], dt * d.velocity_mps.z);
        assert_eq!(dq1[0], dt * d.acceleration_mps2.x);
        assert_eq!(dq1[2], dt * d.acceleration_mps2.y);
        assert_eq!(dq1[4], dt * d.acceleration_mps2.z);
    }

    #[test]
    fn bank_right_turns_toward_negative_y() {
        let controls = PalmerControls {
            bank_deg: 10.0,
            ..climb()
        };
        let state = PalmerState {
            velocity_mps: Vector3::new(40.0, 0.0, 0.0),
            ..flying()
        };
        assert!(derivatives(&CESSNA, &controls, &state).acceleration_mps2.y < 0.0);
        let left = PalmerControls {
            bank_deg: -10.0,
            ..controls
        };
        assert!(derivatives(&CESSNA, &left, &state).acceleration_mps2.y > 0.0);
    }

    #[test]
    fn stall_uses_the_post_stall_line() {
        // Same speed, alpha 15 (pre-stall) vs. 20 (post-stall: cl 3.2 - 2.0 = 1.2
        // < 0.0889 * 15 + 0.178 = 1.5115): less lift past the stall.
        let state = flying();
        let c15 = PalmerControls {
            alpha_deg: 15.0,
            bank_deg: 0.0,
            ..climb()
        };
        let c20 = PalmerControls {
            alpha_deg: 20.0,
            ..c15
        };
        let az15 = derivatives(&CESSNA, &c15, &state).acceleration_mps2.z;
        let az20 = derivatives(&CESSNA, &c20, &state).acceleration_mps2.z;
        assert!(az20 < az15, "{az20} !< {az15}");
    }

    #[test]
    fn zero_dt_keeps_the_state() {
        let s = flying();
        assert_eq!(step(&CESSNA, &climb(), &s, 0.0), s);
    }

    #[test]
    fn try_step_matches_step_and_rejects_bad_input() {
        let (s, c) = (flying(), climb());
        assert_eq!(
            try_step(&CESSNA, &c, &s, 0.1),
            Ok(step(&CESSNA, &c, &s, 0.1))
        );
        for dt in [0.0, -0.1, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let err = try_step(&CESSNA, &c, &s, dt).unwrap_err();
            assert!(
                matches!(err, StepError::InvalidTimeStep { .. }),
                "{dt}: {err}"
            );
        }
        let mut bad = s;
        bad.velocity_mps.y = f64::NAN;
        assert_eq!(
            try_step(&CESSNA, &c, &bad, 0.1),
            Err(StepError::NonFiniteState)
        );
        let mut bad = s;
        bad.time_s = f64::INFINITY;
        assert_eq!(
            try_step(&CESSNA, &c, &bad, 0.1),
            Err(StepError::NonFiniteState)
        );
        let bad = PalmerControls {
            bank_deg: f64::NAN,
            ..c
        };
        assert_eq!(
            try_step(&CESSNA, &bad, &s, 0.1),
            Err(StepError::NonFiniteControls)
        );
        let mut heavy = CESSNA;
        heavy.mass_kg = -1.0;
        let err = try_step(&heavy, &c, &s, 0.1).unwrap_err();
        assert_eq!(
            err,
            StepError::InvalidAircraft(AircraftError::NotPositive {
                field: "mass_kg",
                value: -1.0
            })
        );
        assert_eq!(
            err.to_string(),
            "invalid aircraft: aircraft parameter `mass_kg` must be > 0, got -1"
        );
        assert!(core::error::Error::source(&err).is_some());
        let fast = PalmerState {
            velocity_mps: Vector3::new(1e200, 0.0, 0.0),
            ..s
        };
        assert_eq!(
            try_step(&CESSNA, &c, &fast, 0.1),
            Err(StepError::NonFiniteResult)
        );
    }

    #[test]
    fn step_propagates_nan_without_panicking() {
        let mut s = flying();
        s.position_m.z = f64::NAN;
        let next = step(&CESSNA, &climb(), &s, 0.1);
        assert!(!next.is_finite());
        let c = PalmerControls {
            throttle: f64::NAN,
            ..climb()
        };
        assert!(step(&CESSNA, &c, &flying(), 0.1).velocity_mps.x.is_nan());
    }
}
