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

#[cfg(test)]
mod tests {
    use super::*;

    /// The factors from their definitions: 1 kt = 1852 m per 3600 s;
    /// 1 m/s = 60 m/min = 60 / 0.3048 ft/min (196.85... ft/min).
    #[test]
    fn the_factors_are_their_definitions() {
        assert_eq!(METRES_PER_FOOT, 0.3048);
        assert!((KNOTS_PER_MPS * 1852.0 / 3600.0 - 1.0).abs() < 1e-15);
        assert!((KNOTS_PER_MPS - 1.943_844_492_440_605).abs() < 1e-14);
        assert!((FPM_PER_MPS * METRES_PER_FOOT - 60.0).abs() < 1e-12);
        assert!((FPM_PER_MPS - 196.850_393_700_787_4).abs() < 1e-12);
    }

    /// The time steps are `1 / fps` in each model's type.
    #[test]
    fn time_steps_are_one_over_the_frame_rate() {
        assert_eq!(dt_f64_s(10.0), 0.1);
        assert_eq!(dt_f64_s(4.0), 0.25);
        assert_eq!(dt_f64_s(30.0), 1.0 / 30.0);
        assert_eq!(dt_f32_s(30.0), 1.0f32 / 30.0);
        assert_eq!(dt_f32_s(4.0), 0.25f32);
        assert_eq!(dt_f32_s(60.0), 1.0f32 / 60.0);
    }

    /// Headings land in `[0, 360)`, whatever the turn count or sign;
    /// `-0.0` and a tiny negative angle give `+0.0`; NaN and infinities
    /// give NaN.
    #[test]
    fn headings_wrap_into_0_to_360() {
        for (degrees, wrapped) in [
            (-90.0, 270.0),
            (720.0, 0.0),
            (450.0, 90.0),
            (-450.0, 270.0),
            (359.5, 359.5),
            (360.0, 0.0),
            (-360.0, 0.0),
            (0.0, 0.0),
            (1e-300, 1e-300),
        ] {
            let got = wrap_degrees_360(degrees);
            assert_eq!(got, wrapped, "{degrees}");
            assert!(got.is_sign_positive(), "{degrees} gave {got:?}");
        }
        for tiny in [-0.0, -1e-300, -1e-14] {
            let got = wrap_degrees_360(tiny);
            assert!((0.0..360.0).contains(&got), "{tiny} gave {got:?}");
            assert!(got.is_sign_positive(), "{tiny} gave {got:?}");
            // The same heading: 360 - |tiny| rounds to 360, which is 0 on the
            // circle, so the wrap is within |tiny| of the input there.
            let apart = (got - tiny).rem_euclid(360.0);
            assert!(
                apart.min(360.0 - apart) <= tiny.abs(),
                "{tiny} gave {got:?}"
            );
        }
        assert_eq!(wrap_degrees_360(-0.0).to_bits(), 0.0f64.to_bits());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(wrap_degrees_360(bad).is_nan(), "{bad}");
        }
    }
}
