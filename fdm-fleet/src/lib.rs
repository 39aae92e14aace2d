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
//! Both fleets keep a [`FlightStatus`] per aircraft: their `fly` frames are
//! [`fdm_core::model::fly`] per aircraft (ground contact, touchdown, crash,
//! divergence), their `step` the bare model step.
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
pub mod geodesy;
mod lanes;
pub mod palmer;

pub use bourg::BourgFleet;
pub use palmer::{FleetError, PalmerFleet, Precision};

use fdm_core::bourg::Bourg;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::Palmer;

/// A structure-of-arrays fleet of one model, as model-generic code (the
/// `sim-cli fleet` command, benchmarks) drives it.
pub trait LaneFleet: Sized + Send {
    /// The model the fleet flies.
    type Model: Model;

    /// Members `0..n` of the model's demonstration fleet
    /// ([`Model::fleet_member`]) with the model's default aircraft.
    ///
    /// # Errors
    /// [`FleetError`] if the aircraft cannot be flown.
    fn demonstration(n: usize) -> Result<Self, FleetError>;

    /// Number of aircraft.
    fn len(&self) -> usize;

    /// Whether the fleet has no aircraft.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Aircraft `index`'s state.
    fn state(&self, index: usize) -> Option<<Self::Model as Model>::State>;

    /// Whether the kernel has `precision`.
    ///
    /// # Errors
    /// [`FleetError::PrecisionUnavailable`] when it does not.
    fn check_precision(precision: Precision) -> Result<(), FleetError>;

    /// One step of every aircraft at `fps` frames per second (the model's own
    /// [`Model::time_step`]) on rayon's current pool.
    ///
    /// # Errors
    /// As [`Self::check_precision`].
    fn par_step(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError>;

    /// One whole frame of every aircraft with its flight status at `fps`
    /// frames per second on rayon's current pool: each aircraft as
    /// [`fdm_core::model::fly`] leaves it (bit for bit in
    /// [`Precision::Exact`]).
    ///
    /// # Errors
    /// As [`Self::check_precision`].
    fn par_fly(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError>;

    /// Aircraft `index`'s flight status.
    fn status(&self, index: usize) -> Option<FlightStatus>;

    /// `out` becomes every aircraft's position in the model frame, metres
    /// (x north, y west, z up), in index order: the `position_m` of
    /// [`Model::view`], bit for bit, read straight from the fleet's arrays
    /// (for [`geodesy::BatchGeodesy`]).
    fn positions_m(&self, out: &mut Vec<fdm_core::bourg::Vector3<f64>>);

    /// The instruction set the kernel dispatched to, e.g. `"x86-64-v3"`.
    fn instruction_set(&self) -> &'static str;

    /// Bytes one aircraft takes in the fleet's arrays.
    fn bytes_per_aircraft() -> usize;
}

/// The frame of one lane that the kernel's step alone does not finish (not
/// airborne above the ground plane, or `suspect`: a component too large to be
/// sure the step is finite), as [`fdm_core::model::fly`] would end it: a
/// crashed, diverged or suspect aircraft flies the scalar frame again from
/// its state `before` the step; any other keeps the kernel's step (`after`,
/// `step`'s bits) and only settles its status and ground contact. Both fleets
/// call this for such lanes.
pub(crate) fn finish_lane<M: Model>(
    aircraft: &M::Aircraft,
    controls: &M::Controls,
    status: fdm_core::model::FlightStatus,
    suspect: bool,
    before: impl FnOnce() -> M::State,
    after: impl FnOnce() -> M::State,
    dt: M::TimeStep,
) -> (M::State, fdm_core::model::FlightStatus) {
    if suspect || status.is_final() {
        fdm_core::model::fly::<M>(aircraft, controls, status, &before(), dt)
    } else {
        fdm_core::model::settle::<M>(aircraft, status, &after())
    }
}

impl LaneFleet for PalmerFleet {
    type Model = Palmer;

    fn demonstration(n: usize) -> Result<Self, FleetError> {
        let mut fleet = Self::new(Palmer::default_aircraft())?;
        for i in 0..n {
            let (controls, state) = Palmer::fleet_member(i);
            fleet.push(state, controls);
        }
        Ok(fleet)
    }

    fn len(&self) -> usize {
        self.len()
    }

    fn state(&self, index: usize) -> Option<fdm_core::palmer::PalmerState> {
        self.state(index)
    }

    fn check_precision(_: Precision) -> Result<(), FleetError> {
        Ok(())
    }

    fn par_step(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        self.par_step(Palmer::time_step(fps), precision);
        Ok(())
    }

    fn par_fly(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        self.par_fly(Palmer::time_step(fps), precision);
        Ok(())
    }

    fn status(&self, index: usize) -> Option<FlightStatus> {
        self.status(index)
    }

    fn positions_m(&self, out: &mut Vec<fdm_core::bourg::Vector3<f64>>) {
        self.positions_m(out);
    }

    fn instruction_set(&self) -> &'static str {
        self.instruction_set()
    }

    fn bytes_per_aircraft() -> usize {
        Self::bytes_per_aircraft()
    }
}

impl LaneFleet for BourgFleet {
    type Model = Bourg;

    fn demonstration(n: usize) -> Result<Self, FleetError> {
        let mut fleet = Self::new(Bourg::default_aircraft());
        for i in 0..n {
            let (controls, state) = Bourg::fleet_member(i);
            fleet.push(state, controls);
        }
        Ok(fleet)
    }

    fn len(&self) -> usize {
        self.len()
    }

    fn state(&self, index: usize) -> Option<fdm_core::bourg::BourgState> {
        self.state(index)
    }

    fn check_precision(precision: Precision) -> Result<(), FleetError> {
        match precision {
            Precision::Exact => Ok(()),
            Precision::Fast => Err(FleetError::PrecisionUnavailable {
                model: Bourg::NAME,
                precision,
            }),
        }
    }

    fn par_step(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        Self::check_precision(precision)?;
        self.par_step(Bourg::time_step(fps));
        Ok(())
    }

    fn par_fly(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        Self::check_precision(precision)?;
        self.par_fly(Bourg::time_step(fps));
        Ok(())
    }

    fn status(&self, index: usize) -> Option<FlightStatus> {
        self.status(index)
    }

    fn positions_m(&self, out: &mut Vec<fdm_core::bourg::Vector3<f64>>) {
        self.positions_m(out);
    }

    fn instruction_set(&self) -> &'static str {
        self.instruction_set()
    }

    fn bytes_per_aircraft() -> usize {
        Self::bytes_per_aircraft()
    }
}

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
