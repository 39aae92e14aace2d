//! The float types the Bourg model can run in: [`BourgFloat`], implemented for
//! `f32` (the original program's type, bit-exact) and `f64`.

use core::ops::{Add, Div, Mul, Neg, Sub};

use nalgebra::{ClosedAddAssign, ClosedDivAssign, ClosedMulAssign, ClosedSubAssign, Scalar};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::math;

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// One element of the default airframe's data: `(mass, design position, local
/// inertia, incidence, dihedral, area)`.
#[doc(hidden)]
pub type ElementData<F> = (F, [F; 3], [F; 3], F, F, F);

/// A float type the Bourg model can be instantiated with: `f32` or `f64` (sealed).
///
/// Everything the original C++ computes in `float` is computed in `Self`; the
/// few places where the C++ widens to `double` (`MakeQFromEulerAngles`, parts of
/// `MakeEulerAnglesFromQ`) widen to `f64` through [`to_f64`](Self::to_f64) and
/// [`from_f64`](Self::from_f64). For `f32` this reproduces the original's
/// float/double mix exactly; for `f64` the widening is the identity and the model
/// becomes "the C++ with every float turned into a double".
///
/// The constants, airfoil tables and default airframe are the original's
/// `float` literals (`3.14159265f` is the `f32` value 3.14159274, `0.2f` is
/// 0.200000003). The `f64` model widens these same `f32` values exactly, so it
/// is the C++ with every `float` variable turned into a `double` but its
/// `f`-suffixed literals kept: the `f32` and `f64` models differ only in the
/// rounding of the arithmetic, not in their data. (Using the decimal values in
/// `f64` instead changes the model itself: with `pi = 3.14159265` exactly,
/// `cos(pi/2)` is +1.8e-9 instead of −4.4e-8, which flips the rudder's side
/// force in symmetric flight.)
///
/// The transcendental functions go through [`crate::math`]: the platform libm
/// with the `std` feature (glibc on Linux, as the original), the `libm` crate
/// without it.
pub trait BourgFloat:
    sealed::Sealed
    + Scalar
    + Copy
    + Default
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + ClosedAddAssign
    + ClosedSubAssign
    + ClosedMulAssign
    + ClosedDivAssign
    + Serialize
    + DeserializeOwned
    + Send
    + Sync
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 0.5 (the C++ `0.5f`).
    const HALF: Self;
    /// 2.
    const TWO: Self;
    /// 180 (the C++ `180.0f` of the degree/radian conversions).
    const DEG_180: Self;
    /// π as the original writes it: `3.14159265f` (`f32`: 3.14159274).
    const PI: Self;
    /// Gravitational acceleration, ft/s², negative (earth z is up): −32.174.
    const G_FTPS2: Self;
    /// Air density, slug/ft³: 0.0023769.
    const RHO_SLUG_FT3: Self;
    /// The `Normalize` tolerance: 1e-15.
    const TOL: Self;

    /// Square root (`sqrtf` / `sqrt`; correctly rounded).
    fn sqrt(self) -> Self;
    /// Sine, radians (`sinf` / `sin`).
    fn sin(self) -> Self;
    /// Cosine, radians (`cosf` / `cos`).
    fn cos(self) -> Self;
    /// Arc sine, radians (`asinf` / `asin`).
    fn asin(self) -> Self;
    /// Absolute value (`fabs`: clears the sign bit, also of −0 and NaN).
    fn abs(self) -> Self;
    /// Whether the value is neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// Exact widening to `f64` (the C++'s implicit float → double).
    fn to_f64(self) -> f64;
    /// Rounding narrowing from `f64` (the C++'s `(float)` cast); identity for `f64`.
    fn from_f64(x: f64) -> Self;

    /// Airfoil table abscissae: angle of attack, degrees.
    #[doc(hidden)]
    const AIRFOIL_ALPHA_DEG: [Self; 9];
    /// Lift coefficients, no flap deflection.
    #[doc(hidden)]
    const CL_NEUTRAL: [Self; 9];
    /// Lift coefficients, "flaps down" table (flap code −1).
    #[doc(hidden)]
    const CL_TRAILING_EDGE_DOWN: [Self; 9];
    /// Lift coefficients, "flaps up" table (flap code +1).
    #[doc(hidden)]
    const CL_TRAILING_EDGE_UP: [Self; 9];
    /// Drag coefficients, no flap deflection.
    #[doc(hidden)]
    const CD_NEUTRAL: [Self; 9];
    /// Drag coefficients, "flaps down" table.
    #[doc(hidden)]
    const CD_TRAILING_EDGE_DOWN: [Self; 9];
    /// Drag coefficients, "flaps up" table.
    #[doc(hidden)]
    const CD_TRAILING_EDGE_UP: [Self; 9];
    /// Drag coefficient outside the tables: 0.75.
    #[doc(hidden)]
    const CD_OUTSIDE: Self;
    /// Rudder table abscissae: |angle of attack|, degrees.
    #[doc(hidden)]
    const RUDDER_ALPHA_DEG: [Self; 7];
    /// Rudder lift coefficients (symmetric).
    #[doc(hidden)]
    const RUDDER_CL: [Self; 7];
    /// Rudder drag coefficients (symmetric).
    #[doc(hidden)]
    const RUDDER_CD: [Self; 7];

    /// The default airframe's element data `(mass, design position, local
    /// inertia, incidence, dihedral, area)` as literals of `Self`.
    #[doc(hidden)]
    const DEFAULT_ELEMENTS: [ElementData<Self>; 8];
}

impl BourgFloat for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
    const TWO: Self = 2.0;
    const DEG_180: Self = 180.0;
    #[allow(clippy::excessive_precision, clippy::approx_constant)]
    const PI: Self = 3.14159265;
    const G_FTPS2: Self = -32.174;
    const RHO_SLUG_FT3: Self = 0.0023769;
    const TOL: Self = 1e-15;

    #[inline(always)]
    fn sqrt(self) -> Self {
        math::sqrtf(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        math::sinf(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        math::cosf(self)
    }
    #[inline(always)]
    fn asin(self) -> Self {
        math::asinf(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::from_bits(self.to_bits() & 0x7fff_ffff)
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline(always)]
    #[allow(clippy::cast_possible_truncation)]
    fn from_f64(x: f64) -> Self {
        x as f32
    }

    const AIRFOIL_ALPHA_DEG: [Self; 9] = [-8.0, -4.0, 0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 24.0];
    const CL_NEUTRAL: [Self; 9] = [-0.54, -0.2, 0.2, 0.57, 0.92, 1.21, 1.43, 1.4, 1.0];
    const CL_TRAILING_EDGE_DOWN: [Self; 9] = [0.0, 0.45, 0.85, 1.02, 1.39, 1.65, 1.75, 1.38, 1.17];
    const CL_TRAILING_EDGE_UP: [Self; 9] = [-0.74, -0.4, 0.0, 0.27, 0.63, 0.92, 1.03, 1.1, 0.78];
    const CD_NEUTRAL: [Self; 9] = [0.01, 0.0074, 0.004, 0.009, 0.013, 0.023, 0.05, 0.12, 0.21];
    const CD_TRAILING_EDGE_DOWN: [Self; 9] = [
        0.0065, 0.0043, 0.0055, 0.0153, 0.0221, 0.0391, 0.1, 0.195, 0.3,
    ];
    const CD_TRAILING_EDGE_UP: [Self; 9] = [
        0.005, 0.0043, 0.0055, 0.02601, 0.03757, 0.06647, 0.13, 0.18, 0.25,
    ];
    const CD_OUTSIDE: Self = 0.75;
    const RUDDER_ALPHA_DEG: [Self; 7] = [0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 24.0];
    const RUDDER_CL: [Self; 7] = [0.16, 0.456, 0.736, 0.968, 1.144, 1.12, 0.8];
    const RUDDER_CD: [Self; 7] = [0.0032, 0.0072, 0.0104, 0.0184, 0.04, 0.096, 0.168];

    const DEFAULT_ELEMENTS: [ElementData<Self>; 8] = [
        // 0: outboard port wing, aileron
        (
            6.56,
            [14.5, 12.0, 2.5],
            [13.92, 10.50, 24.00],
            -3.5,
            0.0,
            31.2,
        ),
        // 1: inboard port wing, landing flap
        (
            7.31,
            [14.5, 5.5, 2.5],
            [21.95, 12.22, 33.67],
            -3.5,
            0.0,
            36.4,
        ),
        // 2: inboard starboard wing, landing flap
        (
            7.31,
            [14.5, -5.5, 2.5],
            [21.95, 12.22, 33.67],
            -3.5,
            0.0,
            36.4,
        ),
        // 3: outboard starboard wing, aileron
        (
            6.56,
            [14.5, -12.0, 2.5],
            [13.92, 10.50, 24.00],
            -3.5,
            0.0,
            31.2,
        ),
        // 4: port elevator
        (
            2.62,
            [3.03, 2.5, 3.0],
            [0.837, 0.385, 1.206],
            0.0,
            0.0,
            10.8,
        ),
        // 5: starboard elevator
        (
            2.62,
            [3.03, -2.5, 3.0],
            [0.837, 0.385, 1.206],
            0.0,
            0.0,
            10.8,
        ),
        // 6: vertical tail / rudder
        (
            2.93,
            [2.25, 0.0, 5.0],
            [1.262, 1.942, 0.718],
            0.0,
            90.0,
            12.0,
        ),
        // 7: fuselage
        (
            31.8,
            [15.25, 0.0, 1.5],
            [66.30, 861.9, 861.9],
            0.0,
            0.0,
            84.0,
        ),
    ];
}

/// Exact `f32` → `f64` widening of a constant array.
const fn widen<const N: usize>(a: [f32; N]) -> [f64; N] {
    let mut out = [0.0; N];
    let mut i = 0;
    while i < N {
        out[i] = a[i] as f64;
        i += 1;
    }
    out
}

/// Exact widening of the default airframe's data.
const fn widen_elements(a: [ElementData<f32>; 8]) -> [ElementData<f64>; 8] {
    let mut out = [(0.0, [0.0; 3], [0.0; 3], 0.0, 0.0, 0.0); 8];
    let mut i = 0;
    while i < 8 {
        let (m, d, l, inc, dih, area) = a[i];
        out[i] = (
            m as f64,
            widen(d),
            widen(l),
            inc as f64,
            dih as f64,
            area as f64,
        );
        i += 1;
    }
    out
}

/// The `f64` model: `f64` arithmetic throughout, with the original's `float`
/// constants widened exactly (see [`BourgFloat`]).
impl BourgFloat for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
    const TWO: Self = 2.0;
    const DEG_180: Self = 180.0;
    const PI: Self = <f32 as BourgFloat>::PI as f64;
    const G_FTPS2: Self = <f32 as BourgFloat>::G_FTPS2 as f64;
    const RHO_SLUG_FT3: Self = <f32 as BourgFloat>::RHO_SLUG_FT3 as f64;
    const TOL: Self = <f32 as BourgFloat>::TOL as f64;

    #[inline(always)]
    fn sqrt(self) -> Self {
        math::sqrt(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        math::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        math::cos(self)
    }
    #[inline(always)]
    fn asin(self) -> Self {
        math::asin(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::from_bits(self.to_bits() & 0x7fff_ffff_ffff_ffff)
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x
    }

    const AIRFOIL_ALPHA_DEG: [Self; 9] = widen(<f32 as BourgFloat>::AIRFOIL_ALPHA_DEG);
    const CL_NEUTRAL: [Self; 9] = widen(<f32 as BourgFloat>::CL_NEUTRAL);
    const CL_TRAILING_EDGE_DOWN: [Self; 9] = widen(<f32 as BourgFloat>::CL_TRAILING_EDGE_DOWN);
    const CL_TRAILING_EDGE_UP: [Self; 9] = widen(<f32 as BourgFloat>::CL_TRAILING_EDGE_UP);
    const CD_NEUTRAL: [Self; 9] = widen(<f32 as BourgFloat>::CD_NEUTRAL);
    const CD_TRAILING_EDGE_DOWN: [Self; 9] = widen(<f32 as BourgFloat>::CD_TRAILING_EDGE_DOWN);
    const CD_TRAILING_EDGE_UP: [Self; 9] = widen(<f32 as BourgFloat>::CD_TRAILING_EDGE_UP);
    const CD_OUTSIDE: Self = <f32 as BourgFloat>::CD_OUTSIDE as f64;
    const RUDDER_ALPHA_DEG: [Self; 7] = widen(<f32 as BourgFloat>::RUDDER_ALPHA_DEG);
    const RUDDER_CL: [Self; 7] = widen(<f32 as BourgFloat>::RUDDER_CL);
    const RUDDER_CD: [Self; 7] = widen(<f32 as BourgFloat>::RUDDER_CD);

    const DEFAULT_ELEMENTS: [ElementData<Self>; 8] =
        widen_elements(<f32 as BourgFloat>::DEFAULT_ELEMENTS);
}
