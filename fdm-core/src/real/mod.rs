//! The number type the models' steps are written over: one source, instantiated
//! as a plain float (`f64`, `f32`) for one aircraft and as lane vectors
//! ([`F64s`], [`F32s`]) for many aircraft per SIMD instruction, in the style of
//! dimforge's parry/rapier over simba.
//!
//! * [`Real`]: `+ - * /`, negation, `sqrt`, `abs`, comparisons that give a
//!   [`Mask`], and [`Real::select`] (a scalar `if` as a blend). For `f64` and
//!   `f32` every method is the plain operation (the mask is a `bool`, `select`
//!   an `if`), so the scalar instantiation compiles to the code a hand-written
//!   scalar step would; for lanes every operation is one loop over the lanes
//!   that LLVM turns into vector instructions.
//! * [`Maths`]: the transcendental functions a step calls, as a choice:
//!   [`Exact`] gives every lane the bits of [`crate::math`]'s scalar
//!   function, the bits of the scalar step (for lanes, `pow` and `asinf` are
//!   evaluated lane-wise in vector registers: [`Real::pow_exact`],
//!   [`Real::asinf_exact`]); [`Fast`] replaces those that have a
//!   vectorised form (today `pow(x, 5.25)`, [`fast::pow_5_25`]) and keeps the
//!   exact function for the others. Any model's step takes one as a type
//!   parameter.
//! * [`V3`]: a 3-vector of any [`Real`], with the left-to-right sums of the
//!   original programs.
//! * [`LaneModel`]: a [`Model`] whose step is written over [`Real`]: what a
//!   structure-of-arrays fleet (`fdm-fleet`'s `Fleet<M>`) needs to fly it.
//!
//! # Why a lane has the bits of the scalar step
//!
//! Every operator is the same IEEE operation, lane by lane: `+ - * /` and
//! `sqrt` are correctly rounded in SIMD as in scalar code, and Rust never
//! fuses `a * b + c` into an FMA by itself (it gives LLVM no fast-math or
//! `contract` flags), so a lane's result has the bits of the scalar
//! expression whatever the instruction set. A constant on the left of an
//! operator is written `R::splat(c) * x` (not `x * c`), so even the operand
//! order, which decides which NaN payload survives, is the scalar code's.
//! A scalar `if` becomes a mask and a [`Real::select`] of both branches; the
//! branch not taken may compute a NaN (a division by zero) that the blend
//! drops, which changes no kept value.

#[cfg(feature = "std")]
pub mod kernel;
mod lanes;
mod maths;
mod permute;

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

pub use lanes::{F32s, F64s, LaneMask, Lanes};
pub use maths::{fast, Exact, Fast, Maths};
pub use permute::{NoPermutes, Permutes};

use crate::model::Model;

/// Lane booleans: the result of a lane-wise comparison (`bool` for one
/// aircraft).
pub trait Mask: Copy + Debug + PartialEq + Send + Sync + 'static {
    /// Every lane `b`.
    fn splat(b: bool) -> Self;
    /// Lane-wise `&&`.
    #[must_use]
    fn and(self, rhs: Self) -> Self;
    /// Lane-wise `||`.
    #[must_use]
    fn or(self, rhs: Self) -> Self;
    /// Lane-wise `!`.
    #[must_use]
    fn not(self) -> Self;
    /// Whether any lane is set.
    fn any(self) -> bool;
    /// Lane `i`.
    fn lane(self, i: usize) -> bool;
    /// Sets lane `i` to `b`.
    fn set_lane(&mut self, i: usize, b: bool);
}

impl Mask for bool {
    #[inline(always)]
    fn splat(b: bool) -> Self {
        b
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        self && rhs
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        self || rhs
    }
    #[inline(always)]
    fn not(self) -> Self {
        !self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn lane(self, _: usize) -> bool {
        self
    }
    #[inline(always)]
    fn set_lane(&mut self, _: usize, b: bool) {
        *self = b;
    }
}

/// A number of a model's step: a float for one aircraft, a lane vector for
/// several (see the [module docs](self)).
pub trait Real:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<Self::Scalar, Output = Self>
    + Sub<Self::Scalar, Output = Self>
    + Mul<Self::Scalar, Output = Self>
    + Div<Self::Scalar, Output = Self>
{
    /// The float of one lane (`f64` or `f32`).
    type Scalar: Copy + Debug + PartialEq + PartialOrd + Send + Sync + 'static;
    /// The result of a comparison.
    type Mask: Mask;
    /// Lanes: 1 for a float.
    const LANES: usize;

    /// Every lane `x`.
    fn splat(x: Self::Scalar) -> Self;
    /// Lane `i`.
    fn lane(self, i: usize) -> Self::Scalar;
    /// Sets lane `i` to `x`.
    fn set_lane(&mut self, i: usize, x: Self::Scalar);
    /// `f` applied to every lane (a scalar function called lane by lane).
    #[must_use]
    fn map(self, f: impl Fn(Self::Scalar) -> Self::Scalar) -> Self;
    /// Square root (correctly rounded, through [`crate::math`]).
    #[must_use]
    fn sqrt(self) -> Self;
    /// Absolute value (the sign bit cleared, like C's `fabs`).
    #[must_use]
    fn abs(self) -> Self;
    /// `self * a + b` with one rounding (only the [`Fast`] maths use it, for
    /// exact product errors).
    #[must_use]
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// Lane-wise `self < rhs` (false for NaN, like the scalar `<`).
    fn lt(self, rhs: Self::Scalar) -> Self::Mask;
    /// Lane-wise `self <= rhs`.
    fn le(self, rhs: Self::Scalar) -> Self::Mask;
    /// Lane-wise `self > rhs`.
    fn gt(self, rhs: Self::Scalar) -> Self::Mask;
    /// Lane-wise `self == rhs`.
    fn eq(self, rhs: Self::Scalar) -> Self::Mask;
    /// Lane-wise `is_finite`.
    fn is_finite(self) -> Self::Mask;
    /// Lane-wise `is_normal`.
    fn is_normal(self) -> Self::Mask;
    /// `if_true` in the lanes where `mask` is set, `if_false` elsewhere.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
    /// [`crate::math::pow`]`(x, y)` of every lane `x`, bit for bit. A float
    /// calls it; lanes ([`F64s`]) evaluate its usual path lane-wise in vector
    /// registers and call it only for the lanes off that path.
    #[inline(always)]
    #[must_use]
    fn pow_exact(self, y: f64) -> Self
    where
        Self: Real<Scalar = f64>,
    {
        // Inlined, without a dispatch of its own: the scalar steps run under
        // `crate::math::with_fma` (one run-time check per step).
        self.map(
            #[inline(always)]
            |x| crate::math::pow_inlined(x, y),
        )
    }
    /// [`crate::math::asinf`] of every lane, bit for bit. A float calls it;
    /// lanes ([`F32s`]) evaluate it lane-wise in vector registers and look up
    /// the exception table only for the lanes that may be in it.
    #[inline(always)]
    #[must_use]
    fn asinf_exact(self) -> Self
    where
        Self: Real<Scalar = f32>,
    {
        self.map(crate::math::asinf)
    }
    /// [`Real::asinf_exact`] of eight values (Bourg's eight elements), each
    /// with its own bits. A lane type maps [`Real::asinf_exact`]; a float
    /// evaluates the eight together as eight lanes (`crate::math`'s
    /// lane-wise `asinf`, bit-identical to the scalar one), so the scalar
    /// step gets vector instructions and no branch per element.
    #[inline(always)]
    #[must_use]
    fn asinf_exact_8(values: [Self; 8]) -> [Self; 8]
    where
        Self: Real<Scalar = f32>,
    {
        // Written out, not `values.map(..)`: the compiler kept that map out
        // of line, compiled for the baseline instruction set, in the fleet
        // kernels (36 % of Bourg's kernel time on an AVX-512 machine).
        let [a, b, c, d, e, f, g, h] = values;
        [
            a.asinf_exact(),
            b.asinf_exact(),
            c.asinf_exact(),
            d.asinf_exact(),
            e.asinf_exact(),
            f.asinf_exact(),
            g.asinf_exact(),
            h.asinf_exact(),
        ]
    }
}

macro_rules! scalar_real {
    ($t:ty, $sqrt:path, $bits:ty, $fma:ident $(, $extra:item)*) => {
        impl Real for $t {
            $($extra)*
            type Scalar = $t;
            type Mask = bool;
            const LANES: usize = 1;

            #[inline(always)]
            fn splat(x: $t) -> Self {
                x
            }
            #[inline(always)]
            fn lane(self, _: usize) -> $t {
                self
            }
            #[inline(always)]
            fn set_lane(&mut self, _: usize, x: $t) {
                *self = x;
            }
            #[inline(always)]
            fn map(self, f: impl Fn($t) -> $t) -> Self {
                f(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::from_bits(self.to_bits() & (<$bits>::MAX >> 1))
            }
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                #[cfg(feature = "std")]
                {
                    <$t>::mul_add(self, a, b)
                }
                #[cfg(not(feature = "std"))]
                {
                    libm::$fma(self, a, b)
                }
            }
            #[inline(always)]
            fn lt(self, rhs: $t) -> bool {
                self < rhs
            }
            #[inline(always)]
            fn le(self, rhs: $t) -> bool {
                self <= rhs
            }
            #[inline(always)]
            fn gt(self, rhs: $t) -> bool {
                self > rhs
            }
            #[inline(always)]
            fn eq(self, rhs: $t) -> bool {
                self == rhs
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn is_normal(self) -> bool {
                <$t>::is_normal(self)
            }
            #[inline(always)]
            fn select(mask: bool, if_true: Self, if_false: Self) -> Self {
                if mask {
                    if_true
                } else {
                    if_false
                }
            }
        }
    };
}

scalar_real!(f64, crate::math::sqrt, u64, fma);
scalar_real!(
    f32,
    crate::math::sqrtf,
    u32,
    fmaf,
    #[inline(always)]
    fn asinf_exact_8(values: [f32; 8]) -> [f32; 8] {
        crate::math::asinf_lanes_blended(values)
    }
);

/// A 3-vector of [`Real`]s (`x`, `y`, `z`). Its sums run left to right, as the
/// original programs' (`a + b + c` is `(a + b) + c`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<R> {
    /// First component.
    pub x: R,
    /// Second component.
    pub y: R,
    /// Third component.
    pub z: R,
}

impl<R: Real> V3<R> {
    /// `(x, y, z)`.
    #[inline(always)]
    pub const fn new(x: R, y: R, z: R) -> Self {
        Self { x, y, z }
    }

    /// Every lane of every component from a scalar vector.
    #[inline(always)]
    pub fn splat(x: R::Scalar, y: R::Scalar, z: R::Scalar) -> Self {
        Self::new(R::splat(x), R::splat(y), R::splat(z))
    }

    /// Dot product `ux vx + uy vy + uz vz`, summed left to right.
    #[inline(always)]
    pub fn dot(self, v: Self) -> R {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// Cross product `(uy vz − uz vy, −ux vz + uz vx, ux vy − uy vx)`.
    #[inline(always)]
    #[must_use]
    pub fn cross(self, v: Self) -> Self {
        let u = self;
        Self::new(
            u.y * v.z - u.z * v.y,
            -u.x * v.z + u.z * v.x,
            u.x * v.y - u.y * v.x,
        )
    }

    /// `sqrt(x² + y² + z²)`, the squares summed left to right.
    #[inline(always)]
    pub fn magnitude(self) -> R {
        (self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    /// Lane-wise `if mask { a } else { b }`.
    #[inline(always)]
    pub fn select(mask: R::Mask, a: Self, b: Self) -> Self {
        Self::new(
            R::select(mask, a.x, b.x),
            R::select(mask, a.y, b.y),
            R::select(mask, a.z, b.z),
        )
    }

    /// Lane `i` as a scalar vector.
    #[inline(always)]
    pub fn lane(self, i: usize) -> V3<R::Scalar> {
        V3 {
            x: self.x.lane(i),
            y: self.y.lane(i),
            z: self.z.lane(i),
        }
    }

    /// Sets lane `i` to the scalar vector `v`.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, v: V3<R::Scalar>) {
        self.x.set_lane(i, v.x);
        self.y.set_lane(i, v.y);
        self.z.set_lane(i, v.z);
    }
}

impl<R: Real> Add for V3<R> {
    type Output = Self;
    /// Component-wise sum.
    #[inline(always)]
    fn add(self, v: Self) -> Self {
        Self::new(self.x + v.x, self.y + v.y, self.z + v.z)
    }
}

impl<R: Real> Sub for V3<R> {
    type Output = Self;
    /// Component-wise difference.
    #[inline(always)]
    fn sub(self, v: Self) -> Self {
        Self::new(self.x - v.x, self.y - v.y, self.z - v.z)
    }
}

impl<R: Real> Neg for V3<R> {
    type Output = Self;
    /// Component-wise negation.
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<R: Real> Mul<R> for V3<R> {
    type Output = Self;
    /// Each component times `s`.
    #[inline(always)]
    fn mul(self, s: R) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<R: Real> Div<R> for V3<R> {
    type Output = Self;
    /// Each component divided by `s` (a true division per component).
    #[inline(always)]
    fn div(self, s: R) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }
}

impl<T: nalgebra::Scalar + Copy> From<nalgebra::Vector3<T>> for V3<T> {
    #[inline(always)]
    fn from(v: nalgebra::Vector3<T>) -> Self {
        Self {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

impl<T: nalgebra::Scalar + Copy> From<V3<T>> for nalgebra::Vector3<T> {
    #[inline(always)]
    fn from(v: V3<T>) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

/// A [`Model`] whose step is written once over [`Real`], so that a
/// structure-of-arrays fleet can fly it [`Self::Lanes`] aircraft per SIMD
/// instruction (`fdm-fleet`'s `Fleet<M>`), every aircraft bit-identical to
/// [`Model::step`] with [`Exact`] maths.
///
/// A fleet block holds one [`Self::Vars`] (the integrated state of every lane),
/// one [`Self::Terms`] (what each lane's step derives from its controls alone,
/// computed when the controls are set), the clocks, the controls and the
/// flight statuses; the methods here move one lane in and out of them and
/// step them all.
pub trait LaneModel: Model {
    /// The lane vector: [`F64s`] or [`F32s`] of the block's width.
    type Lanes: Lanes;
    /// What the step derives from the aircraft alone (computed once per fleet).
    type Shared: Clone + Debug + Send + Sync + 'static;
    /// Every lane's integrated state (the clock aside), as lane vectors.
    type Vars: Copy + Debug + Send + Sync + 'static;
    /// Every lane's control terms (what the step reads of the controls).
    type Terms: Copy + Debug + Send + Sync + 'static;
    /// Whether the [`Fast`] maths change this model's step (a step that calls
    /// no function with a vectorised form is the same under both, and a fleet
    /// refuses `fast` for it rather than pretend).
    const HAS_FAST: bool;

    /// Why an aircraft cannot be flown ([`Self::check_aircraft`]).
    type AircraftError: core::error::Error + Send + Sync + 'static;

    /// Why `aircraft` cannot be flown, if it cannot.
    ///
    /// # Errors
    /// The reason.
    fn check_aircraft(aircraft: &Self::Aircraft) -> Result<(), Self::AircraftError>;

    /// The aircraft's [`Self::Shared`] terms.
    fn shared(aircraft: &Self::Aircraft) -> Self::Shared;

    /// A block of idle aircraft: every lane at [`Model::initial_state`] with
    /// [`Model::initial_controls`].
    fn idle(aircraft: &Self::Aircraft) -> (Self::Vars, Self::Terms);

    /// Lane `lane` of `vars` as a state, with its clock `time_s`.
    fn state(vars: &Self::Vars, time_s: f64, lane: usize) -> Self::State;

    /// Writes `state` into lane `lane` of `vars`; returns its clock.
    fn set_state(vars: &mut Self::Vars, lane: usize, state: &Self::State) -> f64;

    /// Writes the terms of `controls` into lane `lane` of `terms`.
    fn set_controls(
        terms: &mut Self::Terms,
        lane: usize,
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        controls: &Self::Controls,
    );

    /// Writes the terms of `controls[lane]` into lane `lane` of `terms` for
    /// the first `count` lanes: [`Self::set_controls`] for each of them
    /// (the provided body), or the same bits computed for the lanes
    /// together.
    #[inline]
    fn set_controls_lanes(
        terms: &mut Self::Terms,
        count: usize,
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        controls: &<Self::Lanes as Lanes>::Array<Self::Controls>,
    ) {
        for (lane, c) in controls.as_ref().iter().enumerate().take(count) {
            Self::set_controls(terms, lane, aircraft, shared, c);
        }
    }

    /// One step of every lane (the clock aside): the model's step, lane-wise,
    /// with the maths `F`. Bit-identical to [`Model::step`] lane by lane with
    /// [`Exact`].
    fn step_lanes<F: Maths>(
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: Self::TimeStep,
    ) -> Self::Vars;

    /// [`Self::step_lanes`] with the instruction set's lane permutes at hand
    /// (the fleet kernel's, [`Permutes`]): the same bits. The provided body
    /// ignores them; a model whose step has table look-ups in lanes (Bourg)
    /// fetches their entries with them.
    #[inline(always)]
    fn step_lanes_permuting<F: Maths, P: Permutes>(
        permutes: P,
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: Self::TimeStep,
    ) -> Self::Vars {
        let _ = permutes;
        Self::step_lanes::<F>(aircraft, shared, terms, vars, dt)
    }

    /// Every component of `vars`, for the fleet's finiteness check: `f` gets
    /// each lane vector in turn.
    fn for_each_component(vars: &Self::Vars, f: impl FnMut(Self::Lanes));

    /// The lanes above the ground plane: height `> 0` ([`Model::height_m`]'s
    /// sign, read in the model's own unit; false for NaN).
    fn above_ground(vars: &Self::Vars) -> <Self::Lanes as Real>::Mask;

    /// Below this magnitude in every component (and a finite clock), a stepped
    /// lane's state is certainly finite for [`Model::is_finite`] (its derived
    /// outputs, e.g. a speed, cannot overflow); a lane at or beyond it goes
    /// through the scalar checks.
    const SUSPECT: <Self::Lanes as Real>::Scalar;

    /// `state`'s position in the model frame, metres (x north, y west, z up):
    /// the `position_m` of [`Model::view`], bit for bit.
    fn position_m(state: &Self::State) -> nalgebra::Vector3<f64>;

    /// The fleet kernel over `blocks` on this thread: [`kernel::run_blocks`]
    /// (the provided body; see there for `arch`, `fast` and `fly`). An
    /// implementation that overrides it has the provided body, written out:
    /// overriding only chooses the crate the kernel is compiled in (the
    /// models of this crate override it so that their kernels are compiled
    /// once, here, and not again in every crate that flies a fleet: see
    /// [`kernel`]).
    #[cfg(feature = "std")]
    fn run_blocks(
        blocks: &mut [kernel::Block<Self>],
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        dt: Self::TimeStep,
        arch: pulp::Arch,
        fast: bool,
        fly: bool,
    ) {
        kernel::run_blocks::<Self>(blocks, aircraft, shared, dt, arch, fast, fly);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scalar step's mask is a `bool`, one lane: every method of [`Mask`]
    /// is the trait's lane-wise operation on that lane (the scalar
    /// instantiation of a step is the hand-written scalar code).
    #[test]
    fn a_bool_is_a_mask_of_one_lane() {
        for a in [false, true] {
            assert_eq!(<bool as Mask>::splat(a), a);
            assert_eq!(Mask::not(a), !a);
            assert_eq!(Mask::any(a), a, "any lane set");
            assert_eq!(Mask::lane(a, 0), a, "lane 0 is the bool");
            for b in [false, true] {
                assert_eq!(Mask::and(a, b), a && b, "{a} and {b}");
                assert_eq!(Mask::or(a, b), a || b, "{a} or {b}");
                let mut m = a;
                m.set_lane(0, b);
                assert_eq!(m, b, "lane 0 of {a} set to {b}");
            }
        }
    }
}
