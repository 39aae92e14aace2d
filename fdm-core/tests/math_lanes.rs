//! The lane-wise exact maths of `fdm_core::real`'s lanes ([`Real::pow_exact`]
//! on [`F64s`], [`Real::asinf_exact`] on [`F32s`]) give the bits of the scalar
//! `fdm_core::math` functions in every lane, whatever the other lanes hold: on
//! the reference cases' range, on random bit patterns and on every special
//! value, mixed in one block so that the regular path and the scalar
//! fallback meet. (`asinf` is also compared on every `f32` by the ignored
//! test in `math_exhaustive.rs`.)

use fdm_core::math::{asinf, pow};
use fdm_core::real::{F32s, F64s, Real};

/// SplitMix64: a fixed sequence of 64-bit patterns.
fn patterns(seed: u64) -> impl FnMut() -> u64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

const SPECIAL_F64: [f64; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    -2.0,
    -0.5,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    f64::MIN_POSITIVE,
    4.9e-324,
    1e-310,
    f64::MAX,
    1.000_000_000_000_000_2,
    0.999_999_999_999_999_9,
    1e300,
];

/// Every lane of `pow_exact` against `pow`, in blocks of 8 and of 3.
fn check_pow(xs: &[f64], y: f64) {
    for block in xs.chunks(8) {
        let mut lanes = F64s([1.5; 8]);
        lanes.0[..block.len()].copy_from_slice(block);
        let out = lanes.pow_exact(y);
        for (l, &x) in lanes.0.iter().enumerate() {
            assert_eq!(out.0[l].to_bits(), pow(x, y).to_bits(), "pow({x:e}, {y:e})");
        }
    }
    for block in xs.chunks(3) {
        let mut lanes = F64s([0.75; 3]);
        lanes.0[..block.len()].copy_from_slice(block);
        let out = lanes.pow_exact(y);
        for (l, &x) in lanes.0.iter().enumerate() {
            assert_eq!(out.0[l].to_bits(), pow(x, y).to_bits(), "pow({x:e}, {y:e})");
        }
    }
    assert_eq!(y.pow_exact(y).to_bits(), pow(y, y).to_bits());
}

#[test]
fn pow_lanes_have_the_scalar_bits() {
    let mut next = patterns(0x0DD_BA11);
    let ys = [
        5.25, // Palmer's pressure
        2.0,
        0.5,
        -1.5,
        3.0,
        -7.0,
        0.1,
        1e-30,
        1e10,
        1e-300,
        1e300,
        0.0,
        -0.0,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        1.0,
        -1.0,
    ];
    for &y in &ys {
        let mut xs: Vec<f64> = Vec::new();
        // Palmer's `1 - 0.0065 z / 288.15` from z = -1 km to 20 km and beyond.
        xs.extend((0..20_000).map(|i| 0.5 + 0.6 * f64::from(i) / 20_000.0));
        // Random bit patterns (every sign, exponent and NaN payload).
        xs.extend((0..20_000).map(|_| f64::from_bits(next())));
        // Random positive values near 1 and across the exponent range
        // (overflow and underflow of x^y).
        xs.extend((0..20_000).map(|_| f64::from_bits(0x3fe0_0000_0000_0000 + (next() >> 11))));
        xs.extend((0..20_000).map(|_| f64::from_bits(next() >> 1)));
        // The special values, alone and between regular ones.
        for (i, &s) in SPECIAL_F64.iter().enumerate() {
            xs.push(s);
            xs.push(0.9 + 0.01 * f64::from(u32::try_from(i).expect("small")));
        }
        check_pow(&xs, y);
    }
}

/// Every lane of `asinf_exact` against `asinf`, in blocks of 16 and of 5.
fn check_asinf(xs: &[f32]) {
    for block in xs.chunks(16) {
        let mut lanes = F32s([0.25; 16]);
        lanes.0[..block.len()].copy_from_slice(block);
        let out = lanes.asinf_exact();
        for (l, &x) in lanes.0.iter().enumerate() {
            assert_eq!(out.0[l].to_bits(), asinf(x).to_bits(), "asinf({x:e})");
        }
    }
    for block in xs.chunks(5) {
        let mut lanes = F32s([-0.75; 5]);
        lanes.0[..block.len()].copy_from_slice(block);
        let out = lanes.asinf_exact();
        for (l, &x) in lanes.0.iter().enumerate() {
            assert_eq!(out.0[l].to_bits(), asinf(x).to_bits(), "asinf({x:e})");
        }
    }
}

#[test]
fn asinf_lanes_have_the_scalar_bits() {
    let mut next = patterns(0xA51F);
    let mut xs: Vec<f32> = Vec::new();
    // Sines of angles of attack from -90 to 90 degrees.
    xs.extend((0..100_000).map(|i| (-1.0 + 2.0 * f64::from(i) / 100_000.0) as f32));
    // Random bit patterns.
    xs.extend((0..100_000).map(|_| f32::from_bits((next() >> 32) as u32)));
    // Each branch's edges and the range's ends.
    for bits in [
        0,
        1,
        0x31ff_ffff,
        0x3200_0000,
        0x3eff_ffff,
        0x3f00_0000,
        0x3f79_9999,
        0x3f79_999a,
        0x3f7f_ffff,
        0x3f80_0000,
        0x3f80_0001,
        0x7f80_0000,
        0x7fc0_0000,
        0x7f80_0001,
        0x3cb1_b351,
        0x3f75_d580,
    ] {
        xs.push(f32::from_bits(bits));
        xs.push(-f32::from_bits(bits));
        xs.push(0.3);
    }
    check_asinf(&xs);
    assert_eq!(0.3f32.asinf_exact().to_bits(), asinf(0.3).to_bits());
}
