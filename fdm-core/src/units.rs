//! Units and their conversions, each written once.
//!
//! Palmer works in metres and seconds, Bourg in feet, slugs and pounds;
//! FlightGear wants feet per second, knots and radians; the shell's common
//! [`FlightView`](crate::model::FlightView) is SI. Every conversion factor the
//! workspace uses is here.

/// Metres per international foot, exact (1959 definition).
pub const METRES_PER_FOOT: f64 = 0.3048;

/// Knots per metre per second (1 kt = 1852 m / 3600 s, exact ratio).
pub const KNOTS_PER_MPS: f64 = 3600.0 / 1852.0;

/// Feet per minute per metre per second (`60 / 0.3048`).
pub const FPM_PER_MPS: f64 = 60.0 / METRES_PER_FOOT;

/// The `f64` time step for `fps` frames per second: `1.0 / fps`, Palmer's
/// `DeltaTime`.
///
/// ```
/// assert_eq!(fdm_core::units::dt_f64_s(10.0), 0.1);
/// ```
#[must_use]
#[inline]
pub fn dt_f64_s(fps: f64) -> f64 {
    1.0 / fps
}

/// The `f32` time step for `fps` frames per second: `1.0f32 / fps as f32`,
/// as Bourg's C++ computes `1.0f / N`. For a whole number of frames per second
/// below 2^24, `fps as f32` is exact.
///
/// ```
/// assert_eq!(fdm_core::units::dt_f32_s(30.0), 1.0f32 / 30.0);
/// ```
#[must_use]
#[inline]
#[allow(clippy::cast_possible_truncation)] // the original's own f32 time step
pub fn dt_f32_s(fps: f64) -> f32 {
    1.0f32 / fps as f32
}

/// `degrees` mod 360 in `[0, 360)`; NaN and infinities give NaN, `-0.0`
/// gives `0.0`. The one heading wrap of the workspace.
///
/// ```
/// use fdm_core::units::wrap_degrees_360;
/// assert_eq!(wrap_degrees_360(-90.0), 270.0);
/// assert_eq!(wrap_degrees_360(720.0), 0.0);
/// assert!(wrap_degrees_360(-1e-300) < 360.0);
/// ```
#[must_use]
#[inline]
pub fn wrap_degrees_360(degrees: f64) -> f64 {
    let mut d = degrees % 360.0;
    if d < 0.0 {
        d += 360.0;
    }
    // A tiny negative input rounds to 360.0 above; -0.0 becomes 0.0.
    if d >= 360.0 {
        d -= 360.0;
    }
    d + 0.0
}
