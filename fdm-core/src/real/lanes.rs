//! `N` f64 or f32 lanes with lane-wise IEEE operations.
//!
//! Every operator is one plain loop over `[f64; N]` (or `[f32; N]`) that LLVM
//! turns into one (or a few) vector instructions of the instruction set the
//! caller was compiled for. Each lane gets exactly the IEEE operation a scalar
//! `f64` (`f32`) expression would (see the [parent module](super)).

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

use super::{Mask, Real};

/// A lane vector of a fleet block: a [`Real`] with per-lane arrays of any
/// type (the block's clocks, controls and statuses).
pub trait Lanes: Real {
    /// `[T; N]`, `N` = [`Real::LANES`].
    type Array<T: Copy + Debug + Send + Sync + 'static>: Copy
        + Debug
        + Send
        + Sync
        + AsRef<[T]>
        + AsMut<[T]>;
    /// The array `[f(0), f(1), ...]`.
    fn array<T: Copy + Debug + Send + Sync + 'static>(f: impl FnMut(usize) -> T) -> Self::Array<T>;
}

/// `N` lane booleans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LaneMask<const N: usize>(pub [bool; N]);

impl<const N: usize> Mask for LaneMask<N> {
    #[inline(always)]
    fn splat(b: bool) -> Self {
        Self([b; N])
    }
    #[inline(always)]
    fn and(self, rhs: Self) -> Self {
        Self(each_lane!(N, |i| self.0[i] & rhs.0[i]))
    }
    #[inline(always)]
    fn or(self, rhs: Self) -> Self {
        Self(each_lane!(N, |i| self.0[i] | rhs.0[i]))
    }
    #[inline(always)]
    fn not(self) -> Self {
        Self(each_lane!(N, |i| !self.0[i]))
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(false, |acc, &b| acc | b)
    }
    #[inline(always)]
    fn lane(self, i: usize) -> bool {
        self.0[i]
    }
    #[inline(always)]
    fn set_lane(&mut self, i: usize, b: bool) {
        self.0[i] = b;
    }
}

impl<const N: usize> LaneMask<N> {
    /// `if_true` in the lanes where the mask is set, `if_false` elsewhere
    /// ([`Real::select`]).
    #[inline(always)]
    #[must_use]
    pub fn select<V: Real<Mask = Self>>(self, if_true: V, if_false: V) -> V {
        V::select(self, if_true, if_false)
    }
}

macro_rules! lane_op {
    ($name:ident, $t:ty, $trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for $name<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self(each_lane!(N, |i| self.0[i] $op rhs.0[i]))
            }
        }
        impl<const N: usize> $trait<$t> for $name<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: $t) -> Self {
                Self(each_lane!(N, |i| self.0[i] $op rhs))
            }
        }
        impl<const N: usize> $trait<$name<N>> for $t {
            type Output = $name<N>;
            #[inline(always)]
            fn $method(self, rhs: $name<N>) -> $name<N> {
                $name(each_lane!(N, |i| self $op rhs.0[i]))
            }
        }
    };
}

macro_rules! lanes {
    ($(#[$doc:meta])* $name:ident, $t:ty, { $($maths:tt)* }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct $name<const N: usize>(pub [$t; N]);

        lane_op!($name, $t, Add, add, +);
        lane_op!($name, $t, Sub, sub, -);
        lane_op!($name, $t, Mul, mul, *);
        lane_op!($name, $t, Div, div, /);

        impl<const N: usize> $name<N> {
            /// Every lane `0.0`.
            #[must_use]
            pub const fn splat_zero() -> Self {
                Self([0.0; N])
            }
        }

        impl<const N: usize> Neg for $name<N> {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self(each_lane!(N, |i| -self.0[i]))
            }
        }

        impl<const N: usize> Real for $name<N> {
            type Scalar = $t;
            type Mask = LaneMask<N>;
            const LANES: usize = N;

            #[inline(always)]
            fn splat(x: $t) -> Self {
                Self([x; N])
            }
            #[inline(always)]
            fn lane(self, i: usize) -> $t {
                self.0[i]
            }
            #[inline(always)]
            fn set_lane(&mut self, i: usize, x: $t) {
                self.0[i] = x;
            }
            #[inline(always)]
            fn map(self, f: impl Fn($t) -> $t) -> Self {
                Self(each_lane!(N, |i| f(self.0[i])))
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                Self(each_lane!(N, |i| Real::sqrt(self.0[i])))
            }
            #[inline(always)]
            fn abs(self) -> Self {
                Self(each_lane!(N, |i| Real::abs(self.0[i])))
            }
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                Self(each_lane!(N, |i| Real::mul_add(self.0[i], a.0[i], b.0[i])))
            }
            #[inline(always)]
            fn lt(self, rhs: $t) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i] < rhs))
            }
            #[inline(always)]
            fn le(self, rhs: $t) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i] <= rhs))
            }
            #[inline(always)]
            fn gt(self, rhs: $t) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i] > rhs))
            }
            #[inline(always)]
            fn eq(self, rhs: $t) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i] == rhs))
            }
            #[inline(always)]
            fn is_finite(self) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i].is_finite()))
            }
            #[inline(always)]
            fn is_normal(self) -> LaneMask<N> {
                LaneMask(each_lane!(N, |i| self.0[i].is_normal()))
            }
            #[inline(always)]
            fn select(mask: LaneMask<N>, if_true: Self, if_false: Self) -> Self {
                Self(each_lane!(N, |i| if mask.0[i] {
                    if_true.0[i]
                } else {
                    if_false.0[i]
                }))
            }
            $($maths)*
        }

        impl<const N: usize> Lanes for $name<N> {
            type Array<T: Copy + Debug + Send + Sync + 'static> = [T; N];
            #[inline(always)]
            fn array<T: Copy + Debug + Send + Sync + 'static>(
                f: impl FnMut(usize) -> T,
            ) -> [T; N] {
                core::array::from_fn(f)
            }
        }
    };
}

lanes!(
    /// `N` `f64` lanes (one aircraft each).
    F64s,
    f64,
    {
        #[inline(always)]
        fn pow_exact(self, y: f64) -> Self {
            Self(crate::math::pow_lanes(self.0, y))
        }
    }
);
lanes!(
    /// `N` `f32` lanes (one aircraft each).
    F32s,
    f32,
    {
        #[inline(always)]
        fn asinf_exact(self) -> Self {
            Self(crate::math::asinf_lanes(self.0))
        }
    }
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operators_are_the_scalar_ones_lane_by_lane() {
        let a = F64s([1.5, -0.0, f64::NAN, 3.0]);
        let b = F64s([0.1, 2.0, 1.0, 0.0]);
        for i in 0..4 {
            let (x, y) = (a.0[i], b.0[i]);
            assert_eq!((a + b).0[i].to_bits(), (x + y).to_bits());
            assert_eq!((a - b).0[i].to_bits(), (x - y).to_bits());
            assert_eq!((a * b).0[i].to_bits(), (x * y).to_bits());
            assert_eq!((a / b).0[i].to_bits(), (x / y).to_bits());
            assert_eq!((-a).0[i].to_bits(), (-x).to_bits());
            assert_eq!(a.sqrt().0[i].to_bits(), Real::sqrt(x).to_bits());
            assert_eq!(a.abs().0[i].to_bits(), x.abs().to_bits());
        }
        assert_eq!(a.lt(1.0), LaneMask([false, true, false, false]));
        assert_eq!(a.le(1.5), LaneMask([true, true, false, false]));
        assert_eq!(a.gt(1.5), LaneMask([false, false, false, true]));
        assert_eq!(b.eq(0.0), LaneMask([false, false, false, true]));
        let m = LaneMask([true, false, true, false]);
        assert_eq!(F64s::select(m, a, b).0[1], 2.0);
        assert_eq!(F64s::select(m, a, b).0[0], 1.5);
        assert!(m.any());
        assert!(!m.and(LaneMask([false, true, false, true])).any());
        assert!(m
            .or(LaneMask([false, true, false, true]))
            .0
            .iter()
            .all(|&b| b));
        let c = F32s([1.0f32, -2.0]);
        assert_eq!(c.abs(), F32s([1.0, 2.0]));
    }

    /// `Mask::lane` reads lane `i` and `Mask::set_lane` writes it alone
    /// (their docs), for every lane of a mask with both values in it.
    #[test]
    fn a_masks_lanes_are_read_and_written_one_by_one() {
        let pattern = [true, false, false, true, false, true];
        let mut m = LaneMask(pattern);
        for (i, &b) in pattern.iter().enumerate() {
            assert_eq!(Mask::lane(m, i), b, "lane {i}");
        }
        for i in 0..pattern.len() {
            let mut expected = m.0;
            expected[i] = !expected[i];
            m.set_lane(i, !Mask::lane(m, i));
            assert_eq!(m.0, expected, "lane {i}");
        }
        assert!(Mask::lane(LaneMask::<3>::splat(true), 2));
        assert!(!Mask::lane(LaneMask::<3>::splat(false), 1));
    }
}
