//! Starting in the air: [`state_at`] (straight and level at an altitude,
//! speed and heading) and [`trim`] (the throttle and angle of attack that hold
//! it), both from the model's own right-hand side ([`derivatives`]).

use nalgebra::Vector3;

use super::{derivatives, PalmerAircraft, PalmerControls, PalmerState, ALPHA_MIN_DEG};
use crate::start::{InitialConditions, StartError, TrimReport, Trimmed};

/// At `conditions.altitude_m` above the origin, flying level at
/// `conditions.speed_mps` toward `conditions.heading_deg` (clockwise from
/// north), time 0. At altitude 0 and speed 0 this is exactly
/// [`PalmerState::at_rest`].
///
/// # Errors
/// [`StartError::InvalidConditions`].
pub fn state_at(conditions: &InitialConditions) -> Result<PalmerState, StartError> {
    if !conditions.is_valid() {
        return Err(StartError::InvalidConditions);
    }
    let [vx, vy, vz] = conditions.velocity_nwu_mps();
    Ok(PalmerState {
        time_s: 0.0,
        position_m: Vector3::new(0.0, 0.0, conditions.altitude_m),
        velocity_mps: Vector3::new(vx, vy, vz),
    })
}

/// Bisection steps on the angle of attack: the interval (36° wide) halves
/// each time, so 60 steps reach the spacing of `f64` near the answer.
const BISECTIONS: u32 = 60;

/// Trim for level flight at `conditions`, wings level (the bank of
/// `controls` is set to 0; its flaps are kept).
///
/// The point-mass model's level flight has two conditions: the vertical
/// acceleration is zero (lift = weight) and the horizontal one is zero
/// (thrust = drag). With the velocity horizontal, thrust acts along it, so
/// the first depends on the angle of attack only: it is found by bisection
/// on [`derivatives`] between −16° and the stall angle (`alpha_cl_max_deg`,
/// below which the lift grows with alpha), down to the spacing of `f64`: the
/// angle returned is the `f64` nearest level flight (the lowest, where
/// several side by side give exactly zero vertical acceleration). The
/// horizontal acceleration is affine in the throttle (thrust is throttle × a
/// function of speed and altitude), so two evaluations give the throttle
/// exactly.
///
/// # Errors
/// [`StartError::InvalidConditions`] (also at altitude 0: level flight needs
/// air under it), [`StartError::BelowStall`] when even the stall angle lifts
/// less than the weight, [`StartError::AboveMaxPower`] when full power cannot
/// hold the speed.
pub fn trim(
    aircraft: &PalmerAircraft,
    controls: &PalmerControls,
    conditions: &InitialConditions,
) -> Result<Trimmed<PalmerControls, PalmerState>, StartError> {
    let state = state_at(conditions)?;
    if conditions.altitude_m <= 0.0 {
        return Err(StartError::InvalidConditions);
    }
    let speed_mps = conditions.speed_mps;
    let base = PalmerControls {
        bank_deg: 0.0,
        ..*controls
    };
    let az = |alpha_deg: f64| {
        let c = PalmerControls { alpha_deg, ..base };
        derivatives(aircraft, &c, &state).acceleration_mps2.z
    };
    // Just below the stall angle: the highest lift of the pre-stall line.
    let mut hi = aircraft.alpha_cl_max_deg - 1e-9;
    let mut lo = ALPHA_MIN_DEG;
    if speed_mps == 0.0 || lifts_less_than_weight(az(hi)) {
        return Err(StartError::BelowStall { speed_mps });
    }
    if lifts_more_than_weight(az(lo)) {
        return Err(StartError::AboveMaxPower { speed_mps });
    }
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if az(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let alpha_deg = if abs(az(lo)) <= abs(az(hi)) { lo } else { hi };
    let ax = |throttle: f64| {
        let c = PalmerControls {
            throttle,
            alpha_deg,
            ..base
        };
        // Along the velocity (horizontal), whatever the heading.
        let a = derivatives(aircraft, &c, &state).acceleration_mps2;
        let v = state.velocity_mps;
        (a.x * v.x + a.y * v.y) / speed_mps
    };
    let (idle, full) = (ax(0.0), ax(1.0));
    let throttle = idle / (idle - full);
    if !(0.0..=1.0).contains(&throttle) || !throttle.is_finite() {
        return Err(StartError::AboveMaxPower { speed_mps });
    }
    let controls = PalmerControls {
        throttle,
        alpha_deg,
        ..base
    };
    Ok(Trimmed {
        controls,
        state,
        report: TrimReport {
            values: [
                ("throttle", throttle, ""),
                ("alpha", alpha_deg, "deg"),
                ("flaps", controls.flaps.degrees(), "deg"),
            ],
        },
    })
}

/// Whether the lift is less than the weight, from the vertical acceleration
/// in level flight: downward (`az < 0`). Exactly 0 is lift = weight, level
/// flight: not less. So at the stall angle, [`trim`]'s "even the stall angle
/// lifts less than the weight" (`BelowStall`).
fn lifts_less_than_weight(az: f64) -> bool {
    az < 0.0
}

/// Whether the lift is more than the weight: upward (`az > 0`); exactly 0 is
/// not more. At −16°, the bisection's other end, the speed is too fast for
/// the angle range (`AboveMaxPower`).
fn lifts_more_than_weight(az: f64) -> bool {
    az > 0.0
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

    /// The bisection's ends at their thresholds, from both sides: a vertical
    /// acceleration of exactly 0 (of either sign) is lift = weight, neither
    /// less nor more; the smallest `f64` either side of it is.
    #[test]
    fn lift_equal_to_the_weight_is_neither_less_nor_more() {
        let tiny = f64::from_bits(1);
        for zero in [0.0, -0.0] {
            assert!(!lifts_less_than_weight(zero));
            assert!(!lifts_more_than_weight(zero));
        }
        assert!(lifts_less_than_weight(-tiny) && !lifts_more_than_weight(-tiny));
        assert!(lifts_more_than_weight(tiny) && !lifts_less_than_weight(tiny));
        assert!(!lifts_less_than_weight(f64::NAN) && !lifts_more_than_weight(f64::NAN));
    }
}
