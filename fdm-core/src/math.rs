//! Scalar math facade.
//!
//! With the `std` feature the functions call the platform's libm through `std`
//! (glibc on Linux, like the original C and C++ programs, so results agree to the
//! last bit); without it they call the pure-Rust [`libm`] crate, which may differ
//! in the last ulp for some transcendental functions. `sqrt` is correctly rounded
//! in both.

macro_rules! facade {
    ($( $(#[$doc:meta])* $name:ident($($arg:ident),+) : $ty:ty => std $std:ident, libm $libm:ident;)*) => {
        $(
            $(#[$doc])*
            #[inline(always)]
            #[must_use]
            pub fn $name($($arg: $ty),+) -> $ty {
                #[cfg(feature = "std")]
                { facade!(@std $std, $($arg),+) }
                #[cfg(not(feature = "std"))]
                { libm::$libm($($arg),+) }
            }
        )*
    };
    (@std $std:ident, $first:ident) => { $first.$std() };
    (@std $std:ident, $first:ident, $second:ident) => { $first.$std($second) };
}

facade! {
    /// Square root (f64).
    sqrt(x): f64 => std sqrt, libm sqrt;
    /// `x` raised to the power `y` (f64), C's `pow`.
    pow(x, y): f64 => std powf, libm pow;
    /// Sine (f64, radians).
    sin(x): f64 => std sin, libm sin;
    /// Cosine (f64, radians).
    cos(x): f64 => std cos, libm cos;
    /// Arc tangent (f64, radians).
    atan(x): f64 => std atan, libm atan;
    /// Four-quadrant arc tangent `atan2(y, x)` (f64, radians).
    atan2(y, x): f64 => std atan2, libm atan2;
    /// Arc sine (f64, radians).
    asin(x): f64 => std asin, libm asin;
    /// `sqrt(x² + y²)` without undue overflow (f64), C's `hypot`.
    hypot(x, y): f64 => std hypot, libm hypot;
    /// Cube root (f64), C's `cbrt`.
    cbrt(x): f64 => std cbrt, libm cbrt;
    /// Square root (f32), C's `sqrtf`.
    sqrtf(x): f32 => std sqrt, libm sqrtf;
    /// Sine (f32, radians), C's `sinf`.
    sinf(x): f32 => std sin, libm sinf;
    /// Cosine (f32, radians), C's `cosf`.
    cosf(x): f32 => std cos, libm cosf;
    /// Arc sine (f32, radians), C's `asinf`.
    asinf(x): f32 => std asin, libm asinf;
    /// Four-quadrant arc tangent (f32, radians), C's `atan2f`.
    atan2f(y, x): f32 => std atan2, libm atan2f;
}

/// Sine and cosine of `x` (f64, radians): `(sin(x), cos(x))`, which is what
/// `f64::sin_cos` computes with `std`.
#[inline(always)]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    (sin(x), cos(x))
}

/// `x * x`, which is what `x.powi(2)` computes (exactly one rounding).
#[inline(always)]
#[must_use]
pub fn square(x: f64) -> f64 {
    x * x
}
