//! The fleet kernel's block loop: what `fdm-fleet`'s `Fleet<M>` runs over
//! its blocks of [`LaneModel::Lanes`] aircraft, compiled here so that each
//! model of this crate has its kernel compiled once, in this crate.
//!
//! A fleet's kernel is the model's whole step inlined into one copy per
//! instruction set, maths and loop (twelve copies of Palmer's RK4 step on
//! x86-64: three instruction sets, exact and fast, steps and whole frames).
//! A generic function is compiled again in every crate that uses it for a
//! given model (optimised builds do not share generic code between crates),
//! so a kernel reached only through generic code would be compiled again in
//! every crate that flies a fleet (measured with `fdm-fleet`: the release
//! build of `sim-cli` took 9 min 03 s of CPU instead of 3 min 55 s). A
//! non-generic function is compiled once, in its own crate. So the loop is
//! reached through [`LaneModel::run_blocks`], whose provided body is
//! [`run_blocks`]: Palmer and Bourg write that body out in their own
//! `LaneModel` implementations (non-generic, so compiled in this crate), and
//! a model outside this crate gets the provided body, compiled in the crates
//! that fly it.
//!
//! The layout, the threads and the precision names are `fdm-fleet`'s; this
//! module owns only the blocks ([`Block`]), the step and flight-status loop
//! over them, and the choice of instruction set (`fdm-fleet`'s module docs
//! say why the instruction set cannot change the bits).

use pulp::{Arch, Simd, WithSimd};

use super::{Exact, Fast, LaneModel, Lanes, Mask, Maths, NoPermutes, Permutes, Real};
use crate::model::{FlightStatus, Model};

/// The lane arrays of model `M`'s blocks.
pub type Array<M, T> = <<M as LaneModel>::Lanes as Lanes>::Array<T>;

/// `LANES` aircraft of model `M`, field by field: one block of a fleet.
#[derive(Debug, Clone, Copy)]
pub struct Block<M: LaneModel> {
    /// Each lane's clock, s.
    pub time: Array<M, f64>,
    /// Each lane's integrated state.
    pub vars: M::Vars,
    /// Each lane's control terms.
    pub terms: M::Terms,
    /// The controls as set (read back by the fleet; the kernel reads the
    /// terms).
    pub controls: Array<M, M::Controls>,
    /// Each aircraft's flight status (whole frames).
    pub status: Array<M, FlightStatus>,
}

impl<M: LaneModel> Block<M> {
    /// A block of idle aircraft.
    pub fn idle(aircraft: &M::Aircraft) -> Self {
        let (vars, terms) = M::idle(aircraft);
        Self {
            time: M::Lanes::array(|_| 0.0),
            vars,
            terms,
            controls: M::Lanes::array(|_| M::initial_controls()),
            status: M::Lanes::array(|_| FlightStatus::initial(M::height_m(&M::initial_state()))),
        }
    }

    /// Lane `lane`'s state.
    pub fn state(&self, lane: usize) -> M::State {
        M::state(&self.vars, self.time.as_ref()[lane], lane)
    }

    /// Writes `state` (and its clock) into lane `lane`.
    pub fn set_state(&mut self, lane: usize, state: &M::State) {
        self.time.as_mut()[lane] = M::set_state(&mut self.vars, lane, state);
    }

    /// One step of every lane with the maths `F` and the lane permutes
    /// `permutes`.
    #[inline(always)]
    fn step<F: Maths, P: Permutes>(
        &mut self,
        permutes: P,
        aircraft: &M::Aircraft,
        shared: &M::Shared,
        dt: M::TimeStep,
    ) {
        self.vars = M::step_lanes_permuting::<F, P>(
            permutes,
            aircraft,
            shared,
            &self.terms,
            &self.vars,
            dt,
        );
        let dt_s: f64 = dt.into();
        for t in self.time.as_mut() {
            *t += dt_s;
        }
    }

    /// The flight-status half of a whole frame for a block the kernel has
    /// just stepped from `time` and `vars`: every lane ends as
    /// [`crate::model::fly`] would have left it.
    #[inline(always)]
    fn settle(
        &mut self,
        time: &Array<M, f64>,
        vars: &M::Vars,
        aircraft: &M::Aircraft,
        dt: M::TimeStep,
    ) {
        // Whether any lane needs more than the step (usually none).
        let mut suspect = <M::Lanes as Real>::Mask::splat(false);
        M::for_each_component(&self.vars, |x| {
            suspect = suspect.or(x.abs().lt(M::SUSPECT).not());
        });
        let mut unfinished = M::above_ground(&self.vars).not();
        for (l, (t, s)) in self
            .time
            .as_ref()
            .iter()
            .zip(self.status.as_ref())
            .enumerate()
        {
            if !t.is_finite() {
                suspect.set_lane(l, true);
            }
            if *s != FlightStatus::Airborne {
                unfinished.set_lane(l, true);
            }
        }
        let unfinished = unfinished.or(suspect);
        if unfinished.any() {
            self.settle_lanes(unfinished, suspect, time, vars, aircraft, dt);
        }
    }

    /// The scalar part of [`Self::settle`], for the lanes `unfinished`
    /// (rare: out of the hot loop).
    #[cold]
    #[inline(never)]
    fn settle_lanes(
        &mut self,
        unfinished: <M::Lanes as Real>::Mask,
        suspect: <M::Lanes as Real>::Mask,
        time: &Array<M, f64>,
        vars: &M::Vars,
        aircraft: &M::Aircraft,
        dt: M::TimeStep,
    ) {
        for lane in 0..M::Lanes::LANES {
            if !unfinished.lane(lane) {
                continue;
            }
            let (state, status) = finish_lane::<M>(
                aircraft,
                &self.controls.as_ref()[lane],
                self.status.as_ref()[lane],
                suspect.lane(lane),
                || M::state(vars, time.as_ref()[lane], lane),
                || self.state(lane),
                dt,
            );
            self.set_state(lane, &state);
            self.status.as_mut()[lane] = status;
        }
    }
}

/// The frame of one lane that the kernel's step alone does not finish (not
/// airborne above the ground plane, or `suspect`: a component too large to be
/// sure the step is finite), as [`crate::model::fly`] would end it: a
/// crashed, diverged or suspect aircraft flies the scalar frame again from
/// its state `before` the step; any other keeps the kernel's step (`after`,
/// `step`'s bits) and only settles its status and ground contact.
fn finish_lane<M: Model>(
    aircraft: &M::Aircraft,
    controls: &M::Controls,
    status: FlightStatus,
    suspect: bool,
    before: impl FnOnce() -> M::State,
    after: impl FnOnce() -> M::State,
    dt: M::TimeStep,
) -> (M::State, FlightStatus) {
    if suspect || status.is_final() {
        crate::model::fly::<M>(aircraft, controls, status, &before(), dt)
    } else {
        crate::model::settle::<M>(aircraft, status, &after())
    }
}

/// The stepping loop over some blocks, generic over the instruction set pulp
/// picked: `with_simd` and everything it calls are inlined into pulp's
/// `#[target_feature]` function, so the lane loops compile to that set.
/// `FastMaths` is the [`Fast`] maths of that instruction set and `P` its
/// lane permutes (see [`dispatch`]).
struct StepBlocks<'a, M: LaneModel, FastMaths, P> {
    blocks: &'a mut [Block<M>],
    aircraft: &'a M::Aircraft,
    shared: &'a M::Shared,
    dt: M::TimeStep,
    /// The [`Fast`] maths rather than [`Exact`] (only if the model has them,
    /// [`LaneModel::HAS_FAST`]).
    fast: bool,
    /// Whole frames with the flight status rather than bare steps.
    fly: bool,
    /// The instruction set's lane permutes.
    permutes: P,
    fast_maths: core::marker::PhantomData<FastMaths>,
}

impl<M: LaneModel, FastMaths: Maths, P: Permutes> WithSimd for StepBlocks<'_, M, FastMaths, P> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        if self.fast && M::HAS_FAST {
            self.each::<FastMaths>();
        } else {
            self.each::<Exact>();
        }
    }
}

impl<'a, M: LaneModel, FastMaths, P: Permutes> StepBlocks<'a, M, FastMaths, P> {
    /// The same loop with the fast maths `F` and the lane permutes `permutes`.
    #[inline(always)]
    fn with<F, Q>(self, permutes: Q) -> StepBlocks<'a, M, F, Q> {
        StepBlocks {
            blocks: self.blocks,
            aircraft: self.aircraft,
            shared: self.shared,
            dt: self.dt,
            fast: self.fast,
            fly: self.fly,
            permutes,
            fast_maths: core::marker::PhantomData,
        }
    }

    /// The kernel on every block, each followed by its flight status with
    /// [`Self::fly`].
    #[inline(always)]
    fn each<F: Maths>(self) {
        let (aircraft, shared, dt, p) = (self.aircraft, self.shared, self.dt, self.permutes);
        if self.fly {
            for b in self.blocks {
                let (time, vars) = (b.time, b.vars);
                b.step::<F, P>(p, aircraft, shared, dt);
                b.settle(&time, &vars, aircraft, dt);
            }
        } else {
            for b in self.blocks {
                b.step::<F, P>(p, aircraft, shared, dt);
            }
        }
    }
}

/// Runs `op` with `arch`'s instruction set: pulp's `Arch::dispatch`, with
/// the fast maths chosen by the instruction set itself rather than by a flag
/// inside the kernel. `Fast<true>` (the `mul_add` of the FMA instruction)
/// for x86-64-v3 and v4, which have FMA; `Fast<false>` (Dekker's splitting)
/// for the baseline and other architectures, treated as not having FMA
/// (always correct, only slower). Each instruction set's copy of the kernel
/// is thereby compiled with the one fast maths it can run: a flag would
/// compile both into every copy (a third more code in the release build,
/// whose time is mostly these copies).
///
/// The lane permutes likewise: x86-64-v4's copy gets pulp's AVX-512 token
/// itself as its [`Permutes`] (`vpermt2ps`), every other copy
/// [`NoPermutes`] (the look-ups' selects), so each copy holds one form.
#[inline(always)]
fn dispatch<M: LaneModel>(arch: Arch, op: StepBlocks<'_, M, (), NoPermutes>) {
    #[cfg(target_arch = "x86_64")]
    match arch {
        Arch::V4(simd) => Simd::vectorize(simd, op.with::<Fast<true>, _>(simd)),
        Arch::V3(simd) => Simd::vectorize(simd, op.with::<Fast<true>, _>(NoPermutes)),
        // The baseline, and any instruction set a later pulp adds (`Arch`
        // is non-exhaustive): the scalar copy is correct on every CPU.
        _ => Simd::vectorize(pulp::Scalar::new(), op.with::<Fast<false>, _>(NoPermutes)),
    }
    #[cfg(not(target_arch = "x86_64"))]
    arch.dispatch(op.with::<Fast<false>, _>(NoPermutes));
}

/// The kernel over `blocks` on this thread with `arch`'s instruction set:
/// one step of every lane with the model's step, with the [`Fast`] maths if
/// `fast` and the model has them ([`LaneModel::HAS_FAST`]), else [`Exact`];
/// with `fly`, each block's flight status after its step (whole frames:
/// every lane ends as [`crate::model::fly`] would leave it, in [`Exact`]
/// bit for bit). The provided body of [`LaneModel::run_blocks`]; generic,
/// so compiled in the crate that instantiates it for a model.
pub fn run_blocks<M: LaneModel>(
    blocks: &mut [Block<M>],
    aircraft: &M::Aircraft,
    shared: &M::Shared,
    dt: M::TimeStep,
    arch: Arch,
    fast: bool,
    fly: bool,
) {
    dispatch(
        arch,
        StepBlocks::<M, (), NoPermutes> {
            blocks,
            aircraft,
            shared,
            dt,
            fast,
            fly,
            permutes: NoPermutes,
            fast_maths: core::marker::PhantomData,
        },
    );
}
