//! Many aircraft of one model: `afit_fdm.Fleet`, over `fdm-fleet`'s SIMD
//! kernels ([`FleetOps`], the one adapter to today's fleet API).
//!
//! The state the Python side sees is the binding's own column buffer: one
//! C-contiguous `(fields, n)` float64 array and one `(n,)` uint8 status array,
//! owned by NumPy, refreshed in place at the end of every call that changes
//! the fleet (`step`, `reset`, construction, the tasks' steps; a task step
//! with `views=False` refreshes the status array only). Reading them never
//! copies: the read-only views handed out are views of those buffers. The
//! kernel's own arrays are lane blocks (8 or 16 aircraft, field by field)
//! that `fdm-fleet` keeps private, so the refresh is one gather per `step`
//! call, not per frame.

use std::marker::PhantomData;
use std::sync::OnceLock;
use std::time::Instant;

use fdm_core::model::{FlightStatus, Model};
use fdm_core::real::kernel::{Array, Block};
use fdm_fleet::{ControlBlocks, FleetError, FleetPiece, Precision};
use fdm_run::model::agent::{MAX_ACTIONS, MAX_CONTROL_OBS, MAX_STATE_FIELDS};
use numpy::ndarray::ArrayView1;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::flight::to_py;
use crate::models::{status_code, BindModel, ControlRange, FleetOps};
use crate::start::StartSpec;
use crate::task;

pub mod pickle;

/// A per-aircraft argument: one number for every aircraft, or one each.
#[derive(Debug, Clone)]
pub enum Column {
    /// The same value for every aircraft.
    Scalar(f64),
    /// One value per aircraft.
    Values(Vec<f64>),
}

impl Column {
    /// The value for aircraft `i`.
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Self::Scalar(v) => *v,
            Self::Values(v) => v[i],
        }
    }

    /// Reads `obj` as argument `name` for `n` aircraft: a Python number, a
    /// NumPy number (a float16, float32 or float64, integer or bool scalar or
    /// 0-d array: float32 is what Gymnasium's action arrays hold, and its
    /// widening to f64 is exact), or a one-dimensional float64 NumPy array of
    /// length `n`.
    ///
    /// # Errors
    /// `TypeError` for anything else (naming the argument and what it got),
    /// `ValueError` for a wrong shape.
    pub fn extract(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> PyResult<Self> {
        if obj.hasattr("dtype")? && obj.hasattr("shape")? {
            let dtype: String = obj.getattr("dtype")?.str()?.extract()?;
            let shape: Vec<usize> = obj.getattr("shape")?.extract()?;
            if shape.is_empty() {
                // A NumPy scalar (or 0-d array): one number. Not a longdouble
                // or a complex one, whose conversion would drop digits or a
                // part.
                let number = matches!(dtype.as_str(), "float16" | "float32" | "float64" | "bool")
                    || dtype.starts_with("int")
                    || dtype.starts_with("uint");
                if !number {
                    return Err(PyTypeError::new_err(format!(
                        "{name}: expected a number or a float64 array, got a {dtype} scalar"
                    )));
                }
                return Ok(Self::Scalar(obj.call_method0("item")?.extract::<f64>()?));
            }
            if dtype != "float64" {
                return Err(PyTypeError::new_err(format!(
                    "{name}: expected a float64 array, got dtype {dtype} \
                     (convert with .astype(numpy.float64))"
                )));
            }
            if shape != [n] {
                return Err(PyValueError::new_err(format!(
                    "{name}: expected shape ({n},), got {shape:?}"
                )));
            }
            let array: PyReadonlyArray1<'_, f64> = obj.extract().map_err(|_| {
                PyTypeError::new_err(format!("{name}: expected a float64 NumPy array"))
            })?;
            let view: ArrayView1<'_, f64> = array.as_array();
            return Ok(Self::Values(view.iter().copied().collect()));
        }
        if obj.is_instance_of::<pyo3::types::PyString>() {
            return Err(PyTypeError::new_err(format!(
                "{name}: expected a number or a float64 array, got a str"
            )));
        }
        obj.extract::<f64>().map(Self::Scalar).map_err(|_| {
            let ty = obj
                .get_type()
                .name()
                .map_or_else(|_| "?".to_owned(), |n| n.to_string());
            PyTypeError::new_err(format!(
                "{name}: expected a number or a float64 array, got {ty}"
            ))
        })
    }

    /// Checks every value is finite and in `lo..=hi`.
    ///
    /// # Errors
    /// `ValueError` naming the argument, the first bad index and its value.
    pub fn check_range(&self, name: &str, lo: f64, hi: f64) -> PyResult<()> {
        let bad = |v: f64| !v.is_finite() || !(lo..=hi).contains(&v);
        match self {
            Self::Scalar(v) if bad(*v) => Err(PyValueError::new_err(format!(
                "{name}: {v} is not a finite number in {lo}..{hi}"
            ))),
            Self::Values(vs) => match vs.iter().position(|&v| bad(v)) {
                Some(i) => Err(PyValueError::new_err(format!(
                    "{name}[{i}]: {} is not a finite number in {lo}..{hi}",
                    vs[i]
                ))),
                None => Ok(()),
            },
            Self::Scalar(_) => Ok(()),
        }
    }
}

/// Per-aircraft start arguments, each optional.
#[derive(Debug, Clone, Default)]
pub struct StartColumns {
    /// Feet above the origin.
    pub altitude_ft: Option<Column>,
    /// Knots.
    pub speed_kt: Option<Column>,
    /// Degrees clockwise from north.
    pub heading_deg: Option<Column>,
    /// Trim each aircraft.
    pub trim: bool,
}

impl StartColumns {
    fn spec(&self, i: usize) -> StartSpec {
        StartSpec {
            altitude_ft: self.altitude_ft.as_ref().map(|c| c.get(i)),
            speed_kt: self.speed_kt.as_ref().map(|c| c.get(i)),
            heading_deg: self.heading_deg.as_ref().map(|c| c.get(i)),
            trim: self.trim,
        }
    }
}

/// Control arguments by the model's control index.
pub type ControlColumns = Vec<(usize, Column)>;

/// Seconds since the first fleet step of the process (a monotonic clock the
/// tests compare between threads).
pub fn now_s() -> f64 {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    EPOCH.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// Aircraft-frames a long `Fleet.step` flies between two looks at Python's
/// pending signals (the crate's `in_chunks`): about 20 to 120 ms of flying on
/// one thread at 10 to 60 ns an aircraft-frame, so Ctrl-C stops it within a
/// fraction of a second while the looks cost nothing next to the flying.
pub const AIRCRAFT_FRAMES_PER_SIGNAL_CHECK: u64 = 1 << 21;

/// Frames a fleet of `n` aircraft flies between two looks at the signals:
/// [`AIRCRAFT_FRAMES_PER_SIGNAL_CHECK`] over `n`, at least one.
#[must_use]
pub fn frames_per_signal_check(n: usize) -> u64 {
    (AIRCRAFT_FRAMES_PER_SIGNAL_CHECK / (n as u64).max(1)).max(1)
}

/// What `Fleet` needs from a fleet of any model.
pub trait AnyFleet: Send + Sync {
    /// The model's name.
    fn model(&self) -> &'static str;
    /// Number of aircraft.
    fn len(&self) -> usize;
    /// Whether the fleet has no aircraft.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The state columns' names.
    fn state_fields(&self) -> &'static [&'static str];
    /// The controls' names and ranges.
    fn control_fields(&self) -> &'static [ControlRange];
    /// Steps `frames` frames (the buffers are not refreshed: [`Self::gather`]
    /// does that). Flying `a` frames then `b` is flying `a + b`, bit for bit
    /// (each frame is the same step of each aircraft).
    ///
    /// # Errors
    /// The kernel refused the fleet's precision (checked when it was made).
    fn fly(&mut self, frames: u64) -> Result<(), FleetError>;
    /// Refreshes the buffers.
    fn gather(&self, columns: &mut [f64], status: &mut [u8]);
    /// Sets controls (already range-checked) for the aircraft with `mask`.
    ///
    /// # Errors
    /// A value in range but not allowed (ValueError).
    fn set_controls(&mut self, controls: &ControlColumns, mask: Option<&[bool]>) -> PyResult<()>;
    /// Each control as a column.
    fn controls(&self) -> Vec<Vec<f64>>;
    /// Restarts the aircraft with `mask` (all without) at `start` with
    /// `controls` (the rest of the controls from the model's start).
    ///
    /// # Errors
    /// As the constructor.
    fn reset(
        &mut self,
        mask: Option<&[bool]>,
        start: &StartColumns,
        controls: &ControlColumns,
    ) -> PyResult<()>;
    /// The kernel's instruction set.
    fn instruction_set(&self) -> &'static str;
    /// Frames per second.
    fn fps(&self) -> f64;
    /// The maths the kernel flies with.
    fn precision(&self) -> Precision;
    /// An independent copy: every aircraft's state, controls and status, bit
    /// for bit, with the same frame rate, precision and threading.
    fn duplicate(&self) -> Box<dyn AnyFleet>;
    /// The fleet as `pickle` holds it ([`pickle::restore`] reads it back).
    fn pickled(&self) -> Vec<u8>;
    /// Actions per aircraft of the Gymnasium tasks.
    fn task_actions(&self) -> usize;
    /// Observations per aircraft of the Gymnasium tasks.
    fn task_observations(&self) -> usize;
    /// Validates `actions` (`n × task_actions` values, row by row); then,
    /// in one pass over runs of blocks (on rayon's pool when the fleet is
    /// parallel), sets every aircraft's controls from them as
    /// `afit_fdm.gym` did in NumPy, flies `frames` frames, counts `steps`
    /// up by one and, with `observe`, refreshes the buffers and fills the
    /// task's outputs ([`crate::task::observe_block`]): what setting the
    /// controls, [`Self::fly`] and [`Self::task_observe`] give one after
    /// the other, bit for bit (the aircraft are independent), with each run
    /// of blocks read once while it is in the cache.
    ///
    /// # Errors
    /// A NaN action, named by the control it sets as `Fleet.set_controls`
    /// words it (nothing changed); a precision the kernel does not have (checked
    /// when the fleet was made).
    fn task_step(
        &mut self,
        actions: ActionValues<'_>,
        frames: u64,
        steps: &mut [i64],
        observe: Option<(&TaskArgs<'_>, TaskOut<'_>)>,
    ) -> Result<(), String>;
    /// Refreshes the buffers and fills the task's outputs
    /// ([`crate::task::observe_block`]) in one pass over the aircraft, with each
    /// aircraft's step count from `steps`.
    fn task_observe(&self, args: &TaskArgs<'_>, steps: &[i64], out: TaskOut<'_>);
}

/// An action array's values, row by row, float32 or float64.
#[derive(Debug, Clone, Copy)]
pub enum ActionValues<'a> {
    /// float32 (the action space's dtype).
    F32(&'a [f32]),
    /// float64.
    F64(&'a [f64]),
}

impl ActionValues<'_> {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            Self::F32(v) => v.len(),
            Self::F64(v) => v.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value `i`, widened exactly to float64 and clipped to -1..1 as
    /// `np.clip` clips (NaN stays NaN).
    pub fn clipped(&self, i: usize) -> f64 {
        match self {
            Self::F32(v) => clip(v[i]),
            Self::F64(v) => clip(v[i]),
        }
    }

    /// Whether any value is NaN (a branch-free scan the compiler vectorises).
    fn any_nan(&self) -> bool {
        match self {
            Self::F32(v) => v.iter().fold(false, |nan, x| nan | x.is_nan()),
            Self::F64(v) => v.iter().fold(false, |nan, x| nan | x.is_nan()),
        }
    }
}

/// An action value widened exactly to float64 and clipped to -1..1 as
/// `np.clip` clips (NaN stays NaN).
#[inline(always)]
fn clip<T: Copy>(v: T) -> f64
where
    f64: From<T>,
{
    crate::task::np_clip(f64::from(v), -1.0, 1.0)
}

/// The first `count` of `from` into `to`: a copy of the fixed length
/// `whole` (a constant where it is called) when `count` is `whole` (inline
/// moves, not a call of `memcpy` for eight numbers).
#[inline(always)]
fn copy_lanes(to: &mut [f64], from: &[f64], count: usize, whole: usize) {
    if count == whole {
        to[..whole].copy_from_slice(&from[..whole]);
    } else {
        to[..count].copy_from_slice(&from[..count]);
    }
}

/// A lane array of a block of model `M`, every lane 0.
#[inline(always)]
fn zeros<M: BindModel>() -> Array<M, f64> {
    <<M as fdm_core::real::LaneModel>::Lanes as fdm_core::real::Lanes>::array(|_| 0.0)
}

/// Sets the controls of a piece's aircraft from their rows of `values`
/// (`k` per aircraft), clipped ([`AgentModel::task_apply`](fdm_run::model::agent::AgentModel::task_apply)), one aircraft at
/// a time (reading a row and writing a lane: a transposition of the
/// actions into lane arrays measured slower), the control terms a block at
/// a time ([`FleetPiece::update_control_blocks`]).
struct ActBlocks<'v, T> {
    values: &'v [T],
    k: usize,
}

impl<M: BindModel, T: Copy> ControlBlocks<M> for ActBlocks<'_, T>
where
    f64: From<T>,
{
    #[inline(always)]
    fn update(&mut self, first: usize, count: usize, controls: &mut Array<M, M::Controls>) {
        let k = self.k;
        let rows = &self.values[first * k..(first + count) * k];
        for (c, row) in controls.as_mut().iter_mut().zip(rows.chunks_exact(k)) {
            let mut clipped = [0.0; MAX_ACTIONS];
            for (a, v) in clipped.iter_mut().zip(row) {
                *a = clip(*v);
            }
            *c = M::task_apply(*c, &clipped[..k]);
        }
    }
}

/// [`ActBlocks`] over `piece`.
#[inline(always)]
fn act_piece<M: BindModel, T: Copy>(piece: &mut FleetPiece<'_, M>, values: &[T], k: usize)
where
    f64: From<T>,
{
    piece.update_control_blocks(&mut ActBlocks { values, k });
}

/// A piece of a task step ([`AnyFleet::task_step`]) with the instruction set
/// pulp picked: each run of [`TASK_GROUP`] blocks has its controls set from
/// the actions ([`act_piece`]: the Palmer block's bank sines and cosines and
/// the other control terms in its vector registers), is flown and, with an
/// observer, is observed ([`Observer::observe_run`]) before the next run,
/// so that each block's memory is touched once per step while it is in the
/// level-1 cache. The aircraft are independent and every operation is
/// correctly rounded and none fused, so neither the order nor the
/// instruction set changes a bit.
struct StepPiece<'x, 'p, 'a, 'f, M: BindModel> {
    /// The piece's runs of blocks, in order.
    runs: &'x mut [FleetPiece<'f, M>],
    actions: ActionValues<'x>,
    dt: M::TimeStep,
    precision: Precision,
    frames: u64,
    observer: Option<Observer<'p, 'a, M>>,
    /// The piece's step counts (already counted up).
    steps: &'x [i64],
}

impl<M: BindModel> pulp::WithSimd for StepPiece<'_, '_, '_, '_, M> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        let (mut observer, steps) = (self.observer, self.steps);
        let first = self.runs.first().map_or(0, FleetPiece::first);
        for run in self.runs.iter_mut() {
            match self.actions {
                ActionValues::F32(v) => act_piece(run, v, M::TASK_ACTIONS),
                ActionValues::F64(v) => act_piece(run, v, M::TASK_ACTIONS),
            }
            for _ in 0..self.frames {
                // The precision was checked by the caller: flying cannot fail.
                let _ = run.fly_with(self.dt, self.precision);
            }
            if let Some(observer) = observer.as_mut() {
                observer.observe_run(simd, run.first() - first, run, steps);
            }
        }
        if let Some(observer) = observer.as_mut() {
            observer.flush_with(simd);
        }
    }
}

/// The task's per-aircraft inputs.
#[derive(Debug)]
pub struct TaskArgs<'a> {
    /// Which task.
    pub task: crate::task::Task,
    /// Target altitudes, ft.
    pub target_alt_ft: &'a [f64],
    /// Target headings, degrees.
    pub target_heading_deg: &'a [f64],
    /// Steps after which an episode is truncated.
    pub max_steps: i64,
}

/// The buffers a task step fills.
#[derive(Debug)]
pub struct TaskOut<'a> {
    /// The state columns, `(fields, n)`, or empty: the columns are then
    /// left as they are (`Fleet.task_step(..., views=False)`), the status
    /// codes still written.
    pub columns: &'a mut [f64],
    /// The status codes.
    pub status: &'a mut [u8],
    /// Observations, `(n, task_observations)`.
    pub obs: &'a mut [f32],
    /// Rewards.
    pub reward: &'a mut [f64],
    /// Ended by status (landed, crashed, diverged).
    pub terminated: &'a mut [bool],
    /// Ended by the step limit.
    pub truncated: &'a mut [bool],
}

/// Most aircraft per piece of work of a task pass (one thread's share at a
/// time; within a piece each run of [`TASK_GROUP`] blocks is acted on,
/// flown and observed before the next: [`StepPiece`]).
const TASK_CHUNK: usize = 2048;
/// Fewest aircraft per piece (below this a piece costs less than handing it
/// to another thread).
const TASK_CHUNK_MIN: usize = 512;

/// Blocks per run of a task step: each run's controls are set, it is flown
/// and observed before the next ([`StepPiece`]). One block: measured
/// against runs of 2, 4, 8 and a whole piece (run P9 in BENCHMARKS.md), one
/// block at a time took the least CPU time per aircraft-step.
const TASK_GROUP: usize = 1;

/// A fleet of model `M` and how it steps.
#[derive(Clone)]
pub struct Lanes<M: BindModel> {
    fleet: M::Fleet,
    len: usize,
    fps: f64,
    precision: Precision,
    parallel: bool,
}

fn start_of<M: BindModel>(
    i: usize,
    start: &StartColumns,
    controls: &ControlColumns,
) -> PyResult<(M::Controls, M::State)> {
    let mut c = M::initial_controls();
    for (index, column) in controls {
        c = M::with_control(c, *index, column.get(i)).map_err(|e| {
            PyValueError::new_err(format!("{}[{i}]: {e}", M::CONTROL_FIELDS[*index].0))
        })?;
    }
    crate::start::start::<M>(&start.spec(i), M::default_aircraft(), c)
        .map_err(|e| PyValueError::new_err(format!("aircraft {i}: {e}")))
}

impl<M: BindModel> Lanes<M> {
    /// `n` aircraft from `start` and `controls`.
    ///
    /// # Errors
    /// ValueError for a start or control that cannot be flown; MemoryError
    /// for a fleet that does not fit in the memory this process can still
    /// allocate ([`check_memory`]).
    pub fn new(
        n: usize,
        fps: f64,
        precision: Precision,
        parallel: bool,
        start: &StartColumns,
        controls: &ControlColumns,
    ) -> PyResult<Self> {
        M::Fleet::check_precision(precision)
            .map_err(|e| PyValueError::new_err(format!("precision: {e}")))?;
        check_memory::<M>(n, fdm_run::memory::available_bytes())?;
        let mut fleet = M::Fleet::empty().map_err(|e| PyValueError::new_err(e.to_string()))?;
        for i in 0..n {
            let (c, s) = start_of::<M>(i, start, controls)?;
            fleet.push(s, c);
        }
        Ok(Self {
            fleet,
            len: n,
            fps,
            precision,
            parallel,
        })
    }
}

impl<M: BindModel> AnyFleet for Lanes<M>
where
    M::Fleet: Sync,
{
    fn model(&self) -> &'static str {
        M::NAME
    }
    fn len(&self) -> usize {
        self.len
    }
    fn state_fields(&self) -> &'static [&'static str] {
        M::STATE_FIELDS
    }
    fn control_fields(&self) -> &'static [ControlRange] {
        M::CONTROL_FIELDS
    }
    fn fly(&mut self, frames: u64) -> Result<(), FleetError> {
        self.fly_frames(frames)
    }
    fn gather(&self, columns: &mut [f64], status: &mut [u8]) {
        let (n, k) = (self.len, M::STATE_FIELDS.len());
        let mut row = vec![0.0; k];
        self.fleet.for_each_state(|i, s| {
            M::state_values(s, &mut row);
            for (f, v) in row.iter().enumerate() {
                columns[f * n + i] = *v;
            }
        });
        self.fleet
            .for_each_status(|i, s| status[i] = status_code(s));
    }
    fn set_controls(&mut self, controls: &ControlColumns, mask: Option<&[bool]>) -> PyResult<()> {
        // Build every new control first, so a refused value changes nothing.
        let mut new = Vec::with_capacity(self.len);
        for i in 0..self.len {
            if mask.is_some_and(|m| !m[i]) {
                continue;
            }
            let mut c = self.fleet.controls(i).unwrap_or_else(M::initial_controls);
            for (index, column) in controls {
                c = M::with_control(c, *index, column.get(i)).map_err(|e| {
                    PyValueError::new_err(format!("{}[{i}]: {e}", M::CONTROL_FIELDS[*index].0))
                })?;
            }
            new.push((i, c));
        }
        for (i, c) in new {
            self.fleet
                .set_controls(i, c)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
        }
        Ok(())
    }
    fn controls(&self) -> Vec<Vec<f64>> {
        let k = M::CONTROL_FIELDS.len();
        let mut out = vec![vec![0.0; self.len]; k];
        let mut row = vec![0.0; k];
        for i in 0..self.len {
            let c = self.fleet.controls(i).unwrap_or_else(M::initial_controls);
            M::control_values(&c, &mut row);
            for (column, v) in out.iter_mut().zip(&row) {
                column[i] = *v;
            }
        }
        out
    }
    fn reset(
        &mut self,
        mask: Option<&[bool]>,
        start: &StartColumns,
        controls: &ControlColumns,
    ) -> PyResult<()> {
        let mut new = Vec::new();
        for i in 0..self.len {
            if mask.is_some_and(|m| !m[i]) {
                continue;
            }
            new.push((i, start_of::<M>(i, start, controls)?));
        }
        for (i, (c, s)) in new {
            let status = FlightStatus::initial(M::height_m(&s));
            self.fleet
                .set(i, &s, c, status)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
        }
        Ok(())
    }
    fn instruction_set(&self) -> &'static str {
        self.fleet.instruction_set()
    }
    fn fps(&self) -> f64 {
        self.fps
    }
    fn precision(&self) -> Precision {
        self.precision
    }
    fn duplicate(&self) -> Box<dyn AnyFleet> {
        Box::new(self.clone())
    }
    fn pickled(&self) -> Vec<u8> {
        pickle::pickled(self)
    }
    fn task_actions(&self) -> usize {
        M::TASK_ACTIONS
    }
    fn task_observations(&self) -> usize {
        crate::task::KINEMATIC_OBS + M::TASK_CONTROL_OBS
    }
    fn task_step(
        &mut self,
        actions: ActionValues<'_>,
        frames: u64,
        steps: &mut [i64],
        observe: Option<(&TaskArgs<'_>, TaskOut<'_>)>,
    ) -> Result<(), String> {
        self.check_actions(actions)?;
        M::Fleet::check_precision(self.precision).map_err(|e| e.to_string())?;
        let n = self.len;
        if n == 0 {
            return Ok(());
        }
        let (dt, precision) = (M::time_step(self.fps), self.precision);
        let (chunk, n_obs, parallel) = (self.chunk(), self.task_observations(), self.parallel);
        let group = TASK_GROUP;
        let mut runs = self.fleet.pieces_mut(group);
        let fleet_pieces: Vec<&mut [FleetPiece<'_, M>]> = runs
            .chunks_mut(chunk / (group * M::Fleet::lanes()))
            .collect();
        let (args, mut outs): (_, Vec<Option<Piece<'_>>>) = match observe {
            Some((args, out)) => (
                Some(args),
                split(out, chunk, M::STATE_FIELDS.len(), n_obs)
                    .into_iter()
                    .map(Some)
                    .collect(),
            ),
            None => (None, (0..fleet_pieces.len()).map(|_| None).collect()),
        };
        let arch = pulp::Arch::new();
        let work = |((runs, steps), out): StepWork<'_, '_, '_, M>| {
            for s in steps.iter_mut() {
                *s = s.saturating_add(1);
            }
            let observer = match (args, out) {
                (Some(args), Some(out)) => Some(Observer::<M>::new(args, out)),
                _ => None,
            };
            arch.dispatch(StepPiece {
                runs,
                actions,
                dt,
                precision,
                frames,
                observer,
                steps,
            });
        };
        if parallel && fleet_pieces.len() > 1 {
            use rayon::prelude::*;
            fleet_pieces
                .into_par_iter()
                .zip(steps.par_chunks_mut(chunk))
                .zip(outs.par_iter_mut())
                .for_each(work);
        } else {
            fleet_pieces
                .into_iter()
                .zip(steps.chunks_mut(chunk))
                .zip(outs.iter_mut())
                .for_each(work);
        }
        Ok(())
    }
    fn task_observe(&self, args: &TaskArgs<'_>, steps: &[i64], out: TaskOut<'_>) {
        if self.len == 0 {
            return;
        }
        let chunk = self.chunk();
        let mut pieces = split(out, chunk, M::STATE_FIELDS.len(), self.task_observations());
        let work = |piece: &mut Piece<'_>| {
            let first = piece.first;
            let mut observer = Observer::<M>::new(args, piece);
            for j in 0..observer.piece.status.len() {
                let i = first + j;
                let (Some(state), Some(status), Some(c)) = (
                    self.fleet.state_at(i),
                    self.fleet.status_at(i),
                    self.fleet.controls(i),
                ) else {
                    continue;
                };
                observer.push(j, steps[i], &state, status, &c);
            }
            observer.flush();
        };
        if self.parallel && pieces.len() > 1 {
            use rayon::prelude::*;
            pieces.par_iter_mut().for_each(work);
        } else {
            pieces.iter_mut().for_each(work);
        }
    }
}

impl<M: BindModel> Lanes<M> {
    /// Flies `frames` frames without refreshing the buffers.
    /// Each cache-sized run of blocks flies all the frames before the next
    /// ([`fdm_fleet::Fleet::fly_frames_with`]): the bits of frame after frame over the
    /// whole fleet, without reading a large fleet from memory every frame.
    fn fly_frames(&mut self, frames: u64) -> Result<(), FleetError> {
        let mut left = frames;
        while left > 0 {
            let now = usize::try_from(left).unwrap_or(usize::MAX);
            self.fleet
                .fly_frames(self.fps, self.precision, self.parallel, now)?;
            left -= now as u64;
        }
        Ok(())
    }

    /// Aircraft per piece of a task pass: about four pieces per thread,
    /// within [`TASK_CHUNK_MIN`]..=[`TASK_CHUNK`], in whole runs of
    /// [`TASK_GROUP`] blocks (the results do not depend on the split).
    fn chunk(&self) -> usize {
        let lanes = M::Fleet::lanes();
        let chunk = if self.parallel {
            self.len
                .div_ceil(4 * rayon::current_num_threads())
                .clamp(TASK_CHUNK_MIN, TASK_CHUNK)
        } else {
            TASK_CHUNK
        };
        let whole = lanes * TASK_GROUP;
        chunk.div_ceil(whole) * whole
    }

    /// The first failure `actions` would cause: a NaN action, named by the
    /// control it sets, in `Fleet.set_controls`'s words for a bad control
    /// array (control by control in the tasks' order, the first bad
    /// aircraft). Entry `p` of [`AgentModel::task_controls`] is set by
    /// action `p` (true of every model's tasks), so a NaN in action `p` is
    /// reported as control `p`: also where only a threshold reads it
    /// (Palmer's flaps, Bourg's surfaces), whose comparisons would
    /// otherwise turn the NaN silently into a setting (40° flaps, a
    /// neutral surface).
    fn check_actions(&self, actions: ActionValues<'_>) -> Result<(), String> {
        if !actions.any_nan() {
            return Ok(());
        }
        let k = M::TASK_ACTIONS;
        let mut clipped = [0.0; 8];
        let row = |i: usize, clipped: &mut [f64; 8]| {
            for (j, a) in clipped.iter_mut().take(k).enumerate() {
                *a = actions.clipped(i * k + j);
            }
            M::task_controls(&clipped[..k])
        };
        let (_, count) = row(0, &mut clipped);
        for p in 0..count.min(k) {
            for i in 0..self.len {
                let (index, value) = row(i, &mut clipped).0[p];
                let (name, lo, hi) = M::CONTROL_FIELDS[index];
                // The action's own NaN, not the setting a threshold made of it.
                let value = if clipped[p].is_nan() { f64::NAN } else { value };
                if !value.is_finite() || !(lo..=hi).contains(&value) {
                    return Err(format!(
                        "{name}[{i}]: {value} is not a finite number in {lo}..{hi}"
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `out` cut into runs of `chunk` aircraft, in order.
fn split<'a>(out: TaskOut<'a>, chunk: usize, fields: usize, n_obs: usize) -> Vec<Piece<'a>> {
    let n = out.status.len();
    let chunks = n.div_ceil(chunk);
    let mut column_parts: Vec<Vec<&mut [f64]>> =
        (0..chunks).map(|_| Vec::with_capacity(fields)).collect();
    for row in out.columns.chunks_mut(n) {
        for (c, part) in row.chunks_mut(chunk).enumerate() {
            column_parts[c].push(part);
        }
    }
    column_parts
        .into_iter()
        .zip(out.status.chunks_mut(chunk))
        .zip(out.obs.chunks_mut(chunk * n_obs))
        .zip(out.reward.chunks_mut(chunk))
        .zip(out.terminated.chunks_mut(chunk))
        .zip(out.truncated.chunks_mut(chunk))
        .enumerate()
        .map(
            |(first, (((((columns, status), obs), reward), terminated), truncated))| Piece {
                first: first * chunk,
                columns,
                status,
                obs,
                reward,
                terminated,
                truncated,
            },
        )
        .collect()
}

/// One piece of a task step as a thread takes it: its runs of fleet blocks,
/// its step counts and, when it observes, its part of the buffers.
type StepWork<'r, 'f, 'o, M> = (
    (&'r mut [FleetPiece<'f, M>], &'r mut [i64]),
    &'r mut Option<Piece<'o>>,
);

/// A run of aircraft of a task pass and their parts of the buffers.
struct Piece<'a> {
    /// The first aircraft's index.
    first: usize,
    /// Each state column's part, or none: the columns are not written
    /// ([`TaskOut::columns`] empty), and the derived fields, which only go
    /// there, are not computed.
    columns: Vec<&'a mut [f64]>,
    status: &'a mut [u8],
    obs: &'a mut [f32],
    reward: &'a mut [f64],
    terminated: &'a mut [bool],
    truncated: &'a mut [bool],
}

/// The observation half of a task pass over a piece: each aircraft's state
/// columns and status code written as it comes ([`Self::push`]), and its
/// observation, reward and flags ([`crate::task::observe_block`]) a block of
/// [`task::BLOCK`] consecutive aircraft at a time.
struct Observer<'p, 'a, M: BindModel> {
    args: &'p TaskArgs<'p>,
    piece: &'p mut Piece<'a>,
    /// The lanes [`Self::push`] gathers ([`Self::push_block`] uses a block
    /// of its own).
    block: task::Block<{ task::BLOCK }>,
    /// Each lane's state, for [`ColumnModel::block_fields`](fdm_run::model::columns::ColumnModel::block_fields) (only with some).
    states: [M::State; task::BLOCK],
    /// The instruction set of the block's observation.
    arch: pulp::Arch,
    /// Each lane's step count.
    steps: [i64; task::BLOCK],
    /// The piece index of lane 0.
    first: usize,
    /// Lanes filled.
    len: usize,
    /// Scratch of [`Self::push_block`]: a fleet block's state columns.
    columns: [Array<M, f64>; MAX_STATE_FIELDS],
    /// Scratch of [`Self::push_block`]: a fleet block's observed controls.
    observed: [Array<M, f64>; MAX_CONTROL_OBS],
    /// Scratch of [`Self::push_block`]: a fleet block's derived fields
    /// ([`fdm_run::model::agent::LaneAgent::block_tail_values`]).
    tail: [Array<M, f64>; crate::models::MAX_BLOCK_FIELDS],
    model: PhantomData<M>,
}

impl<'p, 'a, M: BindModel> Observer<'p, 'a, M> {
    fn new(args: &'p TaskArgs<'p>, piece: &'p mut Piece<'a>) -> Self {
        Self {
            args,
            piece,
            block: task::Block::default(),
            states: [M::initial_state(); task::BLOCK],
            arch: pulp::Arch::new(),
            steps: [0; task::BLOCK],
            first: 0,
            len: 0,
            columns: core::array::from_fn(|_| zeros::<M>()),
            observed: core::array::from_fn(|_| zeros::<M>()),
            tail: core::array::from_fn(|_| zeros::<M>()),
            model: PhantomData,
        }
    }

    /// Aircraft `j` of the piece, `steps` into its episode: its state
    /// columns and status code written, it joins the block (flushed with
    /// the instruction set pulp picks).
    #[inline(always)]
    fn push(
        &mut self,
        j: usize,
        steps: i64,
        state: &M::State,
        flight_status: FlightStatus,
        c: &M::Controls,
    ) {
        let arch = self.arch;
        self.push_by(Dispatch(arch), j, steps, state, flight_status, c);
    }

    /// [`Self::push`] inside a function already compiled for `simd`'s
    /// instruction set.
    #[inline(always)]
    fn push_with<S: pulp::Simd>(
        &mut self,
        simd: S,
        j: usize,
        steps: i64,
        state: &M::State,
        flight_status: FlightStatus,
        c: &M::Controls,
    ) {
        self.push_by(WithSimd(simd), j, steps, state, flight_status, c);
    }

    /// [`Self::push`], the blocks' numbers computed by `run`.
    #[inline(always)]
    fn push_by(
        &mut self,
        run: impl RunFlush + Copy,
        j: usize,
        steps: i64,
        state: &M::State,
        flight_status: FlightStatus,
        c: &M::Controls,
    ) {
        const MAX_FIELDS: usize = 32;
        const MAX_CONTROLS: usize = 8;
        if self.len > 0 && j != self.first + self.len {
            self.flush_by(run);
        }
        if self.len == 0 {
            self.first = j;
        }
        let mut values = [0.0; MAX_FIELDS];
        let values = &mut values[..M::STATE_FIELDS.len()];
        let mut controls = [0.0; MAX_CONTROLS];
        let controls = &mut controls[..M::CONTROL_FIELDS.len()];
        let mut observed = [0.0; MAX_CONTROLS];
        let observed = &mut observed[..M::TASK_CONTROL_OBS];
        M::state_values_head(state, values);
        let piece = &mut *self.piece;
        let head = M::STATE_FIELDS.len() - M::BLOCK_FIELDS;
        for (column, v) in piece.columns.iter_mut().zip(values.iter()).take(head) {
            column[j] = *v;
        }
        piece.status[j] = status_code(flight_status);
        M::control_values(c, controls);
        M::task_control_obs(controls, observed);
        let (l, i) = (self.len, piece.first + j);
        let block = &mut self.block;
        let kinematics = M::task_kinematics(values);
        block.alt_ft[l] = kinematics.altitude_ft;
        block.vz_fps[l] = kinematics.climb_ftps;
        block.vx[l] = kinematics.vx;
        block.vy[l] = kinematics.vy;
        block.target_alt_ft[l] = self.args.target_alt_ft[i];
        block.target_heading_deg[l] = self.args.target_heading_deg[i];
        for (row, v) in block.observed.iter_mut().zip(observed.iter()) {
            row[l] = *v;
        }
        block.airborne[l] = flight_status == FlightStatus::Airborne;
        if M::BLOCK_FIELDS > 0 {
            self.states[l] = *state;
        }
        self.steps[l] = steps;
        self.len += 1;
        if self.len == task::BLOCK {
            self.flush_by(run);
        }
    }

    /// The piece's aircraft `j0..j0 + count`, lanes `0..count` of a block
    /// of the fleet (`steps` the piece's step counts), read a block at a
    /// time ([`fdm_run::model::agent::LaneAgent`]): their state columns and status codes written,
    /// and their observations, rewards and flags, [`task::BLOCK`] lanes at
    /// a time ([`flush_lanes`] of a block of its own, with `simd`; the
    /// lanes [`Self::push`] gathered before are flushed first): what
    /// [`Self::push`] of each and [`Self::flush`] give, bit for bit.
    #[inline(always)]
    fn push_block<S: pulp::Simd>(
        &mut self,
        simd: S,
        j0: usize,
        count: usize,
        block: &Block<M>,
        steps: &[i64],
    ) {
        self.flush_with(simd);
        let head = M::STATE_FIELDS.len() - M::BLOCK_FIELDS;
        let (columns, observed) = (&mut self.columns, &mut self.observed);
        M::block_state_values(block, count, &mut columns[..head]);
        M::block_control_obs(&block.controls, count, observed);
        let piece = &mut *self.piece;
        for (column, values) in piece.columns.iter_mut().zip(&columns[..head]) {
            copy_lanes(&mut column[j0..], values.as_ref(), count, M::Fleet::lanes());
        }
        if M::BLOCK_FIELDS > 0 && !piece.columns.is_empty() {
            // The derived fields from the block's lanes too (not each lane's
            // state at the flushes).
            let tail = &mut self.tail;
            M::block_tail_values(block, count, tail);
            for (column, values) in piece.columns[head..].iter_mut().zip(&tail[..]) {
                copy_lanes(&mut column[j0..], values.as_ref(), count, M::Fleet::lanes());
            }
        }
        let statuses = &block.status.as_ref()[..count];
        for (code, status) in piece.status[j0..j0 + count].iter_mut().zip(statuses) {
            *code = status_code(*status);
        }
        let mut kinematics: [Array<M, f64>; 4] = core::array::from_fn(|_| zeros::<M>());
        M::block_kinematics(&self.columns[..head], &mut kinematics);
        for start in (0..count).step_by(task::BLOCK) {
            let len = (count - start).min(task::BLOCK);
            let (first, i) = (j0 + start, self.piece.first + j0 + start);
            // Every lane of the sub-block (it is within the fleet's block:
            // `task::BLOCK` divides the lanes), whole arrays (lanes past
            // `len` computed along and never written).
            let lanes = |a: &Array<M, f64>| -> [f64; task::BLOCK] {
                core::array::from_fn(|l| a.as_ref()[start + l])
            };
            let mut target_alt_ft = [0.0; task::BLOCK];
            let mut target_heading_deg = [0.0; task::BLOCK];
            copy_lanes(
                &mut target_alt_ft,
                &self.args.target_alt_ft[i..],
                len,
                task::BLOCK,
            );
            copy_lanes(
                &mut target_heading_deg,
                &self.args.target_heading_deg[i..],
                len,
                task::BLOCK,
            );
            // A block of this function's own, not the observer's
            // [`Self::block`]: its arrays can stay in registers from here to
            // the observation (stored into the observer and read back in
            // other widths, they stalled the loads: store forwarding).
            let b = task::Block {
                alt_ft: lanes(&kinematics[0]),
                vz_fps: lanes(&kinematics[1]),
                vx: lanes(&kinematics[2]),
                vy: lanes(&kinematics[3]),
                target_alt_ft,
                target_heading_deg,
                observed: core::array::from_fn(|c| lanes(&self.observed[c])),
                airborne: core::array::from_fn(|l| {
                    block.status.as_ref()[start + l] == FlightStatus::Airborne
                }),
            };
            // The derived fields are written above.
            flush_lanes::<M>(
                WithSimd(simd),
                self.args,
                self.piece,
                &b,
                None,
                first,
                &steps[first..first + len],
            );
        }
    }

    /// The aircraft of `run`, a run of blocks of the fleet whose first
    /// aircraft is the piece's aircraft `offset` (`steps` the piece's step
    /// counts): [`Self::push_block`] of each block, or, for a model that
    /// reads its aircraft one at a time
    /// ([`fdm_run::model::agent::LaneAgent::BLOCK_READS`] false),
    /// [`Self::push_with`] of each aircraft, each state read once.
    #[inline(always)]
    fn observe_run<S: pulp::Simd>(
        &mut self,
        simd: S,
        offset: usize,
        run: &FleetPiece<'_, M>,
        steps: &[i64],
    ) {
        if M::BLOCK_READS {
            for (j0, count, block) in run.blocks() {
                self.push_block(simd, offset + j0, count, block, steps);
            }
        } else {
            for (j0, count, block) in run.blocks() {
                for l in 0..count {
                    let (status, c) = (block.status.as_ref()[l], &block.controls.as_ref()[l]);
                    let j = offset + j0 + l;
                    self.push_with(simd, j, steps[j], &block.state(l), status, c);
                }
            }
        }
    }

    /// The block's outputs (the lanes past `len` hold earlier aircraft or
    /// the default block: computed along, never written), with the
    /// instruction set pulp picks.
    #[inline(always)]
    fn flush(&mut self) {
        let arch = self.arch;
        self.flush_by(Dispatch(arch));
    }

    /// [`Self::flush`] inside a function already compiled for `simd`'s
    /// instruction set.
    #[inline(always)]
    fn flush_with<S: pulp::Simd>(&mut self, simd: S) {
        self.flush_by(WithSimd(simd));
    }

    /// [`Self::flush`], the block's numbers computed by `run`, the model's
    /// [`ColumnModel::block_fields`](fdm_run::model::columns::ColumnModel::block_fields)
    /// of the lanes' `states` too ([`Self::push_block`] writes its blocks'
    /// derived fields itself and flushes through [`flush_lanes`]).
    #[inline(always)]
    fn flush_by(&mut self, run: impl RunFlush) {
        let (j0, len) = (self.first, self.len);
        if len == 0 {
            return;
        }
        flush_lanes::<M>(
            run,
            self.args,
            self.piece,
            &self.block,
            Some(&self.states),
            j0,
            &self.steps[..len],
        );
        self.len = 0;
    }
}

/// The outputs of the piece's aircraft `j0..j0 + steps.len()`, lanes
/// `0..steps.len()` of `block` (`steps` their step counts; the lanes past
/// them computed along, never written), the block's numbers computed by
/// `run`; the model's
/// [`ColumnModel::block_fields`](fdm_run::model::columns::ColumnModel::block_fields)
/// of `states` too if given (else they are written already:
/// [`Observer::push_block`]). A function of its parts rather than a method
/// of the [`Observer`], so that [`Observer::push_block`] can pass a block
/// of its own.
#[inline(always)]
fn flush_lanes<M: BindModel>(
    run: impl RunFlush,
    args: &TaskArgs<'_>,
    piece: &mut Piece<'_>,
    block: &task::Block<{ task::BLOCK }>,
    states: Option<&[M::State; task::BLOCK]>,
    j0: usize,
    steps: &[i64],
) {
    let len = steps.len();
    let n_obs = task::KINEMATIC_OBS + M::TASK_CONTROL_OBS;
    let head = M::STATE_FIELDS.len() - M::BLOCK_FIELDS;
    // No columns: the state views are not written.
    let columns = piece.columns.get_mut(head..).unwrap_or_default();
    let ended = &mut piece.terminated[j0..j0 + len];
    run.run(FlushBlock::<M> {
        task: args.task,
        block,
        states,
        columns,
        first: j0,
        out: task::BlockOut {
            obs: &mut piece.obs[j0 * n_obs..(j0 + len) * n_obs],
            reward: &mut piece.reward[j0..j0 + len],
            ended,
        },
    });
    // An episode ended by status is the block's aircraft not airborne (what
    // `observe_block` wrote as `terminated`), read from the block rather
    // than from the bytes just written (a vector load of single-byte stores
    // cannot be forwarded and stalled).
    for ((truncated, airborne), steps) in piece.truncated[j0..j0 + len]
        .iter_mut()
        .zip(&block.airborne)
        .zip(steps)
    {
        *truncated = *steps >= args.max_steps && *airborne;
    }
}

/// How [`Observer::flush_by`] runs a block's numbers (a trait with an
/// always-inlined method, not a closure: a closure may be compiled as a
/// function of its own, without the caller's instruction set).
trait RunFlush {
    /// Computes `block`.
    fn run<M: BindModel>(self, block: FlushBlock<'_, '_, M>);
}

/// With the instruction set pulp picks, through its dispatch.
#[derive(Clone, Copy)]
struct Dispatch(pulp::Arch);

impl RunFlush for Dispatch {
    #[inline(always)]
    fn run<M: BindModel>(self, block: FlushBlock<'_, '_, M>) {
        self.0.dispatch(block);
    }
}

/// Inline, inside a function already compiled for `S`'s instruction set.
#[derive(Clone, Copy)]
struct WithSimd<S>(S);

impl<S: pulp::Simd> RunFlush for WithSimd<S> {
    #[inline(always)]
    fn run<M: BindModel>(self, block: FlushBlock<'_, '_, M>) {
        pulp::WithSimd::with_simd(block, self.0);
    }
}

/// One block's numbers, computed with the instruction set pulp picked:
/// the model's [`ColumnModel::block_fields`](fdm_run::model::columns::ColumnModel::block_fields) written into their columns
/// (rows `first..` of each), and [`crate::task::observe_block`]. Every
/// operation is correctly rounded and none is fused, so the instruction
/// set cannot change a bit (as fdm-fleet's kernels).
struct FlushBlock<'x, 'c, M: BindModel> {
    task: task::Task,
    block: &'x task::Block<{ task::BLOCK }>,
    /// The lanes' states, whose block fields to compute and write (`None`:
    /// written already).
    states: Option<&'x [M::State; task::BLOCK]>,
    columns: &'x mut [&'c mut [f64]],
    first: usize,
    out: task::BlockOut<'x>,
}

impl<M: BindModel> pulp::WithSimd for FlushBlock<'_, '_, M> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let len = self.out.reward.len();
        let views = !self.columns.is_empty();
        if let Some(states) = self.states.filter(|_| M::BLOCK_FIELDS > 0 && views) {
            let mut fields = [[0.0; task::BLOCK]; crate::models::MAX_BLOCK_FIELDS];
            M::block_fields(states, &mut fields);
            for (column, values) in self.columns.iter_mut().zip(&fields) {
                column[self.first..self.first + len].copy_from_slice(&values[..len]);
            }
        }
        task::observe_block(
            self.task,
            M::GROUND_MPS_PER_SPEED,
            self.block,
            M::TASK_CONTROL_OBS,
            self.out,
        );
    }
}

/// The start and control keyword arguments of `Fleet(...)` and
/// `Fleet.reset(...)`, read and range-checked for `n` aircraft.
///
/// # Errors
/// TypeError/ValueError naming the argument.
pub fn read_arguments(
    controls_fields: &[ControlRange],
    model: &str,
    n: usize,
    start: [(&str, Option<&Bound<'_, PyAny>>); 3],
    trim: bool,
    kwargs: Option<&Bound<'_, pyo3::types::PyDict>>,
) -> PyResult<(StartColumns, ControlColumns)> {
    let limits = [
        (0.0, crate::start::MAX_ALTITUDE_FT),
        (0.0, crate::start::MAX_SPEED_KT),
        (
            -crate::start::MAX_HEADING_DEG,
            crate::start::MAX_HEADING_DEG,
        ),
    ];
    let mut cols: [Option<Column>; 3] = [None, None, None];
    for (k, (name, obj)) in start.into_iter().enumerate() {
        if let Some(obj) = obj.filter(|o| !o.is_none()) {
            let c = Column::extract(obj, name, n)?;
            c.check_range(name, limits[k].0, limits[k].1)?;
            cols[k] = Some(c);
        }
    }
    let [altitude_ft, speed_kt, heading_deg] = cols;
    let mut controls = Vec::new();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let Some(index) = controls_fields.iter().position(|c| c.0 == key) else {
                let known: Vec<&str> = controls_fields.iter().map(|c| c.0).collect();
                return Err(to_py((
                    true,
                    format!(
                        "{key}: not a control of {model} (controls: {})",
                        known.join(", ")
                    ),
                )));
            };
            let (_, lo, hi) = controls_fields[index];
            let c = Column::extract(&value, &key, n)?;
            c.check_range(&key, lo, hi)?;
            controls.push((index, c));
        }
    }
    Ok((
        StartColumns {
            altitude_ft,
            speed_kt,
            heading_deg,
            trim,
        },
        controls,
    ))
}

/// Buffers: the `(fields, n)` state array and the `(n,)` status array, and
/// their read-only views.
pub struct Buffers {
    /// The state columns (written by the binding only).
    pub columns: Py<PyArray2<f64>>,
    /// The status codes (written by the binding only).
    pub status: Py<PyArray1<u8>>,
    /// Read-only view of `columns`.
    pub columns_view: Py<PyAny>,
    /// Read-only view of `status`.
    pub status_view: Py<PyAny>,
}

impl Buffers {
    /// New zeroed buffers for `fields × n`.
    ///
    /// # Errors
    /// NumPy's.
    pub fn new(py: Python<'_>, fields: usize, n: usize) -> PyResult<Self> {
        let columns = PyArray2::<f64>::zeros(py, [fields, n], false);
        let status = PyArray1::<u8>::zeros(py, n, false);
        let read_only = |a: &Bound<'_, PyAny>| -> PyResult<Py<PyAny>> {
            let v = a.call_method0("view")?;
            v.getattr("flags")?.setattr("writeable", false)?;
            Ok(v.unbind())
        };
        Ok(Self {
            columns_view: read_only(columns.as_any())?,
            status_view: read_only(status.as_any())?,
            columns: columns.unbind(),
            status: status.unbind(),
        })
    }

    /// The buffers, borrowed for writing (see [`buffer_slices`]).
    ///
    /// # Errors
    /// If the buffers are borrowed elsewhere in Rust.
    pub fn borrow_mut<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(
        numpy::PyReadwriteArray2<'py, f64>,
        numpy::PyReadwriteArray1<'py, u8>,
    )> {
        Ok((
            self.columns.bind(py).try_readwrite()?,
            self.status.bind(py).try_readwrite()?,
        ))
    }

    /// Runs `f` on the buffers' memory (while the GIL is held or released
    /// by `f`'s caller).
    ///
    /// # Errors
    /// If the buffers are borrowed elsewhere in Rust.
    pub fn with_mut<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut [f64], &mut [u8]) -> R,
    ) -> PyResult<R> {
        let columns = self.columns.bind(py);
        let status = self.status.bind(py);
        let mut c = columns.try_readwrite()?;
        let mut s = status.try_readwrite()?;
        let c = c
            .as_slice_mut()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let s = s
            .as_slice_mut()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(f(c, s))
    }
}

/// The buffers' memory, borrowed by [`Buffers::borrow_mut`].
///
/// # Errors
/// Not contiguous (the buffers always are).
pub fn buffer_slices<'a>(
    columns: &'a mut numpy::PyReadwriteArray2<'_, f64>,
    status: &'a mut numpy::PyReadwriteArray1<'_, u8>,
) -> PyResult<(&'a mut [f64], &'a mut [u8])> {
    Ok((
        columns
            .as_slice_mut()
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
        status
            .as_slice_mut()
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
    ))
}

/// Bytes one aircraft of model `M` takes in a Python fleet: its share of
/// the kernel's blocks, its state columns (float64) and status (one byte)
/// in the NumPy buffers, and its controls while `set_controls` builds the
/// new ones before it sets them.
pub fn bytes_per_aircraft<M: BindModel>() -> u64 {
    let kernel = fdm_fleet::Fleet::<M>::bytes_per_aircraft();
    let buffers = 8 * M::STATE_FIELDS.len() + 1;
    (kernel + buffers + std::mem::size_of::<M::Controls>()) as u64
}

/// Refuses a fleet of `n` aircraft of model `M` that does not fit in
/// `available` bytes, as `sim-cli fleet` refuses one
/// ([`fdm_run::memory::check_fleet`]: twice [`bytes_per_aircraft`] each,
/// for the arrays' growth, and the allocator must grant that much): a
/// clear `MemoryError` at once, rather than a fleet that grows until the
/// machine runs out of memory. `None` available: nothing to check against.
///
/// # Errors
/// MemoryError saying what the fleet needs and the process has.
pub fn check_memory<M: BindModel>(n: usize, available: Option<u64>) -> PyResult<()> {
    fdm_run::memory::check_fleet(M::NAME, n as u64, bytes_per_aircraft::<M>(), available)
        .map_err(|e| PyMemoryError::new_err(e.to_string()))
}

/// Shorthand: a fleet of model `M` boxed.
///
/// # Errors
/// As [`Lanes::new`].
pub fn new_lanes<M: BindModel>(
    n: usize,
    fps: f64,
    precision: Precision,
    parallel: bool,
    start: &StartColumns,
    controls: &ControlColumns,
) -> PyResult<Box<dyn AnyFleet>>
where
    M::Fleet: Sync,
{
    Ok(Box::new(Lanes::<M>::new(
        n, fps, precision, parallel, start, controls,
    )?))
}

/// The model's name, for messages.
pub fn model_name<M: Model>() -> &'static str {
    M::NAME
}
