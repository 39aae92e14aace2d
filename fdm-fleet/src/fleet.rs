//! [`Fleet`]: many aircraft of one [`LaneModel`] laid out as structure-of-arrays
//! and stepped [`Real::LANES`] aircraft per SIMD instruction, for any model
//! whose step is written over `fdm_core::real`'s number type. The physics is
//! the model's own (`LaneModel::step_lanes`, the one source of its scalar
//! step); this module owns only the layout, the precision, the instruction
//! set, the threads and the flight status.
//!
//! # Layout
//!
//! The fleet is a `Vec` of blocks of `LANES` aircraft ("array of structures of
//! arrays"): inside a block every value of the model's state and control
//! terms is one lane vector (`[f64; LANES]` or `[f32; LANES]`), which the
//! kernel loads as one vector; beside them the clocks, the controls as set and
//! the flight statuses, one per lane. The last block is padded with idle
//! aircraft, stepped along and never shown, so any fleet size works; rayon
//! hands whole runs of blocks to its threads. What depends only on the
//! aircraft and the controls (the model's `Terms`) is computed when the
//! controls are set, with the scalar step's own functions: the same bits, and
//! off the per-step path.
//!
//! # The models of `fdm-core`
//!
//! * `Fleet<Palmer>`: Palmer's one RK4 step, written over the number type
//!   (`fdm_core`'s `palmer/dynamics.rs` and `palmer/lanes.rs` say what a
//!   block's lanes read and write): `fdm_core::palmer::LANES` (8) `f64`
//!   aircraft per block, 136 bytes per aircraft, every aircraft
//!   bit-identical to `fdm_core::palmer::step` in [`Precision::Exact`] and
//!   within 1e-9 m and 1e-9 m/s of it after 1,800 steps in
//!   [`Precision::Fast`].
//! * `Fleet<Bourg>`: Bourg's one loads-and-Euler step, written over the
//!   number type with the table look-ups as hooks of the number type
//!   (`bourg/generic.rs` and `bourg/lanes.rs`): `fdm_core::bourg::LANES` (16)
//!   `f32` aircraft per block, every aircraft bit-identical to
//!   `fdm_core::bourg::step`; only `Exact` (its step's one transcendental
//!   function, `asinf`, is evaluated lane-wise with the scalar bits already,
//!   and has no faster inexact form).
//!
//! # Precisions
//!
//! * [`Precision::Exact`]: the step with [`Exact`] maths: every aircraft
//!   bit-identical to [`Model::step`] (`fdm_core::math`'s `pow` and `asinf`
//!   evaluated lane-wise in vector registers with the scalar functions' bits,
//!   the scalar function only for special lanes; every other operation SIMD).
//! * [`Precision::Fast`]: the step with [`Fast`] maths (vectorised forms of
//!   the functions that have one; for Palmer the pressure's `pow`: every
//!   aircraft within 1e-9 m and 1e-9 m/s of `Exact` after 1,800 steps). A
//!   model whose step calls no such function ([`LaneModel::HAS_FAST`] false,
//!   e.g. Bourg) refuses it.
//!
//! # Why the instruction set cannot change the `Exact` bits
//!
//! The kernel is compiled several times and one copy is picked at run time
//! ([`pulp::Arch`]: x86-64-v4 with AVX-512, x86-64-v3 with AVX2 and FMA, or the
//! SSE2 baseline). Addition, subtraction, multiplication, division and square
//! root are correctly rounded IEEE operations in every one of these
//! instruction sets, so a lane of `vdivpd ymm` has the bits of a scalar
//! `divsd`. The one thing that could differ is fusion: `a * b + c` as one FMA
//! rounds once instead of twice. Rust never contracts a multiplication and an
//! addition into an FMA on its own (it gives LLVM no fast-math or `contract`
//! flags, with or without the `fma` target feature), so the FMA copy computes
//! the same roundings. The exact `pow` calls a fused multiply-add explicitly,
//! where the scalar `fdm_core::math::pow` does, lane for lane: the FMA
//! instruction in the FMA copies, the correctly rounded software `fma` in the
//! baseline copy, the same bits either way; the scalar functions the exact
//! maths fall back to are the same whichever copy calls them. The fast `pow` calls
//! `mul_add` only where the CPU has FMA, to get the exact rounding error of a
//! product, which the baseline copy gets exactly too with Dekker's splitting,
//! so `Fast` is also the same bits on every instruction set. The tests step
//! the same fleet through the dispatched copy and the baseline copy
//! ([`Fleet::step_baseline_with`]) and compare the bits.
//!
//! # The flight status
//!
//! [`Fleet::fly_with`] frames are [`fdm_core::model::fly`] per aircraft. The
//! kernel steps every block; a lane-wise check then finds the lanes the step
//! alone does not finish (not airborne above the ground plane, or with a
//! component at or beyond [`LaneModel::SUSPECT`], too large to be sure the
//! state is finite), and only those go through the scalar rule of
//! `fdm_core::real::kernel`'s `finish_lane`.

use core::fmt;
use core::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use fdm_core::model::FlightStatus;
#[cfg(doc)]
use fdm_core::model::Model;
use fdm_core::real::kernel::{Array, Block};
#[cfg(doc)]
use fdm_core::real::{Exact, Fast};
use fdm_core::real::{LaneModel, Real};
use nalgebra::Vector3;
use pulp::Arch;
use rayon::prelude::*;

/// Blocks per rayon task in the parallel methods: large enough that
/// scheduling costs nothing next to the stepping, small enough to balance two
/// threads on a 1,000-aircraft fleet.
const BLOCKS_PER_TASK: usize = 32;

/// Bytes of a fleet's arrays that the `_frames` methods
/// ([`Fleet::step_frames_with`], ...) fly all their frames before going on
/// to the next blocks: well inside the 1 to 2 MiB L2 cache of a core of the
/// project's machines, so that every frame after the first reads its blocks
/// from L2 rather than from L3 or memory (BENCHMARKS.md, "Bourg: the asinf
/// filter, the loads' arrays, several frames in cache").
const FRAMES_PIECE_BYTES: usize = 256 * 1024;

/// Which maths a fleet's step uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// [`Exact`] maths: every aircraft bit-identical to the model's scalar
    /// step.
    #[default]
    Exact,
    /// [`Fast`] maths: vectorised functions where the model's step has one
    /// (Palmer: every aircraft within 1e-9 m and 1e-9 m/s of
    /// [`Precision::Exact`] after 1,800 steps).
    Fast,
}

impl Precision {
    /// The name `FromStr` reads: `"exact"` or `"fast"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Fast => "fast",
        }
    }
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Precision {
    type Err = FleetError;

    /// `"exact"` or `"fast"` (as `sim-cli fleet --precision` takes them).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "exact" => Ok(Self::Exact),
            "fast" => Ok(Self::Fast),
            _ => Err(FleetError::UnknownPrecision(s.to_owned())),
        }
    }
}

/// What a fleet operation refused.
#[derive(Debug, Clone)]
pub enum FleetError {
    /// The shared aircraft cannot be flown: [`LaneModel::check_aircraft`]'s
    /// error (the model's own type, e.g. Palmer's `AircraftError`; it is the
    /// [`source`](std::error::Error::source) of this error).
    InvalidAircraft(Arc<dyn std::error::Error + Send + Sync>),
    /// An aircraft index past the end of the fleet.
    OutOfRange {
        /// The index asked for.
        index: usize,
        /// The fleet's size.
        len: usize,
    },
    /// A precision name other than `exact` or `fast`.
    UnknownPrecision(String),
    /// The model has no kernel of this precision (its step calls no function
    /// with a fast form: Bourg has only `exact`).
    PrecisionUnavailable {
        /// The model's name.
        model: &'static str,
        /// The precision asked for.
        precision: Precision,
    },
}

impl fmt::Display for FleetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidAircraft(err) => write!(f, "invalid aircraft: {err}"),
            Self::OutOfRange { index, len } => {
                write!(f, "aircraft {index} is out of range for a fleet of {len}")
            }
            Self::UnknownPrecision(name) => {
                write!(f, "precision must be `exact` or `fast`, got `{name}`")
            }
            Self::PrecisionUnavailable { model, precision } => {
                write!(
                    f,
                    "the {model} fleet kernel has no `{precision}` precision (use `exact`)"
                )
            }
        }
    }
}

/// Equal variants with equal fields; two [`FleetError::InvalidAircraft`] are
/// equal when their reasons read the same.
impl PartialEq for FleetError {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::InvalidAircraft(a), Self::InvalidAircraft(b)) => a.to_string() == b.to_string(),
            (Self::OutOfRange { index: i, len: n }, Self::OutOfRange { index: j, len: m }) => {
                (i, n) == (j, m)
            }
            (Self::UnknownPrecision(a), Self::UnknownPrecision(b)) => a == b,
            (
                Self::PrecisionUnavailable {
                    model: a,
                    precision: p,
                },
                Self::PrecisionUnavailable {
                    model: b,
                    precision: q,
                },
            ) => (a, p) == (b, q),
            _ => false,
        }
    }
}

impl std::error::Error for FleetError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::InvalidAircraft(err) => Some(err.as_ref()),
            _ => None,
        }
    }
}

/// A fleet of one [`LaneModel`]'s aircraft sharing one aircraft type, each
/// with its own state, controls and flight status, stepped as
/// structure-of-arrays (see the [module docs](self)).
///
/// ```
/// use fdm_core::model::Model;
/// use fdm_core::palmer::Palmer;
/// use fdm_fleet::{Fleet, Precision};
///
/// let aircraft = Palmer::default_aircraft();
/// let mut fleet = Fleet::<Palmer>::try_new(aircraft)?;
/// let (controls, state) = Palmer::fleet_member(3);
/// for _ in 0..10 {
///     fleet.push(state, controls);
/// }
/// let mut one = state;
/// for _ in 0..100 {
///     fleet.step_with(0.1, Precision::Exact)?;
///     one = Palmer::step(&aircraft, &controls, &one, 0.1);
/// }
/// assert_eq!(fleet.state(9), Some(one)); // bit for bit
/// # Ok::<(), fdm_fleet::FleetError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Fleet<M: LaneModel> {
    aircraft: M::Aircraft,
    shared: M::Shared,
    blocks: Vec<Block<M>>,
    len: usize,
    arch: Arch,
}

impl<M: LaneModel> Fleet<M> {
    /// An empty fleet of `aircraft`, which must pass
    /// [`LaneModel::check_aircraft`]. Detects the CPU's instruction set once.
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the aircraft cannot be flown.
    pub fn try_new(aircraft: M::Aircraft) -> Result<Self, FleetError> {
        M::check_aircraft(&aircraft).map_err(|e| FleetError::InvalidAircraft(Arc::new(e)))?;
        Ok(Self {
            shared: M::shared(&aircraft),
            aircraft,
            blocks: Vec::new(),
            len: 0,
            arch: Arch::new(),
        })
    }

    /// [`Fleet::try_new`], under the name every model's fleet has always
    /// had.
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the aircraft cannot be flown.
    pub fn new(aircraft: M::Aircraft) -> Result<Self, FleetError> {
        Self::try_new(aircraft)
    }

    /// A fleet of `aircraft` flying the given states and controls, in order.
    ///
    /// # Errors
    /// [`FleetError::InvalidAircraft`] if the aircraft cannot be flown.
    pub fn from_states(
        aircraft: M::Aircraft,
        members: impl IntoIterator<Item = (M::State, M::Controls)>,
    ) -> Result<Self, FleetError> {
        let mut fleet = Self::try_new(aircraft)?;
        for (state, controls) in members {
            fleet.push(state, controls);
        }
        Ok(fleet)
    }

    /// Whether the fleet has `precision`.
    ///
    /// # Errors
    /// [`FleetError::PrecisionUnavailable`] for [`Precision::Fast`] when the
    /// model's step has no function with a fast form
    /// ([`LaneModel::HAS_FAST`]).
    pub const fn check_precision(precision: Precision) -> Result<(), FleetError> {
        match precision {
            Precision::Fast if !M::HAS_FAST => Err(FleetError::PrecisionUnavailable {
                model: M::NAME,
                precision,
            }),
            _ => Ok(()),
        }
    }

    /// Adds an aircraft; returns its index. Its flight status starts as
    /// [`FlightStatus::initial`] of its height. States and controls are not
    /// checked, as in [`Model::step`]: non-finite values propagate into that
    /// aircraft's lanes only.
    pub fn push(&mut self, state: M::State, controls: M::Controls) -> usize {
        let index = self.len;
        let lane = index % M::Lanes::LANES;
        if lane == 0 {
            self.blocks.push(Block::idle(&self.aircraft));
        }
        if let Some(block) = self.blocks.last_mut() {
            block.set_state(lane, &state);
            M::set_controls(
                &mut block.terms,
                lane,
                &self.aircraft,
                &self.shared,
                &controls,
            );
            block.controls.as_mut()[lane] = controls;
            block.status.as_mut()[lane] = FlightStatus::initial(M::height_m(&state));
        }
        self.len += 1;
        index
    }

    /// Number of aircraft.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the fleet has no aircraft.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The shared aircraft parameters.
    #[must_use]
    pub const fn aircraft(&self) -> &M::Aircraft {
        &self.aircraft
    }

    /// Block and lane of aircraft `index`.
    const fn at(index: usize) -> (usize, usize) {
        (index / M::Lanes::LANES, index % M::Lanes::LANES)
    }

    fn check(&self, index: usize) -> Result<(usize, usize), FleetError> {
        if index < self.len {
            Ok(Self::at(index))
        } else {
            Err(FleetError::OutOfRange {
                index,
                len: self.len,
            })
        }
    }

    /// Aircraft `index`'s state, `None` past the end.
    #[must_use]
    pub fn state(&self, index: usize) -> Option<M::State> {
        let (b, l) = self.check(index).ok()?;
        Some(self.blocks[b].state(l))
    }

    /// Aircraft `index`'s controls, `None` past the end.
    #[must_use]
    pub fn controls(&self, index: usize) -> Option<M::Controls> {
        let (b, l) = self.check(index).ok()?;
        Some(self.blocks[b].controls.as_ref()[l])
    }

    /// Every aircraft's state, in index order.
    pub fn states(&self) -> impl ExactSizeIterator<Item = M::State> + '_ {
        (0..self.len).map(|i| {
            let (b, l) = Self::at(i);
            self.blocks[b].state(l)
        })
    }

    /// Replaces aircraft `index`'s state (its flight status is kept: see
    /// [`Fleet::set_status`]).
    ///
    /// # Errors
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_state(&mut self, index: usize, state: &M::State) -> Result<(), FleetError> {
        let (b, l) = self.check(index)?;
        self.blocks[b].set_state(l, state);
        Ok(())
    }

    /// Replaces aircraft `index`'s controls (and recomputes its control
    /// terms).
    ///
    /// # Errors
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_controls(&mut self, index: usize, controls: M::Controls) -> Result<(), FleetError> {
        let (b, l) = self.check(index)?;
        let block = &mut self.blocks[b];
        M::set_controls(&mut block.terms, l, &self.aircraft, &self.shared, &controls);
        block.controls.as_mut()[l] = controls;
        Ok(())
    }

    /// Replaces every aircraft's controls with `f(index, current controls)`
    /// (and recomputes their control terms) on this thread, in index order:
    /// the same fleet as [`Fleet::set_controls`] called for each index in
    /// turn, without its per-index checks ([`Fleet::par_update_controls`]
    /// on a rayon pool).
    pub fn update_controls(&mut self, mut f: impl FnMut(usize, M::Controls) -> M::Controls) {
        let (aircraft, shared, len) = (&self.aircraft, &self.shared, self.len);
        let lanes = M::Lanes::LANES;
        for (b, block) in self.blocks.iter_mut().enumerate() {
            let first = b * lanes;
            for lane in 0..lanes.min(len.saturating_sub(first)) {
                let controls = f(first + lane, block.controls.as_ref()[lane]);
                M::set_controls(&mut block.terms, lane, aircraft, shared, &controls);
                block.controls.as_mut()[lane] = controls;
            }
        }
    }

    /// Replaces every aircraft's controls with `f(index, current controls)`
    /// (and recomputes their control terms), on the threads of the current
    /// rayon pool: the same fleet as [`Fleet::set_controls`] called for each
    /// index in turn, in a fraction of the time for large fleets (the
    /// control terms of both models take trigonometry). `f` sees each index
    /// once; the order of the calls is not defined.
    pub fn par_update_controls(&mut self, f: impl Fn(usize, M::Controls) -> M::Controls + Sync)
    where
        M::Controls: Send + Sync,
    {
        let (aircraft, shared, len) = (&self.aircraft, &self.shared, self.len);
        let lanes = M::Lanes::LANES;
        self.blocks
            .par_chunks_mut(BLOCKS_PER_TASK)
            .enumerate()
            .for_each(|(chunk, blocks)| {
                for (k, block) in blocks.iter_mut().enumerate() {
                    let first = (chunk * BLOCKS_PER_TASK + k) * lanes;
                    for lane in 0..lanes.min(len.saturating_sub(first)) {
                        let controls = f(first + lane, block.controls.as_ref()[lane]);
                        M::set_controls(&mut block.terms, lane, aircraft, shared, &controls);
                        block.controls.as_mut()[lane] = controls;
                    }
                }
            });
    }

    /// The fleet as runs of `blocks` whole blocks each (the last may be
    /// shorter; at least one block each), in order: for one pass that sets
    /// controls, flies and reads back each run while it is in the cache,
    /// the runs on different threads. Each aircraft is in exactly one piece;
    /// what a piece does to its aircraft is what the fleet's own methods do
    /// to them, bit for bit.
    pub fn pieces_mut(&mut self, blocks: usize) -> Vec<FleetPiece<'_, M>> {
        let (aircraft, shared, len, arch) = (&self.aircraft, &self.shared, self.len, self.arch);
        let per = blocks.max(1);
        let lanes = M::Lanes::LANES;
        self.blocks
            .chunks_mut(per)
            .enumerate()
            .map(|(k, blocks)| {
                let first = k * per * lanes;
                FleetPiece {
                    aircraft,
                    shared,
                    len: (blocks.len() * lanes).min(len.saturating_sub(first)),
                    blocks,
                    first,
                    arch,
                }
            })
            .collect()
    }

    /// Aircraft `index`'s flight status, `None` past the end.
    #[must_use]
    pub fn status(&self, index: usize) -> Option<FlightStatus> {
        let (b, l) = self.check(index).ok()?;
        Some(self.blocks[b].status.as_ref()[l])
    }

    /// Every aircraft's flight status, in index order.
    pub fn statuses(&self) -> impl ExactSizeIterator<Item = FlightStatus> + '_ {
        (0..self.len).map(|i| {
            let (b, l) = Self::at(i);
            self.blocks[b].status.as_ref()[l]
        })
    }

    /// Replaces aircraft `index`'s flight status.
    ///
    /// # Errors
    /// [`FleetError::OutOfRange`] past the end.
    pub fn set_status(&mut self, index: usize, status: FlightStatus) -> Result<(), FleetError> {
        let (b, l) = self.check(index)?;
        self.blocks[b].status.as_mut()[l] = status;
        Ok(())
    }

    /// `out` becomes every aircraft's position in the model frame, metres (x
    /// north, y west, z up), in index order: the `position_m` of
    /// [`Model::view`], bit for bit ([`LaneModel::position_m`]).
    pub fn positions_m(&self, out: &mut Vec<Vector3<f64>>) {
        out.clear();
        out.extend(self.states().map(|s| M::position_m(&s)));
    }

    /// The instruction set the kernel runs on, as detected at construction:
    /// `"x86-64-v4"` (AVX-512), `"x86-64-v3"` (AVX2 and FMA) or `"baseline"`
    /// (SSE2 on x86-64, or another architecture's default).
    #[must_use]
    pub const fn instruction_set(&self) -> &'static str {
        match self.arch {
            #[cfg(target_arch = "x86_64")]
            Arch::V4(_) => "x86-64-v4",
            #[cfg(target_arch = "x86_64")]
            Arch::V3(_) => "x86-64-v3",
            _ => "baseline",
        }
    }

    /// Memory per aircraft in the fleet's arrays, bytes (the last block's
    /// padding aside): the state, the control terms, the clock, the controls
    /// as set and the status.
    #[must_use]
    pub const fn bytes_per_aircraft() -> usize {
        core::mem::size_of::<Block<M>>() / M::Lanes::LANES
    }

    /// Memory the fleet's arrays take now, bytes (whole blocks, padding
    /// included; the `Vec`'s spare capacity not counted).
    #[must_use]
    pub const fn bytes(&self) -> usize {
        self.blocks.len() * core::mem::size_of::<Block<M>>()
    }
}

/// A run of whole blocks of a [`Fleet`], borrowed for writing
/// ([`Fleet::pieces_mut`]): its aircraft's controls set, flown and read back
/// by one thread, while the run is in that core's cache.
#[derive(Debug)]
pub struct FleetPiece<'a, M: LaneModel> {
    aircraft: &'a M::Aircraft,
    shared: &'a M::Shared,
    blocks: &'a mut [Block<M>],
    /// The fleet index of the piece's first aircraft.
    first: usize,
    /// Aircraft in the piece (the padding lanes of the fleet's last block
    /// not counted).
    len: usize,
    arch: Arch,
}

impl<M: LaneModel> FleetPiece<'_, M> {
    /// The fleet index of the piece's first aircraft.
    #[must_use]
    pub const fn first(&self) -> usize {
        self.first
    }

    /// Number of aircraft in the piece.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the piece has no aircraft.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Replaces each of the piece's aircraft's controls with `f(fleet
    /// index, current controls)`, in index order, and recomputes their
    /// control terms a block at a time ([`LaneModel::set_controls_lanes`]):
    /// what [`Fleet::update_controls`] does to them, bit for bit. Always
    /// inlined, so that a caller running it with a wider instruction set
    /// (pulp's dispatch) compiles the block's terms with that set too.
    #[inline(always)]
    pub fn update_controls(&mut self, f: impl FnMut(usize, M::Controls) -> M::Controls) {
        self.update_control_blocks(&mut EachAircraft(f));
    }

    /// Calls `update.update(fleet index of lane 0, lanes in use, the
    /// block's controls)` for each of the piece's blocks, in order, and
    /// recomputes the block's control terms from its controls
    /// ([`LaneModel::set_controls_lanes`], the first `count` lanes): for
    /// setting a block's controls together. [`Self::update_controls`] is
    /// this with one aircraft at a time; always inlined, as it is.
    #[inline(always)]
    pub fn update_control_blocks(&mut self, update: &mut impl ControlBlocks<M>) {
        let (aircraft, shared, len, first) = (self.aircraft, self.shared, self.len, self.first);
        let lanes = M::Lanes::LANES;
        for (b, block) in self.blocks.iter_mut().enumerate() {
            let start = b * lanes;
            let count = lanes.min(len.saturating_sub(start));
            update.update(first + start, count, &mut block.controls);
            M::set_controls_lanes(&mut block.terms, count, aircraft, shared, &block.controls);
        }
    }

    /// The piece's blocks, in order, each as `(index in the piece of lane
    /// 0, lanes in use, block)`: the kernel's own arrays, read a block at a
    /// time (lane `l < count` is the piece's aircraft `index + l`; the lanes
    /// past `count`, in the fleet's last block, belong to no aircraft).
    #[inline(always)]
    pub fn blocks(&self) -> impl Iterator<Item = (usize, usize, &Block<M>)> + '_ {
        let (len, lanes) = (self.len, M::Lanes::LANES);
        self.blocks.iter().enumerate().map(move |(b, block)| {
            let start = b * lanes;
            (start, lanes.min(len.saturating_sub(start)), block)
        })
    }

    /// Calls `f(index in the piece, state, status, controls)` for each of
    /// the piece's aircraft, in order.
    pub fn for_each(&self, mut f: impl FnMut(usize, &M::State, FlightStatus, &M::Controls)) {
        let (len, lanes) = (self.len, M::Lanes::LANES);
        for (b, block) in self.blocks.iter().enumerate() {
            let start = b * lanes;
            for lane in 0..lanes.min(len.saturating_sub(start)) {
                f(
                    start + lane,
                    &block.state(lane),
                    block.status.as_ref()[lane],
                    &block.controls.as_ref()[lane],
                );
            }
        }
    }
}

impl<M: FleetKernel> FleetPiece<'_, M> {
    /// One whole frame of each of the piece's aircraft with its flight
    /// status, on this thread: what [`Fleet::fly_with`] does to them, bit
    /// for bit.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn fly_with(&mut self, dt: M::TimeStep, precision: Precision) -> Result<(), FleetError> {
        Fleet::<M>::check_precision(precision)?;
        let run = KernelRun {
            arch: self.arch,
            dt,
            precision,
            fly: true,
            parallel: false,
        };
        M::run_kernel_piece(self, run);
        Ok(())
    }
}

/// What [`FleetPiece::update_control_blocks`] does to each block's
/// controls (a trait, so that the work can be an always-inlined method: a
/// closure may be compiled as a function of its own, without the
/// instruction set of the function it is called from).
pub trait ControlBlocks<M: LaneModel> {
    /// Sets the first `count` lanes of `controls`, the controls of the
    /// block whose lane 0 is the fleet's aircraft `first` (the lanes past
    /// `count`, in the fleet's last block, belong to no aircraft and must
    /// be left as they are).
    fn update(&mut self, first: usize, count: usize, controls: &mut Array<M, M::Controls>);
}

/// [`FleetPiece::update_controls`]'s one aircraft at a time.
struct EachAircraft<F>(F);

impl<M: LaneModel, F: FnMut(usize, M::Controls) -> M::Controls> ControlBlocks<M>
    for EachAircraft<F>
{
    #[inline(always)]
    fn update(&mut self, first: usize, count: usize, controls: &mut Array<M, M::Controls>) {
        for (lane, c) in controls.as_mut().iter_mut().enumerate().take(count) {
            *c = (self.0)(first + lane, *c);
        }
    }
}

/// One piece of a fleet right after its frame, as
/// [`Fleet::par_fly_pieces_with`] (and [`crate::LaneFleet::par_fly_then`])
/// hands it on: its aircraft's states and statuses, read from the kernel's
/// arrays while they are in the cache, and how long its frame took.
#[derive(Debug)]
pub struct FlownPiece<'a, S> {
    /// The fleet index of the piece's first aircraft: aircraft `first + k`
    /// is at `k` below.
    pub first: usize,
    /// Each aircraft's state after the frame, every one `Some` (the
    /// receiver may set to `None` those it leaves out, e.g. the diverged).
    pub states: &'a mut [Option<S>],
    /// Each aircraft's flight status after the frame.
    pub statuses: &'a [FlightStatus],
    /// Wall-clock seconds the piece's frame (step and flight status) took
    /// on its thread, the reading of the states not included.
    pub fly_seconds: f64,
    /// When the piece's frame ended (the reading of the states began): the
    /// receiver's own work on the piece is timed from here.
    pub flown_at: Instant,
}

/// What needs the model's kernel: stepping and flying. The short names
/// (`step`, `par_step`, `step_baseline`, `fly`, `par_fly`, `fly_baseline`)
/// are [`Precision::Exact`], which every model has, so they cannot fail; the
/// `_with` forms take the precision and refuse one the model lacks.
impl<M: FleetKernel> Fleet<M> {
    /// [`Fleet::step_with`] in [`Precision::Exact`]: one step of every
    /// aircraft, each with the bits of [`Model::step`].
    pub fn step(&mut self, dt: M::TimeStep) {
        self.run(self.arch, dt, Precision::Exact, false, false);
    }

    /// [`Fleet::par_step_with`] in [`Precision::Exact`].
    pub fn par_step(&mut self, dt: M::TimeStep) {
        self.run(self.arch, dt, Precision::Exact, false, true);
    }

    /// [`Fleet::step_baseline_with`] in [`Precision::Exact`].
    pub fn step_baseline(&mut self, dt: M::TimeStep) {
        self.run(Arch::Scalar, dt, Precision::Exact, false, false);
    }

    /// [`Fleet::fly_with`] in [`Precision::Exact`]: one whole frame of every
    /// aircraft with its flight status.
    pub fn fly(&mut self, dt: M::TimeStep) {
        self.run(self.arch, dt, Precision::Exact, true, false);
    }

    /// [`Fleet::par_fly_with`] in [`Precision::Exact`].
    pub fn par_fly(&mut self, dt: M::TimeStep) {
        self.run(self.arch, dt, Precision::Exact, true, true);
    }

    /// [`Fleet::fly_baseline_with`] in [`Precision::Exact`].
    pub fn fly_baseline(&mut self, dt: M::TimeStep) {
        self.run(Arch::Scalar, dt, Precision::Exact, true, false);
    }

    /// [`Fleet::par_fly_with`] in pieces of `piece_aircraft` aircraft
    /// (rounded up to whole blocks, at least one; [`Fleet::pieces_mut`]),
    /// each flown on one of the threads of rayon's current pool and at once,
    /// on the same thread, given to `then` with the payload of the same rank
    /// in `payloads` and its states and statuses ([`FlownPiece`]): whatever
    /// `then` reads of the piece is still in that core's cache. A piece
    /// without a payload is flown only; payloads beyond the last piece are
    /// dropped. Returns `then`'s results in piece order. Every aircraft ends
    /// as [`Fleet::par_fly_with`] leaves it, bit for bit (the same kernel on
    /// the same blocks).
    ///
    /// # Errors
    /// As [`Fleet::check_precision`] (nothing is flown then).
    pub fn par_fly_pieces_with<P: Send, T: Send>(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        piece_aircraft: usize,
        payloads: Vec<P>,
        then: impl Fn(P, FlownPiece<'_, M::State>) -> T + Sync,
    ) -> Result<Vec<T>, FleetError> {
        Self::check_precision(precision)?;
        let blocks = piece_aircraft.div_ceil(M::Lanes::LANES).max(1);
        let mut payloads = payloads.into_iter();
        let work: Vec<_> = self
            .pieces_mut(blocks)
            .into_iter()
            .map(|piece| (piece, payloads.next()))
            .collect();
        let done: Result<Vec<Option<T>>, FleetError> = work
            .into_par_iter()
            .map_init(
                || (Vec::new(), Vec::new()),
                |(states, statuses), (mut piece, payload)| {
                    let start = Instant::now();
                    piece.fly_with(dt, precision)?;
                    let flown_at = Instant::now();
                    let Some(payload) = payload else {
                        return Ok(None);
                    };
                    states.clear();
                    statuses.clear();
                    piece.for_each(|_, state, status, _| {
                        states.push(Some(*state));
                        statuses.push(status);
                    });
                    Ok(Some(then(
                        payload,
                        FlownPiece {
                            first: piece.first(),
                            states,
                            statuses,
                            fly_seconds: (flown_at - start).as_secs_f64(),
                            flown_at,
                        },
                    )))
                },
            )
            .collect();
        Ok(done?.into_iter().flatten().collect())
    }

    /// Advances every aircraft by `dt` with one step of the model, on this
    /// thread, with the best instruction set of this CPU. Like
    /// [`Model::step`] it checks nothing: a non-finite `dt` makes every state
    /// non-finite. The statuses are not read or changed.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn step_with(&mut self, dt: M::TimeStep, precision: Precision) -> Result<(), FleetError> {
        self.checked_run(self.arch, dt, precision, false, false)
    }

    /// [`Fleet::step_with`] on the threads of the current rayon pool (the
    /// global pool, or the one `ThreadPool::install` runs in), in runs of
    /// blocks. The same bits: each aircraft is stepped by the same code
    /// whichever thread takes it.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn par_step_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
    ) -> Result<(), FleetError> {
        self.checked_run(self.arch, dt, precision, false, true)
    }

    /// [`Fleet::step_with`] with the kernel compiled for the SSE2 baseline,
    /// whatever the CPU has: for comparing instruction sets.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn step_baseline_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
    ) -> Result<(), FleetError> {
        self.checked_run(Arch::Scalar, dt, precision, false, false)
    }

    /// One whole frame of every aircraft with its flight status, on this
    /// thread. In [`Precision::Exact`] each aircraft's state and status become
    /// those of [`fdm_core::model::fly`], bit for bit (the model's step, then
    /// the ground contact and the touchdown; a crashed aircraft stays at
    /// rest; a step that is not finite is not kept and the aircraft is
    /// [`Diverged`](FlightStatus::Diverged) from then on). In
    /// [`Precision::Fast`] the aircraft the scalar `fly` takes (crashed,
    /// diverged, or with a component too large to be sure the state is
    /// finite) get the exact step for that frame.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn fly_with(&mut self, dt: M::TimeStep, precision: Precision) -> Result<(), FleetError> {
        self.checked_run(self.arch, dt, precision, true, false)
    }

    /// [`Fleet::fly_with`] on the threads of the current rayon pool; the same
    /// bits.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn par_fly_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
    ) -> Result<(), FleetError> {
        self.checked_run(self.arch, dt, precision, true, true)
    }

    /// [`Fleet::fly_with`] with the kernel compiled for the SSE2 baseline.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn fly_baseline_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
    ) -> Result<(), FleetError> {
        self.checked_run(Arch::Scalar, dt, precision, true, false)
    }

    /// `frames` calls of [`Fleet::step_with`], with the same bits, each run
    /// of blocks of a cache's size (256 kB) stepped all `frames` times before
    /// the next: a fleet larger than the core's cache is read from memory
    /// once per call rather than once per frame. Aircraft do not interact
    /// and a block's step reads only that block, so every aircraft ends as
    /// after `frames` calls (the tests compare the two). No frame for
    /// `frames = 0`.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`] (nothing is stepped then).
    pub fn step_frames_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        frames: usize,
    ) -> Result<(), FleetError> {
        self.run_frames(dt, precision, false, false, frames)
    }

    /// [`Fleet::step_frames_with`] on the threads of the current rayon pool,
    /// in runs of at most 32 blocks: `frames` calls of
    /// [`Fleet::par_step_with`], the same bits.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn par_step_frames_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        frames: usize,
    ) -> Result<(), FleetError> {
        self.run_frames(dt, precision, false, true, frames)
    }

    /// `frames` calls of [`Fleet::fly_with`] (whole frames with the flight
    /// status), a cache-sized run of blocks at a time as
    /// [`Fleet::step_frames_with`]: the same bits.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn fly_frames_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        frames: usize,
    ) -> Result<(), FleetError> {
        self.run_frames(dt, precision, true, false, frames)
    }

    /// [`Fleet::fly_frames_with`] on the threads of the current rayon pool:
    /// `frames` calls of [`Fleet::par_fly_with`], the same bits.
    ///
    /// # Errors
    /// As [`Fleet::check_precision`].
    pub fn par_fly_frames_with(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        frames: usize,
    ) -> Result<(), FleetError> {
        self.run_frames(dt, precision, true, true, frames)
    }

    /// `frames` frames of every aircraft, each run of blocks of at most
    /// [`FRAMES_PIECE_BYTES`] (and, in parallel, at most
    /// [`BLOCKS_PER_TASK`] blocks, so that small fleets still use every
    /// thread) flown all `frames` times through the model's
    /// [`FleetKernel::run_kernel_piece`] before the next.
    fn run_frames(
        &mut self,
        dt: M::TimeStep,
        precision: Precision,
        fly: bool,
        parallel: bool,
        frames: usize,
    ) -> Result<(), FleetError> {
        Self::check_precision(precision)?;
        let mut blocks = (FRAMES_PIECE_BYTES / core::mem::size_of::<Block<M>>()).max(1);
        if parallel {
            blocks = blocks.min(BLOCKS_PER_TASK);
        }
        let fly_piece = |piece: &mut FleetPiece<'_, M>| {
            for _ in 0..frames {
                let run = KernelRun {
                    arch: piece.arch,
                    dt,
                    precision,
                    fly,
                    parallel: false,
                };
                M::run_kernel_piece(piece, run);
            }
        };
        let mut pieces = self.pieces_mut(blocks);
        if parallel {
            pieces.par_iter_mut().for_each(fly_piece);
        } else {
            pieces.iter_mut().for_each(fly_piece);
        }
        Ok(())
    }

    /// [`Self::run`] after [`Fleet::check_precision`].
    fn checked_run(
        &mut self,
        arch: Arch,
        dt: M::TimeStep,
        precision: Precision,
        fly: bool,
        parallel: bool,
    ) -> Result<(), FleetError> {
        Self::check_precision(precision)?;
        self.run(arch, dt, precision, fly, parallel);
        Ok(())
    }

    /// The kernel over every block with `arch`'s instruction set
    /// (`precision` already checked, or `Exact`), through the model's
    /// [`FleetKernel::run_kernel`].
    fn run(
        &mut self,
        arch: Arch,
        dt: M::TimeStep,
        precision: Precision,
        fly: bool,
        parallel: bool,
    ) {
        M::run_kernel(
            self,
            KernelRun {
                arch,
                dt,
                precision,
                fly,
                parallel,
            },
        );
    }
}

/// One call of a fleet's kernel, as [`FleetKernel::run_kernel`] receives it:
/// the instruction set, the time step, the maths, and whether to fly whole
/// frames and on rayon's pool. Made by [`Fleet`]'s stepping methods; opaque.
pub struct KernelRun<M: LaneModel> {
    arch: Arch,
    dt: M::TimeStep,
    precision: Precision,
    fly: bool,
    parallel: bool,
}

impl<M: LaneModel> KernelRun<M> {
    /// Runs the kernel over every block of `fleet`, in runs of blocks on
    /// rayon's pool if `parallel`: each run through the model's
    /// [`LaneModel::run_blocks`] (compiled in the model's crate, see
    /// [`FleetKernel`]). The body of [`FleetKernel::run_kernel`].
    pub fn apply(self, fleet: &mut Fleet<M>) {
        let Self {
            arch,
            dt,
            precision,
            fly,
            parallel,
        } = self;
        let (aircraft, shared) = (&fleet.aircraft, &fleet.shared);
        let fast = precision == Precision::Fast;
        let run = |blocks: &mut [Block<M>]| {
            M::run_blocks(blocks, aircraft, shared, dt, arch, fast, fly);
        };
        if parallel {
            fleet.blocks.par_chunks_mut(BLOCKS_PER_TASK).for_each(run);
        } else {
            run(&mut fleet.blocks);
        }
    }

    /// Runs the kernel over the blocks of `piece`, on this thread (the body
    /// of [`FleetKernel::run_kernel_piece`]): the same compiled kernel as
    /// [`KernelRun::apply`] over a fleet.
    pub fn apply_to_piece(self, piece: &mut FleetPiece<'_, M>) {
        let Self {
            arch,
            dt,
            precision,
            fly,
            parallel: _,
        } = self;
        M::run_blocks(
            piece.blocks,
            piece.aircraft,
            piece.shared,
            dt,
            arch,
            precision == Precision::Fast,
            fly,
        );
    }
}

impl<M: LaneModel> fmt::Debug for KernelRun<M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let dt_s: f64 = self.dt.into();
        f.debug_struct("KernelRun")
            .field("arch", &self.arch)
            .field("dt_s", &dt_s)
            .field("precision", &self.precision)
            .field("fly", &self.fly)
            .field("parallel", &self.parallel)
            .finish()
    }
}

/// A [`LaneModel`] a [`Fleet`] can step: every one, through this blanket
/// implementation.
///
/// The kernel itself is [`LaneModel::run_blocks`], compiled in the model's
/// own crate when the model writes out its provided body, as Palmer and
/// Bourg do in `fdm-core` (`fdm_core::real::kernel` says why: a generic
/// kernel would be compiled again in every crate that flies a fleet, since
/// optimised builds do not share generic code between crates; measured, the
/// release build of `sim-cli` took 9 min 03 s of CPU instead of 3 min
/// 55 s). This crate's part (the runs of blocks on rayon's threads) is
/// small and generic. A model outside `fdm-core` needs nothing more than
/// its `LaneModel` implementation: the provided `run_blocks`, compiled in
/// the crates that fly it.
pub trait FleetKernel: LaneModel + Sized {
    /// Runs `run` over every block of `fleet`: the kernel, then (for whole
    /// frames) each aircraft's flight status (`run.apply(fleet)`).
    fn run_kernel(fleet: &mut Fleet<Self>, run: KernelRun<Self>) {
        run.apply(fleet);
    }

    /// Runs `run` over the blocks of one piece of a fleet
    /// ([`FleetPiece::fly_with`]), on this thread
    /// (`run.apply_to_piece(piece)`).
    fn run_kernel_piece(piece: &mut FleetPiece<'_, Self>, run: KernelRun<Self>) {
        run.apply_to_piece(piece);
    }
}

impl<M: LaneModel> FleetKernel for M {}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;

    /// A kernel run prints what it runs: the instruction set, the time step
    /// in seconds (Bourg's `f32` step widened), the maths and the two flags.
    #[test]
    fn a_kernel_run_prints_its_fields() {
        let palmer = KernelRun::<Palmer> {
            arch: Arch::Scalar,
            dt: 0.5,
            precision: Precision::Fast,
            fly: true,
            parallel: false,
        };
        assert_eq!(
            format!("{palmer:?}"),
            "KernelRun { arch: Scalar, dt_s: 0.5, precision: Fast, fly: true, parallel: false }"
        );
        let bourg = KernelRun::<Bourg> {
            arch: Arch::Scalar,
            dt: 0.25_f32,
            precision: Precision::Exact,
            fly: false,
            parallel: true,
        };
        assert_eq!(
            format!("{bourg:?}"),
            "KernelRun { arch: Scalar, dt_s: 0.25, precision: Exact, fly: false, parallel: true }"
        );
    }
}
