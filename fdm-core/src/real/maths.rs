//! The transcendental functions of the models' steps, as a choice of
//! [`Maths`]: [`Exact`] (the scalar step's functions on every lane) or
//! [`Fast`] (vectorised forms where there are some).

use super::Real;

/// The functions a model's step calls besides `+ - * /` and `sqrt`. A step
/// takes its `Maths` as a type parameter, so the choice costs nothing at run
/// time and is the same for every model.
///
/// The defaults are the [`Exact`] ones: [`crate::math`]'s functions with
/// their bits in every lane ([`Real::pow_exact`], [`Real::asinf_exact`]: for
/// lanes, evaluated lane-wise in vector registers), the bits of the scalar
/// step.
pub trait Maths: Copy + Default + Send + Sync + 'static {
    /// Whether any function differs from [`Exact`]'s.
    const VECTORISED: bool;

    /// `x` raised to the power `y` (C's `pow`), lane-wise.
    #[inline(always)]
    fn pow<R: Real<Scalar = f64>>(x: R, y: f64) -> R {
        x.pow_exact(y)
    }

    /// Arc sine in `f32` (C's `asinf`), lane-wise.
    #[inline(always)]
    fn asinf<R: Real<Scalar = f32>>(x: R) -> R {
        x.asinf_exact()
    }

    /// [`Maths::asinf`] of eight values (one per lifting element), each
    /// with the bits [`Maths::asinf`] gives it. [`Exact`] and [`Fast`]
    /// evaluate the eight together ([`Real::asinf_exact_8`]).
    #[inline(always)]
    fn asinf_8<R: Real<Scalar = f32>>(values: [R; 8]) -> [R; 8] {
        values.map(Self::asinf)
    }
}

/// Every function exactly as the scalar step calls it: a lane has the bits of
/// the scalar step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Exact;

impl Maths for Exact {
    const VECTORISED: bool = false;

    #[inline(always)]
    fn asinf_8<R: Real<Scalar = f32>>(values: [R; 8]) -> [R; 8] {
        R::asinf_exact_8(values)
    }
}

/// Vectorised forms where there are some, [`Exact`]'s functions elsewhere:
///
/// * `pow(x, 5.25)` (Palmer's pressure) is [`fast::pow_5_25`]: all lane-wise
///   operations, within 1 ulp of glibc's `pow` (the same bits for 99.9 % of
///   the arguments). Other exponents call the exact `pow`.
/// * `asinf` is the exact one ([`Real::asinf_exact`], already lane-wise in
///   vector registers, with the bits of [`crate::math::asinf`]).
///
/// `FMA` says whether the instruction set has fused multiply-adds (used only
/// for exact product errors, which Dekker's splitting gets without them: the
/// same bits either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Fast<const FMA: bool>;

impl<const FMA: bool> Maths for Fast<FMA> {
    const VECTORISED: bool = true;

    #[inline(always)]
    fn asinf_8<R: Real<Scalar = f32>>(values: [R; 8]) -> [R; 8] {
        R::asinf_exact_8(values)
    }

    #[inline(always)]
    #[allow(clippy::float_cmp)] // a constant exponent, folded after inlining
    fn pow<R: Real<Scalar = f64>>(x: R, y: f64) -> R {
        if y == 5.25 {
            fast::pow_5_25::<R, FMA>(x)
        } else {
            Exact::pow(x, y)
        }
    }
}

/// Vectorisable replacements for libm calls.
pub mod fast {
    use crate::real::{Mask, Real};

    /// `x^5.25` as `x⁵ · x^¼` in double-double arithmetic (a value carried as
    /// an unevaluated sum `hi + lo` of two f64), rounded to f64 at the end:
    /// only lane-wise multiplications, additions, one division and two square
    /// roots, all SIMD instructions (glibc's `pow` is a scalar call per lane).
    ///
    /// `x⁵` is computed exactly enough with error-free products (`a · b = p +
    /// e` with `e` exact); `x^¼ = √√x` gets one Newton correction `(x - t⁴) /
    /// 4t³` with `t⁴` in double-double. The result is the correctly rounded
    /// power except in rare near-halfway cases: the test below measures at
    /// most 1 ulp from glibc's `pow` (itself within 0.52 ulp of the exact
    /// power), with the same bits for all but 0.1 % of the arguments. The
    /// plain f64 form `x⁵ · √√x` (six roundings) is up to 4 ulp away, which
    /// over 1,800 RK4 steps of a banked turn moves an aircraft by several
    /// 1e-9 m.
    ///
    /// With `FMA` the exact product error `e` is one fused multiply-add
    /// (`a.mul_add(b, -p)`); without, Dekker's splitting computes the same
    /// exact `e` with plain operations. Both are exact, so the result has the
    /// same bits on every instruction set.
    ///
    /// Special values (`0`, `∞`, NaN, negative or subnormal `x`, overflow)
    /// take the plain f64 form, which follows `pow` (`+0` for `±0`, `+∞` for
    /// `+∞`, NaN for NaN and for a finite negative `x`) except at `x = -∞` (an
    /// infinite altitude), where this gives NaN and `pow` gives `+∞`.
    #[inline(always)]
    pub fn pow_5_25<R: Real<Scalar = f64>, const FMA: bool>(x: R) -> R {
        // The plain form, kept for the special values.
        let x2 = x * x;
        let x4 = x2 * x2;
        let x5 = x4 * x;
        let t = x.sqrt().sqrt();
        let plain = x5 * t;
        let regular = plain.is_finite().and(plain.gt(0.0)).and(x.is_normal());
        if !regular.any() {
            return plain;
        }
        let zero = R::splat(0.0);
        // x⁵ in double-double.
        let x2 = two_prod::<R, FMA>(x, x);
        let x4 = dd_mul::<R, FMA>(x2, x2);
        let x5 = dd_mul::<R, FMA>(x4, (x, zero));
        // x^¼: t plus one Newton step on t⁴ = x. `x - t4.0` is exact (the two
        // are within a few ulp of each other).
        let t2 = two_prod::<R, FMA>(t, t);
        let t4 = dd_mul::<R, FMA>(t2, t2);
        let residual = (x - t4.0) - t4.1;
        let root = fast_two_sum(t, residual / (R::splat(4.0) * t * t2.0));
        let (hi, _) = dd_mul::<R, FMA>(x5, root);
        R::select(regular, hi, plain)
    }

    /// Veltkamp's split of `a` into two halves of 26 bits: `a = hi + lo`
    /// exactly.
    #[inline(always)]
    fn split<R: Real<Scalar = f64>>(a: R) -> (R, R) {
        let c = R::splat(134_217_729.0) * a; // 2^27 + 1
        let hi = c - (c - a);
        (hi, a - hi)
    }

    /// `a + b = s + e` exactly, for `|a| >= |b|`.
    #[inline(always)]
    fn fast_two_sum<R: Real<Scalar = f64>>(a: R, b: R) -> (R, R) {
        let s = a + b;
        (s, b - (s - a))
    }

    /// `a * b = p + e` exactly: `e` by one FMA, or by Dekker's product of the
    /// halves (the same value, since it is exact either way).
    #[inline(always)]
    fn two_prod<R: Real<Scalar = f64>, const FMA: bool>(a: R, b: R) -> (R, R) {
        let p = a * b;
        let e = if FMA {
            a.mul_add(b, -p)
        } else {
            let (ah, al) = split(a);
            let (bh, bl) = split(b);
            ((ah * bh - p) + ah * bl + al * bh) + al * bl
        };
        (p, e)
    }

    /// Double-double product (relative error about 2⁻¹⁰⁴).
    #[inline(always)]
    fn dd_mul<R: Real<Scalar = f64>, const FMA: bool>(a: (R, R), b: (R, R)) -> (R, R) {
        let (p, e) = two_prod::<R, FMA>(a.0, b.0);
        fast_two_sum(p, e + (a.0 * b.1 + a.1 * b.0))
    }

    // Two attributes, not `cfg(all(test, feature = "std"))`: cargo-mutants
    // recognises a test module by its plain `#[cfg(test)]` and would
    // otherwise mutate these tests' helpers as if they were the library.
    #[cfg(test)]
    #[cfg(feature = "std")]
    mod tests {
        use super::*;
        use crate::real::F64s;

        #[test]
        fn fma_and_dekker_give_the_same_bits() {
            for i in 0..200_000_u32 {
                let x = 0.5 + 0.6 * f64::from(i) / 200_000.0;
                let fused = pow_5_25::<f64, true>(x);
                let split = pow_5_25::<f64, false>(x);
                assert_eq!(fused.to_bits(), split.to_bits(), "{x}");
                let lanes = pow_5_25::<F64s<2>, false>(F64s([x, x]));
                assert_eq!(lanes.0[1].to_bits(), split.to_bits(), "{x}");
            }
        }

        /// Largest distance from glibc's `pow(x, 5.25)` over `x` in `[lo, hi)`,
        /// and how many samples differ at all.
        fn max_ulps(lo: f64, hi: f64, samples: u32) -> (u64, usize) {
            let d: Vec<u64> = (0..samples)
                .map(|i| {
                    let x = lo + (hi - lo) * f64::from(i) / f64::from(samples);
                    pow_5_25::<f64, false>(x)
                        .to_bits()
                        .abs_diff(x.powf(5.25).to_bits())
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
            // And the same bits for all but 0.1 % of them (the docs above;
            // 1,599 of these 2e6 differ, each by 1 ulp).
            assert!(differ <= 2_000, "{differ} of 2e6 differ");
        }

        #[test]
        fn up_to_and_beyond_overflow_as_pow() {
            // Overflow is one of the special values that take the plain form
            // (docs above): where `pow(x, 5.25)` overflows (x beyond about
            // 4.6e58) the result is +∞ as `pow`'s, and just below the
            // threshold it is still the double-double power, within 1 ulp.
            let mut overflowed = 0;
            for i in 0..=20_000_u32 {
                let x = 10_f64.powf(50.0 + 20.0 * f64::from(i) / 20_000.0);
                let (ours, glibc) = (pow_5_25::<f64, false>(x), x.powf(5.25));
                if glibc.is_infinite() {
                    overflowed += 1;
                    assert_eq!(ours.to_bits(), glibc.to_bits(), "{x}");
                } else {
                    assert!(ours.to_bits().abs_diff(glibc.to_bits()) <= 1, "{x}");
                }
            }
            assert!(overflowed > 0 && overflowed < 20_000, "{overflowed}");
            for x in [1e100, 1e300, f64::MAX] {
                assert_eq!(pow_5_25::<f64, true>(x), f64::INFINITY, "{x}");
            }
        }

        #[test]
        fn special_values_follow_pow() {
            for x in [0.0, -0.0, f64::INFINITY, 1.0] {
                let ours = pow_5_25::<f64, false>(x);
                assert_eq!(ours.to_bits(), x.powf(5.25).to_bits(), "{x}");
            }
            for x in [-1.0, -0.5, f64::NAN] {
                assert!(pow_5_25::<f64, false>(x).is_nan(), "{x}");
                assert!(x.powf(5.25).is_nan(), "{x}");
            }
            assert!(pow_5_25::<f64, false>(f64::NEG_INFINITY).is_nan());
            assert_eq!(f64::NEG_INFINITY.powf(5.25), f64::INFINITY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{fast, Exact, Fast, Maths};
    use crate::real::{F32s, F64s};

    /// Bases for the pressure power: Palmer's `1 - 0.0065 z / 288.15` over the
    /// atmosphere (about 0.55 to 1.03), and a few others.
    const BASES: [f64; 8] = [0.55, 0.7, 0.812_345, 0.9, 0.999_9, 1.0, 1.03, 2.5];

    /// Arc-sine arguments: the interior, the ends, both signs.
    const SINES: [f32; 8] = [0.0, -0.25, 0.3, -0.5, 0.7, -0.9, 0.999, -1.0];

    /// A `Maths` that keeps every provided method: the trait's own defaults,
    /// which its docs say are the [`Exact`] functions.
    #[derive(Debug, Clone, Copy, Default)]
    struct Defaults;

    impl Maths for Defaults {
        const VECTORISED: bool = false;
    }

    fn same_pow<M: Maths>(exponent: f64) -> bool {
        BASES.iter().all(|&x| {
            let want = crate::math::pow(x, exponent).to_bits();
            let lanes = M::pow(F64s([x, 0.5 * x]), exponent);
            M::pow(x, exponent).to_bits() == want
                && lanes.0[0].to_bits() == want
                && lanes.0[1].to_bits() == crate::math::pow(0.5 * x, exponent).to_bits()
        })
    }

    fn same_asinf<M: Maths>() -> bool {
        let want = SINES.map(crate::math::asinf);
        let one_by_one = SINES.map(M::asinf);
        let eight = M::asinf_8(SINES);
        let lanes = M::asinf_8(SINES.map(|s| F32s([s, -s])));
        (0..8).all(|i| {
            one_by_one[i].to_bits() == want[i].to_bits()
                && eight[i].to_bits() == want[i].to_bits()
                && lanes[i].0[0].to_bits() == want[i].to_bits()
                && lanes[i].0[1].to_bits() == crate::math::asinf(-SINES[i]).to_bits()
        })
    }

    /// The trait's docs: its defaults, and `Exact`, are `crate::math`'s
    /// functions with their bits in every lane, `asinf_8` each value's
    /// `asinf`.
    #[test]
    fn the_defaults_and_exact_are_the_scalar_functions_bits() {
        for exponent in [5.25, 2.0, 0.190_263, -1.5] {
            assert!(
                same_pow::<Defaults>(exponent),
                "defaults, pow(x, {exponent})"
            );
            assert!(same_pow::<Exact>(exponent), "Exact, pow(x, {exponent})");
        }
        assert!(same_asinf::<Defaults>(), "defaults, asinf");
        assert!(same_asinf::<Exact>(), "Exact, asinf");
    }

    /// `Fast`'s docs: `pow(x, 5.25)` is `fast::pow_5_25`, other exponents
    /// the exact `pow`; `asinf` the exact one.
    #[test]
    fn fast_replaces_only_the_power_5_25() {
        // A base where `pow_5_25` (within 1 ulp of `pow`, the same bits for
        // all but about 0.1 % of the bases) and `pow` differ, so that taking
        // one for the other shows.
        let differs = (0..200_000_u32)
            .map(|i| 0.55 + 0.48 * f64::from(i) / 200_000.0)
            .find(|&x| {
                fast::pow_5_25::<f64, true>(x).to_bits() != crate::math::pow(x, 5.25).to_bits()
            })
            .expect("pow_5_25 has pow's bits everywhere sampled");
        fn check<const FMA: bool>(differs: f64) {
            for x in BASES.into_iter().chain([differs]) {
                let lanes = F64s([x, 0.5 * x]);
                assert_eq!(
                    Fast::<FMA>::pow(x, 5.25).to_bits(),
                    fast::pow_5_25::<f64, FMA>(x).to_bits(),
                    "{x}^5.25"
                );
                assert_eq!(
                    Fast::<FMA>::pow(lanes, 5.25),
                    fast::pow_5_25::<F64s<2>, FMA>(lanes),
                    "{x}^5.25 in lanes"
                );
            }
            for exponent in [2.0, 5.0, 5.5, -1.5] {
                assert!(same_pow::<Fast<FMA>>(exponent), "pow(x, {exponent})");
            }
            assert!(same_asinf::<Fast<FMA>>(), "asinf");
        }
        check::<true>(differs);
        check::<false>(differs);
    }
}
