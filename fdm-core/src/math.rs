//! Deterministic scalar maths: the same bits on every target, with or without
//! `std`.
//!
//! Every function here is pure Rust and uses only IEEE 754 operations that are
//! correctly rounded by definition (`+ − × ÷`, `sqrt`, and fused multiply-add
//! called explicitly through [`fma`]); Rust never contracts `a * b + c` into
//! an FMA on its own. None of them calls the platform's libm, so a build for
//! x86-64, aarch64 or a `no_std` target computes the same bits. Where the
//! models' reference cases need glibc's bits (the original programs were built
//! against glibc 2.36 on x86-64), the functions reproduce them:
//!
//! | function | implementation | agrees with x86-64 glibc 2.36 |
//! | --- | --- | --- |
//! | [`pow`] | port of ARM optimized-routines' `pow` (glibc's own), FMA form | on every sampled input (see docs/determinism.md) |
//! | [`asinf`] | fdlibm's `asinf` structure with a polynomial fitted to glibc's outputs, plus a table of 5,058 exceptions | on every `f32` |
//! | [`sqrt`], [`sqrtf`] | IEEE square root | everywhere (correctly rounded) |
//! | [`cbrt`] | the `libm` crate's port of CORE-MATH | correctly rounded; glibc is not (half the inputs differ by 1 ulp) |
//! | [`sinf`], [`cosf`] | f64 `sin`/`cos` rounded to f32 | on the default airframe's angles; elsewhere ours is correctly rounded, glibc is not on 0.08 % / 0.03 % of `[-π, π]` |
//! | [`sin`], [`cos`], [`atan`], [`atan2`], [`asin`], [`hypot`], [`atan2f`] | the `libm` crate (fdlibm) | on the reference cases' inputs; not everywhere (fdlibm and glibc both miss correct rounding at times) |
//! | [`acos`], [`tan`] (outputs only: FlightGear multiplayer, DIS) | the `libm` crate (fdlibm) | not needed: no reference case calls them |
//!
//! [`atan2_lanes`], [`hypot_lanes`], [`asin_lanes`] and [`sin_cos_lanes`] are those functions for several
//! arguments at once, bit for bit (the same operations in the same order, lane by lane, and
//! the scalar function for any lane off their main path).
//!
//! docs/determinism.md has the study behind this table (exhaustive over `f32`,
//! dense samples for `f64`) and the targets on which it is proven.

mod asinf_table;
mod pow;
mod pow_data;

/// `a × b + c` with a single rounding (IEEE 754 fused multiply-add): the
/// CPU's instruction or glibc's `fma` with `std`, the `libm` crate's software
/// `fma` without. Both are correctly rounded, so the bits are the same.
#[inline(always)]
#[must_use]
pub fn fma(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::fma(a, b, c)
    }
}

/// Square root (f64), correctly rounded.
#[inline(always)]
#[must_use]
pub fn sqrt(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}

/// Square root (f32), C's `sqrtf`, correctly rounded.
#[inline(always)]
#[must_use]
pub fn sqrtf(x: f32) -> f32 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrtf(x)
    }
}

/// `x` raised to the power `y` (f64), C's `pow`: glibc's algorithm (ARM
/// optimized-routines), within 0.52 ulp of the exact power.
///
/// With `std` on x86-64, a CPU with AVX2 and FMA (x86-64-v3: every x86-64 CPU
/// since about 2013) runs it in a function compiled for that instruction set,
/// chosen at run time: its fused multiply-adds are then single instructions
/// instead of calls to the C library's `fma`. The bits are the same (a fused
/// multiply-add is correctly rounded however it is computed, and Rust never
/// contracts other operations), which `pow_of_both_instruction_sets_agree`
/// checks on dense samples.
#[inline]
#[must_use]
pub fn pow(x: f64, y: f64) -> f64 {
    with_fma(
        #[inline(always)]
        move || pow::pow(x, y),
    )
}

/// [`pow`] always inlined into its caller, with no dispatch of its own: the
/// scalar steps call it under [`with_fma`], where its fused multiply-adds are
/// instructions; anywhere else it is still correct (the `fma` calls of the
/// baseline give the same bits).
#[inline(always)]
pub(crate) fn pow_inlined(x: f64, y: f64) -> f64 {
    pow::pow(x, y)
}

/// Whether a fused multiply-add is one instruction here: with `std`, on
/// x86-64 when the CPU has FMA (checked at run time, once), and on every
/// aarch64 CPU. [`pow`] then takes one product error from it instead of
/// from Dekker's product (the same exact number, fewer operations in the
/// chain); [`fma`] is correctly rounded either way.
#[inline(always)]
pub(crate) fn fma_is_an_instruction() -> bool {
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    {
        std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(all(feature = "std", target_arch = "aarch64"))]
    {
        true
    }
    #[cfg(not(all(feature = "std", any(target_arch = "x86_64", target_arch = "aarch64"))))]
    {
        false
    }
}

/// Runs `f` in a function compiled for AVX2 and FMA (x86-64-v3) when the CPU
/// has them (with `std` on x86-64), else as it is. A whole scalar step runs
/// through it (one run-time check per step, none per `pow`), so that
/// [`pow_inlined`]'s fused multiply-adds become instructions. The numbers
/// are those of `f()` however it runs: Rust never contracts `a * b + c` into
/// a fused multiply-add, and every operation the wider instruction set may
/// use instead (the AVX forms of `+ − × ÷ √`) is correctly rounded as the
/// baseline's. Only a NaN's sign or payload may differ, which Rust leaves
/// unspecified and docs/determinism.md does not cover.
#[inline(always)]
pub(crate) fn with_fma<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    if let Some(v3) = pulp::x86::V3::try_new() {
        return v3.vectorize(f);
    }
    f()
}

/// [`pow`] of every lane of `x` with one exponent `y`, bit for bit, in vector
/// registers where it can (`crate::real`'s lanes use it).
#[inline(always)]
pub(crate) fn pow_lanes<const N: usize>(x: [f64; N], y: f64) -> [f64; N] {
    pow::pow_lanes(x, y)
}

/// Sine (f64, radians): the `libm` crate's (fdlibm's), under 1 ulp.
#[inline]
#[must_use]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// Cosine (f64, radians): the `libm` crate's (fdlibm's), under 1 ulp.
#[inline]
#[must_use]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// Arc tangent (f64, radians): the `libm` crate's (fdlibm's), under 1 ulp.
#[inline]
#[must_use]
pub fn atan(x: f64) -> f64 {
    libm::atan(x)
}

/// Four-quadrant arc tangent `atan2(y, x)` (f64, radians): the `libm`
/// crate's (fdlibm's).
#[inline]
#[must_use]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// Arc sine (f64, radians): the `libm` crate's (fdlibm's), under 1 ulp.
#[inline]
#[must_use]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// Arc cosine (f64, radians, in `[0, π]`; NaN for `|x| > 1`): the `libm`
/// crate's (fdlibm's), under 1 ulp. The models do not call it; the
/// FlightGear multiplayer orientation does.
#[inline]
#[must_use]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// Tangent (f64, radians): the `libm` crate's (fdlibm's), under 1 ulp. The
/// models do not call it; the DIS dead-reckoning threshold does.
#[inline]
#[must_use]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// `sqrt(x² + y²)` without undue overflow (f64), C's `hypot`: the `libm`
/// crate's.
#[inline]
#[must_use]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// Cube root (f64), C's `cbrt`: correctly rounded (the `libm` crate's port of
/// CORE-MATH's `cbrt`).
#[inline]
#[must_use]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// Sine (f32, radians), C's `sinf`: the f64 sine rounded to f32 (correctly
/// rounded but for double-rounding cases rarer than 1 in 2²⁸).
#[inline]
#[must_use]
pub fn sinf(x: f32) -> f32 {
    libm::sin(f64::from(x)) as f32
}

/// Cosine (f32, radians), C's `cosf`: the f64 cosine rounded to f32.
#[inline]
#[must_use]
pub fn cosf(x: f32) -> f32 {
    libm::cos(f64::from(x)) as f32
}

/// Four-quadrant arc tangent (f32, radians), C's `atan2f`: the `libm`
/// crate's (fdlibm's).
#[inline]
#[must_use]
pub fn atan2f(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Arc sine (f32, radians), C's `asinf`: the bits of x86-64 glibc 2.36's
/// `asinf` on every `f32` (NaN for `|x| > 1`).
///
/// Clean-room: fdlibm's `asinf` structure (Sun Microsystems, freely
/// redistributable) with the minimax polynomial of Cephes' `asinf`
/// (S. L. Moshier) whose coefficients were moved by a few ulp to fit glibc's
/// outputs, and a table of the 5,058 positive inputs where glibc's result still
/// differs (found by comparing the two on every `f32`; no glibc code was
/// read or copied).
#[inline]
#[must_use]
pub fn asinf(x: f32) -> f32 {
    let ix = x.to_bits() & 0x7fff_ffff;
    if ix > 0x3f80_0000 {
        return f32::NAN;
    }
    if ix < 0x3200_0000 {
        return x;
    }
    let r = match asinf_exception(ix) {
        Some(glibc) => f32::from_bits(glibc),
        None => asinf_poly(f32::from_bits(ix)),
    };
    if x.is_sign_negative() {
        -r
    } else {
        r
    }
}

/// The coefficients of `asinf`'s series in `t` (IEEE bits), shared by the
/// scalar [`asinf_poly`] and the lane-wise [`asinf_blend`] so that the two
/// cannot drift apart.
const ASINF_P: [u32; 5] = [
    0x3e2a_aae4,
    0x3d99_80f5,
    0x3d3a_3ec8,
    0x3cc6_17e0,
    0x3d2c_b352,
];

/// π/2 split into a head and a negated tail, and the head of π/4 (`f32`).
const ASINF_PIO2_HI: f32 = f32::from_bits(0x3fc9_0fdb);
const ASINF_PIO2_LO: f32 = -f32::from_bits(0x333b_bd2e);
const ASINF_PIO4_HI: f32 = f32::from_bits(0x3f49_0fdb);

/// `asinf`'s series `p0 + t(p1 + t(p2 + t(p3 + t p4)))`, in this order.
#[inline(always)]
fn asinf_series(t: f32) -> f32 {
    let p = [
        f32::from_bits(ASINF_P[0]),
        f32::from_bits(ASINF_P[1]),
        f32::from_bits(ASINF_P[2]),
        f32::from_bits(ASINF_P[3]),
        f32::from_bits(ASINF_P[4]),
    ];
    p[0] + t * (p[1] + t * (p[2] + t * (p[3] + t * p[4])))
}

/// `asinf` for `2⁻²⁷ <= a <= 1` before the exceptions.
#[inline(always)]
fn asinf_poly(a: f32) -> f32 {
    if a < 0.5 {
        return asinf_below_half(a);
    }
    let (pio2_hi, pio2_lo, pio4_hi) = (ASINF_PIO2_HI, ASINF_PIO2_LO, ASINF_PIO4_HI);
    let t = (1.0 - a) * 0.5;
    let p = t * asinf_series(t);
    let s = sqrtf(t);
    if a.to_bits() >= 0x3f79_999a {
        // |x| > 0.975.
        return pio2_hi - (2.0 * (s + s * p) - pio2_lo);
    }
    // s split into a 12-bit head w and the rest, so that s*s - w*w is exact.
    let w = f32::from_bits(s.to_bits() & 0xffff_f000);
    let c = (t - w * w) / (s + w);
    let p = 2.0 * s * p - (pio2_lo - 2.0 * c);
    let q = pio4_hi - 2.0 * w;
    pio4_hi - (p - q)
}

/// The bits of `|x|` from which [`asinf_lanes`]'s exception filter counts,
/// below the table's first input (`0x3cb1_b351`).
const EXCEPTION_FILTER_BASE: u32 = 0x3c00_0000;
/// Inputs per bit of the exception filter (`2^10`).
const EXCEPTION_FILTER_SHIFT: u32 = 10;
/// Bytes of the exception filter: one bit per `2^10` inputs from
/// [`EXCEPTION_FILTER_BASE`] to 1.0.
const EXCEPTION_FILTER_BYTES: usize =
    (((0x3f80_0000 - EXCEPTION_FILTER_BASE) >> EXCEPTION_FILTER_SHIFT) as usize + 1).div_ceil(8);

/// Bit `k` is set when some input of [`asinf_table::EXCEPTIONS`] lies in the
/// `k`-th run of `2^10` inputs from [`EXCEPTION_FILTER_BASE`] (4,487 of the
/// 57,345 runs; 7 kB, built at compile time from the table itself).
static EXCEPTION_FILTER: [u8; EXCEPTION_FILTER_BYTES] = {
    let mut filter = [0u8; EXCEPTION_FILTER_BYTES];
    let mut i = 0;
    while i < asinf_table::EXCEPTIONS.len() {
        let k = ((asinf_table::EXCEPTIONS[i][0] - EXCEPTION_FILTER_BASE) >> EXCEPTION_FILTER_SHIFT)
            as usize;
        filter[k / 8] |= 1 << (k % 8);
        i += 1;
    }
    filter
};

/// Whether the exception table may hold the input bits `ix` (`|x|` between
/// `2^-27` and 1): false means it certainly does not.
#[inline(always)]
fn may_be_exception(ix: u32) -> bool {
    if ix < EXCEPTION_FILTER_BASE {
        return false;
    }
    let k = ((ix - EXCEPTION_FILTER_BASE) >> EXCEPTION_FILTER_SHIFT) as usize;
    EXCEPTION_FILTER[(k / 8).min(EXCEPTION_FILTER_BYTES - 1)] & (1 << (k % 8)) != 0
}

/// Inputs per bucket of the exception index (`2^16`).
const EXCEPTION_BUCKET_SHIFT: u32 = 16;
/// Buckets of the exception index: `2^16` inputs each from
/// [`EXCEPTION_FILTER_BASE`] to 1.0 (897).
const EXCEPTION_BUCKETS: usize =
    ((0x3f80_0000 - EXCEPTION_FILTER_BASE) >> EXCEPTION_BUCKET_SHIFT) as usize + 1;

/// The bucket of the exception index that holds the input bits `ix`
/// (`EXCEPTION_FILTER_BASE <= ix <= 0x3f80_0000`).
#[inline(always)]
const fn exception_bucket(ix: u32) -> usize {
    ((ix - EXCEPTION_FILTER_BASE) >> EXCEPTION_BUCKET_SHIFT) as usize
}

/// `EXCEPTION_INDEX[b]..EXCEPTION_INDEX[b + 1]` are the positions in
/// [`asinf_table::EXCEPTIONS`] of the inputs in bucket `b` (at most a few
/// dozen; 1.8 kB, built at compile time from the sorted table), so a look-up
/// searches one bucket instead of the 5,058 entries.
static EXCEPTION_INDEX: [u16; EXCEPTION_BUCKETS + 1] = {
    let table = &asinf_table::EXCEPTIONS;
    let mut index = [0u16; EXCEPTION_BUCKETS + 1];
    let mut bucket = 0;
    let mut i = 0;
    while bucket <= EXCEPTION_BUCKETS {
        while i < table.len() && exception_bucket(table[i][0]) < bucket {
            i += 1;
        }
        // The table has 5,058 entries: every position fits in a u16.
        #[allow(clippy::cast_possible_truncation)]
        {
            index[bucket] = i as u16;
        }
        bucket += 1;
    }
    index
};

/// glibc's `asinf` bits for the input bits `ix` (`|x|` from `2^-27` to 1)
/// when they are not the polynomial's: the bit filter rules most inputs out,
/// and the bucket index finds the few entries to search for the rest.
#[inline(always)]
fn asinf_exception(ix: u32) -> Option<u32> {
    if !may_be_exception(ix) {
        return None;
    }
    let bucket = exception_bucket(ix);
    let entries = &asinf_table::EXCEPTIONS
        [usize::from(EXCEPTION_INDEX[bucket])..usize::from(EXCEPTION_INDEX[bucket + 1])];
    entries
        .binary_search_by_key(&ix, |e| e[0])
        .ok()
        .map(|i| entries[i][1])
}

/// [`asinf`] of every lane, bit for bit, in vector registers: the
/// polynomial's branches (`|x| < 0.5` and above) are evaluated lane-wise with
/// the scalar branch's operations in its order and the lane's one kept (a
/// blend, [`asinf_blend`], in one plain loop that LLVM vectorises); when no
/// lane is at or above 0.5 (the usual case for angles of attack) only the
/// first branch is evaluated ([`asinf_small`], the same operations). The
/// exception table is searched only for the lanes that a 7 kB bit filter
/// cannot rule out (2.4 % of the lanes of Bourg's demonstration fleet,
/// tested without a branch per lane), and the lanes outside
/// `2^-27 <= |x| <= 1` take [`asinf`]'s own answer ([`asinf_other`]).
#[inline(always)]
pub(crate) fn asinf_lanes<const N: usize>(x: [f32; N]) -> [f32; N] {
    let mut r = [0.0_f32; N];
    // Whether a lane takes one of the branches for |x| >= 0.5 (or is
    // outside the domain, answered below anyway): a plain `|` over the
    // lanes, no branch per lane.
    let mut large = false;
    for v in &x {
        large |= (v.to_bits() & 0x7fff_ffff) >= 0x3f00_0000;
    }
    if large {
        for l in 0..N {
            r[l] = asinf_blend(x[l]);
        }
    } else {
        for l in 0..N {
            r[l] = asinf_small(x[l]);
        }
    }
    // The lanes the polynomial may not answer: outside 2^-27 <= |x| <= 1, or
    // possibly in the exception table. Each lane's test is branch-free (it
    // had two branches on the lane's value, which is data).
    let mut other = [false; N];
    let mut any = false;
    for l in 0..N {
        let ix = x[l].to_bits() & 0x7fff_ffff;
        let outside = ix.wrapping_sub(0x3200_0000) > 0x3f80_0000 - 0x3200_0000;
        other[l] = outside | exception_filter_bit(ix);
        any |= other[l];
    }
    if any {
        for l in 0..N {
            if other[l] {
                r[l] = asinf_other(x[l], r[l]);
            }
        }
    }
    r
}

/// [`asinf_lanes`] as it was before the branch-free filter and the
/// `|x| < 0.5` shortcut: every lane through [`asinf_blend`], the filter
/// tested lane by lane, a lane it does not rule out through the scalar
/// [`asinf`]. The same bits; kept for the scalar step's eight `asinf`s
/// (`Real::asinf_exact_8` of `f32`), which it serves about 6 % faster than
/// [`asinf_lanes`] does (BENCHMARKS.md, "Bourg: the asinf filter, the loads'
/// arrays, several frames in cache").
#[inline(always)]
pub(crate) fn asinf_lanes_blended<const N: usize>(x: [f32; N]) -> [f32; N] {
    let mut r = [0.0_f32; N];
    for l in 0..N {
        r[l] = asinf_blend(x[l]);
    }
    // The lanes the polynomial does not answer: outside 2^-27 <= |x| <= 1, or
    // possibly in the exception table.
    let mut other = [false; N];
    let mut any = false;
    for l in 0..N {
        let ix = x[l].to_bits() & 0x7fff_ffff;
        other[l] = !(0x3200_0000..=0x3f80_0000).contains(&ix) || may_be_exception(ix);
        any |= other[l];
    }
    if any {
        for l in 0..N {
            if other[l] {
                r[l] = asinf(x[l]);
            }
        }
    }
    r
}

/// [`may_be_exception`] without a branch, for any `ix` (`|x|`'s bits): the
/// filter bit of `ix`'s run, the run clamped into the filter (inputs below
/// [`EXCEPTION_FILTER_BASE`] read run 0, which holds no exception; inputs
/// above 1 read the last run, and are outside `asinf`'s domain anyway).
///
/// No branch, but not free in lanes: each lane reads its own byte of the
/// filter by its own index, which no vector instruction of x86-64-v3/v4
/// does without a gather, so the compiler takes the indices out of the
/// vector register (a `vpmovzxdq` and a `vpextrq` or `vmovq` for each pair
/// of lanes), loads the bytes one at a time and inserts them back into a
/// vector (`vpinsrb`, 15 for 16 lanes). In Bourg's lanes kernel
/// this filter is 9-10 % of the samples; the forms tried to avoid the
/// extracts (the indices through memory) were slower (BENCHMARKS.md, "Bourg:
/// the profile of the permuting kernel, and the asinf filter's indices
/// through memory").
#[inline(always)]
fn exception_filter_bit(ix: u32) -> bool {
    let k = (ix.saturating_sub(EXCEPTION_FILTER_BASE) >> EXCEPTION_FILTER_SHIFT) as usize;
    let k = k.min(EXCEPTION_FILTER_BYTES * 8 - 1);
    EXCEPTION_FILTER[k / 8] & (1 << (k % 8)) != 0
}

// Run 0 of the filter holds no exception, so that the inputs below the
// filter's base, clamped to it by `exception_filter_bit`, are ruled out.
const _: () = assert!(EXCEPTION_FILTER[0] & 1 == 0);

/// A lane of [`asinf_lanes`] the bit filter did not rule out, or outside
/// `2^-27 <= |x| <= 1`: [`asinf`]'s answer, from `poly` ([`asinf_blend`]'s
/// or [`asinf_small`]'s answer for `x`, which is [`asinf`]'s when `x` is in
/// that range and not in the exception table) without computing it again.
#[inline(never)]
fn asinf_other(x: f32, poly: f32) -> f32 {
    let ix = x.to_bits() & 0x7fff_ffff;
    if !(0x3200_0000..=0x3f80_0000).contains(&ix) {
        return asinf(x);
    }
    // `asinf`'s negation of the table's (positive) answer is its sign bit
    // flipped, as `asinf_blend`'s.
    asinf_exception(ix).map_or(poly, |glibc| {
        f32::from_bits(glibc ^ (x.to_bits() & 0x8000_0000))
    })
}

/// [`asinf_blend`] for `|x| < 0.5`: its first branch alone, the same
/// operations in the same order (so the same bits there).
#[inline(always)]
fn asinf_small(x: f32) -> f32 {
    let ix = x.to_bits() & 0x7fff_ffff;
    let small = asinf_below_half(f32::from_bits(ix));
    f32::from_bits(small.to_bits() ^ (x.to_bits() & 0x8000_0000))
}

/// [`asinf_poly`]'s branch for `a < 0.5`: `a + a·(t·P(t))`, `t = a²`.
#[inline(always)]
fn asinf_below_half(a: f32) -> f32 {
    let t = a * a;
    let w = t * asinf_series(t);
    a + a * w
}

/// [`asinf`] for `2^-27 <= |x| <= 1` outside the exception table, without a
/// branch: [`asinf_poly`]'s three branches all computed, with their
/// operations in their order, and the one the scalar takes kept; the sign as
/// [`asinf`]'s negation (the sign bit flipped).
#[inline(always)]
fn asinf_blend(x: f32) -> f32 {
    let (pio2_hi, pio2_lo, pio4_hi) = (ASINF_PIO2_HI, ASINF_PIO2_LO, ASINF_PIO4_HI);
    let ix = x.to_bits() & 0x7fff_ffff;
    let a = f32::from_bits(ix);
    // |x| < 0.5.
    let small = asinf_below_half(a);
    // |x| >= 0.5.
    let t = (1.0 - a) * 0.5;
    let pt = t * asinf_series(t);
    let s = sqrtf(t);
    let near_one = pio2_hi - (2.0 * (s + s * pt) - pio2_lo);
    let wh = f32::from_bits(s.to_bits() & 0xffff_f000);
    let c = (t - wh * wh) / (s + wh);
    let pm = 2.0 * s * pt - (pio2_lo - 2.0 * c);
    let q = pio4_hi - 2.0 * wh;
    let middle = pio4_hi - (pm - q);
    let r = if ix < 0x3f00_0000 {
        small
    } else if ix >= 0x3f79_999a {
        near_one
    } else {
        middle
    };
    f32::from_bits(r.to_bits() ^ (x.to_bits() & 0x8000_0000))
}

/// Sine and cosine of `x` (f64, radians): `(sin(x), cos(x))` bit for bit,
/// with one argument reduction for both (the `libm` crate's `sincos`: the
/// same fdlibm kernels on the same reduced argument; its own cut-off for
/// tiny `x`, `2^-27·√2` against `sin`'s `2^-26`, gives `x` there too).
/// `sin_cos_is_sin_and_cos` checks the bits on dense samples and at the
/// cut-offs.
#[inline(always)]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// [`sin_cos`] of every lane, bit for bit. When every lane is in the range
/// where fdlibm's `sincos` calls its kernels directly (`|x|` from about
/// 2^-27·√2 to π/4 by the high word: the bank angles of the controls),
/// those kernels (`__kernel_sin(x, 0, 0)` and `__kernel_cos(x, 0)`) are
/// evaluated lane by lane with the same operations in the same order, which
/// the compiler may put in vector registers (every operation is correctly
/// rounded, none is fused); otherwise each lane goes through [`sin_cos`].
#[inline(always)]
#[must_use]
pub fn sin_cos_lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    // fdlibm's coefficients (k_sin.c, k_cos.c), by their bits.
    const S1: f64 = f64::from_bits(0xbfc5_5555_5555_5549);
    const S2: f64 = f64::from_bits(0x3f81_1111_1110_f8a6);
    const S3: f64 = f64::from_bits(0xbf2a_01a0_19c1_61d5);
    const S4: f64 = f64::from_bits(0x3ec7_1de3_57b1_fe7d);
    const S5: f64 = f64::from_bits(0xbe5a_e5e6_8a2b_9ceb);
    const S6: f64 = f64::from_bits(0x3de5_d93a_5acf_d57c);
    const C1: f64 = f64::from_bits(0x3fa5_5555_5555_554c);
    const C2: f64 = f64::from_bits(0xbf56_c16c_16c1_5177);
    const C3: f64 = f64::from_bits(0x3efa_01a0_19cb_1590);
    const C4: f64 = f64::from_bits(0xbe92_7e4f_809c_52ad);
    const C5: f64 = f64::from_bits(0x3e21_ee9e_bdb4_b1c4);
    const C6: f64 = f64::from_bits(0xbda8_fae9_be88_38d4);
    let kernels = x.iter().fold(true, |all, x| {
        #[allow(clippy::cast_possible_truncation)] // the high word, as fdlibm reads it
        let high = (x.to_bits() >> 32) as u32 & 0x7fff_ffff;
        all & (0x3e46_a09e..=0x3fe9_21fb).contains(&high)
    });
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    if kernels {
        for ((s, c), &x) in sin.iter_mut().zip(&mut cos).zip(&x) {
            // __kernel_sin(x, 0, 0)
            let z = x * x;
            let w = z * z;
            let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
            let v = z * x;
            *s = x + v * (S1 + z * r);
            // __kernel_cos(x, 0)
            let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
            let hz = 0.5 * z;
            let w = 1.0 - hz;
            *c = w + (((1.0 - w) - hz) + (z * r - x * 0.0));
        }
    } else {
        for ((s, c), &x) in sin.iter_mut().zip(&mut cos).zip(&x) {
            (*s, *c) = sin_cos(x);
        }
    }
    (sin, cos)
}

/// The high 32 bits of `x`'s pattern, as fdlibm reads them.
#[inline(always)]
#[allow(clippy::cast_possible_truncation)] // the high word
const fn high_word(x: f64) -> u32 {
    (x.to_bits() >> 32) as u32
}

/// [`atan2`] of every lane, bit for bit. A lane whose arguments take
/// fdlibm's main path (both finite and non-zero, `x` not 1, `|y / x|` from
/// 2^-27 to 2^66 by the high word and neither of `atan2`'s `2^±64`
/// shortcuts) is evaluated with `atan`'s operations in the same order, its
/// interval's reduction `(p·t − q) / (r + s·t)` with the interval's
/// constants (each form's operations exactly: `1·t`, `0·t` and the `± 0`
/// are exact), which the compiler may put in vector registers (every
/// operation is correctly rounded, none is fused); any other lane goes
/// through [`atan2`].
#[inline(always)]
#[must_use]
pub fn atan2_lanes<const N: usize>(y: [f64; N], x: [f64; N]) -> [f64; N] {
    // fdlibm's constants (s_atan.c, e_atan2.c), by their bits.
    const ATANHI: [f64; 4] = [
        f64::from_bits(0x3fdd_ac67_0561_bb4f),
        f64::from_bits(0x3fe9_21fb_5444_2d18),
        f64::from_bits(0x3fef_730b_d281_f69b),
        f64::from_bits(0x3ff9_21fb_5444_2d18),
    ];
    const ATANLO: [f64; 4] = [
        f64::from_bits(0x3c7a_2b7f_222f_65e2),
        f64::from_bits(0x3c81_a626_3314_5c07),
        f64::from_bits(0x3c70_0788_7af0_cbbd),
        f64::from_bits(0x3c91_a626_3314_5c07),
    ];
    const AT: [f64; 11] = [
        f64::from_bits(0x3fd5_5555_5555_550d),
        f64::from_bits(0xbfc9_9999_9998_ebc4),
        f64::from_bits(0x3fc2_4924_9200_83ff),
        f64::from_bits(0xbfbc_71c6_fe23_1671),
        f64::from_bits(0x3fb7_45cd_c54c_206e),
        f64::from_bits(0xbfb3_b0f2_af74_9a6d),
        f64::from_bits(0x3fb1_0d66_a0d0_3d51),
        f64::from_bits(0xbfad_de2d_52de_fd9a),
        f64::from_bits(0x3fa9_7b4b_2476_0deb),
        f64::from_bits(0xbfa2_b444_2c6a_6c2f),
        f64::from_bits(0x3f90_ad3a_e322_da11),
    ];
    const PI: f64 = f64::from_bits(0x4009_21fb_5444_2d18);
    const PI_LO: f64 = f64::from_bits(0x3ca1_a626_3314_5c07);
    let mut out = [0.0; N];
    let mut main = [true; N];
    for l in 0..N {
        let (yl, xl) = (y[l], x[l]);
        let t = (yl / xl).abs();
        let (ix, iy, it) = (
            high_word(xl) & 0x7fff_ffff,
            high_word(yl) & 0x7fff_ffff,
            high_word(t),
        );
        let x_negative = xl.to_bits() >> 63 == 1;
        main[l] = ix < 0x7ff0_0000
            && iy < 0x7ff0_0000
            && xl != 0.0
            && yl != 0.0
            && xl != 1.0
            && ix.wrapping_add(64 << 20) >= iy
            && !(x_negative && iy.wrapping_add(64 << 20) < ix)
            && (0x3e40_0000..0x4410_0000).contains(&it);
        // atan(t): the interval (by selects, not a table, so that the lanes
        // stay in vector registers) and its reduction's constants (p, q, r,
        // s): none below 7/16 (1, 0, 1, 0), (2t − 1)/(2 + t), (t − 1)/(1 + t),
        // (t − 1.5)/(1 + 1.5t), −1/t (0, 1, 0, 1).
        let (small, i0, i1, i2) = (
            it < 0x3fdc_0000,
            it < 0x3fe6_0000,
            it < 0x3ff3_0000,
            it < 0x4003_8000,
        );
        let pick = |v: [f64; 5]| {
            if small {
                v[0]
            } else if i0 {
                v[1]
            } else if i1 {
                v[2]
            } else if i2 {
                v[3]
            } else {
                v[4]
            }
        };
        let (p, q) = (
            pick([1.0, 2.0, 1.0, 1.0, 0.0]),
            pick([0.0, 1.0, 1.0, 1.5, 1.0]),
        );
        let (r, s) = (p, q);
        let tr = (p * t - q) / (r + s * t);
        let z = tr * tr;
        let w = z * z;
        let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
        let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
        let hi = pick([0.0, ATANHI[0], ATANHI[1], ATANHI[2], ATANHI[3]]);
        let lo = pick([0.0, ATANLO[0], ATANLO[1], ATANLO[2], ATANLO[3]]);
        let reduced = hi - (tr * (s1 + s2) - lo - tr);
        let atan = if small { tr - tr * (s1 + s2) } else { reduced };
        let y_negative = yl.to_bits() >> 63 == 1;
        out[l] = match (x_negative, y_negative) {
            (false, false) => atan,
            (false, true) => -atan,
            (true, false) => PI - (atan - PI_LO),
            (true, true) => (atan - PI_LO) - PI,
        };
    }
    for l in 0..N {
        if !main[l] {
            out[l] = atan2(y[l], x[l]);
        }
    }
    out
}

/// [`hypot`] of every lane, bit for bit. A lane whose larger magnitude is
/// finite and at most 2^511, whose smaller is non-zero and at least 2^-450,
/// and whose exponents are at most 64 apart (the `libm` crate's unscaled
/// path) is evaluated with the same operations in the same order (the
/// squares split exactly, their four parts summed, the square root), which
/// the compiler may put in vector registers; any other lane goes through
/// [`hypot`].
#[inline(always)]
#[must_use]
pub fn hypot_lanes<const N: usize>(x: [f64; N], y: [f64; N]) -> [f64; N] {
    const SPLIT: f64 = 134_217_728.0 + 1.0;
    /// `x²` as `hi + lo` (Dekker's splitting), as the `libm` crate's `sq`.
    #[inline(always)]
    fn sq(x: f64) -> (f64, f64) {
        let xc = x * SPLIT;
        let xh = x - xc + xc;
        let xl = x - xh;
        let hi = x * x;
        let lo = xh * xh - hi + 2. * xh * xl + xl * xl;
        (hi, lo)
    }
    let mut out = [0.0; N];
    let mut main = [true; N];
    for l in 0..N {
        let (a, b) = (x[l].abs(), y[l].abs());
        // The larger first, by the bit patterns (the values' order for
        // anything but NaN, which takes the scalar path).
        let (big, small) = if a.to_bits() < b.to_bits() {
            (b, a)
        } else {
            (a, b)
        };
        #[allow(clippy::cast_possible_wrap)] // 11-bit exponents
        let (ex, ey) = ((big.to_bits() >> 52) as i64, (small.to_bits() >> 52) as i64);
        main[l] = ex <= 0x3ff + 510 && ey >= 0x3ff - 450 && ex - ey <= 64;
        let (hx, lx) = sq(big);
        let (hy, ly) = sq(small);
        out[l] = sqrt(ly + lx + hy + hx);
    }
    for l in 0..N {
        if !main[l] {
            out[l] = hypot(x[l], y[l]);
        }
    }
    out
}

/// [`asin`] of every lane, bit for bit. A lane with `2^-26 <= |x| < 1` (by
/// the high word: fdlibm's polynomial paths) is evaluated with fdlibm's
/// operations in the same order: `x + x·R(x²)` below 0.5, and above it
/// `π/2 − 2(s + s·R(z))` (past 0.975) or the split-`s` form, `z = (1 − |x|)/2`
/// and `s = √z`. When no lane is at or above 0.5 (the usual pitch angles)
/// only the first is evaluated; otherwise each lane computes both and keeps
/// its own. The compiler may put the lanes in vector registers (every
/// operation is correctly rounded, none is fused); any other lane (±0,
/// tiny, subnormal, `|x| >= 1`, NaN) goes through [`asin`].
#[inline(always)]
#[must_use]
pub fn asin_lanes<const N: usize>(x: [f64; N]) -> [f64; N] {
    // fdlibm's constants (e_asin.c), by their bits.
    const PIO2_HI: f64 = f64::from_bits(0x3ff9_21fb_5444_2d18);
    const PIO2_LO: f64 = f64::from_bits(0x3c91_a626_3314_5c07);
    const P_S0: f64 = f64::from_bits(0x3fc5_5555_5555_5555);
    const P_S1: f64 = f64::from_bits(0xbfd4_d612_03eb_6f7d);
    const P_S2: f64 = f64::from_bits(0x3fc9_c155_0e88_4455);
    const P_S3: f64 = f64::from_bits(0xbfa4_8228_b568_8f3b);
    const P_S4: f64 = f64::from_bits(0x3f49_efe0_7501_b288);
    const P_S5: f64 = f64::from_bits(0x3f02_3de1_0dfd_f709);
    const Q_S1: f64 = f64::from_bits(0xc003_3a27_1c8a_2d4b);
    const Q_S2: f64 = f64::from_bits(0x4000_2ae5_9c59_8ac8);
    const Q_S3: f64 = f64::from_bits(0xbfe6_066c_1b8d_0159);
    const Q_S4: f64 = f64::from_bits(0x3fb3_b8c5_b12e_9282);
    /// fdlibm's `R(z)`, `p / q` (`comp_r`).
    #[inline(always)]
    fn comp_r(z: f64) -> f64 {
        let p = z * (P_S0 + z * (P_S1 + z * (P_S2 + z * (P_S3 + z * (P_S4 + z * P_S5)))));
        let q = 1.0 + z * (Q_S1 + z * (Q_S2 + z * (Q_S3 + z * Q_S4)));
        p / q
    }
    let mut out = [0.0; N];
    let mut main = [true; N];
    // Whether a lane is at or above 0.5 (or outside the domain, answered
    // below anyway): a plain `|` over the lanes, no branch per lane.
    let mut large = false;
    for (m, &v) in main.iter_mut().zip(&x) {
        let ix = high_word(v) & 0x7fff_ffff;
        *m = (0x3e50_0000..0x3ff0_0000).contains(&ix);
        large |= ix >= 0x3fe0_0000;
    }
    if large {
        for (o, &v) in out.iter_mut().zip(&x) {
            let ix = high_word(v) & 0x7fff_ffff;
            let below_half = ix < 0x3fe0_0000;
            let z = if below_half {
                v * v
            } else {
                (1.0 - v.abs()) * 0.5
            };
            let r = comp_r(z);
            let small = v + v * r;
            let s = sqrt(z);
            let far = PIO2_HI - (2.0 * (s + s * r) - PIO2_LO);
            // s with its low word cleared, and c with f + c = √z.
            let f = f64::from_bits(s.to_bits() & 0xffff_ffff_0000_0000);
            let c = (z - f * f) / (s + f);
            let near =
                0.5 * PIO2_HI - (2.0 * s * r - (PIO2_LO - 2.0 * c) - (0.5 * PIO2_HI - 2.0 * f));
            let big = if ix >= 0x3fef_3333 { far } else { near };
            let big = if v.is_sign_negative() { -big } else { big };
            *o = if below_half { small } else { big };
        }
    } else {
        for (o, &v) in out.iter_mut().zip(&x) {
            *o = v + v * comp_r(v * v);
        }
    }
    for l in 0..N {
        if !main[l] {
            out[l] = asin(x[l]);
        }
    }
    out
}

/// `x * x`, which is what `x.powi(2)` computes (exactly one rounding).
#[inline(always)]
#[must_use]
pub fn square(x: f64) -> f64 {
    x * x
}

/// A fixed, reproducible sequence of 64-bit patterns for the tests' samples
/// (xorshift64* from `seed`).
#[cfg(test)]
pub(crate) fn test_bits(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed;
    move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        state.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every entry of the exception table is found through the bit filter
    /// and the bucket index, with its own result, and the inputs next to an
    /// entry that are not in the table are not found: the index is the
    /// table, not an approximation of it.
    #[test]
    fn the_exception_index_finds_exactly_the_table() {
        let table = &asinf_table::EXCEPTIONS;
        for pair in table.windows(2) {
            assert!(pair[0][0] < pair[1][0], "the table is sorted");
        }
        for &[input, result] in table {
            assert_eq!(asinf_exception(input), Some(result), "{input:#x}");
            for neighbour in [input - 1, input + 1] {
                let expected = table
                    .binary_search_by_key(&neighbour, |e| e[0])
                    .ok()
                    .map(|i| table[i][1]);
                assert_eq!(asinf_exception(neighbour), expected, "{neighbour:#x}");
            }
        }
        assert_eq!(usize::from(EXCEPTION_INDEX[EXCEPTION_BUCKETS]), table.len());
        assert_eq!(
            asinf_exception(0x3f80_0000),
            None,
            "1.0 is not an exception"
        );
    }

    /// `sin_cos(x)` is `(sin(x), cos(x))` bit for bit (the scalar Palmer step
    /// and the multiplayer attitude call it instead of the two): at every
    /// threshold of fdlibm's kernels and their neighbours (tiny arguments,
    /// where `sincos` and `sin` cut off differently; π/4; the reductions'
    /// edges), on 2^20 random bit patterns (every exponent, NaN and the
    /// infinities included) and on a dense sweep of the angles the models
    /// give it (±2π, bank angles in degrees converted). Exact comparison of
    /// the bits: any difference is a bug.
    /// The lane form is [`sin_cos`] bit for bit: whole vectors of bank
    /// angles (every `f64` bank in -20..=20 degrees of a dense sample, and
    /// the kernels' range edges), and vectors with one lane outside the
    /// kernels' range (zero, tiny, past π/4, large, infinite, NaN), which
    /// take the scalar path.
    #[test]
    fn sin_cos_lanes_is_sin_cos() {
        let check = |x: [f64; 8]| {
            let (s, c) = sin_cos_lanes(x);
            for l in 0..8 {
                let (ws, wc) = sin_cos(x[l]);
                assert_eq!(
                    (s[l].to_bits(), c[l].to_bits()),
                    (ws.to_bits(), wc.to_bits()),
                    "sin_cos_lanes({:e}) [{:#x}]",
                    x[l],
                    x[l].to_bits()
                );
            }
        };
        let mut bits = test_bits(0x5eed_0b5a);
        let mut next = || {
            #[allow(clippy::cast_precision_loss)] // 53 random bits, exact
            let unit = (bits() >> 11) as f64 / (1_u64 << 53) as f64;
            let bank_deg = -20.0 + 40.0 * unit;
            bank_deg * core::f64::consts::PI / 180.0
        };
        for _ in 0..250_000 {
            check(core::array::from_fn(|_| next()));
        }
        let edges = [
            f64::from_bits(0x3e46_a09e_0000_0000),
            f64::from_bits(0x3e46_a09d_ffff_ffff),
            f64::from_bits(0x3fe9_21fb_ffff_ffff),
            f64::from_bits(0x3fe9_21fc_0000_0000),
            core::f64::consts::FRAC_PI_4,
            20.0 * core::f64::consts::PI / 180.0,
        ];
        for e in edges {
            check([e, -e, e, -e, e, -e, e, -e]);
        }
        // Every lane the same argument, of every size and both signs: the
        // kernels only when that argument is in their range (a vector of 10.0
        // is not: each lane through `sin_cos`).
        for e in -60..=60 {
            for m in [1.0, 1.37, 1.9] {
                let v = m * 2f64.powi(e);
                check([v; 8]);
                check([-v; 8]);
            }
        }
        for odd in [
            0.0,
            -0.0,
            1e-300,
            f64::from_bits(1),
            1.0,
            -3.0,
            1e6,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            for lane in 0..8 {
                let mut x: [f64; 8] = core::array::from_fn(|_| next());
                x[lane] = odd;
                check(x);
            }
        }
    }

    /// Random `f64` with random sign and an exponent in `-exp..exp`
    /// (powers of two), from `bits`.
    fn spread(bits: &mut impl FnMut() -> u64, exp: i32) -> f64 {
        let r = bits();
        #[allow(clippy::cast_precision_loss, clippy::cast_possible_truncation)]
        // 52 bits; small range
        let (mantissa, e) = (
            1.0 + (r >> 12) as f64 / (1_u64 << 52) as f64,
            (r % (2 * exp as u64)) as i32 - exp,
        );
        let v = mantissa * 2f64.powi(e);
        if r & 0x800 == 0 {
            v
        } else {
            -v
        }
    }

    /// Special values for the lane functions' scalar paths.
    const ODD: [f64; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        f64::MIN_POSITIVE,
        5e-324,
        1e-300,
        1e-20,
        1e20,
        1e160,
        1e300,
        f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        -f64::NAN,
    ];

    /// The lane `atan2` is [`atan2`] bit for bit: vectors of velocities
    /// (every quadrant, magnitudes 2^-8..2^8: the tasks' track), of
    /// arguments of any size (2^-80..2^80 each, so ratios past `atan2`'s
    /// 2^±64 shortcuts and `atan`'s 2^-27 and 2^66 edges), each `atan`
    /// interval's edges, and vectors with special values in one lane.
    #[test]
    fn atan2_lanes_is_atan2() {
        let check = |y: [f64; 8], x: [f64; 8]| {
            let a = atan2_lanes(y, x);
            for l in 0..8 {
                let want = atan2(y[l], x[l]);
                assert!(
                    a[l].to_bits() == want.to_bits() || (a[l].is_nan() && want.is_nan()),
                    "atan2_lanes({:e}, {:e}) = {:e}, atan2 {:e}",
                    y[l],
                    x[l],
                    a[l],
                    want
                );
            }
        };
        let mut bits = test_bits(0xa7a2_1a2e);
        for exp in [8, 80] {
            for _ in 0..200_000 {
                let y = core::array::from_fn(|_| spread(&mut bits, exp));
                let x = core::array::from_fn(|_| spread(&mut bits, exp));
                check(y, x);
            }
        }
        // atan's interval edges and atan2's shortcuts, by the ratio's high
        // word, each side of the edge.
        for high in [
            0x3e40_0000_u64,
            0x3fdc_0000,
            0x3fe6_0000,
            0x3ff3_0000,
            0x4003_8000,
            0x4410_0000,
        ] {
            for t in [f64::from_bits(high << 32), f64::from_bits((high << 32) - 1)] {
                for x in [1.5, -1.5, 3.0, -0.75] {
                    check([t * x; 8], [x; 8]);
                    check([-t * x; 8], [x; 8]);
                }
            }
        }
        // Ratios whose high word is exactly an interval's edge, with any low
        // word (2^32 ratios per edge, which random ratios almost never hit):
        // `atan`'s intervals are chosen by the high word alone. y = 2t and
        // x = 2 keep the ratio exactly t; every quadrant.
        for high in [0x3fdc_0000_u64, 0x3fe6_0000, 0x3ff3_0000, 0x4003_8000] {
            for _ in 0..512 {
                let t: [f64; 8] =
                    core::array::from_fn(|_| f64::from_bits(high << 32 | (bits() >> 32)));
                for (sy, sx) in [(2.0, 2.0), (-2.0, 2.0), (2.0, -2.0), (-2.0, -2.0)] {
                    check(t.map(|t| sy * t), [sx; 8]);
                }
            }
        }
        for odd in ODD {
            for lane in 0..8 {
                let mut y: [f64; 8] = core::array::from_fn(|_| spread(&mut bits, 8));
                let mut x: [f64; 8] = core::array::from_fn(|_| spread(&mut bits, 8));
                y[lane] = odd;
                check(y, x);
                x[lane] = odd;
                check(y, x);
                y[lane] = 2.0;
                check(y, x);
                check(x, y);
            }
        }
    }

    /// The lane `hypot` is [`hypot`] bit for bit: vectors of velocities
    /// (2^-8..2^8), of arguments of any size (2^-600..2^600, past the
    /// scaled paths' thresholds and the 2^64 ratio), and vectors with
    /// special values in one lane.
    #[test]
    fn hypot_lanes_is_hypot() {
        let check = |x: [f64; 8], y: [f64; 8]| {
            let h = hypot_lanes(x, y);
            for l in 0..8 {
                let want = hypot(x[l], y[l]);
                assert!(
                    h[l].to_bits() == want.to_bits() || (h[l].is_nan() && want.is_nan()),
                    "hypot_lanes({:e}, {:e}) = {:e}, hypot {:e}",
                    x[l],
                    y[l],
                    h[l],
                    want
                );
            }
        };
        let mut bits = test_bits(0x4790_7ba5);
        for exp in [8, 80, 600] {
            for _ in 0..200_000 {
                let x = core::array::from_fn(|_| spread(&mut bits, exp));
                let y = core::array::from_fn(|_| spread(&mut bits, exp));
                check(x, y);
            }
        }
        for odd in ODD {
            for lane in 0..8 {
                let mut x: [f64; 8] = core::array::from_fn(|_| spread(&mut bits, 8));
                let y: [f64; 8] = core::array::from_fn(|_| spread(&mut bits, 8));
                x[lane] = odd;
                check(x, y);
                check(y, x);
            }
        }
    }

    /// The lane `asin` is [`asin`] bit for bit: vectors of sines of pitch
    /// angles (every lane below 0.5, the shortcut), of any value in -1..1
    /// (lanes on both sides of 0.5 and 0.975), each path edge by the high
    /// word (2^-26, 0.5, 0.975, 1) with its neighbours and any low word, in
    /// vectors of that value alone and beside other lanes, thousands of
    /// numbers under the high words of 0.5 and 0.975 alone in a vector,
    /// vectors of one magnitude past 1 of every exponent, and vectors with
    /// special values in one lane (±0, subnormals, ±1, past 1, infinities,
    /// NaN).
    #[test]
    fn asin_lanes_is_asin() {
        let check = |x: [f64; 8]| {
            let a = asin_lanes(x);
            for l in 0..8 {
                let want = asin(x[l]);
                // Every bit, a NaN's sign and payload too: the lanes the
                // forms do not answer are the scalar function's own.
                assert!(
                    a[l].to_bits() == want.to_bits(),
                    "asin_lanes({:e}) [{:#x}] = {:e} [{:#x}], asin {:e} [{:#x}]",
                    x[l],
                    x[l].to_bits(),
                    a[l],
                    a[l].to_bits(),
                    want,
                    want.to_bits()
                );
            }
        };
        let mut bits = test_bits(0xa5_1e_1a_e5);
        #[allow(clippy::cast_precision_loss)] // 53 random bits, exact
        let mut unit = move || (bits() >> 11) as f64 / (1_u64 << 53) as f64;
        for _ in 0..200_000 {
            // Pitch angles within ±29°: every lane below 0.5.
            check(core::array::from_fn(|_| {
                libm::sin((unit() - 0.5) * 58.0 * core::f64::consts::PI / 180.0)
            }));
            // Anywhere in -1..1.
            check(core::array::from_fn(|_| 2.0 * unit() - 1.0));
            // Near ±1, where the two forms above 0.5 meet.
            check(core::array::from_fn(|_| {
                let v = 1.0 - unit() * 0.1;
                if unit() < 0.5 {
                    v
                } else {
                    -v
                }
            }));
        }
        let mut next = test_bits(0x0a51_7e57);
        for high in [0x3e50_0000_u64, 0x3fe0_0000, 0x3fef_3333, 0x3ff0_0000] {
            for low in [0_u64, 1, 0xffff_ffff, next() >> 32, next() >> 32] {
                let b = (high << 32) | low;
                for e in [b - 1, b, b + 1].map(f64::from_bits) {
                    for v in [e, -e] {
                        check([v; 8]);
                        let mut mixed: [f64; 8] = core::array::from_fn(|_| 0.4 * unit() - 0.2);
                        mixed[(next() % 8) as usize] = v;
                        check(mixed);
                    }
                }
            }
        }
        // Every low word's first 4,096 and 4,096 random ones under the high
        // words of 0.5 and 0.975, alone in a vector: the two forms above 0.5
        // differ from the one below it for about a fifth of the numbers
        // whose high word is 0.5's (0.5 + 5 ulp is one), so the choice of
        // form must be made at 0.5 exactly, by the whole word.
        for high in [0x3fe0_0000_u64, 0x3fef_3333] {
            for k in 0..8192_u64 {
                let low = if k < 4096 { k } else { next() >> 32 };
                let v = f64::from_bits((high << 32) | low);
                check([v; 8]);
                check([-v; 8]);
            }
        }
        // Vectors of one magnitude past 1 alone, of every exponent (no lane
        // in the domain: each answer is the scalar function's NaN, never a
        // number from the lanes' forms).
        for exponent in 0..=1024_u64 {
            for _ in 0..4 {
                let v = f64::from_bits(((0x3ff + exponent).min(0x7ff) << 52) | (next() >> 12));
                check([v; 8]);
                check([-v; 8]);
            }
        }
        for _ in 0..100_000 {
            // Random bit patterns of magnitudes below 2 (every exponent).
            check(core::array::from_fn(|_| {
                f64::from_bits(next() & 0xbfff_ffff_ffff_ffff)
            }));
        }
        for odd in ODD.into_iter().chain([
            0.5,
            -0.5,
            0.975,
            -0.975,
            1.0 + f64::EPSILON,
            -1.0 - f64::EPSILON,
            2.0_f64.powi(-26),
            2.0_f64.powi(-1022),
        ]) {
            for lane in 0..8 {
                let mut x: [f64; 8] = core::array::from_fn(|_| 0.8 * unit() - 0.4);
                x[lane] = odd;
                check(x);
                let mut x: [f64; 8] = core::array::from_fn(|_| 2.0 * unit() - 1.0);
                x[lane] = odd;
                check(x);
            }
        }
    }

    /// Both lane forms of `asinf` are [`asinf`] in every lane, every bit (a
    /// NaN's sign and payload too): [`asinf_lanes`] (the lane types'
    /// `asinf_exact`) and [`asinf_lanes_blended`] (`Real::asinf_exact_8` of
    /// `f32`, the scalar step's eight elements), eight and five lanes at a
    /// time. On every input of the exception table and its two neighbours
    /// (the table is where the polynomial is not glibc, so a filter, an index
    /// or a fallback that misses one shows), each range edge alone in a
    /// vector and among ordinary sines (the `|x| < 0.5` shortcut, the
    /// polynomial's range `2^-27..=1`, the filter's base, NaN, the
    /// infinities), random bit patterns (every exponent, half of them past 1)
    /// and a sweep of the sines of angles of attack.
    #[test]
    fn asinf_lanes_are_asinf() {
        fn check<const N: usize>(x: [f32; N]) {
            for (form, got) in [
                ("asinf_lanes", asinf_lanes(x)),
                ("asinf_lanes_blended", asinf_lanes_blended(x)),
            ] {
                for l in 0..N {
                    let want = asinf(x[l]);
                    assert!(
                        got[l].to_bits() == want.to_bits(),
                        "{form}({:e}) [{:#x}] = {:e} [{:#x}], asinf {:e} [{:#x}] (lane {l} of {x:?})",
                        x[l],
                        x[l].to_bits(),
                        got[l],
                        got[l].to_bits(),
                        want,
                        want.to_bits()
                    );
                }
            }
        }
        fn check_all(xs: &[f32]) {
            for block in xs.chunks(8) {
                let mut lanes = [0.25_f32; 8];
                lanes[..block.len()].copy_from_slice(block);
                check(lanes);
            }
            for block in xs.chunks(5) {
                let mut lanes = [-0.75_f32; 5];
                lanes[..block.len()].copy_from_slice(block);
                check(lanes);
            }
        }
        let mut xs: Vec<f32> = Vec::new();
        for &[input, _] in &asinf_table::EXCEPTIONS {
            for ix in [input - 1, input, input + 1] {
                xs.push(f32::from_bits(ix));
                xs.push(-f32::from_bits(ix));
            }
        }
        check_all(&xs);
        // Exceptions below 0.5 only (no lane takes the branches above it),
        // eight at a time.
        let below_half: Vec<f32> = asinf_table::EXCEPTIONS
            .iter()
            .filter(|e| e[0] < 0x3f00_0000)
            .map(|e| f32::from_bits(e[0]))
            .collect();
        assert!(below_half.len() > 100, "{}", below_half.len());
        check_all(&below_half);

        let edges = [
            0,
            1,
            0x007f_ffff,
            0x0080_0000,
            0x31ff_ffff,
            0x3200_0000,
            0x3200_0001,
            EXCEPTION_FILTER_BASE - 1,
            EXCEPTION_FILTER_BASE,
            0x3eff_ffff,
            0x3f00_0000,
            0x3f79_9999,
            0x3f79_999a,
            0x3f7f_ffff,
            0x3f80_0000,
            0x3f80_0001,
            0x3fc0_0000,
            0x4000_0000,
            0x7f7f_ffff,
            0x7f80_0000,
            0x7f80_0001,
            0x7fc0_0000,
            0x7fff_ffff,
        ];
        for ix in edges {
            for x in [f32::from_bits(ix), -f32::from_bits(ix)] {
                check([x; 8]);
                check([x; 5]);
                for lane in [0, 3, 7] {
                    let mut v = [0.1_f32, -0.2, 0.3, -0.4, 0.05, -0.01, 0.45, 0.2];
                    v[lane] = x;
                    check(v);
                }
            }
        }

        let mut bits = test_bits(0xa51f_1ae5);
        let mut xs: Vec<f32> = (0..200_000)
            .map(|_| f32::from_bits((bits() >> 32) as u32))
            .collect();
        xs.extend((0..=100_000).map(|i| (-1.0 + 2.0 * f64::from(i) / 100_000.0) as f32));
        check_all(&xs);
    }

    /// `square` is `x * x`, one rounding, which is what `powi(2)` computes
    /// (WGS-84's conversions call it for the original's `pow(v, 2)`): the
    /// same bits on samples of every size and sign, and on special values.
    #[test]
    fn square_is_x_times_x() {
        let mut bits = test_bits(0x5a0a_2e00);
        for exp in [8, 600] {
            for _ in 0..10_000 {
                let x = spread(&mut bits, exp);
                assert_eq!(square(x).to_bits(), (x * x).to_bits(), "{x:e}");
                assert_eq!(square(x).to_bits(), x.powi(2).to_bits(), "{x:e}");
            }
        }
        assert_eq!(square(3.0), 9.0);
        assert_eq!(square(-0.5), 0.25);
        assert_eq!(square(-0.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(square(f64::NEG_INFINITY), f64::INFINITY);
        assert_eq!(square(1e200), f64::INFINITY);
        assert!(square(f64::NAN).is_nan());
    }

    #[test]
    fn sin_cos_is_sin_and_cos() {
        let check = |x: f64| {
            let (s, c) = sin_cos(x);
            assert_eq!(
                s.to_bits(),
                sin(x).to_bits(),
                "sin({x:e}) [{:#x}]",
                x.to_bits()
            );
            assert_eq!(
                c.to_bits(),
                cos(x).to_bits(),
                "cos({x:e}) [{:#x}]",
                x.to_bits()
            );
        };
        // Thresholds on the high word: 2^-27·√2 (sincos and cos), 2^-26
        // (sin), π/4, 3π/4 and 5π/4-ish reduction edges, 2^20·π/2 (the
        // medium reduction's limit), the infinities.
        for high in [
            0x3e46_a09e_u64,
            0x3e50_0000,
            0x3fe9_21fb,
            0x4002_d97c,
            0x400f_6a7a,
            0x4139_21fb,
            0x7fef_ffff,
            0x7ff0_0000,
        ] {
            for low in [0_u64, 1, 0x5444_2d18, 0xffff_ffff] {
                let bits = (high << 32) | low;
                for b in [bits - 1, bits, bits + 1] {
                    check(f64::from_bits(b));
                    check(-f64::from_bits(b));
                }
            }
        }
        let mut next = test_bits(0x2545_f491_4f6c_dd1d);
        for _ in 0..1 << 20 {
            check(f64::from_bits(next()));
        }
        for i in -200_000..=200_000 {
            check(f64::from(i) * (core::f64::consts::TAU / 200_000.0));
            check(f64::from(i) * 1e-3 * core::f64::consts::PI / 180.0);
        }
        check(0.0);
        check(-0.0);
        check(f64::NAN);
    }

    /// The AVX2/FMA instance of `pow` that `pow` picks at run time has the
    /// baseline instance's bits (the two compute the same correctly rounded
    /// operations), on dense samples of the models' arguments and on the
    /// special values. Exact comparison: any difference is a bug.
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    #[test]
    fn pow_of_both_instruction_sets_agree() {
        let mut next = test_bits(0x9e37_79b9_7f4a_7c15);
        let mut unit_bits = test_bits(0x9e37_79b9_7f4a_7c15); // a sequence of its own
        #[allow(clippy::cast_precision_loss)]
        let mut unit = move || (unit_bits() >> 11) as f64 / (1u64 << 53) as f64;
        let check = |x: f64, y: f64| {
            // `pow_inlined` outside `with_fma`: the baseline instance (SSE2,
            // `fma` by call), whatever the CPU.
            let (ours, baseline) = (pow(x, y), pow_inlined(x, y));
            assert!(
                ours.to_bits() == baseline.to_bits() || (ours.is_nan() && baseline.is_nan()),
                "pow({x:e}, {y:e}) = {ours:e}, baseline {baseline:e}"
            );
        };
        // Palmer's pressure ratio (temperature ratio to the power 5.25) and
        // friends: x from 0.5 to 1.1, y near the models' exponents.
        for _ in 0..200_000 {
            let x = 0.5 + 0.6 * unit();
            for y in [5.25, 5.256, -5.256, 0.5, 1.5, 1.0 / 3.0, 4.0 * unit() - 2.0] {
                check(x, y);
            }
        }
        // Anywhere: x over 2^-1074..2^1023 (subnormals, the rescaling of
        // results that overflow or underflow), y over ±2^-70..±2^70.
        for _ in 0..200_000 {
            let x = f64::from_bits(next() & 0x7fef_ffff_ffff_ffff);
            let y =
                f64::from_bits((next() & 0x800f_ffff_ffff_ffff) | ((0x3b9 + next() % 140) << 52));
            check(x, y);
            check(-x, y.round());
        }
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            2.0,
            f64::INFINITY,
            -f64::INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -3.0,
            1e-300,
            1e300,
        ];
        for x in special {
            for y in special {
                check(x, y);
            }
        }
    }
}
