//! The kernels this crate compiles, once, for every crate that flies them:
//! the only place `fdm-fleet` names a model, and only to choose where a
//! kernel is compiled (see [`FleetKernel`] for why that matters).
//!
//! Any other model gets its kernel from an empty implementation of
//! [`FleetKernel`] in its own crate (the provided bodies, compiled there); a
//! line here for it would only move its compilation into this crate. Nothing
//! else of `fdm-fleet` depends on this list.
//!
//! Measured when the per-model front doors were made generic (2-core
//! machine, other builds running): with a blanket `impl<M: LaneModel>
//! FleetKernel for M` instead of this list, a release build of
//! `afit-fdm-cli` after a change to `fdm-fleet` took 11 min 06 s (9 min 03 s
//! of CPU) instead of 5 min 34 s (3 min 55 s of CPU): `fdm-run`,
//! `fdm-study` and `afit-fdm-cli` each compiled both kernels again. The
//! workspace's debug test build (`cargo test --workspace --no-run`,
//! `CARGO_INCREMENTAL=0` as in CI) was no slower (48 s against 52 s of CPU:
//! debug builds share generic code between crates). The kernel cannot be
//! compiled with the model in `fdm-core` (which cannot see this crate), nor
//! in the run library's model modules (the orphan rule: neither the trait
//! nor the model is theirs), so the list stays here.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;

use crate::fleet::{Fleet, FleetKernel, FleetPiece, KernelRun};

/// Implements [`FleetKernel`] for each model with the provided bodies
/// written out, so that they are compiled in this crate.
macro_rules! compiled_here {
    ($($model:ty),* $(,)?) => {$(
        impl FleetKernel for $model {
            fn run_kernel(fleet: &mut Fleet<Self>, run: KernelRun<Self>) {
                run.apply(fleet);
            }
            fn run_kernel_piece(piece: &mut FleetPiece<'_, Self>, run: KernelRun<Self>) {
                run.apply_to_piece(piece);
            }
        }
    )*};
}

compiled_here!(Palmer, Bourg);
