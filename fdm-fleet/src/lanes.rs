//! `N` f64 or f32 lanes with lane-wise IEEE operations.
//!
//! Every operator is one plain loop over `[f64; N]` (or `[f32; N]`) that LLVM turns into one
//! (or a few) vector instructions of the instruction set the caller was
//! compiled for (see [`crate::palmer`]'s dispatch). Each lane gets exactly the
//! IEEE operation a scalar `f64` (`f32`) expression would: `+ - * /` and `sqrt` are
//! correctly rounded, in SIMD as in scalar code, and Rust never fuses `a * b + c`
//! into an FMA by itself (it emits no fast-math or `contract` flags), so a lane's
//! result has the bits of the scalar expression whatever the instruction set.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// `N` lane booleans (the result of a lane-wise comparison).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Mask<const N: usize>(pub(crate) [bool; N]);

impl<const N: usize> Mask<N> {
    /// `if_true` in the lanes where the mask is set, `if_false` elsewhere: a
    /// scalar `if` turned into a blend.
    #[inline(always)]
    pub(crate) fn select<V: Blend<N>>(self, if_true: V, if_false: V) -> V {
        V::blend(self, if_true, if_false)
    }

    /// Lane-wise `&&`.
    #[inline(always)]
    pub(crate) fn and(self, rhs: Self) -> Self {
        Self(core::array::from_fn(|i| self.0[i] && rhs.0[i]))
    }

    /// Whether any lane is set.
    #[inline(always)]
    pub(crate) fn any(self) -> bool {
        self.0.iter().fold(false, |acc, &b| acc | b)
    }
}

macro_rules! lane_op {
    ($name:ident, $t:ty, $trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for $name<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self(core::array::from_fn(|i| self.0[i] $op rhs.0[i]))
            }
        }
        impl<const N: usize> $trait<$t> for $name<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: $t) -> Self {
                Self(core::array::from_fn(|i| self.0[i] $op rhs))
            }
        }
        impl<const N: usize> $trait<$name<N>> for $t {
            type Output = $name<N>;
            #[inline(always)]
            fn $method(self, rhs: $name<N>) -> $name<N> {
                $name(core::array::from_fn(|i| self $op rhs.0[i]))
            }
        }
    };
}

/// Lane vectors a [`Mask`] can blend.
pub(crate) trait Blend<const N: usize>: Sized {
    /// `a` where `mask` is set, `b` elsewhere.
    fn blend(mask: Mask<N>, a: Self, b: Self) -> Self;
}

macro_rules! lanes {
    ($name:ident, $t:ty) => {
        impl<const N: usize> Blend<N> for $name<N> {
            #[inline(always)]
            fn blend(mask: Mask<N>, a: Self, b: Self) -> Self {
                Self(core::array::from_fn(|i| if mask.0[i] { a.0[i] } else { b.0[i] }))
            }
        }

/// `N` lanes of the float type (one per aircraft).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct $name<const N: usize>(pub(crate) [$t; N]);

impl<const N: usize> $name<N> {
    /// Every lane `x`.
    #[inline(always)]
    pub(crate) const fn splat(x: $t) -> Self {
        Self([x; N])
    }

    /// `f` applied to every lane.
    #[inline(always)]
    pub(crate) fn map(self, f: impl Fn($t) -> $t) -> Self {
        Self(core::array::from_fn(|i| f(self.0[i])))
    }

    /// Lane-wise square root (correctly rounded, `sqrtpd`).
    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        self.map(<$t>::sqrt)
    }

    /// Lane-wise `self < rhs` (false where either is NaN, like scalar `<`).
    #[inline(always)]
    pub(crate) fn lt(self, rhs: $t) -> Mask<N> {
        Mask(core::array::from_fn(|i| self.0[i] < rhs))
    }

    /// Lane-wise `self > rhs`.
    #[allow(dead_code)] // used by the f32 lanes only
    #[inline(always)]
    pub(crate) fn gt(self, rhs: $t) -> Mask<N> {
        Mask(core::array::from_fn(|i| self.0[i] > rhs))
    }

    /// Lane-wise absolute value (clears the sign bit, like C's `fabs`).
    #[allow(dead_code)] // used by the f32 lanes only
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        self.map(<$t>::abs)
    }

    /// Lane-wise `self <= rhs`.
    #[inline(always)]
    pub(crate) fn le(self, rhs: $t) -> Mask<N> {
        Mask(core::array::from_fn(|i| self.0[i] <= rhs))
    }

    /// Lane-wise `self == rhs`.
    #[inline(always)]
    pub(crate) fn eq(self, rhs: $t) -> Mask<N> {
        Mask(core::array::from_fn(|i| self.0[i] == rhs))
    }
}


        lane_op!($name, $t, Add, add, +);
        lane_op!($name, $t, Sub, sub, -);
        lane_op!($name, $t, Mul, mul, *);
        lane_op!($name, $t, Div, div, /);

impl<const N: usize> Neg for $name<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|x| -x)
    }
}

    };
}

lanes!(F64s, f64);
lanes!(F32s, f32);

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
            assert_eq!(a.sqrt().0[i].to_bits(), x.sqrt().to_bits());
        }
        assert_eq!(a.lt(1.0), Mask([false, true, false, false]));
        assert_eq!(a.le(1.5), Mask([true, true, false, false]));
        assert_eq!(b.eq(0.0), Mask([false, false, false, true]));
        let m = Mask([true, false, true, false]);
        assert_eq!(m.select(a, b).0[1], 2.0);
        assert_eq!(m.select(a, b).0[0], 1.5);
        assert!(m.any());
        assert!(!m.and(Mask([false, true, false, true])).any());
    }
}
