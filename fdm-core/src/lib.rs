//! Pure flight dynamics models from the 2021 AFIT thesis that ported them to Rust:
//!
//! * [`palmer`]: Grant Palmer's Cessna 172 point-mass model, 4th-order Runge-Kutta, `f64`.
//! * [`bourg`]: David Bourg's 6-DoF rigid-body aircraft of 8 lifting elements,
//!   quaternion attitude, explicit Euler, `f32`.
//!
//! Every step is a pure function of (parameters, controls, state, dt): no I/O, no
//! allocation, no global state, no panics. The crate is `#![no_std]` without the
//! default `std` feature. Every transcendental function comes from [`math`],
//! pure Rust in every build, so the results match the original programs bit
//! for bit with and without `std` and on every target (docs/determinism.md);
//! [`fingerprint`] hashes a state and the maths in use.
//!
//!
//! `script` parses the `START-END action` control scripts shared by the tests
//! and the `sim-cli` binary (needs the `alloc` feature).
#![cfg_attr(not(feature = "std"), no_std)]
// The link only where the module is (a build without `alloc` has no `script`).
#![cfg_attr(feature = "alloc", doc = "See [`script`].")]

#[cfg(feature = "alloc")]
extern crate alloc;

/// `each_lane!(N, |l| expr)`: the array of `expr` for `l` in `0..N`, one
/// lane-wise operation over all lanes (what LLVM turns into one vector
/// instruction), for `real`'s lane types and `math`'s lane-wise functions.
///
/// In optimised builds it is one `while` loop with the lane's expression
/// written inside it: no closure and no iterator, hence nothing the compiler
/// can leave out of line. With `core::array::from_fn`, some of those closures
/// stayed out of line in the large fleet kernels, compiled for the baseline
/// instruction set and called across pulp's instruction-set boundary (36 % of
/// Bourg's kernel time on an AVX-512 machine). In builds with debug
/// assertions it is `core::array::from_fn`: there nothing is optimised, and
/// the loop, inlined into the kernels' `#[inline(always)]` functions, would
/// give them one stack slot per operation (more than a thread's 2 MiB stack
/// for Bourg's step). Both forms evaluate `expr` once per lane: the same bits.
#[cfg(not(debug_assertions))]
macro_rules! each_lane {
    ($n:expr, |$l:ident| $e:expr) => {{
        let mut out = [Default::default(); $n];
        let mut $l = 0;
        while $l < $n {
            out[$l] = $e;
            $l += 1;
        }
        out
    }};
}

/// See the optimised form above.
#[cfg(debug_assertions)]
macro_rules! each_lane {
    ($n:expr, |$l:ident| $e:expr) => {
        core::array::from_fn::<_, { $n }, _>(|$l| $e)
    };
}

pub mod bourg;
pub mod fingerprint;
pub mod geodesy;
pub mod math;
pub mod message;
pub mod model;
pub mod palmer;
pub mod real;
#[cfg(feature = "alloc")]
pub mod script;
pub mod start;
pub mod units;

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
