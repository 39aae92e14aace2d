//! `fdm_core::math::asinf` on every `f32` it can be given: its bits are x86-64
//! glibc 2.36's `asinf` bits on all of `[-1, 1]` (2,130,706,433 inputs) and NaN
//! outside. The check is a 64-bit FNV-1a hash of the results' bits for every
//! non-negative input, recorded from glibc (the negative inputs give the
//! negated results, checked on a sweep), so it proves the same on any target;
//! on an x86-64 glibc host every result is also compared with `std`'s (glibc's)
//! directly.
//!
//! About a minute in release mode, so ignored by default; run it with
//! `cargo test --release -p fdm-core --test math_exhaustive -- --ignored`.
//! CI optimises only fdm-core (`--config
//! 'profile.dev.package.fdm-core.opt-level=3'` instead of `--release`), which
//! reuses the debug build of the dev-dependencies.

use fdm_core::math::{asinf, pow};
use fdm_core::real::{F32s, F64s, Real};

/// FNV-1a over the little-endian bytes of `asinf(x).to_bits()` for the bits of
/// `x` from `0` to `0x3f80_0000` (1.0), computed with x86-64 glibc 2.36's
/// `asinf`.
const GLIBC_ASINF_HASH: u64 = 0x9f8f_a575_5e07_d9ed;

/// SplitMix64 from `seed`: the samples' bit patterns, the same sequence on
/// every machine.
fn splitmix64(seed: u64) -> impl FnMut() -> u64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

const GLIBC_X86_64: bool = cfg!(all(
    target_arch = "x86_64",
    target_os = "linux",
    target_env = "gnu"
));

#[test]
#[ignore = "exhaustive: run with --release --ignored"]
fn asinf_has_glibcs_bits_on_every_f32() {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for bits in 0..=0x3f80_0000_u32 {
        let x = f32::from_bits(bits);
        let r = asinf(x).to_bits();
        if GLIBC_X86_64 {
            assert_eq!(r, x.asin().to_bits(), "asinf({x:e})");
        }
        for byte in r.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    assert_eq!(hash, GLIBC_ASINF_HASH, "{hash:#x}");
}

/// The lane-wise `asinf` of `fdm_core::real`'s lanes ([`Real::asinf_exact`]
/// on [`F32s`]) against the scalar `asinf` on every one of the 2^32 bit
/// patterns, 16 consecutive patterns per block: the fleet's vector `asinf`
/// has the scalar's bits (and so glibc's) everywhere.
#[test]
#[ignore = "exhaustive: run with --release --ignored"]
fn asinf_lanes_have_the_scalar_bits_on_every_f32() {
    for first in (0..=u32::MAX).step_by(16) {
        let x = F32s::<16>(core::array::from_fn(|l| {
            f32::from_bits(first + u32::try_from(l).expect("lane"))
        }));
        let lanes = x.asinf_exact();
        for l in 0..16 {
            let scalar = asinf(x.0[l]);
            assert_eq!(
                lanes.0[l].to_bits(),
                scalar.to_bits(),
                "asinf({:e})",
                x.0[l]
            );
        }
    }
}

#[test]
fn asinf_is_odd_and_nan_outside_its_domain() {
    for bits in (0..=0x3f80_0000_u32).step_by(997) {
        let x = f32::from_bits(bits);
        assert_eq!(asinf(-x).to_bits(), (-asinf(x)).to_bits(), "{x:e}");
    }
    for bits in (0x3f80_0001..=0x7f80_0000_u32).step_by(9_973) {
        let x = f32::from_bits(bits);
        assert!(asinf(x).is_nan() && asinf(-x).is_nan(), "{x:e}");
    }
    assert!(asinf(f32::NAN).is_nan());
    assert_eq!(asinf(1.0), core::f32::consts::FRAC_PI_2);
    assert_eq!(asinf(-1.0), -core::f32::consts::FRAC_PI_2);
}

/// `pow` against x86-64 glibc's on 20,000,000 inputs: half `pow(x, 5.25)` with
/// `x` in `[0.5, 1.05)` (Palmer's density ratio), half `x` in `[0.001, 100)` and
/// `y` in `[-20, 20)`. Only where `std` is x86-64 glibc.
#[test]
#[ignore = "20 million samples: run with --release --ignored"]
fn pow_has_glibcs_bits_on_20_million_samples() {
    if !GLIBC_X86_64 {
        return;
    }
    let mut bits = splitmix64(1);
    let mut uniform = || (bits() >> 11) as f64 / (1_u64 << 53) as f64;
    for i in 0..20_000_000 {
        let (x, y) = if i % 2 == 0 {
            (0.5 + 0.55 * uniform(), 5.25)
        } else {
            (1e-3 + 100.0 * uniform(), -20.0 + 40.0 * uniform())
        };
        assert_eq!(
            pow(x, y).to_bits(),
            x.powf(y).to_bits(),
            "pow({x:e}, {y:e})"
        );
    }
}

/// The lane-wise `pow` of `fdm_core::real`'s lanes ([`Real::pow_exact`] on
/// [`F64s`]) against the scalar `pow` on 40,000,000 inputs: `pow(x, 5.25)`
/// with `x` in `[0.5, 1.05)` (Palmer's density ratio), `x` in `[0.001, 100)`
/// with `y` in `[-20, 20)` (one `y` per block of 8), and random bit patterns
/// of `x` with `y` 5.25.
#[test]
#[ignore = "40 million samples: run with --release --ignored"]
fn pow_lanes_have_the_scalar_bits_on_40_million_samples() {
    let mut bits = splitmix64(7);
    let unit = |b: u64| (b >> 11) as f64 / (1_u64 << 53) as f64;
    for block in 0..5_000_000 {
        let (x, y) = match block % 3 {
            0 => (
                F64s::<8>(core::array::from_fn(|_| 0.5 + 0.55 * unit(bits()))),
                5.25,
            ),
            1 => {
                let y = -20.0 + 40.0 * unit(bits());
                (
                    F64s(core::array::from_fn(|_| 1e-3 + 100.0 * unit(bits()))),
                    y,
                )
            }
            _ => (
                F64s::<8>(core::array::from_fn(|_| f64::from_bits(bits()))),
                5.25,
            ),
        };
        let lanes = x.pow_exact(y);
        for l in 0..8 {
            let scalar = pow(x.0[l], y);
            assert_eq!(
                lanes.0[l].to_bits(),
                scalar.to_bits(),
                "pow({:e}, {y:e})",
                x.0[l]
            );
        }
    }
}

/// `pow` against x86-64 glibc's `pow` (the same algorithm, so the same bits;
/// docs/determinism.md) where the exhaustive samples above rarely go, quick
/// enough to run with every test: C's special cases (zeros of both signs,
/// ±1, ±∞, NaN, negative bases with odd, even and non-integer exponents,
/// subnormal bases, exponents below 2^-65 and beyond 2^63), results at the
/// edges of overflow and underflow (into the subnormals, and to zero), and
/// random pairs over every exponent of `x` and `y`. A NaN is compared as a
/// NaN (C does not fix its sign or payload). Only where `std` is x86-64 glibc.
#[test]
fn pow_has_glibcs_bits_on_its_special_cases_and_edges() {
    if !GLIBC_X86_64 {
        return;
    }
    let check = |x: f64, y: f64| {
        let (ours, glibc) = (pow(x, y), x.powf(y));
        assert!(
            ours.to_bits() == glibc.to_bits() || (ours.is_nan() && glibc.is_nan()),
            "pow({x:e}, {y:e}) = {ours:e}, glibc {glibc:e}"
        );
    };
    let tiny_y = f64::from_bits(0x3be0_0000_0000_0000); // 2^-65
    let huge_y = f64::from_bits(0x43e0_0000_0000_0000); // 2^63
    let below_one = f64::from_bits(1f64.to_bits() - 1);
    let above_one = f64::from_bits(1f64.to_bits() + 1);
    let special = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        -0.5,
        2.0,
        -2.0,
        3.0,
        -3.0,
        below_one,
        above_one,
        -below_one,
        -above_one,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        f64::MIN_POSITIVE / 3.0, // subnormal
        -f64::MIN_POSITIVE / 3.0,
        5e-324,
        -5e-324,
        f64::MAX,
        -f64::MAX,
        1e-300,
        1e300,
        tiny_y,
        tiny_y / 2.0,
        -tiny_y / 2.0,
        tiny_y * 2.0,
        huge_y,
        -huge_y,
        huge_y / 2.0,
        huge_y * 2.0,
        0.25,
        1.5,
        -1.5,
        5.25,
        1e10,
        -1e10,
        1e20,
        1e-20,
        2f64.powi(52) + 1.0, // an odd integer with the last bit
        -(2f64.powi(52) + 1.0),
        2f64.powi(53),       // even
        2f64.powi(52) + 0.5, // not an integer
    ];
    for x in special {
        for y in special {
            check(x, y);
        }
    }
    // Results near overflow (2^1024) and near and below the smallest normal
    // and subnormal numbers (2^-1022, 2^-1074), from both signs of x.
    for e in [
        1023.0, 1024.0, -1021.0, -1022.0, -1023.0, -1060.0, -1074.0, -1075.0, -1076.0,
    ] {
        for k in -64_i32..=64 {
            let y = e + f64::from(k) / 64.0;
            check(2.0, y);
            check(0.5, -y);
            check(-2.0, y.round());
            check(-0.5, -y.round());
            check(core::f64::consts::E, y * core::f64::consts::LN_2);
            check(10.0, y * core::f64::consts::LOG10_2);
        }
    }
    // Results in the subnormal range, rounded once to its grid (not twice):
    // bases that are not powers of two, both signs (negative bases with odd
    // and even integer exponents), over every exponent from just above the
    // smallest normal number to below the smallest subnormal one.
    for base in [3.0, 10.0, 1.1, 7.5, 1.0001, 0.9, 0.3] {
        let lowest = -1077.0 * core::f64::consts::LN_2 / f64::ln(base);
        let highest = -1021.0 * core::f64::consts::LN_2 / f64::ln(base);
        let (from, to) = (lowest.min(highest).floor(), lowest.max(highest).ceil());
        let step = ((to - from) / 400.0).max(1.0).floor();
        let mut y = from;
        while y <= to {
            check(base, y);
            check(-base, y);
            check(-base, y + 1.0);
            check(base, y + 0.5);
            y += step;
        }
    }
    // Pairs whose last bit depends on the logarithm's tail (the low part of
    // its double-double result): y log x far from 0, mostly x near 1 with a
    // large y. Found by comparing, on 2 million samples, a `pow` whose tail
    // was computed wrongly with glibc's; glibc's bits, by their bits.
    for (x, y) in [
        (0x3fef_fbf9_982d_e422_u64, 0x411c_011b_4d5d_33ed_u64),
        (0x3fef_fcdf_63ce_2d7c, 0x4124_dda2_f0c0_999c),
        (0x4051_8c05_b709_d1ad, 0x4023_d8e9_cb45_1274),
        (0x3ff0_0121_e673_a673, 0x40fd_1f4f_b00e_4bba),
        (0x3ff0_0135_ad83_9635, 0xc125_12c3_660d_920b),
        (0x404b_63c8_a0c4_71a4, 0x4033_1b94_5c12_0112),
        (0x3fef_fd61_a550_8dd3, 0x4123_8e43_36da_e840),
        (0x3ff0_00e6_abc4_e15c, 0xc10a_66e6_3d34_b2b9),
    ] {
        check(f64::from_bits(x), f64::from_bits(y));
    }
    // Random pairs: x over every exponent (either sign: the negative ones
    // with integer exponents and without), y over ±2^-70..±2^70.
    let mut bits = splitmix64(3);
    for _ in 0..100_000 {
        let x = f64::from_bits(bits() & 0x7fef_ffff_ffff_ffff);
        let y = f64::from_bits((bits() & 0x800f_ffff_ffff_ffff) | ((0x3b9 + bits() % 140) << 52));
        check(x, y);
        check(-x, y);
        check(-x, y.round());
        check(x, 5.25);
    }
}

/// `asinf` against x86-64 glibc's `asinf` on a sample quick enough to run with
/// every test (the exhaustive check above is ignored by default): every 1009th
/// `f32` of `[0, 1]`, both signs, and each branch's edges (2^-27, 0.5, 0.975,
/// 1) with their neighbours. Only where `std` is x86-64 glibc.
#[test]
fn asinf_has_glibcs_bits_on_a_sample() {
    if !GLIBC_X86_64 {
        return;
    }
    let check = |x: f32| {
        assert_eq!(
            asinf(x).to_bits(),
            x.asin().to_bits(),
            "asinf({x:e}) [{:#x}]",
            x.to_bits()
        );
    };
    for bits in (0..=0x3f80_0000_u32).step_by(1009) {
        check(f32::from_bits(bits));
        check(-f32::from_bits(bits));
    }
    for edge in [0x3200_0000_u32, 0x3f00_0000, 0x3f79_999a, 0x3f80_0000] {
        for bits in edge - 64..=edge + 64 {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
        }
    }
}
