//! Fleet kernels: many aircraft of one model laid out as structure-of-arrays
//! and stepped several per SIMD instruction.
//!
//! * [`Fleet`]: the one container, for any model whose step is written over
//!   `fdm_core::real`'s number type ([`LaneModel`]): the blocks, clocks,
//!   controls and flight statuses, `step`/`fly` on one thread or rayon's
//!   pool, the instruction-set dispatch, the [`Precision`] and the
//!   [`FleetError`]s. No physics: each model's step is its own, one source
//!   for one aircraft and for lanes.
//! * For the models of `fdm-core`, `Fleet<Palmer>` flies Palmer's Cessna 172
//!   (RK4, f64) in two precisions: [`Precision::Exact`] (every aircraft
//!   bit-identical to `fdm_core::palmer::step`) and [`Precision::Fast`] (a
//!   vectorised `pow`, within 1e-9 m and 1e-9 m/s of `Exact` after 1,800
//!   steps); `Fleet<Bourg>` flies Bourg's 6-DoF aircraft (Euler, f32), every
//!   aircraft bit-identical to `fdm_core::bourg::step` (see the
//!   [`fleet`] module for each model's lanes and bytes per aircraft).
//!
//! A third model gets a fleet by implementing [`LaneModel`] (its step over
//! the number type, and the moves of one aircraft in and out of a block):
//! `fdm-ecs/examples/third_model.rs` flies a glider that way. The crate names
//! no model: the kernel's block loop is `fdm_core::real::kernel`, compiled
//! once for each of `fdm-core`'s models in `fdm-core` ([`FleetKernel`] says
//! why).
//!
//! Every fleet keeps a [`FlightStatus`] per aircraft: its `fly` frames are
//! [`fdm_core::model::fly`] per aircraft (ground contact, touchdown, crash,
//! divergence), its `step` the bare model step.
//!
//! Safe Rust throughout (the workspace forbids `unsafe`): the instruction set is
//! chosen at run time by [`pulp::Arch`] (SSE2 baseline, AVX2/FMA, AVX-512),
//! whose `#[target_feature]` functions hold the only `unsafe`, inside pulp. No
//! `-C target-cpu` flag is needed.
//!
//! The per-entity ECS path (`fdm-ecs`) stays the one for mixed and interactive
//! worlds; a fleet is for many aircraft of one type flown together.

pub mod fleet;
pub mod geodesy;

pub use fdm_core::real::LaneModel;
pub use fleet::{
    ControlBlocks, Fleet, FleetError, FleetKernel, FleetPiece, FlownPiece, KernelRun, Precision,
};

use fdm_core::model::{FlightStatus, Model};

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

    /// A fleet of `aircraft` flying the given starts `(controls, state)`, in
    /// order ([`Fleet::from_states`]).
    ///
    /// # Errors
    /// [`FleetError`] if the aircraft cannot be flown.
    fn from_starts(
        aircraft: <Self::Model as Model>::Aircraft,
        starts: impl IntoIterator<
            Item = (
                <Self::Model as Model>::Controls,
                <Self::Model as Model>::State,
            ),
        >,
    ) -> Result<Self, FleetError>;

    /// Number of aircraft.
    fn len(&self) -> usize;

    /// Whether the fleet has no aircraft.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Aircraft `index`'s state.
    fn state(&self, index: usize) -> Option<<Self::Model as Model>::State>;

    /// Aircraft `index`'s controls.
    fn controls(&self, index: usize) -> Option<<Self::Model as Model>::Controls>;

    /// The aircraft every member flies.
    fn aircraft(&self) -> &<Self::Model as Model>::Aircraft;

    /// Replaces every aircraft's controls with `f(index, current controls)`
    /// on rayon's current pool ([`Fleet::par_update_controls`]).
    fn par_update_controls(
        &mut self,
        f: impl Fn(usize, <Self::Model as Model>::Controls) -> <Self::Model as Model>::Controls + Sync,
    );

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

    /// The aircraft in each piece of [`Self::par_fly_then`] asked for
    /// `requested` aircraft a piece: `requested` rounded up to whole blocks
    /// of the kernel's lanes (at least one block; the fleet's last piece may
    /// have fewer).
    fn piece_aircraft(requested: usize) -> usize;

    /// [`Self::par_fly`] in pieces, each piece's aircraft handed on right
    /// after their frame: the fleet is cut into runs of
    /// [`Self::piece_aircraft`]`(piece_aircraft)` aircraft, in order; each
    /// piece is flown on one of the threads of rayon's current pool and then,
    /// on the same thread while its aircraft are in that core's cache, given
    /// to `then` with the payload of the same rank in `payloads` and its
    /// aircraft's states and statuses ([`FlownPiece`]). A piece without a
    /// payload is flown only; payloads beyond the last piece are dropped.
    /// Returns `then`'s results in piece order. Every aircraft ends as
    /// [`Self::par_fly`] leaves it, bit for bit.
    ///
    /// # Errors
    /// As [`Self::check_precision`] (nothing is flown then).
    fn par_fly_then<P: Send, T: Send>(
        &mut self,
        fps: f64,
        precision: Precision,
        piece_aircraft: usize,
        payloads: Vec<P>,
        then: impl Fn(P, FlownPiece<'_, <Self::Model as Model>::State>) -> T + Sync,
    ) -> Result<Vec<T>, FleetError>;

    /// Aircraft `index`'s flight status.
    fn status(&self, index: usize) -> Option<FlightStatus>;

    /// `out` becomes every aircraft's position in the model frame, metres
    /// (x north, y west, z up), in index order: the `position_m` of
    /// [`Model::view`], bit for bit, read straight from the fleet's arrays
    /// (for [`geodesy::BatchGeodesy`]).
    fn positions_m(&self, out: &mut Vec<nalgebra::Vector3<f64>>);

    /// The instruction set the kernel dispatched to, e.g. `"x86-64-v3"`.
    fn instruction_set(&self) -> &'static str;

    /// Bytes one aircraft takes in the fleet's arrays.
    fn bytes_per_aircraft() -> usize;
}

impl<M: FleetKernel> LaneFleet for Fleet<M> {
    type Model = M;

    fn demonstration(n: usize) -> Result<Self, FleetError> {
        Self::from_states(
            M::default_aircraft(),
            (0..n).map(|i| {
                let (controls, state) = M::fleet_member(i);
                (state, controls)
            }),
        )
    }

    fn from_starts(
        aircraft: M::Aircraft,
        starts: impl IntoIterator<Item = (M::Controls, M::State)>,
    ) -> Result<Self, FleetError> {
        Self::from_states(
            aircraft,
            starts
                .into_iter()
                .map(|(controls, state)| (state, controls)),
        )
    }

    fn len(&self) -> usize {
        self.len()
    }

    fn state(&self, index: usize) -> Option<M::State> {
        self.state(index)
    }

    fn controls(&self, index: usize) -> Option<M::Controls> {
        self.controls(index)
    }

    fn aircraft(&self) -> &M::Aircraft {
        self.aircraft()
    }

    fn par_update_controls(&mut self, f: impl Fn(usize, M::Controls) -> M::Controls + Sync) {
        self.par_update_controls(f);
    }

    fn check_precision(precision: Precision) -> Result<(), FleetError> {
        Self::check_precision(precision)
    }

    fn par_step(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        self.par_step_with(M::time_step(fps), precision)
    }

    fn par_fly(&mut self, fps: f64, precision: Precision) -> Result<(), FleetError> {
        self.par_fly_with(M::time_step(fps), precision)
    }

    fn piece_aircraft(requested: usize) -> usize {
        let lanes = <M::Lanes as fdm_core::real::Real>::LANES;
        requested.div_ceil(lanes).max(1) * lanes
    }

    fn par_fly_then<P: Send, T: Send>(
        &mut self,
        fps: f64,
        precision: Precision,
        piece_aircraft: usize,
        payloads: Vec<P>,
        then: impl Fn(P, FlownPiece<'_, M::State>) -> T + Sync,
    ) -> Result<Vec<T>, FleetError> {
        self.par_fly_pieces_with(
            M::time_step(fps),
            precision,
            Self::piece_aircraft(piece_aircraft),
            payloads,
            then,
        )
    }

    fn status(&self, index: usize) -> Option<FlightStatus> {
        self.status(index)
    }

    fn positions_m(&self, out: &mut Vec<nalgebra::Vector3<f64>>) {
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
