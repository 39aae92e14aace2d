//! Fleet kernels: many aircraft of one model laid out as structure-of-arrays and
//! stepped several per SIMD instruction.
//!
//! * [`palmer`]: [`PalmerFleet`], Palmer's Cessna 172 (RK4, f64) in lanes of
//!   [`palmer::LANES`] aircraft, in two precisions: [`Precision::Exact`] (every
//!   aircraft bit-identical to [`fdm_core::palmer::step`]) and
//!   [`Precision::Fast`] (a vectorised `pow`, within 1e-9 m and 1e-9 m/s of
//!   `Exact` after 1,800 steps).
//!
//! * [`bourg`]: [`BourgFleet`], Bourg's 6-DoF aircraft (Euler, f32) in lanes
//!   of [`bourg::LANES`] aircraft, every aircraft bit-identical to
//!   [`fdm_core::bourg::step`].
//!
//! Safe Rust throughout (the workspace forbids `unsafe`): the instruction set is
//! chosen at run time by [`pulp::Arch`] (SSE2 baseline, AVX2/FMA, AVX-512),
//! whose `#[target_feature]` functions hold the only `unsafe`, inside pulp. No
//! `-C target-cpu` flag is needed.
//!
//! The per-entity ECS path (`fdm-ecs`) stays the one for mixed and interactive
//! worlds; a fleet is for many aircraft of one type flown together.

pub mod bourg;
mod fastmath;
mod lanes;
pub mod palmer;

pub use bourg::BourgFleet;
pub use palmer::{FleetError, PalmerFleet, Precision};
