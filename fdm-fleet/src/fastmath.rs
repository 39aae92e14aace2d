//! Vectorisable replacements for the libm calls of the hot loops (the `fast`
//! precision).

use crate::lanes::{F64s, Mask};

/// `x^5.25` as `x⁵ · x^¼` in double-double arithmetic (a value carried as an
/// unevaluated sum `hi + lo` of two f64), rounded to f64 at the end: only
/// lane-wise multiplications, additions, one division and two square roots, all
/// SIMD instructions (glibc's `pow` is a scalar call per lane).
///
/// `x⁵` is computed exactly enough with error-free products (`a · b = p + e`
/// with `e` exact); `x^¼ = √√x` gets one Newton correction `(x - t⁴) / 4t³`
/// with `t⁴` in double-double. The result is the correctly rounded power
/// except in rare near-halfway cases: the test below measures at most 1 ulp from
/// glibc's `pow` (itself within 0.52 ulp of the exact power), with the same bits
/// for all but 0.1 % of the arguments. The plain f64 form `x⁵ · √√x` (six
/// roundings) is up to 4 ulp away, which over 1,800 RK4 steps of a banked turn
/// moves an aircraft by several 1e-9 m.
///
/// With `FMA` the exact product error `e` is one fused multiply-add
/// (`a.mul_add(b, -p)`); without, Dekker's splitting computes the same exact
/// `e` with plain operations. Both are exact, so the result has the same bits
/// on every instruction set.
///
/// Special values (`0`, `∞`, NaN, negative or subnormal `x`, overflow) take the
/// plain f64 form, which follows `pow` (`+0` for `±0`, `+∞` for `+∞`, NaN for
/// NaN and for a finite negative `x`) except at `x = -∞` (an infinite
/// altitude), where this gives NaN and `pow` gives `+∞`.
#[inline(always)]
pub(crate) fn pow_5_25<const N: usize, const FMA: bool>(x: F64s<N>) -> F64s<N> {
    // The plain form, kept for the special values.
    let x2 = x * x;
    let x4 = x2 * x2;
    let x5 = x4 * x;
    let t = x.sqrt().sqrt();
    let plain = x5 * t;
    let regular = Mask(core::array::from_fn(|i| {
        plain.0[i].is_finite() && plain.0[i] > 0.0 && x.0[i].is_normal()
    }));
    if !regular.any() {
        return plain;
    }
    let zero = F64s::splat(0.0);
    // x⁵ in double-double.
    let x2 = two_prod::<N, FMA>(x, x);
    let x4 = dd_mul::<N, FMA>(x2, x2);
    let x5 = dd_mul::<N, FMA>(x4, (x, zero));
    // x^¼: t plus one Newton step on t⁴ = x. `x - t4.0` is exact (the two are
    // within a few ulp of each other).
    let t2 = two_prod::<N, FMA>(t, t);
    let t4 = dd_mul::<N, FMA>(t2, t2);
    let residual = (x - t4.0) - t4.1;
    let root = fast_two_sum(t, residual / (4.0 * t * t2.0));
    let (hi, _) = dd_mul::<N, FMA>(x5, root);
    regular.select(hi, plain)
}

type Dd<const N: usize> = (F64s<N>, F64s<N>);

/// Veltkamp's split of `a` into two halves of 26 bits: `a = hi + lo` exactly.
#[inline(always)]
fn split<const N: usize>(a: F64s<N>) -> Dd<N> {
    let c = 134_217_729.0 * a; // 2^27 + 1
    let hi = c - (c - a);
    (hi, a - hi)
}

/// `a + b = s + e` exactly, for `|a| >= |b|`.
#[inline(always)]
fn fast_two_sum<const N: usize>(a: F64s<N>, b: F64s<N>) -> Dd<N> {
    let s = a + b;
    (s, b - (s - a))
}

/// `a * b = p + e` exactly: `e` by one FMA, or by Dekker's product of the
/// halves (the same value, since it is exact either way).
#[inline(always)]
fn two_prod<const N: usize, const FMA: bool>(a: F64s<N>, b: F64s<N>) -> Dd<N> {
    let p = a * b;
    let e = if FMA {
        F64s(core::array::from_fn(|i| a.0[i].mul_add(b.0[i], -p.0[i])))
    } else {
        let (ah, al) = split(a);
        let (bh, bl) = split(b);
        ((ah * bh - p) + ah * bl + al * bh) + al * bl
    };
    (p, e)
}

/// Double-double product (relative error about 2⁻¹⁰⁴).
#[inline(always)]
fn dd_mul<const N: usize, const FMA: bool>(a: Dd<N>, b: Dd<N>) -> Dd<N> {
    let (p, e) = two_prod::<N, FMA>(a.0, b.0);
    fast_two_sum(p, e + (a.0 * b.1 + a.1 * b.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fma_and_dekker_give_the_same_bits() {
        // Here `mul_add` is libm's correctly rounded `fma` (or the instruction):
        // both ways of getting the product error are exact.
        for i in 0..200_000_u32 {
            let x = 0.5 + 0.6 * f64::from(i) / 200_000.0;
            let fused = pow_5_25::<1, true>(F64s([x])).0[0];
            let split = pow_5_25::<1, false>(F64s([x])).0[0];
            assert_eq!(fused.to_bits(), split.to_bits(), "{x}");
        }
    }

    fn ulps(a: f64, b: f64) -> u64 {
        a.to_bits().abs_diff(b.to_bits())
    }

    /// Largest distance from glibc's `pow(x, 5.25)` over `x` in `[lo, hi)`,
    /// and how many samples differ at all.
    fn max_ulps(lo: f64, hi: f64, samples: u32) -> (u64, usize) {
        let d: Vec<u64> = (0..samples)
            .map(|i| {
                let x = lo + (hi - lo) * f64::from(i) / f64::from(samples);
                ulps(pow_5_25::<1, false>(F64s([x])).0[0], x.powf(5.25))
            })
            .collect();
        (
            d.iter().copied().max().unwrap_or(0),
            d.iter().filter(|&&u| u > 0).count(),
        )
    }

    #[test]
    fn within_one_ulp_of_glibc_over_the_atmosphere() {
        // `1 - 0.0065 z / 288.15` for z from -1 km to 20 km is 0.55..1.03.
        // Tolerance 1 ulp: both are within about half an ulp of the exact
        // power, so they can only round a near-halfway case differently.
        let (worst, differ) = max_ulps(0.55, 1.03, 2_000_000);
        println!("pow_5_25: at most {worst} ulp from glibc's pow, {differ} of 2e6 differ");
        assert!(worst <= 1, "{worst} ulp");
    }

    #[test]
    fn special_values_follow_pow() {
        for x in [0.0, -0.0, f64::INFINITY, 1.0] {
            let ours = pow_5_25::<1, false>(F64s([x])).0[0];
            assert_eq!(ours.to_bits(), x.powf(5.25).to_bits(), "{x}");
        }
        for x in [-1.0, -0.5, f64::NAN] {
            assert!(pow_5_25::<1, false>(F64s([x])).0[0].is_nan(), "{x}");
            assert!(x.powf(5.25).is_nan(), "{x}");
        }
        assert!(pow_5_25::<1, false>(F64s([f64::NEG_INFINITY])).0[0].is_nan());
        assert_eq!(f64::NEG_INFINITY.powf(5.25), f64::INFINITY);
    }
}
