//! Starting in the air: [`state_at`] (straight and level at an altitude,
//! speed and heading) and [`trim`] (thrust, pitch attitude and pitch trim
//! that hold it), both from the model's own [`loads`].

use nalgebra::Vector3;

use super::controls::BourgControls;
use super::model::{loads, BourgState};
use super::ops::{conjugate, quat_from_euler_deg, qv_rotate};
use super::BourgAircraft;
use crate::start::{InitialConditions, StartError, TrimReport, Trimmed};
use crate::units::METRES_PER_FOOT;

/// The horizontal position a Bourg start keeps from the original's initial
/// state: x = −5000 ft, y = 0.
const START_X_FT: f32 = -5000.0;

/// At `conditions.altitude_m` (in feet) above the origin, 5000 ft south of it
/// as the original's start, flying level at `conditions.speed_mps` toward
/// `conditions.heading_deg`, wings level, nose `pitch_deg` above the horizon,
/// no rotation, time 0. Unlike the original's start (whose body-frame
/// velocity is zero for the first frame), the body-frame velocity is the
/// earth-frame one rotated into the body, so the first frame already has its
/// aerodynamic loads.
///
/// # Errors
/// [`StartError::InvalidConditions`].
pub fn state_at_attitude(
    conditions: &InitialConditions,
    pitch_deg: f32,
) -> Result<BourgState, StartError> {
    if !conditions.is_valid() || !pitch_deg.is_finite() {
        return Err(StartError::InvalidConditions);
    }
    let to_ft = |m: f64| (m / METRES_PER_FOOT) as f32;
    let [vn, vw, vu] = conditions.velocity_nwu_mps();
    let velocity = Vector3::new(to_ft(vn), to_ft(vw), to_ft(vu));
    // Euler angles as the model's: x roll, y pitch (positive nose down), z
    // yaw (positive toward the west, i.e. minus the compass heading).
    let yaw = (0.0 - conditions.heading_deg) as f32;
    let orientation = quat_from_euler_deg(&Vector3::new(0.0, -pitch_deg, yaw));
    Ok(BourgState {
        time_s: 0.0,
        position_ft: Vector3::new(START_X_FT, 0.0, to_ft(conditions.altitude_m)),
        velocity_ftps: velocity,
        velocity_body_ftps: qv_rotate(&conjugate(&orientation), &velocity),
        angular_velocity_radps: Vector3::zeros(),
        orientation,
        stalling: false,
    })
}

/// [`state_at_attitude`] with the nose on the horizon.
///
/// # Errors
/// [`StartError::InvalidConditions`].
pub fn state_at(conditions: &InitialConditions) -> Result<BourgState, StartError> {
    state_at_attitude(conditions, 0.0)
}

/// Newton iterations of [`trim`].
const ITERATIONS: usize = 60;

/// The three residuals of level flight at `x = [thrust_lb, pitch_deg,
/// pitch_trim]`: the force along the heading and the vertical force (lb,
/// gravity included) and the pitching moment (ft·lb), from [`loads`].
fn residuals(
    aircraft: &BourgAircraft,
    base: &BourgControls,
    conditions: &InitialConditions,
    x: [f64; 3],
) -> Option<[f64; 3]> {
    let controls = BourgControls {
        thrust_lb: x[0] as f32,
        pitch_trim: x[2] as f32,
        ..*base
    };
    let state = state_at_attitude(conditions, x[1] as f32).ok()?;
    let l = loads(aircraft, &controls, &state);
    let h = conditions.heading_deg.to_radians();
    let f = l.force_earth.map(f64::from);
    let along = f.x * crate::math::cos(h) - f.y * crate::math::sin(h);
    let r = [along, f.z, f64::from(l.moment_body.y)];
    r.iter().all(|v| v.is_finite()).then_some(r)
}

/// Solves the 3×3 system `j · d = −r` by Cramer's rule; `None` if singular.
fn solve(j: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(j);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let mut out = [0.0; 3];
    for (col, o) in out.iter_mut().enumerate() {
        let mut m = j;
        for row in 0..3 {
            m[row][col] = -r[row];
        }
        *o = det(m) / d;
    }
    Some(out)
}

/// Trim for level, wings-level flight at `conditions`: the thrust, the pitch
/// attitude (equal to the angle of attack in level flight) and the elevator
/// [`pitch_trim`](BourgControls::pitch_trim) that zero the force along the
/// path, the vertical force and the pitching moment of [`loads`]; the other
/// settings of `controls` (landing flaps) are kept, the surfaces neutral.
///
/// Newton's method with a finite-difference Jacobian (steps 1 lb, 0.01°,
/// 0.001), from 1000 lb, 2° and no trim; a step is limited to 500 lb, 2° and
/// 0.1. It stops when the forces are below 0.5 lb and the moment below
/// 5 ft·lb: at the default aircraft's weight (about 2200 lb) and inertia, a
/// residual that small moves the aircraft by well under a foot in a minute.
/// The lateral axes are not trimmed: the model's rudder table gives a small
/// side force at zero incidence (CL 0.16), so a trimmed Bourg drifts slowly
/// in heading.
///
/// # Errors
/// [`StartError::InvalidConditions`] (also at altitude 0),
/// [`StartError::AboveMaxPower`] when the thrust needed exceeds the
/// aircraft's maximum, [`StartError::BelowStall`] when no attitude up to
/// the stall carries the weight, [`StartError::OutOfTrim`] when the pitch
/// trim would have to go beyond ±1 (or the thrust below 0). A thrust of
/// exactly the maximum, or 0, and a trim of exactly ±1 are within.
pub fn trim(
    aircraft: &BourgAircraft,
    controls: &BourgControls,
    conditions: &InitialConditions,
) -> Result<Trimmed<BourgControls, BourgState>, StartError> {
    state_at(conditions)?;
    let speed_mps = conditions.speed_mps;
    if conditions.altitude_m <= 0.0 {
        return Err(StartError::InvalidConditions);
    }
    if speed_mps == 0.0 {
        return Err(StartError::BelowStall { speed_mps });
    }
    let base = controls.neutralize_surfaces();
    let steps = [1.0, 0.01, 0.001];
    let limits = [500.0, 2.0, 0.1];
    let mut x = [1000.0, 2.0, 0.0];
    let mut converged = false;
    let mut last = [0.0; 3];
    for _ in 0..ITERATIONS {
        let r = residuals(aircraft, &base, conditions, x)
            .ok_or(StartError::BelowStall { speed_mps })?;
        last = r;
        if within_tolerance(r) {
            converged = true;
            break;
        }
        let mut j = [[0.0; 3]; 3];
        for col in 0..3 {
            let mut xp = x;
            xp[col] += steps[col];
            let rp = residuals(aircraft, &base, conditions, xp)
                .ok_or(StartError::BelowStall { speed_mps })?;
            for row in 0..3 {
                j[row][col] = (rp[row] - r[row]) / steps[col];
            }
        }
        let Some(d) = solve(j, r) else { break };
        for i in 0..3 {
            x[i] += d[i].clamp(-limits[i], limits[i]);
        }
    }
    verdict(
        converged,
        x,
        last,
        f64::from(aircraft.max_thrust_lb),
        speed_mps,
    )?;
    let controls = BourgControls {
        thrust_lb: x[0] as f32,
        pitch_trim: x[2] as f32,
        ..base
    };
    let state = state_at_attitude(conditions, x[1] as f32)?;
    Ok(Trimmed {
        controls,
        state,
        report: TrimReport {
            values: [
                ("thrust", f64::from(controls.thrust_lb), "lb"),
                ("pitch", f64::from(x[1] as f32), "deg"),
                ("elevator trim", f64::from(controls.pitch_trim), ""),
            ],
        },
    })
}

/// [`trim`]'s tolerance: the forces along the path and vertical (`r[0]`,
/// `r[1]`) below 0.5 lb and the pitching moment (`r[2]`) below 5 ft·lb, in
/// magnitude (strictly: a residual of exactly 0.5 lb is not within).
fn within_tolerance(r: [f64; 3]) -> bool {
    abs(r[0]) < 0.5 && abs(r[1]) < 0.5 && abs(r[2]) < 5.0
}

/// How [`trim`]'s iteration ended, as its errors document: with the
/// solution `x = [thrust_lb, pitch_deg, pitch_trim]` of a `converged`
/// iteration, `Ok` while the thrust is within `0..=max_thrust` and the trim
/// within `-1..=1`; [`StartError::AboveMaxPower`] when the thrust exceeds
/// `max_thrust`, [`StartError::OutOfTrim`] when the trim is beyond ±1 or the
/// thrust below 0. Without convergence, from the `last` residuals and
/// where `x` ran to: [`StartError::BelowStall`] when the vertical force was
/// still downward (`last[1] < 0`: the lift short of the weight) at a thrust
/// within the maximum, else [`StartError::AboveMaxPower`] if the thrust ran
/// beyond the maximum, else [`StartError::OutOfTrim`].
fn verdict(
    converged: bool,
    x: [f64; 3],
    last: [f64; 3],
    max_thrust: f64,
    speed_mps: f64,
) -> Result<(), StartError> {
    if converged && (x[0] > max_thrust) {
        return Err(StartError::AboveMaxPower { speed_mps });
    }
    if !converged {
        // Not enough lift at any attitude reached: too slow; otherwise the
        // thrust or the trim ran away.
        return Err(if last[1] < 0.0 && x[0] <= max_thrust {
            StartError::BelowStall { speed_mps }
        } else if x[0] > max_thrust {
            StartError::AboveMaxPower { speed_mps }
        } else {
            StartError::OutOfTrim { speed_mps }
        });
    }
    if x[0] < 0.0 {
        return Err(StartError::OutOfTrim { speed_mps });
    }
    if abs(x[2]) > 1.0 {
        return Err(StartError::OutOfTrim { speed_mps });
    }
    Ok(())
}

/// `|x|` (without relying on `f64::abs` being in `core`).
fn abs(x: f64) -> f64 {
    if x < 0.0 {
        -x
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `solve`: `j · d = −r` by Cramer's rule, on a system worked by hand with
    /// every entry of `j` nonzero and distinct (so each product of every
    /// minor matters): det j = 2(20 − 2) − 1(5 − 3) + 3(2 − 12) = 4, and for
    /// d = (1, −2, 3), j · d = (9, −4, 14). Exact: small integers, and each
    /// Cramer determinant is a multiple of 4.
    #[test]
    fn solve_gives_the_step_that_zeroes_the_linearised_residuals() {
        let j = [[2.0, 1.0, 3.0], [1.0, 4.0, 1.0], [3.0, 2.0, 5.0]];
        assert_eq!(solve(j, [-9.0, 4.0, -14.0]), Some([1.0, -2.0, 3.0]));
        // Another right-hand side: d = (−3, 5, 2), j · d = (5, 19, 11).
        assert_eq!(solve(j, [-5.0, -19.0, -11.0]), Some([-3.0, 5.0, 2.0]));
        // Another matrix, nine different entries: det = 1(55 − 56) −
        // 2(44 − 42) + 3(32 − 30) = 1; for d = (2, −1, 1), k · d = (3, 10, 15).
        let k = [[1.0, 2.0, 3.0], [4.0, 5.0, 7.0], [6.0, 8.0, 11.0]];
        assert_eq!(solve(k, [-3.0, -10.0, -15.0]), Some([2.0, -1.0, 1.0]));
        // Singular (the third row the sum of the first two): no step.
        let singular = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [5.0, 7.0, 9.0]];
        assert_eq!(solve(singular, [1.0, 1.0, 1.0]), None);
    }

    /// The tolerance of `trim`'s doc: each force below 0.5 lb and the moment
    /// below 5 ft·lb, in magnitude, each on its own; exactly at a limit, on
    /// either side of zero, is not converged, and the largest `f64` below it
    /// is.
    #[test]
    fn the_tolerance_is_below_half_a_pound_and_five_foot_pounds() {
        let below = |limit: f64| f64::from_bits(limit.to_bits() - 1);
        assert!(within_tolerance([0.0, 0.0, 0.0]));
        assert!(within_tolerance([below(0.5), -below(0.5), below(5.0)]));
        assert!(within_tolerance([-below(0.5), below(0.5), -below(5.0)]));
        for r in [
            [0.5, 0.0, 0.0],
            [-0.5, 0.0, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, -0.5, 0.0],
            [0.0, 0.0, 5.0],
            [0.0, 0.0, -5.0],
            [f64::NAN, 0.0, 0.0],
        ] {
            assert!(!within_tolerance(r), "{r:?}");
        }
    }

    /// `trim`'s errors at their documented limits, landed exactly from both
    /// sides: a thrust up to and including the aircraft's maximum (3000 lb
    /// here) and down to and including 0, and a trim up to and including ±1,
    /// are trimmed; the next `f64` beyond is refused, with the documented
    /// error. Without convergence: a vertical force still downward at a
    /// thrust within the maximum is below the stall (exactly 0 is not
    /// downward), a thrust run beyond the maximum is above full power, and
    /// anything else is out of trim.
    #[test]
    fn the_limits_are_the_documented_ones_from_both_sides() {
        let max = 3000.0;
        let speed = 40.0;
        let up = |v: f64| f64::from_bits(v.to_bits() + 1);
        let over = up(max);
        let above_max = Err(StartError::AboveMaxPower { speed_mps: speed });
        let out_of_trim = Err(StartError::OutOfTrim { speed_mps: speed });
        let below_stall = Err(StartError::BelowStall { speed_mps: speed });
        let done = |x: [f64; 3]| verdict(true, x, [0.0; 3], max, speed);

        assert_eq!(done([1500.0, 3.0, 0.25]), Ok(()));
        assert_eq!(done([max, 3.0, 0.25]), Ok(()));
        assert_eq!(done([over, 3.0, 0.25]), above_max);
        assert_eq!(done([0.0, 3.0, 0.25]), Ok(()));
        assert_eq!(done([-f64::MIN_POSITIVE, 3.0, 0.25]), out_of_trim);
        assert_eq!(done([1500.0, 3.0, 1.0]), Ok(()));
        assert_eq!(done([1500.0, 3.0, -1.0]), Ok(()));
        assert_eq!(done([1500.0, 3.0, up(1.0)]), out_of_trim);
        assert_eq!(done([1500.0, 3.0, -up(1.0)]), out_of_trim);

        let stopped =
            |x: [f64; 3], vertical: f64| verdict(false, x, [0.25, vertical, 1.0], max, speed);
        // Still short of lift, thrust within the maximum: too slow.
        assert_eq!(stopped([max, 10.0, 0.0], -1e-9), below_stall);
        assert_eq!(stopped([1500.0, 10.0, 0.0], -100.0), below_stall);
        // Short of lift but the thrust ran away: above full power.
        assert_eq!(stopped([over, 10.0, 0.0], -100.0), above_max);
        // The weight carried (a vertical force of 0 or upward).
        assert_eq!(stopped([1500.0, 10.0, 0.0], 0.0), out_of_trim);
        assert_eq!(stopped([max, 10.0, 0.0], 100.0), out_of_trim);
        assert_eq!(stopped([over, 10.0, 0.0], 100.0), above_max);
        assert_eq!(stopped([over, 10.0, 0.0], 0.0), above_max);
    }
}
