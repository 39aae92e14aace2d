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
//!
//! # One source for one aircraft and for lanes
//!
//! The right-hand side and the RK4 step (`rhs`, `rk4`) are written once over
//! the number type [`Real`](crate::real::Real) and the maths
//! [`Maths`](crate::real::Maths): [`step`] is `rk4::<f64, Exact>`, a fleet's
//! kernel `rk4::<PalmerLanes, Exact or Fast>` (`palmer/lanes.rs`). Only two
//! spellings differ from a plain `f64` program, and neither changes a bit:
//!
//! | plain `f64` | generic | why |
//! |---|---|---|
//! | `0.5 * cl` | `c(0.5) * cl` (`c = R::splat`) | a constant on the left stays on the left (the same operation, and the same NaN operand order) |
//! | `if z < 5.0 { a } else { b }` | `R::select(z.lt(5.0), a, b)` | lanes take both branches and blend; for `f64` it is the `if` |
//! | `pow(grp, 5.25)` | `F::pow(grp, 5.25)` | `Exact` is [`crate::math::pow`]; `Fast` a vectorised form for fleets |
//!
//! What the step reads and writes, per aircraft:
//!
//! | value | read | written |
//! |---|---|---|
//! | `q = [vx, x, vy, y, vz, z]` | `vx, vy, vz, z` by every stage; all six by the RK sum | all six: `q + (dq1 + 2·dq2 + 2·dq3 + dq4) / 6` |
//! | `time_s` | | `time_s + dt` (by the caller: [`step`], or the fleet) |
//! | [`ControlTerms`] | bank's `cos`/`sin`, `cl`, `0.5·cl`, `0.5·cd`, throttle | never |
//! | [`AircraftTerms`] and the aircraft | `rps·d`, `π·AR·e`, `m·G`, mass, areas, propeller, `cdp` | never |
//!
//! The ground-effect values (below 5 m) are computed only when a lane is that
//! low (`low.any()`), so a fleet in the air skips them as the scalar step does.

use core::f64::consts::PI;
use core::fmt;

use crate::message::ShortNumber;

use nalgebra::Vector3;

use super::{AircraftError, Flaps, PalmerAircraft, PalmerControls, PalmerState};
use crate::math::sin_cos;
use crate::real::{Exact, Mask, Maths, Real};

/// Gravitational acceleration along z, m/s² (`G` of docs/palmer-model.md).
pub const GRAVITY_MPS2: f64 = -9.81;

/// Friction coefficient of braked tyres on dry pavement (our extension, not
/// in the thesis; docs/palmer-model.md "Wheel brakes"). Raymer (Aircraft
/// Design, table 17.1) gives 0.3–0.5 for dry concrete with the brakes on,
/// rolling resistance included; this is the middle of that range.
///
/// While [`PalmerControls::brakes`] is set and the ground holds the
/// aircraft up (step 12), a friction force of at most this coefficient
/// times the normal force (weight less lift) opposes the horizontal
/// velocity. It never does more than stop the roll within one RK stage, so
/// a braked aircraft comes to rest instead of rolling backwards, and at rest
/// it holds the aircraft against up to that much thrust. With the brakes off
/// there is no wheel friction, as in the original model (whose reference
/// cases start with a ground roll, so an always-on rolling resistance would
/// change them).
pub const BRAKING_FRICTION_COEFFICIENT: f64 = 0.4;

/// The model's state vector `[vx, x, vy, y, vz, z]` (the original's order),
/// of one aircraft (`R = f64`) or of lanes.
type Q<R> = [R; 6];

/// What the right-hand side derives from the aircraft alone: the same in
/// every RK stage, every step and every aircraft of a fleet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AircraftTerms {
    /// `engine_rps * prop_diameter`.
    pub rps_times_diameter: f64,
    /// `pi * aspect_ratio * eff`, `aspect_ratio = span * span / area`.
    pub induced_drag_divisor: f64,
    /// `mass * G` (step 11's weight term).
    pub weight: f64,
}

impl AircraftTerms {
    /// The terms of `aircraft`.
    #[inline(always)]
    #[must_use]
    pub fn new(aircraft: &PalmerAircraft) -> Self {
        // Step 9, the aspect ratio.
        let aspect_ratio = aircraft.wing_span_m * aircraft.wing_span_m / aircraft.wing_area_m2;
        Self {
            rps_times_diameter: aircraft.engine_rps * aircraft.prop_diameter_m,
            induced_drag_divisor: PI * aspect_ratio * aircraft.eff,
            weight: aircraft.mass_kg * GRAVITY_MPS2,
        }
    }
}

/// What the right-hand side derives from one aircraft's controls (and the
/// aircraft): the same in all four RK stages. `R = f64` for one aircraft,
/// lanes for a fleet (computed when the controls are set).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlTerms<R> {
    /// `cos(bank * pi / 180)`.
    pub cos_w: R,
    /// `sin(bank * pi / 180)`.
    pub sin_w: R,
    /// Lift coefficient from alpha and flaps (without ground effect).
    pub cl_without_ground_effect: R,
    /// `0.5 * cl` of that lift coefficient (the first product of step 8's lift).
    pub half_cl_without_ground_effect: R,
    /// Step 9's drag coefficient `cdp + cl * cl / (pi * aspect_ratio * eff)`
    /// of that lift coefficient, times 0.5 (the first product of the drag).
    pub half_cd_without_ground_effect: R,
    /// The throttle (step 6).
    pub throttle: R,
    /// The wheels' friction coefficient: [`BRAKING_FRICTION_COEFFICIENT`]
    /// with the brakes set, 0 without (no wheel friction, the original model).
    pub wheel_friction: R,
}

impl ControlTerms<f64> {
    /// The terms of `controls` on `aircraft` (whose [`AircraftTerms`] are
    /// `at`).
    #[inline(always)]
    #[must_use]
    pub fn new(aircraft: &PalmerAircraft, at: &AircraftTerms, controls: &PalmerControls) -> Self {
        // step 10, bank: `sin` and `cos`, one reduction
        Self::with_sin_cos(aircraft, at, controls, sin_cos(Self::bank_rad(controls)))
    }

    /// Step 1: the bank in radians (alpha stays in degrees).
    #[inline(always)]
    #[must_use]
    pub fn bank_rad(controls: &PalmerControls) -> f64 {
        bank_rad(controls.bank_deg)
    }

    /// [`Self::new`] with the sine and cosine of [`Self::bank_rad`] given
    /// (computed for several aircraft at once, with the same bits:
    /// [`crate::math::sin_cos_lanes`]).
    #[inline(always)]
    #[must_use]
    pub fn with_sin_cos(
        aircraft: &PalmerAircraft,
        at: &AircraftTerms,
        controls: &PalmerControls,
        (sin_w, cos_w): (f64, f64),
    ) -> Self {
        Self::from_parts(
            aircraft,
            at,
            &ControlParts {
                alpha_deg: controls.alpha_deg,
                flaps_up: controls.flaps == Flaps::Up,
                flaps_lift: flaps_lift(controls.flaps),
                throttle: controls.throttle,
                brakes: controls.brakes,
            },
            (sin_w, cos_w),
        )
    }
}

/// Step 1: a bank in degrees in radians (of one aircraft or of lanes:
/// [`ControlTerms::bank_rad`]).
#[inline(always)]
#[must_use]
pub fn bank_rad<R: Real<Scalar = f64>>(bank_deg: R) -> R {
    bank_deg * PI / 180.0
}

/// The lift coefficient the flaps add when down (step 7): 0.25 at 20°,
/// 0.5 at 40° (flaps up add nothing: [`ControlParts::flaps_up`]).
#[inline(always)]
#[must_use]
pub const fn flaps_lift(flaps: Flaps) -> f64 {
    match flaps {
        Flaps::Deg20 => 0.25,
        Flaps::Up | Flaps::Deg40 => 0.5,
    }
}

/// What [`ControlTerms`] are computed from, as numbers of `R` (one
/// aircraft's controls for `f64`, a block's lane by lane for lanes).
#[derive(Debug, Clone, Copy)]
pub struct ControlParts<R: Real> {
    /// The angle of attack, degrees.
    pub alpha_deg: R,
    /// Whether the flaps are up (they add no lift then).
    pub flaps_up: R::Mask,
    /// The lift the flaps add when down ([`flaps_lift`]).
    pub flaps_lift: R,
    /// The throttle.
    pub throttle: R,
    /// Whether the brakes are set.
    pub brakes: R::Mask,
}

impl<R: Real<Scalar = f64>> ControlTerms<R> {
    /// The terms of `parts` on `aircraft` (whose [`AircraftTerms`] are
    /// `at`), the bank's sine and cosine given: one source for one aircraft
    /// ([`ControlTerms::with_sin_cos`]) and a block's lanes (every lane the
    /// scalar operations in the same order; each `if` a select of both
    /// values, which are plain arithmetic).
    #[inline(always)]
    #[must_use]
    pub fn from_parts(
        aircraft: &PalmerAircraft,
        at: &AircraftTerms,
        parts: &ControlParts<R>,
        (sin_w, cos_w): (R, R),
    ) -> Self {
        let c = R::splat;
        // Step 7, the part that does not depend on z.
        let alpha = parts.alpha_deg;
        let cl = R::select(
            alpha.lt(aircraft.alpha_cl_max_deg),
            c(aircraft.cl_slope0_per_deg) * alpha + c(aircraft.cl0),
            c(aircraft.cl_slope1_per_deg) * alpha + c(aircraft.cl1),
        );
        // `cl + 0.0` would turn a -0.0 into 0.0: flaps up keep `cl` itself.
        let cl = R::select(parts.flaps_up, cl, cl + parts.flaps_lift);
        Self {
            cos_w,
            sin_w,
            cl_without_ground_effect: cl,
            half_cl_without_ground_effect: c(0.5) * cl,
            half_cd_without_ground_effect: c(0.5)
                * (c(aircraft.cdp) + cl * cl / c(at.induced_drag_divisor)),
            throttle: parts.throttle,
            wheel_friction: R::select(parts.brakes, c(BRAKING_FRICTION_COEFFICIENT), c(0.0)),
        }
    }
}

impl<R: Real<Scalar = f64>> ControlTerms<R> {
    /// Every lane `t`.
    #[inline(always)]
    #[must_use]
    pub fn splat(t: &ControlTerms<f64>) -> Self {
        Self {
            cos_w: R::splat(t.cos_w),
            sin_w: R::splat(t.sin_w),
            cl_without_ground_effect: R::splat(t.cl_without_ground_effect),
            half_cl_without_ground_effect: R::splat(t.half_cl_without_ground_effect),
            half_cd_without_ground_effect: R::splat(t.half_cd_without_ground_effect),
            throttle: R::splat(t.throttle),
            wheel_friction: R::splat(t.wheel_friction),
        }
    }

    /// Sets lane `i` to `t`.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, t: &ControlTerms<f64>) {
        self.cos_w.set_lane(i, t.cos_w);
        self.sin_w.set_lane(i, t.sin_w);
        self.cl_without_ground_effect
            .set_lane(i, t.cl_without_ground_effect);
        self.half_cl_without_ground_effect
            .set_lane(i, t.half_cl_without_ground_effect);
        self.half_cd_without_ground_effect
            .set_lane(i, t.half_cd_without_ground_effect);
        self.throttle.set_lane(i, t.throttle);
        self.wheel_friction.set_lane(i, t.wheel_friction);
    }
}

/// Step 4's pressure at altitude `z`: `101325 * pow(1 - 0.0065 * z / 288.15, 5.25)`.
#[inline(always)]
fn pressure_at<R: Real<Scalar = f64>, F: Maths>(z: R) -> R {
    let c = R::splat;
    let grp = c(1.0) - c(0.0065) * z / 288.15;
    c(101_325.0) * F::pow(grp, 5.25)
}

/// The `rhs(` of docs/palmer-model.md: `rhs(q, delta_q, ds, q_scale)`: the change of `q` over `ds`
/// (already multiplied by `ds`) at the intermediate state `q + q_scale * delta_q`,
/// given [`pressure_at`] that state's altitude `q[5] + q_scale * delta_q[5]`.
///
/// Written over [`Real`]: each scalar `if` is a mask and a
/// [`Real::select`] of both values (for `f64` a plain `if`).
#[inline(always)]
#[allow(clippy::similar_names, clippy::too_many_arguments)] // names follow the original C: cosW/cosP/cosT, sinW/...
fn rhs<R: Real<Scalar = f64>>(
    aircraft: &PalmerAircraft,
    at: &AircraftTerms,
    k: &ControlTerms<R>,
    q: &Q<R>,
    delta_q: &Q<R>,
    ds: f64,
    q_scale: f64,
    pressure: R,
) -> Q<R> {
    let c = R::splat;
    // Step 2 (x and y of the intermediate state are never read).
    let vx = q[0] + c(q_scale) * delta_q[0];
    let vy = q[2] + c(q_scale) * delta_q[2];
    let vz = q[4] + c(q_scale) * delta_q[4];
    let z = q[5] + c(q_scale) * delta_q[5];
    // Step 3.
    let vh = (vx * vx + vy * vy).sqrt();
    let vtotal = (vx * vx + vy * vy + vz * vz).sqrt();

    // Step 4: atmosphere (the pressure at this `z` comes from [`pressure_at`]).
    let temperature = c(288.15) - c(0.0065) * z;
    let density = c(0.00348) * pressure / temperature;

    // Step 5: power drop-off.
    let omega = density / 1.225;
    let factor = (omega - 0.12) / 0.88;

    // Step 6: thrust.
    let advance_ratio = vtotal / at.rps_times_diameter;
    let thrust = k.throttle
        * factor
        * aircraft.engine_power_w
        * (c(aircraft.prop_a) + c(aircraft.prop_b) * advance_ratio * advance_ratio)
        / at.rps_times_diameter;

    // Step 7: lift coefficient; ground effect below 5 m. Step 9's drag
    // coefficient depends on nothing else, so away from the ground both come
    // precomputed (as `0.5 * cl` and `0.5 * cd`, the first products of steps
    // 8 and 9); the ground-effect values are computed only when an aircraft
    // (a lane) is that low.
    let low = z.lt(5.0);
    let (half_cl, half_cd) = if low.any() {
        let cl = k.cl_without_ground_effect + 0.25;
        (
            R::select(low, c(0.5) * cl, k.half_cl_without_ground_effect),
            R::select(
                low,
                c(0.5) * (c(aircraft.cdp) + cl * cl / at.induced_drag_divisor),
                k.half_cd_without_ground_effect,
            ),
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

    // Step 10 (a zero speed's divisions give NaN that the select drops).
    let (cos_w, sin_w) = (k.cos_w, k.sin_w);
    let still = vtotal.eq(0.0);
    let cos_p = R::select(still, c(1.0), vh / vtotal);
    let sin_p = R::select(still, c(0.0), vz / vtotal);
    let vertical = vh.eq(0.0);
    let cos_t = R::select(vertical, c(1.0), vx / vh);
    let sin_t = R::select(vertical, c(0.0), vy / vh);

    // Step 11.
    let fx = cos_t * cos_p * (thrust - drag) + (sin_t * sin_w - cos_t * sin_p * cos_w) * lift;
    let fy = sin_t * cos_p * (thrust - drag) + (-cos_t * sin_w - sin_t * sin_p * cos_w) * lift;
    let fz = sin_p * (thrust - drag) + cos_p * cos_w * lift;
    let fz = fz + at.weight; // `Fz = Fz + mass * G`

    // Step 12: the ground holds the aircraft up.
    let on_ground = z.le(0.0).and(fz.le(0.0));
    let mass = aircraft.mass_kg;
    // Our extension: the wheel brakes, computed only when an aircraft (a
    // lane) has them set and is on the ground, so with the brakes off the
    // step is the original's, bit for bit.
    let braking = on_ground.and(k.wheel_friction.gt(0.0));
    let (fx, fy) = if braking.any() {
        // The ground pushes back with the normal force `-fz`; the friction
        // opposes the horizontal velocity (along +x when at rest, where the
        // thrust points). It is at most `mu * normal`, and never more than
        // what stops the roll within this stage (`mass * vh / ds`) plus the
        // horizontal force along the travel: no roll backwards, and a hold at
        // rest against thrust below `mu * normal`.
        let full = k.wheel_friction * -fz;
        let along = fx * cos_t + fy * sin_t;
        let stop = R::select(vh.eq(0.0), c(0.0), c(mass) * vh / ds);
        let room = along + stop;
        let room = R::select(room.lt(0.0), c(0.0), room);
        let friction = R::select((full - room).lt(0.0), full, room);
        (
            R::select(braking, fx - friction * cos_t, fx),
            R::select(braking, fy - friction * sin_t, fy),
        )
    } else {
        (fx, fy)
    };
    let fz = R::select(on_ground, c(0.0), fz);

    // Step 13 (force divided by the mass first, see the module docs).
    [
        c(ds) * (fx / mass),
        c(ds) * vx,
        c(ds) * (fy / mass),
        c(ds) * vy,
        c(ds) * (fz / mass),
        c(ds) * vz,
    ]
}

/// One RK4 step of `q` (one aircraft, or lanes) over `ds` seconds with the
/// maths `F`, the clock aside: `q + (dq1 + 2·dq2 + 2·dq3 + dq4) / 6`. [`step`]
/// is this with `R = f64` and [`Exact`]; a fleet's kernel is this with lanes.
#[inline(always)]
pub(crate) fn rk4<R: Real<Scalar = f64>, F: Maths>(
    aircraft: &PalmerAircraft,
    at: &AircraftTerms,
    k: &ControlTerms<R>,
    q: &Q<R>,
    ds: f64,
) -> Q<R> {
    let c = R::splat;
    // Stage k's altitude is `q[5] + q_scale_k * dq_(k-1)[5]` with
    // `dq_(k-1)[5] = ds * (q[4] + q_scale_(k-1) * dq_(k-2)[4])`: it depends on
    // the vertical force of stage k-2, not k-1. So each stage's pressure (the
    // `pow`, the slowest operation) is computed one stage early, from the same
    // operations on the same values as `rhs` would use, and overlaps with the
    // previous stage's forces instead of lengthening the chain.
    let p1 = pressure_at::<R, F>(q[5] + c(0.0) * q[5]);
    let p2 = pressure_at::<R, F>(q[5] + c(0.5) * (c(ds) * (q[4] + c(0.0) * q[4])));
    let dq1 = rhs(aircraft, at, k, q, q, ds, 0.0, p1);
    let p3 = pressure_at::<R, F>(q[5] + c(0.5) * (c(ds) * (q[4] + c(0.5) * dq1[4])));
    let dq2 = rhs(aircraft, at, k, q, &dq1, ds, 0.5, p2);
    let p4 = pressure_at::<R, F>(q[5] + c(1.0) * (c(ds) * (q[4] + c(0.5) * dq2[4])));
    let dq3 = rhs(aircraft, at, k, q, &dq2, ds, 0.5, p3);
    let dq4 = rhs(aircraft, at, k, q, &dq3, ds, 1.0, p4);
    // Written out component by component, not with `core::array::from_fn`:
    // the compiler kept that closure out of line, compiled for the baseline
    // instruction set (two lanes per division) and called through the
    // instruction-set boundary six times a step, in every fleet kernel.
    let sum = |j: usize| q[j] + (dq1[j] + c(2.0) * dq2[j] + c(2.0) * dq3[j] + dq4[j]) / 6.0;
    [sum(0), sum(1), sum(2), sum(3), sum(4), sum(5)]
}

#[inline(always)]
fn to_q(state: &PalmerState) -> Q<f64> {
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
    let at = AircraftTerms::new(aircraft);
    let k = ControlTerms::new(aircraft, &at, controls);
    let q = to_q(state);
    let dq = crate::math::with_fma(
        #[inline(always)]
        move || {
            let pressure = pressure_at::<f64, Exact>(q[5] + 0.0 * q[5]);
            rhs(aircraft, &at, &k, &q, &q, 1.0, 0.0, pressure)
        },
    );
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
/// let controls = PalmerControls { throttle: 1.0, alpha_deg: 4.0, bank_deg: 0.0, flaps: Flaps::Up, brakes: false };
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
    let at = AircraftTerms::new(aircraft);
    let k = ControlTerms::new(aircraft, &at, controls);
    let ds = dt_s;
    let q = to_q(state);
    // In the CPU's FMA instance when it has one: `pow`'s fused multiply-adds
    // as instructions, the same numbers (`crate::math::with_fma`).
    let next = crate::math::with_fma(
        #[inline(always)]
        move || rk4::<f64, Exact>(aircraft, &at, &k, &q, ds),
    );
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
                write!(
                    f,
                    "time step must be finite and > 0 s, got {}",
                    ShortNumber(*dt_s)
                )
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

    /// The terms as `ControlTerms::with_sin_cos` computed them before
    /// `ControlTerms::from_parts` (branches, not selects): the oracle.
    fn terms_with_branches(
        aircraft: &PalmerAircraft,
        at: &AircraftTerms,
        controls: &PalmerControls,
        (sin_w, cos_w): (f64, f64),
    ) -> ControlTerms<f64> {
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
        ControlTerms {
            cos_w,
            sin_w,
            cl_without_ground_effect: cl,
            half_cl_without_ground_effect: 0.5 * cl,
            half_cd_without_ground_effect: 0.5 * (aircraft.cdp + cl * cl / at.induced_drag_divisor),
            throttle: controls.throttle,
            wheel_friction: if controls.brakes {
                BRAKING_FRICTION_COEFFICIENT
            } else {
                0.0
            },
        }
    }

    /// `from_parts` (selects) gives the branches' bits for every flap
    /// setting and brake, over angles of attack across the slope change
    /// (16° and its neighbours), zeros of both signs, the ends of the range
    /// and NaN, and with an aircraft whose lift is exactly zero at an
    /// angle (`-0.0` must stay `-0.0` with the flaps up).
    #[test]
    fn terms_from_parts_are_the_branches_bits() {
        let mut alphas: Vec<f64> = (0..=400).map(|i| -20.0 + 0.1 * f64::from(i)).collect();
        let max = CESSNA.alpha_cl_max_deg;
        alphas.extend([
            max,
            max.next_up(),
            max.next_down(),
            0.0,
            -0.0,
            f64::NAN,
            90.0,
            -90.0,
        ]);
        let zero_lift = PalmerAircraft {
            cl0: -0.0,
            cl1: -0.0,
            ..CESSNA
        };
        for aircraft in [CESSNA, zero_lift] {
            let at = AircraftTerms::new(&aircraft);
            for &alpha_deg in &alphas {
                for flaps in [Flaps::Up, Flaps::Deg20, Flaps::Deg40] {
                    for brakes in [false, true] {
                        let c = PalmerControls {
                            throttle: 0.37,
                            alpha_deg,
                            bank_deg: 5.0,
                            flaps,
                            brakes,
                        };
                        let sc = sin_cos(ControlTerms::bank_rad(&c));
                        let got = ControlTerms::with_sin_cos(&aircraft, &at, &c, sc);
                        let want = terms_with_branches(&aircraft, &at, &c, sc);
                        assert_eq!(format!("{got:?}"), format!("{want:?}"), "{c:?}");
                        let bits = |t: &ControlTerms<f64>| {
                            [
                                t.cl_without_ground_effect,
                                t.half_cl_without_ground_effect,
                                t.half_cd_without_ground_effect,
                                t.wheel_friction,
                            ]
                            .map(f64::to_bits)
                        };
                        assert_eq!(bits(&got), bits(&want), "{c:?}");
                    }
                }
            }
        }
    }

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
            brakes: false,
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
        let at = AircraftTerms::new(&CESSNA);
        let k = ControlTerms::new(&CESSNA, &at, &controls);
        let q = to_q(&state);
        let dq1 = rhs(
            &CESSNA,
            &at,
            &k,
            &q,
            &q,
            dt,
            0.0,
            pressure_at::<f64, Exact>(q[5]),
        );
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
