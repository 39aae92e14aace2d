//! `fdm_core::math::asinf` on every `f32` it can be given: its bits are x86-64
//! glibc 2.36's `asinf` bits on all of `[-1, 1]` (2,130,706,433 inputs) and NaN
//! outside. The check is a 64-bit FNV-1a hash of the results' bits for every
//! non-negative input, recorded from glibc (the negative inputs give the
//! negated results, checked on a sweep), so it proves the same on any target;
//! on an x86-64 glibc host every result is also compared with `std`'s (glibc's)
//! directly.
//!
//! About a minute in release mode, so ignored by default; CI runs it with
//! `cargo test --release -p fdm-core --test math_exhaustive -- --ignored`.

use fdm_core::math::{asinf, pow};

/// FNV-1a over the little-endian bytes of `asinf(x).to_bits()` for the bits of
/// `x` from `0` to `0x3f80_0000` (1.0), computed with x86-64 glibc 2.36's
/// `asinf`.
const GLIBC_ASINF_HASH: u64 = 0x9f8f_a575_5e07_d9ed;

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
    let mut s = 1_u64;
    let mut uniform = || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1_u64 << 53) as f64
    };
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
