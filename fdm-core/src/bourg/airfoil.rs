//! Bourg's aerodynamic data: the airfoil tables of the wing and elevator
//! elements, the rudder's tables, the drag outside the tables, the air density
//! and gravity, and the table look-ups ([`airfoil_coefficients`],
//! [`rudder_coefficients`]).
//!
//! The values are the original's `float` literals (`0.2f` is the `f32`
//! 0.200000003, ...).

use super::airframe::Flap;

/// Gravitational acceleration, ft/s², negative (earth z is up): −32.174.
pub const G_FTPS2: f32 = -32.174;
/// Air density, slug/ft³: 0.0023769.
pub const RHO_SLUG_FT3: f32 = 0.0023769;

/// Airfoil table abscissae: angle of attack, degrees.
pub const AIRFOIL_ALPHA_DEG: [f32; 9] = [-8.0, -4.0, 0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 24.0];
/// Lift coefficients, no flap deflection.
pub const CL_NEUTRAL: [f32; 9] = [-0.54, -0.2, 0.2, 0.57, 0.92, 1.21, 1.43, 1.4, 1.0];
/// Lift coefficients, "flaps down" table (flap code −1).
pub const CL_TRAILING_EDGE_DOWN: [f32; 9] = [0.0, 0.45, 0.85, 1.02, 1.39, 1.65, 1.75, 1.38, 1.17];
/// Lift coefficients, "flaps up" table (flap code +1).
pub const CL_TRAILING_EDGE_UP: [f32; 9] = [-0.74, -0.4, 0.0, 0.27, 0.63, 0.92, 1.03, 1.1, 0.78];
/// Drag coefficients, no flap deflection.
pub const CD_NEUTRAL: [f32; 9] = [0.01, 0.0074, 0.004, 0.009, 0.013, 0.023, 0.05, 0.12, 0.21];
/// Drag coefficients, "flaps down" table.
pub const CD_TRAILING_EDGE_DOWN: [f32; 9] = [
    0.0065, 0.0043, 0.0055, 0.0153, 0.0221, 0.0391, 0.1, 0.195, 0.3,
];
/// Drag coefficients, "flaps up" table.
pub const CD_TRAILING_EDGE_UP: [f32; 9] = [
    0.005, 0.0043, 0.0055, 0.02601, 0.03757, 0.06647, 0.13, 0.18, 0.25,
];
/// Drag coefficient outside the tables (airfoil and rudder): 0.75.
pub const CD_OUTSIDE: f32 = 0.75;
/// Rudder table abscissae: |angle of attack|, degrees.
pub const RUDDER_ALPHA_DEG: [f32; 7] = [0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 24.0];
/// Rudder lift coefficients (symmetric).
pub const RUDDER_CL: [f32; 7] = [0.16, 0.456, 0.736, 0.968, 1.144, 1.12, 0.8];
/// Rudder drag coefficients (symmetric).
pub const RUDDER_CD: [f32; 7] = [0.0032, 0.0072, 0.0104, 0.0184, 0.04, 0.096, 0.168];

/// The airfoil tables' interval search, as the original: the first `i` with
/// `a[i] ≤ angle < a[i+1]`; `None` outside the table or for NaN.
#[inline(always)]
fn interval<const N: usize>(a: &[f32; N], angle: f32) -> Option<usize> {
    (0..N - 1).find(|&i| a[i] <= angle && a[i + 1] > angle)
}

/// The original's linear interpolation in interval `i`:
/// `t[i] − (a[i] − angle)·(t[i] − t[i+1])/(a[i] − a[i+1])`.
#[inline(always)]
fn lerp<const N: usize>(a: &[f32; N], t: &[f32; N], i: usize, angle: f32) -> f32 {
    t[i] - (a[i] - angle) * (t[i] - t[i + 1]) / (a[i] - a[i + 1])
}

/// Lift and drag coefficients of a wing or elevator element at an angle of
/// attack in degrees, from the tables of `flap` (`LiftCoefficient`,
/// `DragCoefficient`; both use the same angle table, so the interval is
/// searched once). Outside −8..24° (or for NaN): CL 0, CD 0.75.
#[inline]
#[must_use]
pub fn airfoil_coefficients(angle_deg: f32, flap: Flap) -> (f32, f32) {
    let (cl, cd) = match flap {
        Flap::Neutral => (&CL_NEUTRAL, &CD_NEUTRAL),
        Flap::TrailingEdgeDown => (&CL_TRAILING_EDGE_DOWN, &CD_TRAILING_EDGE_DOWN),
        Flap::TrailingEdgeUp => (&CL_TRAILING_EDGE_UP, &CD_TRAILING_EDGE_UP),
    };
    let a = &AIRFOIL_ALPHA_DEG;
    match interval(a, angle_deg) {
        Some(i) => (lerp(a, cl, i, angle_deg), lerp(a, cd, i, angle_deg)),
        None => (0.0, CD_OUTSIDE),
    }
}

/// Lift coefficient of a wing or elevator element (`LiftCoefficient`); see
/// [`airfoil_coefficients`].
#[must_use]
pub fn lift_coefficient(angle_deg: f32, flap: Flap) -> f32 {
    airfoil_coefficients(angle_deg, flap).0
}

/// Drag coefficient of a wing or elevator element (`DragCoefficient`); see
/// [`airfoil_coefficients`].
#[must_use]
pub fn drag_coefficient(angle_deg: f32, flap: Flap) -> f32 {
    airfoil_coefficients(angle_deg, flap).1
}

/// Rudder lift and drag coefficients (`RudderLiftCoefficient`,
/// `RudderDragCoefficient`), symmetric: the tables at `|angle|`, the lift
/// negated for `angle < 0`. So CL jumps from +0.16 at 0° to −0.16 just below.
/// Outside ±24° (or for NaN): CL 0, CD 0.75.
#[inline]
#[must_use]
pub fn rudder_coefficients(angle_deg: f32) -> (f32, f32) {
    let a = &RUDDER_ALPHA_DEG;
    let abs = super::ops::abs(angle_deg);
    match interval(a, abs) {
        Some(i) => {
            let cl = lerp(a, &RUDDER_CL, i, abs);
            let cl = if angle_deg < 0.0 { -cl } else { cl };
            (cl, lerp(a, &RUDDER_CD, i, abs))
        }
        None => (0.0, CD_OUTSIDE),
    }
}

/// Rudder lift coefficient; see [`rudder_coefficients`].
#[must_use]
pub fn rudder_lift_coefficient(angle_deg: f32) -> f32 {
    rudder_coefficients(angle_deg).0
}

/// Rudder drag coefficient; see [`rudder_coefficients`].
#[must_use]
pub fn rudder_drag_coefficient(angle_deg: f32) -> f32 {
    rudder_coefficients(angle_deg).1
}
