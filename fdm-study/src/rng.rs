//! The random numbers of a study: a counter-based generator and the samplers
//! of the dispersions.
//!
//! Each run's random values come from Philox4x32-10 (Salmon et al., "Parallel
//! random numbers: as easy as 1, 2, 3", SC 2011; the Random123 library), keyed
//! by the study's seed and counted by `(run index, dispersion index)`. A draw
//! is a pure function of `(seed, run, dispersion)`: run `i` gets the same
//! values whatever the number of runs, threads, blocks, shards or machines,
//! and adding a dispersion after the others never moves the earlier draws.
//!
//! The samplers use one uniform each and invert the distribution's CDF with
//! the pure-Rust `libm` crate and `fdm_core::math` (never the platform's
//! libm), so they give the same bits on every machine.

/// Philox4x32's first round multiplier (Random123's `PHILOX_M4x32_0`).
const M0: u32 = 0xD251_1F53;
/// Philox4x32's second round multiplier (`PHILOX_M4x32_1`).
const M1: u32 = 0xCD9E_8D57;
/// The key's first Weyl increment (`PHILOX_W32_0`, golden ratio).
const W0: u32 = 0x9E37_79B9;
/// The key's second Weyl increment (`PHILOX_W32_1`, sqrt(3) - 1).
const W1: u32 = 0xBB67_AE85;

/// Philox4x32-10: the 4 × 32-bit block of counter `counter` under `key`,
/// exactly as Random123's `philox4x32(ctr, key)` with 10 rounds.
///
/// ```
/// use fdm_study::rng::philox4x32_10;
///
/// // Random123's known-answer vector for a zero counter and key.
/// assert_eq!(
///     philox4x32_10([0; 4], [0; 2]),
///     [0x6627_e8d5, 0xe169_c58d, 0xbc57_ac4c, 0x9b00_dbd8]
/// );
/// ```
#[must_use]
pub fn philox4x32_10(counter: [u32; 4], key: [u32; 2]) -> [u32; 4] {
    let mut x = counter;
    let mut k = key;
    for round in 0..10 {
        if round > 0 {
            k = [k[0].wrapping_add(W0), k[1].wrapping_add(W1)];
        }
        let p0 = u64::from(M0) * u64::from(x[0]);
        let p1 = u64::from(M1) * u64::from(x[2]);
        let (hi0, lo0) = ((p0 >> 32) as u32, p0 as u32);
        let (hi1, lo1) = ((p1 >> 32) as u32, p1 as u32);
        x = [hi1 ^ x[1] ^ k[0], lo1, hi0 ^ x[3] ^ k[1], lo0];
    }
    x
}

/// The uniform of dispersion `draw` of run `run` in a study seeded `seed`: a
/// value in the open interval (0, 1) with 53 random bits, from the first two
/// words of Philox4x32-10 at counter `(run low, run high, draw, 0)` under the
/// key `(seed low, seed high)`.
#[must_use]
pub fn uniform(seed: u64, run: u64, draw: u32) -> f64 {
    let key = [seed as u32, (seed >> 32) as u32];
    let block = philox4x32_10([run as u32, (run >> 32) as u32, draw, 0], key);
    let bits = (u64::from(block[0]) << 32 | u64::from(block[1])) >> 11;
    // (k + 1/2) / 2^53: never 0 nor 1, so the inversions below stay finite.
    (bits as f64 + 0.5) * (1.0 / 9_007_199_254_740_992.0)
}

/// The standard normal CDF Φ(x), from the pure-Rust `erfc`.
#[must_use]
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x * core::f64::consts::FRAC_1_SQRT_2)
}

/// The standard normal quantile Φ⁻¹(p) for p in (0, 1): Wichura's algorithm
/// AS 241 (PPND16, relative accuracy about 1e-16), with the pure-Rust `log`
/// and `fdm_core::math::sqrt`. `p` outside (0, 1) gives ±infinity at the ends
/// (the callers never pass them).
#[must_use]
#[allow(clippy::excessive_precision, clippy::unreadable_literal)]
pub fn normal_quantile(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        return q
            * (((((((2509.0809287301226727 * r + 33430.575583588128105) * r
                + 67265.770927008700853)
                * r
                + 45921.953931549871457)
                * r
                + 13731.693765509461125)
                * r
                + 1971.5909503065514427)
                * r
                + 133.14166789178437745)
                * r
                + 3.387132872796366608)
            / (((((((5226.495278852545925 * r + 28729.085735721942674) * r
                + 39307.89580009271061)
                * r
                + 21213.794301586595867)
                * r
                + 5394.1960214247511077)
                * r
                + 687.1870074920579083)
                * r
                + 42.313330701600911252)
                * r
                + 1.0);
    }
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let mut r = fdm_core::math::sqrt(-libm::log(tail));
    let value = if r <= 5.0 {
        r -= 1.6;
        (((((((7.7454501427834140764e-4 * r + 0.0227238449892691845833) * r
            + 0.24178072517745061177)
            * r
            + 1.27045825245236838258)
            * r
            + 3.64784832476320460504)
            * r
            + 5.7694972214606914055)
            * r
            + 4.6303378461565452959)
            * r
            + 1.42343711074968357734)
            / (((((((1.05075007164441684324e-9 * r + 5.475938084995344946e-4) * r
                + 0.0151986665636164571966)
                * r
                + 0.14810397642748007459)
                * r
                + 0.68976733498510000455)
                * r
                + 1.6763848301838038494)
                * r
                + 2.05319162663775882187)
                * r
                + 1.0)
    } else {
        r -= 5.0;
        (((((((2.01033439929228813265e-7 * r + 2.71155556874348757815e-5) * r
            + 0.0012426609473880784386)
            * r
            + 0.026532189526576123093)
            * r
            + 0.29656057182850489123)
            * r
            + 1.7848265399172913358)
            * r
            + 5.4637849111641143699)
            * r
            + 6.6579046435011037772)
            / (((((((2.04426310338993978564e-15 * r + 1.4215117583164458887e-7) * r
                + 1.8463183175100546818e-5)
                * r
                + 7.868691311456132591e-4)
                * r
                + 0.0148753612908506148525)
                * r
                + 0.13692988092273580531)
                * r
                + 0.59983220655588793769)
                * r
                + 1.0)
    };
    if q < 0.0 {
        -value
    } else {
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random123's known-answer vectors for philox4x32 with 10 rounds
    /// (`kat_vectors`): counter, key, expected block. Exact equality: the
    /// generator is integer arithmetic.
    #[test]
    fn philox_matches_random123_known_answers() {
        let cases: [([u32; 4], [u32; 2], [u32; 4]); 3] = [
            (
                [0, 0, 0, 0],
                [0, 0],
                [0x6627_e8d5, 0xe169_c58d, 0xbc57_ac4c, 0x9b00_dbd8],
            ),
            (
                [u32::MAX; 4],
                [u32::MAX; 2],
                [0x408f_276d, 0x41c8_3b0e, 0xa20b_c7c6, 0x6d54_51fd],
            ),
            (
                [0x243f_6a88, 0x85a3_08d3, 0x1319_8a2e, 0x0370_7344],
                [0xa409_3822, 0x299f_31d0],
                [0xd16c_fe09, 0x94fd_cceb, 0x5001_e420, 0x2412_6ea1],
            ),
        ];
        for (counter, key, expected) in cases {
            assert_eq!(philox4x32_10(counter, key), expected, "{counter:x?}");
        }
    }

    /// Uniforms pinned to the values of an independent Philox4x32-10
    /// written in Python from Random123's description (checked there against
    /// its first known answer), with `(bits + 0.5) / 2^53` in Python floats:
    /// seeds and runs above 2^32 (their high words go into the key and the
    /// counter), the largest of each coordinate, and `1 << 32`, whose low
    /// words are 0. Exact equality: integer arithmetic and one rounding of
    /// `bits + 0.5`, the same in both languages. A study's runs are these
    /// values, so they are also its promise across releases.
    #[test]
    fn uniforms_are_those_of_an_independent_philox() {
        let cases: [(u64, u64, u32, u64); 5] = [
            (0, 0, 0, 0x3fd9_89fa_3578_5a71),
            (2026, 17, 3, 0x3fe2_cda1_62b6_66a8),
            (
                0xdead_beef_0000_0001,
                0x1_0000_0002,
                7,
                0x3feb_23b4_d78b_3e1a,
            ),
            (u64::MAX, u64::MAX, u32::MAX, 0x3fed_d807_049c_983c),
            (1 << 32, 1 << 32, 0, 0x3fd4_cbc4_c88d_b225),
        ];
        for (seed, run, draw, bits) in cases {
            let u = uniform(seed, run, draw);
            assert_eq!(u.to_bits(), bits, "{seed} {run} {draw}: {u}");
        }
    }

    #[test]
    fn uniforms_are_open_and_depend_on_every_coordinate() {
        let u = uniform(7, 3, 1);
        assert!(u > 0.0 && u < 1.0);
        assert_ne!(u, uniform(8, 3, 1));
        assert_ne!(u, uniform(7, 4, 1));
        assert_ne!(u, uniform(7, 3, 2));
        assert_eq!(u.to_bits(), uniform(7, 3, 1).to_bits());
    }

    /// The quantile inverts the CDF: Φ(Φ⁻¹(p)) within 1e-14 of p above 1/2
    /// and within 1e-12 of p relative below it, over the body (|p − 1/2| ≤
    /// 0.425), the near tail (√−ln p ≤ 5, p ≥ about 1.4e-11) and the far
    /// tail, each on both sides. AS 241 is accurate to about 1e-16 relative
    /// in x and erfc to about as much in the lower tail, where Φ keeps its
    /// relative precision: a relative error e in x moves Φ by about x²·e
    /// relative, 1e-13 at x = −37 (p = 1e-300). Above 1/2 the tail is 1 − p,
    /// which `f64` holds only to 1.1e-16 absolute. The far tail's
    /// coefficients each move p by far more than that.
    #[test]
    fn quantile_inverts_the_cdf() {
        let lower = [
            1e-300, 1e-100, 1e-30, 1e-12, 1.3e-11, 2e-11, 1e-8, 1e-4, 0.01, 0.074, 0.076, 0.2,
        ];
        for p in lower {
            let x = normal_quantile(p);
            assert!(x.is_finite() && x < 0.0);
            let back = normal_cdf(x);
            assert!((back - p).abs() <= p * 1e-12, "{p} {x} {back}");
            // The upper side: q = 1 - p rounded, whose own 1 - q is exact
            // (Sterbenz, q >= 1/2), so the upper tail's quantile is the lower
            // one's of 1 - q negated, bit for bit. (For the smallest p, q
            // rounds to 1 and its quantile is infinite.)
            let q = 1.0 - p;
            if q < 1.0 {
                assert_eq!(normal_quantile(q), -normal_quantile(1.0 - q), "{p}");
            }
        }
        for p in [0.5, 0.7, 0.926, 0.975, 1.0 - 1e-9, 1.0 - 2f64.powi(-40)] {
            let x = normal_quantile(p);
            assert!(x.is_finite());
            let back = normal_cdf(x);
            assert!((back - p).abs() <= 1e-14, "{p} {x} {back}");
        }
        // The upper far tail against the lower one: 1 - 2^-50 is exact.
        let p = 2f64.powi(-50);
        assert_eq!(normal_quantile(1.0 - p), -normal_quantile(p));
        assert!((normal_cdf(normal_quantile(p)) - p).abs() <= p * 1e-12);
        assert_eq!(normal_quantile(0.5), 0.0);
        assert!((normal_quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-14);
    }

    /// Over 200,000 draws the sample mean and standard deviation of
    /// Φ⁻¹(uniform) are those of N(0, 1) within 5 standard errors
    /// (mean: 5/sqrt(n) = 0.011; sd: 5/sqrt(2n) = 0.008).
    #[test]
    fn normal_draws_look_normal() {
        let n = 200_000u32;
        let xs: Vec<f64> = (0..n)
            .map(|i| normal_quantile(uniform(1, u64::from(i), 0)))
            .collect();
        let mean = xs.iter().sum::<f64>() / f64::from(n);
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / f64::from(n - 1);
        assert!(mean.abs() < 0.011, "{mean}");
        assert!((var.sqrt() - 1.0).abs() < 0.008, "{var}");
    }
}
