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
//! [`script`] parses the `START-END action` control scripts shared by the tests
//! and the `sim-cli` binary (needs the `alloc` feature).
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "alloc")]
extern crate alloc;

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
