//! `pow` for f64: a Rust port of the algorithm of ARM's optimized-routines
//! `pow` (Szabolcs Nagy, 2018; published under MIT OR Apache-2.0 WITH
//! LLVM-exception, and the `pow` of musl and of glibc since 2.28), in the form
//! glibc 2.36 runs on an x86-64 CPU with FMA (`__pow_fma`): the three places
//! the algorithm writes a fused multiply-add, and the products the compiler
//! contracts into fused multiply-adds there, are fused here too, through
//! [`fma`](super::fma) (correctly rounded on every target, so the bits do not
//! depend on the CPU).
//!
//! `log(x)` is computed in double-double from a 128-entry table, multiplied
//! by `y`, and `exp` of that from another 128-entry table: within 0.52 ulp of
//! the exact power (not always correctly rounded: see docs/determinism.md).

use super::fma;
use super::pow_data::{
    EXP_POLY, EXP_TAB, INV_LN2_N, LN2HI, LN2LO, LOG_POLY, LOG_TAB, NEG_LN2_HI_N, NEG_LN2_LO_N,
    SHIFT,
};

const OFF: u64 = 0x3fe6_9555_0000_0000;
const SIGN_BIAS: u64 = 0x800 << 7;

#[inline(always)]
fn d(bits: u64) -> f64 {
    f64::from_bits(bits)
}

#[inline(always)]
fn top12(x: f64) -> u32 {
    (x.to_bits() >> 52) as u32
}

/// `log(x)` for the bits `ix` of a positive normal x, as `hi + tail`.
#[inline(always)]
fn log_inline(ix: u64, fma_instruction: bool) -> (f64, f64) {
    let tmp = ix.wrapping_sub(OFF);
    let i = ((tmp >> (52 - 7)) % 128) as usize;
    let k = (tmp as i64) >> 52;
    let iz = ix.wrapping_sub(tmp & (0xfff << 52));
    let z = d(iz);
    let kd = k as f64;
    let [invc, logc, logctail] = LOG_TAB[i];
    let (invc, logc, logctail) = (d(invc), d(logc), d(logctail));
    // r = z/c - 1, exact. glibc's FMA form computes it with one fused
    // multiply-add; since the result is exact, the split form (invc has at most
    // 9 significant bits, so zhi*invc and zlo*invc are exact) gives the same
    // bits without one.
    let zhi = d(iz & !((1 << 27) - 1));
    let zlo = z - zhi;
    let r = (zhi * invc - 1.0) + zlo * invc;
    // k*ln2 + log(c) + r. LN2HI has 42 significant bits and |k| < 2^11, so the
    // product is exact and the fused multiply-add of the FMA form is one
    // rounding of the sum.
    let t1 = kd * d(LN2HI) + logc;
    let t2 = t1 + r;
    let lo1 = fma(kd, d(LN2LO), logctail);
    let lo2 = t1 - t2 + r;
    let a = each_lane!(LOG_POLY.len(), |i| d(LOG_POLY[i]));
    let ar = a[0] * r;
    let ar2 = r * ar;
    let ar3 = r * ar2;
    let hi = t2 + ar2;
    // The exact error of ar2 = r * ar with ar = -r/2: the FMA form's
    // `fma(ar, r, -ar2)` where a fused multiply-add is one instruction,
    // else minus half the error of r*r by Dekker's product (nine operations
    // in a chain). Both are the exact error, the same number
    // (`both_product_errors_give_the_same_pow` checks the bits).
    let lo3 = if fma_instruction {
        fma(ar, r, -ar2)
    } else {
        -0.5 * square_error(r, -2.0 * ar2)
    };
    let lo4 = t2 - hi + ar2;
    // p = log1p(r) - r - A[0]*r*r; the compiler fuses each product into the
    // sum that takes it.
    let q = fma(ar2, fma(r, a[6], a[5]), fma(r, a[4], a[3]));
    let q = fma(ar2, q, fma(r, a[2], a[1]));
    let lo = fma(ar3, q, lo1 + lo2 + lo3 + lo4);
    let y = hi + lo;
    (y, hi - y + lo)
}

/// `r*r - q` exactly, for `q = round(r*r)` (Dekker's product with Veltkamp's
/// split; exact while `r*r` neither overflows nor underflows, as here:
/// `|r| < 2^-6` and `r` is 0 or above 2^-62).
#[inline(always)]
fn square_error(r: f64, q: f64) -> f64 {
    let c = 134_217_729.0 * r; // 2^27 + 1
    let rh = c - (c - r);
    let rl = r - rh;
    ((rh * rh - q) + 2.0 * rh * rl) + rl * rl
}

/// 2^`n` for a normal power of two (−1022 ≤ `n` ≤ 1023), exactly: its bits, so that
/// `no_std` builds (where `f64::powi` does not exist) compute the same constant.
#[allow(clippy::cast_sign_loss)] // 1023 + n > 0 for the normal powers it is used for
const fn pow2(n: i32) -> f64 {
    f64::from_bits(((1023 + n) as u64) << 52)
}

/// The scaling when the result may overflow or underflow.
#[inline(never)]
fn special_case(tmp: f64, sbits: u64, ki: u64) -> f64 {
    if ki & 0x8000_0000 == 0 {
        // k > 0: the exponent of scale may have overflowed by <= 460.
        let scale = d(sbits.wrapping_sub(1009 << 52));
        return pow2(1009) * fma(scale, tmp, scale);
    }
    // k < 0: care in the subnormal range. The rescaled bits carry the
    // result's sign (the unscaled exponent may have wrapped into bit 63).
    let sbits = sbits.wrapping_add(1022 << 52);
    let scale = d(sbits);
    let mut y = fma(scale, tmp, scale);
    if y.abs() < 1.0 {
        let one = if y < 0.0 { -1.0 } else { 1.0 };
        let lo = fma(scale, tmp, scale - y);
        let hi = one + y;
        let lo = one - hi + y + lo;
        y = (hi + lo) - one;
        if y == 0.0 {
            // A result that rounds to zero keeps the result's sign.
            y = d(sbits & 0x8000_0000_0000_0000);
        }
    }
    f64::MIN_POSITIVE * y
}

/// `exp(x + xtail)`, negated when `sign_bias` is set.
#[inline(always)]
fn exp_inline(x: f64, xtail: f64, sign_bias: u64) -> f64 {
    let mut abstop = top12(x) & 0x7ff;
    if abstop.wrapping_sub(top12(pow2(-54))) >= top12(512.0) - top12(pow2(-54)) {
        if abstop.wrapping_sub(top12(pow2(-54))) >= 0x8000_0000 {
            // Tiny x: exp(x) rounds to 1.
            let one = 1.0 + x;
            return if sign_bias != 0 { -one } else { one };
        }
        if abstop >= top12(1024.0) {
            let sign = if sign_bias != 0 { -1.0 } else { 1.0 };
            return if x.to_bits() >> 63 != 0 {
                sign * 0.0
            } else {
                sign * f64::INFINITY
            };
        }
        // Large |x| is special-cased below.
        abstop = 0;
    }
    let mut kd = fma(d(INV_LN2_N), x, d(SHIFT));
    let ki = kd.to_bits();
    kd -= d(SHIFT);
    let r = fma(kd, d(NEG_LN2_LO_N), fma(kd, d(NEG_LN2_HI_N), x));
    let r = r + xtail;
    let idx = (2 * (ki % 128)) as usize;
    let top = ki.wrapping_add(sign_bias) << (52 - 7);
    let tail = d(EXP_TAB[idx]);
    let sbits = EXP_TAB[idx + 1].wrapping_add(top);
    let c = each_lane!(EXP_POLY.len(), |i| d(EXP_POLY[i]));
    let r2 = r * r;
    let tmp = fma(
        r2 * r2,
        fma(r, c[3], c[2]),
        fma(r2, fma(r, c[1], c[0]), tail + r),
    );
    if abstop == 0 {
        return special_case(tmp, sbits, ki);
    }
    let scale = d(sbits);
    fma(scale, tmp, scale)
}

/// 0 if the bits `iy` of a finite non-zero y are not an integer, 1 if an odd
/// integer, 2 if an even one.
#[inline(always)]
fn checkint(iy: u64) -> u32 {
    let e = (iy >> 52 & 0x7ff) as i32;
    if e < 0x3ff {
        return 0;
    }
    if e > 0x3ff + 52 {
        return 2;
    }
    let unit = 1u64 << (0x3ff + 52 - e);
    if iy & (unit - 1) != 0 {
        return 0;
    }
    if iy & unit != 0 {
        1
    } else {
        2
    }
}

/// True for the bits of 0, infinity or NaN.
#[inline(always)]
fn zeroinfnan(i: u64) -> bool {
    (i << 1).wrapping_sub(1) >= (f64::INFINITY.to_bits() << 1) - 1
}

/// `x` raised to the power `y`, C's `pow`. Always inlined, so that
/// [`super::pow`]'s AVX2/FMA instance compiles every [`fma`] of the usual
/// path to one instruction.
#[inline(always)]
pub(super) fn pow(x: f64, y: f64) -> f64 {
    pow_with(x, y, super::fma_is_an_instruction())
}

/// [`pow`] with the exact product error of `log_inline` taken from a fused
/// multiply-add (`fma_instruction`) or from Dekker's product: the same bits
/// either way, only the speed differs.
#[inline(always)]
fn pow_with(x: f64, y: f64, fma_instruction: bool) -> f64 {
    let mut sign_bias = 0;
    let mut ix = x.to_bits();
    let iy = y.to_bits();
    let mut topx = top12(x);
    let topy = top12(y);
    if topx.wrapping_sub(0x001) >= 0x7ff - 0x001
        || (topy & 0x7ff).wrapping_sub(0x3be) >= 0x43e - 0x3be
    {
        // Special cases: x < 2^-1022 (or negative), inf or NaN; |y| < 2^-65,
        // |y| >= 2^63 or NaN.
        if zeroinfnan(iy) {
            if iy << 1 == 0 {
                return 1.0;
            }
            if ix == 1f64.to_bits() {
                return 1.0;
            }
            if ix << 1 > f64::INFINITY.to_bits() << 1 || iy << 1 > f64::INFINITY.to_bits() << 1 {
                return x + y;
            }
            if ix << 1 == 1f64.to_bits() << 1 {
                return 1.0;
            }
            if ((ix << 1) < 1f64.to_bits() << 1) == (iy >> 63 == 0) {
                return 0.0; // |x| < 1 and y = inf, or |x| > 1 and y = -inf.
            }
            return y * y;
        }
        if zeroinfnan(ix) {
            let mut x2 = x * x;
            if ix >> 63 != 0 && checkint(iy) == 1 {
                x2 = -x2;
            }
            return if iy >> 63 != 0 { 1.0 / x2 } else { x2 };
        }
        // x and y are non-zero finite.
        if ix >> 63 != 0 {
            // x < 0.
            let yint = checkint(iy);
            if yint == 0 {
                return f64::NAN;
            }
            if yint == 1 {
                sign_bias = SIGN_BIAS;
            }
            ix &= 0x7fff_ffff_ffff_ffff;
            topx &= 0x7ff;
        }
        if (topy & 0x7ff).wrapping_sub(0x3be) >= 0x43e - 0x3be {
            // sign_bias == 0 here: y is not odd.
            if ix == 1f64.to_bits() {
                return 1.0;
            }
            if (topy & 0x7ff) < 0x3be {
                // |y| < 2^-65: x^y ~= 1 + y*log(x).
                return if ix > 1f64.to_bits() {
                    1.0 + y
                } else {
                    1.0 - y
                };
            }
            return if (ix > 1f64.to_bits()) == (topy < 0x800) {
                f64::INFINITY
            } else {
                0.0
            };
        }
        if topx == 0 {
            // Subnormal x: normalise so that the exponent becomes negative.
            ix = (x * pow2(52)).to_bits();
            ix &= 0x7fff_ffff_ffff_ffff;
            ix = ix.wrapping_sub(52 << 52);
        }
    }
    let (hi, lo) = log_inline(ix, fma_instruction);
    let ehi = y * hi;
    let elo = fma(y, lo, fma(y, hi, -ehi));
    exp_inline(ehi, elo, sign_bias)
}

/// [`pow`] of every lane of `x` with one exponent `y`, bit for bit: the
/// regular path (a positive normal `x` and a result that needs no rescaling)
/// evaluated lane-wise, each operation the scalar path's in the scalar path's
/// order (`+ − × ÷` and [`fma`] are correctly rounded lane by lane as in a
/// scalar register); the table reads are one load per lane. A lane off that
/// path (zero, negative, subnormal, infinite or NaN `x`; a result that may
/// overflow or underflow, or `|y log x| < 2^-54`) is computed again by the
/// scalar [`pow`], as is every lane when `y` itself is special.
#[inline(always)]
#[allow(clippy::cast_possible_truncation, clippy::cast_possible_wrap)] // bit fields, as `pow`'s
pub(crate) fn pow_lanes<const N: usize>(x: [f64; N], y: f64) -> [f64; N] {
    let topy = top12(y);
    if zeroinfnan(y.to_bits()) || (topy & 0x7ff).wrapping_sub(0x3be) >= 0x43e - 0x3be {
        return x.map(|x| pow(x, y));
    }
    // log_inline, lane-wise.
    let ix: [u64; N] = each_lane!(N, |l| x[l].to_bits());
    let tmp: [u64; N] = each_lane!(N, |l| ix[l].wrapping_sub(OFF));
    let i: [usize; N] = each_lane!(N, |l| ((tmp[l] >> (52 - 7)) % 128) as usize);
    let kd: [f64; N] = each_lane!(N, |l| ((tmp[l] as i64) >> 52) as f64);
    let iz: [u64; N] = each_lane!(N, |l| ix[l].wrapping_sub(tmp[l] & (0xfff << 52)));
    let z: [f64; N] = each_lane!(N, |l| d(iz[l]));
    let invc: [f64; N] = each_lane!(N, |l| d(LOG_TAB[i[l]][0]));
    let logc: [f64; N] = each_lane!(N, |l| d(LOG_TAB[i[l]][1]));
    let logctail: [f64; N] = each_lane!(N, |l| d(LOG_TAB[i[l]][2]));
    let zhi: [f64; N] = each_lane!(N, |l| d(iz[l] & !((1 << 27) - 1)));
    let zlo: [f64; N] = each_lane!(N, |l| z[l] - zhi[l]);
    let r: [f64; N] = each_lane!(N, |l| (zhi[l] * invc[l] - 1.0) + zlo[l] * invc[l]);
    let t1: [f64; N] = each_lane!(N, |l| kd[l] * d(LN2HI) + logc[l]);
    let t2: [f64; N] = each_lane!(N, |l| t1[l] + r[l]);
    let lo1: [f64; N] = each_lane!(N, |l| fma(kd[l], d(LN2LO), logctail[l]));
    let lo2: [f64; N] = each_lane!(N, |l| t1[l] - t2[l] + r[l]);
    let a = each_lane!(LOG_POLY.len(), |i| d(LOG_POLY[i]));
    let ar: [f64; N] = each_lane!(N, |l| a[0] * r[l]);
    let ar2: [f64; N] = each_lane!(N, |l| r[l] * ar[l]);
    let ar3: [f64; N] = each_lane!(N, |l| r[l] * ar2[l]);
    let hi: [f64; N] = each_lane!(N, |l| t2[l] + ar2[l]);
    let lo3: [f64; N] = each_lane!(N, |l| -0.5 * square_error(r[l], -2.0 * ar2[l]));
    let lo4: [f64; N] = each_lane!(N, |l| t2[l] - hi[l] + ar2[l]);
    let q: [f64; N] = each_lane!(N, |l| fma(
        ar2[l],
        fma(r[l], a[6], a[5]),
        fma(r[l], a[4], a[3])
    ));
    let q: [f64; N] = each_lane!(N, |l| fma(ar2[l], q[l], fma(r[l], a[2], a[1])));
    let lo: [f64; N] = each_lane!(N, |l| fma(ar3[l], q[l], lo1[l] + lo2[l] + lo3[l] + lo4[l]));
    let log_hi: [f64; N] = each_lane!(N, |l| hi[l] + lo[l]);
    let log_lo: [f64; N] = each_lane!(N, |l| hi[l] - log_hi[l] + lo[l]);
    // pow's product y * log(x).
    let ehi: [f64; N] = each_lane!(N, |l| y * log_hi[l]);
    let elo: [f64; N] = each_lane!(N, |l| fma(y, log_lo[l], fma(y, log_hi[l], -ehi[l])));
    // exp_inline's regular path (sign_bias 0: x > 0), lane-wise.
    let mut kd: [f64; N] = each_lane!(N, |l| fma(d(INV_LN2_N), ehi[l], d(SHIFT)));
    let ki: [u64; N] = each_lane!(N, |l| kd[l].to_bits());
    kd = each_lane!(N, |l| kd[l] - d(SHIFT));
    let r: [f64; N] = each_lane!(N, |l| fma(
        kd[l],
        d(NEG_LN2_LO_N),
        fma(kd[l], d(NEG_LN2_HI_N), ehi[l])
    ));
    let r: [f64; N] = each_lane!(N, |l| r[l] + elo[l]);
    let idx: [usize; N] = each_lane!(N, |l| (2 * (ki[l] % 128)) as usize);
    let top: [u64; N] = each_lane!(N, |l| ki[l] << (52 - 7));
    let tail: [f64; N] = each_lane!(N, |l| d(EXP_TAB[idx[l]]));
    let sbits: [u64; N] = each_lane!(N, |l| EXP_TAB[idx[l] + 1].wrapping_add(top[l]));
    let c = each_lane!(EXP_POLY.len(), |i| d(EXP_POLY[i]));
    let r2: [f64; N] = each_lane!(N, |l| r[l] * r[l]);
    let tmp: [f64; N] = each_lane!(N, |l| fma(
        r2[l] * r2[l],
        fma(r[l], c[3], c[2]),
        fma(r2[l], fma(r[l], c[1], c[0]), tail[l] + r[l])
    ));
    let scale: [f64; N] = each_lane!(N, |l| d(sbits[l]));
    let result: [f64; N] = each_lane!(N, |l| fma(scale[l], tmp[l], scale[l]));
    // The lanes on the regular path: pow's first test (x a positive normal
    // number) and exp_inline's (2^-54 <= |y log x| < 512).
    let regular: [bool; N] = each_lane!(N, |l| top12(x[l]).wrapping_sub(0x001) < 0x7ff - 0x001
        && (top12(ehi[l]) & 0x7ff).wrapping_sub(top12(pow2(-54)))
            < top12(512.0) - top12(pow2(-54)));
    if regular.iter().all(|&r| r) {
        return result;
    }
    each_lane!(N, |l| if regular[l] { result[l] } else { pow(x[l], y) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `square_error` is its doc's "`r*r - q` exactly" over its whole range
    /// (`|r|` from 2^-62 to 2^-6, every significand, both signs): the same
    /// number as the fused multiply-add's `fma(r, r, -q)`, including for `|r|`
    /// below 2^-26, where a wrong split of `r` would still make most of the
    /// products exact, and at the range's ends.
    #[test]
    fn square_error_is_the_exact_error_of_the_square() {
        let mut next = crate::math::test_bits(0x5eed_5e11);
        let check = |r: f64| {
            let q = r * r;
            assert_eq!(
                square_error(r, q).to_bits(),
                fma(r, r, -q).to_bits(),
                "r = {r:e} [{:#x}]",
                r.to_bits()
            );
        };
        for _ in 0..200_000 {
            let bits = next();
            // Exponents 2^-62 ..= 2^-7 (biased 961 ..= 1016), any significand.
            let exponent = 961 + (bits >> 52) % 56;
            let r = f64::from_bits((exponent << 52) | (bits & 0x000f_ffff_ffff_ffff));
            check(r);
            check(-r);
        }
        for r in [pow2(-62), pow2(-26), pow2(-6)] {
            for bits in r.to_bits() - 3..=r.to_bits() + 3 {
                check(f64::from_bits(bits));
            }
        }
        check(0.0);
    }

    /// `log_inline`'s product error from a fused multiply-add and from
    /// Dekker's product are the same exact number, so `pow` has the same bits
    /// whichever it takes: on 2^20 random positive `x` over every exponent
    /// (and a negative `x` with integer `y`), `x` on the log table's centres
    /// (where `r` is 0 and the two errors are zeros of opposite signs), near
    /// 1, and the exponents Palmer's step uses (5.25) and random ones. Exact
    /// comparison of the bits: any difference is a bug.
    #[test]
    fn both_product_errors_give_the_same_pow() {
        let mut next = crate::math::test_bits(0x9e37_79b9_7f4a_7c15);
        let check = |x: f64, y: f64| {
            let (a, b) = (pow_with(x, y, true), pow_with(x, y, false));
            assert_eq!(a.to_bits(), b.to_bits(), "pow({x:e}, {y:e}): {a:e} / {b:e}");
        };
        for _ in 0..1 << 20 {
            let x = f64::from_bits(next() >> 1); // every positive bit pattern
            check(x, 5.25);
            let y = f64::from_bits((next() >> 2) | 0x3000_0000_0000_0000) - 1.5; // |y| up to 2^513
            check(x, y);
            // The pressure's base, 1 - 0.0065 z / 288.15, for z from -1 km to 45 km.
            let base =
                1.0 - 0.0065 * ((next() >> 11) as f64 / (1u64 << 53) as f64 * 46e3 - 1e3) / 288.15;
            check(base, 5.25);
        }
        check(-3.0, 3.0);
        check(-0.5, 4.0);
        for entry in LOG_TAB {
            // 1/invc is near the centre of the entry's interval: r is 0 or tiny there.
            let centre = 1.0 / d(entry[0]);
            for x in [centre, centre * 2.0, centre / 1024.0] {
                for bits in x.to_bits() - 2..=x.to_bits() + 2 {
                    check(f64::from_bits(bits), 5.25);
                    check(f64::from_bits(bits), -0.75);
                }
            }
        }
        for bits in 1f64.to_bits() - 1000..1f64.to_bits() + 1000 {
            check(f64::from_bits(bits), 5.25);
        }
    }
}
