//! A fleet of Palmer aircraft: [`PalmerFleet`], the generic [`Fleet`] of
//! [`Palmer`], with the names and signatures the Palmer fleet has always had.
//!
//! The physics is `fdm_core::palmer`'s one RK4 step, written over
//! `fdm_core::real`'s number type (see `fdm_core`'s `palmer/dynamics.rs` and
//! `palmer/lanes.rs` for what a block's lanes read and write): [`LANES`]
//! aircraft per block, 136 bytes per aircraft, every aircraft bit-identical to
//! [`fdm_core::palmer::step`] in [`Precision::Exact`], and within 1e-9 m and
//! 1e-9 m/s of it after 1,800 steps in [`Precision::Fast`] (the vectorised
//! `pow` of `fdm_core::real::fast`). See [`crate::fleet`] for the layout, the
//! precisions and why the instruction set cannot change the bits.

use fdm_core::palmer::{Palmer, PalmerAircraft};
use pulp::Arch;

use crate::fleet::{Fleet, FleetKernel, FleetPiece, KernelRun};
pub use crate::fleet::{FleetError, Precision};
pub use fdm_core::palmer::LANES;

/// A fleet of Palmer aircraft sharing one [`PalmerAircraft`], each with its
/// own state and controls.
///
/// ```
/// use fdm_core::palmer::{step, PalmerAircraft, PalmerControls, PalmerState};
/// use fdm_fleet::palmer::{PalmerFleet, Precision};
///
/// let cessna = PalmerAircraft::cessna_172();
/// let controls = PalmerControls { throttle: 1.0, alpha_deg: 4.0, ..PalmerControls::default() };
/// let mut fleet = PalmerFleet::new(cessna)?;
/// for _ in 0..10 {
///     fleet.push(PalmerState::at_rest(), controls);
/// }
/// let mut one = PalmerState::at_rest();
/// for _ in 0..100 {
///     fleet.step(0.1, Precision::Exact);
///     one = step(&cessna, &controls, &one, 0.1);
/// }
/// assert_eq!(fleet.state(9), Some(one)); // bit for bit
/// # Ok::<(), fdm_fleet::palmer::FleetError>(())
/// ```
pub type PalmerFleet = Fleet<Palmer>;

/// Palmer's kernel compiled here, once, for every crate that flies a Palmer fleet
/// (the provided body; see [`FleetKernel`] for why it is written out).
impl FleetKernel for Palmer {
    fn run_kernel(fleet: &mut Fleet<Self>, run: KernelRun<Self>) {
        run.apply(fleet);
    }
    fn run_kernel_piece(piece: &mut FleetPiece<'_, Self>, run: KernelRun<Self>) {
        run.apply_to_piece(piece);
    }
}

/// The Palmer fleet's own names: every precision is available, so stepping
/// cannot fail.
impl Fleet<Palmer> {
    /// An empty fleet of `aircraft`, which must pass
    /// [`PalmerAircraft::validate`] ([`Fleet::try_new`]).
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the parameters cannot be flown.
    pub fn new(aircraft: PalmerAircraft) -> Result<Self, FleetError> {
        Self::try_new(aircraft)
    }

    /// [`Fleet::step_with`]: one RK4 step of every aircraft.
    pub fn step(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch(), dt_s, precision, false, false);
    }

    /// [`Fleet::par_step_with`].
    pub fn par_step(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch(), dt_s, precision, false, true);
    }

    /// [`Fleet::step_baseline_with`].
    pub fn step_baseline(&mut self, dt_s: f64, precision: Precision) {
        self.run(Arch::Scalar, dt_s, precision, false, false);
    }

    /// [`Fleet::fly_with`]: one whole frame with the flight status.
    pub fn fly(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch(), dt_s, precision, true, false);
    }

    /// [`Fleet::par_fly_with`].
    pub fn par_fly(&mut self, dt_s: f64, precision: Precision) {
        self.run(self.arch(), dt_s, precision, true, true);
    }

    /// [`Fleet::fly_baseline_with`].
    pub fn fly_baseline(&mut self, dt_s: f64, precision: Precision) {
        self.run(Arch::Scalar, dt_s, precision, true, false);
    }
}
