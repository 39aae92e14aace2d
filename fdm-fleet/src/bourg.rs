//! A fleet of Bourg aircraft: [`BourgFleet`], the generic [`Fleet`] of
//! [`Bourg`], with the names and signatures the Bourg fleet has always had.
//!
//! The physics is `fdm_core::bourg`'s one loads-and-Euler step, written over
//! `fdm_core::real`'s number type, with the table look-ups as hooks of the
//! number type (see `fdm_core`'s `bourg/generic.rs` and `bourg/lanes.rs` for
//! what a block's lanes read and write): [`LANES`] `f32` aircraft per block,
//! every aircraft bit-identical to [`fdm_core::bourg::step`] (only `exact`:
//! its step's one transcendental function, `asinf`, is evaluated lane-wise
//! with the scalar bits already, and has no faster inexact form).

use fdm_core::bourg::{Bourg, BourgAircraft};
use pulp::Arch;

use crate::fleet::{Fleet, FleetKernel, FleetPiece, KernelRun, Precision};
pub use fdm_core::bourg::LANES;

/// A fleet of Bourg aircraft sharing one [`BourgAircraft`], each with its own
/// state and controls.
///
/// ```
/// use fdm_core::bourg::{step, BourgAircraft, BourgControls, BourgState};
/// use fdm_fleet::bourg::BourgFleet;
///
/// let aircraft = BourgAircraft::bourg_default();
/// let controls = BourgControls::initial();
/// let mut fleet = BourgFleet::new(aircraft.clone());
/// for _ in 0..3 {
///     fleet.push(BourgState::initial(), controls);
/// }
/// let mut one = BourgState::initial();
/// for _ in 0..100 {
///     fleet.step(1.0 / 30.0);
///     one = step(&aircraft, &controls, &one, 1.0 / 30.0);
/// }
/// assert_eq!(fleet.state(2), Some(one)); // bit for bit
/// ```
pub type BourgFleet = Fleet<Bourg>;

/// Bourg's kernel compiled here, once, for every crate that flies a Bourg fleet
/// (the provided body; see [`FleetKernel`] for why it is written out).
impl FleetKernel for Bourg {
    fn run_kernel(fleet: &mut Fleet<Self>, run: KernelRun<Self>) {
        run.apply(fleet);
    }
    fn run_kernel_piece(piece: &mut FleetPiece<'_, Self>, run: KernelRun<Self>) {
        run.apply_to_piece(piece);
    }
}

/// The Bourg fleet's own names: `exact` only, so no precision argument.
impl Fleet<Bourg> {
    /// An empty fleet of `aircraft` (already validated by its constructor).
    #[must_use]
    pub fn new(aircraft: BourgAircraft) -> Self {
        Self::unchecked(aircraft)
    }

    /// [`Fleet::step_with`] in `exact`: one Euler step of every aircraft.
    pub fn step(&mut self, dt: f32) {
        self.run(self.arch(), dt, Precision::Exact, false, false);
    }

    /// [`Fleet::par_step_with`] in `exact`.
    pub fn par_step(&mut self, dt: f32) {
        self.run(self.arch(), dt, Precision::Exact, false, true);
    }

    /// [`Fleet::step_baseline_with`] in `exact`.
    pub fn step_baseline(&mut self, dt: f32) {
        self.run(Arch::Scalar, dt, Precision::Exact, false, false);
    }

    /// [`Fleet::fly_with`] in `exact`: one whole frame with the flight status.
    pub fn fly(&mut self, dt: f32) {
        self.run(self.arch(), dt, Precision::Exact, true, false);
    }

    /// [`Fleet::par_fly_with`] in `exact`.
    pub fn par_fly(&mut self, dt: f32) {
        self.run(self.arch(), dt, Precision::Exact, true, true);
    }

    /// [`Fleet::fly_baseline_with`] in `exact`.
    pub fn fly_baseline(&mut self, dt: f32) {
        self.run(Arch::Scalar, dt, Precision::Exact, true, false);
    }
}
