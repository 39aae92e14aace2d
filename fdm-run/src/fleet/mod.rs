//! Fleet runs: many aircraft of one model flown together headless, to
//! measure how many this machine can fly, with outputs attached (DIS, Tacview
//! ACMI), or streamed to FlightGear as multiplayer aircraft ([`show`]).
//!
//! A [`FleetScenario`] (model `M`, how many aircraft, frames, frame rate,
//! threads, [`Kernel`] and [`Precision`], start, real-time pacing, DIS)
//! becomes a [`FleetRun`] that a program drives frame by frame
//! ([`FleetRun::step_frame`]) or to the end ([`FleetRun::run_to_end`]), and
//! whose counters are data ([`FleetReport`], [`StatusCounts`]).
//!
//! ```
//! use fdm_core::palmer::Palmer;
//! use fdm_run::fleet::{FleetRun, FleetScenario, Kernel};
//!
//! // 100 Cessnas of the demonstration fleet, one second at 30 frames per
//! // second, one entity each, on this thread.
//! let mut scenario = FleetScenario::new(100, 30);
//! scenario.kernel = Kernel::Ecs;
//! scenario.threads = Some(1);
//! let mut run = FleetRun::<Palmer>::new(scenario, &mut |_done, _total| {})?;
//! run.run_to_end(|| false, |_warning| {})?;
//! run.finish()?;
//! let report = run.report();
//! assert_eq!((report.frames, report.statuses.airborne), (30, 100));
//! # Ok::<(), fdm_run::fleet::FleetError>(())
//! ```
//!
//! Two kernels fly the same demonstration fleet ([`Model::fleet_member`]):
//!
//! * [`Kernel::Ecs`]: every aircraft a flying-only entity of an fdm-ecs
//!   [`Simulation`]. Each frame runs the EquationsOfMotion system on a rayon
//!   pool of `threads` threads ([`equations_of_motion_parallel`]), or on
//!   this thread when `threads` is 1 ([`equations_of_motion_sequential`]).
//!   Only those steps are timed; after each, untimed, the FlightStatus system
//!   ([`flight_status`]) updates every aircraft's status and ground contact,
//!   so each aircraft ends as [`fdm_core::model::fly`] leaves it. The other
//!   systems (keyboard input, FlightGear packets) are per-aircraft I/O a
//!   headless fleet does not need, so the figure is the model's throughput
//!   through the ECS, the quantity of the `fleet` criterion benchmark. Only
//!   this kernel starts elsewhere than the demonstration fleet (every
//!   aircraft at one [`StartOptions`] start, trimmed or not).
//! * [`Kernel::Lanes`]: the model's structure-of-arrays kernel
//!   ([`FleetModel::Lanes`], [`LaneFleet::par_fly`]), status included in its
//!   timed frame, bit-identical to the model's step in [`Precision::Exact`].
//!
//! After every frame the outputs see the fleet: the attached
//! [`FleetOutput`]s ([`FleetRun::attach`]; the Tacview ACMI writer is one)
//! get every aircraft's view and status, the DIS output
//! (feature `dis`, `FleetScenario::dis`) publishes every aircraft as an
//! entity (the time that takes is reported apart), then real-time pacing
//! waits for the frame's end. On the lanes kernel DIS does not wait for
//! the whole frame: each piece of the fleet is published right after its
//! step, on the thread that stepped it, while its states are in that
//! core's cache (`FleetDis::fly_and_publish_lanes`); the frame's wall clock
//! is then split between the steps and DIS in proportion to the time the
//! threads spent in each. Without outputs or pacing
//! [`FleetRun::run_to_end`] flies in chunks of one second of flight, timing
//! only the steps. Before spawning, a fleet that does not fit in this
//! process's memory is refused ([`crate::memory`]).

pub mod output;
pub mod report;
pub mod show;

use std::sync::Arc;
use std::time::Instant;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, Model};
use fdm_ecs::systems::{
    equations_of_motion_parallel, equations_of_motion_sequential, flight_status,
};
use fdm_ecs::{EcsError, Entity, Execution, FleetOutputs, Resources, Simulation};
pub use fdm_fleet::Precision;
use fdm_fleet::{FleetError as KernelError, LaneFleet};

use crate::memory;
pub use crate::memory::MemoryRefused;
use crate::model::FleetModel;
use crate::pacer::FramePacer;
use crate::scenario::{StartOptions, StartRefused};
use output::ViewSource;
pub use output::{FleetFrame, FleetOutput, Views};
pub use report::{FleetReport, StatusCounts};

/// The frame rate fleets fly at by default (`sim-cli fleet`'s), frames per
/// second.
pub const FLEET_FPS: u32 = 30;

/// The frame rate [`FleetReport::aircraft_at_30hz`] refers to, frames per
/// second.
pub const REFERENCE_FPS: u32 = 30;

/// Aircraft spawned between two progress calls.
const SPAWN_CHUNK: usize = 50_000;

/// How a fleet's aircraft are stepped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The model's structure-of-arrays SIMD kernel ([`FleetModel::Lanes`]).
    #[default]
    Lanes,
    /// One hecs entity per aircraft through the EquationsOfMotion system.
    Ecs,
}

impl Kernel {
    /// The report's name: `"lanes"` or `"ecs"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Lanes => "lanes",
            Self::Ecs => "ecs",
        }
    }
}

/// A fleet's DIS output (feature `dis`): the shared settings and the entity
/// number of its first aircraft (aircraft `i` is
/// [`fleet_identity`](crate::dis::fleet_identity)`(…, entity_base, i)`).
#[cfg(feature = "dis")]
#[derive(Debug, Clone, PartialEq)]
pub struct FleetDisConfig {
    /// Target, site, application, exercise, version, dead reckoning.
    pub settings: crate::dis::DisSettings,
    /// Entity number of the first aircraft (1 to 65 533).
    pub entity_base: u16,
}

/// What a fleet run flies.
#[derive(Debug, Clone, PartialEq)]
pub struct FleetScenario {
    /// Aircraft in the fleet (at least 1).
    pub aircraft: u64,
    /// Frames [`FleetRun::run_to_end`] flies.
    pub frames: u64,
    /// Frames per second (1 to [`crate::MAX_FPS`]).
    pub fps: u32,
    /// Threads of the rayon pool stepping the fleet (1: the ECS kernel steps
    /// on the calling thread); `None`: one per available core.
    pub threads: Option<usize>,
    /// How the aircraft are stepped.
    pub kernel: Kernel,
    /// The lanes kernel's precision ([`Kernel::Ecs`] flies
    /// [`Precision::Exact`] only).
    pub precision: Precision,
    /// Where every aircraft starts: the default (no option) is the
    /// demonstration fleet ([`Model::fleet_member`]); any option starts every
    /// aircraft there instead, [`Kernel::Ecs`] only.
    pub start: StartOptions,
    /// Paces the frames at 1/fps s of wall-clock time.
    pub realtime: bool,
    /// Publishes every aircraft over DIS after every frame. A scenario
    /// field, not a [`FleetOutput`]: its entity numbers are checked before
    /// anything is spawned, and the ECS kernel keeps a tracker component on
    /// every aircraft, publishing from the world in parallel batches.
    #[cfg(feature = "dis")]
    pub dis: Option<FleetDisConfig>,
}

impl FleetScenario {
    /// `aircraft` aircraft of the demonstration fleet flying `frames` frames
    /// at [`FLEET_FPS`] on the lanes kernel in [`Precision::Exact`], one
    /// thread per core, headless, no outputs.
    #[must_use]
    pub fn new(aircraft: u64, frames: u64) -> Self {
        Self {
            aircraft,
            frames,
            fps: FLEET_FPS,
            threads: None,
            kernel: Kernel::Lanes,
            precision: Precision::Exact,
            start: StartOptions::default(),
            realtime: false,
            #[cfg(feature = "dis")]
            dis: None,
        }
    }

    /// Checks that the kernel can fly this scenario for model `M`: the ECS
    /// kernel flies exact maths only; the lanes kernel flies the
    /// demonstration fleet only, in a precision its kernel has.
    ///
    /// # Errors
    /// [`FleetError::EcsNeedsExact`], [`FleetError::LanesNeedDemonstration`],
    /// [`FleetError::Precision`].
    pub fn check_kernel<M: FleetModel>(&self) -> Result<(), FleetError> {
        match self.kernel {
            Kernel::Ecs if self.precision != Precision::Exact => Err(FleetError::EcsNeedsExact),
            Kernel::Ecs => Ok(()),
            Kernel::Lanes if !self.start.is_thesis() => Err(FleetError::LanesNeedDemonstration),
            Kernel::Lanes => {
                M::Lanes::check_precision(self.precision).map_err(FleetError::Precision)
            }
        }
    }

    /// The threads the pool gets: [`Self::threads`] or one per core.
    fn thread_count(&self) -> Result<usize, FleetError> {
        threads_or_cores(self.threads)
    }
}

/// `threads`, or one per available core for `None`.
fn threads_or_cores(threads: Option<usize>) -> Result<usize, FleetError> {
    match threads {
        Some(0) => Err(FleetError::NoThreads),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, usize::from)),
    }
}

/// Why a fleet could not be flown.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FleetError {
    /// The ECS kernel was asked for [`Precision::Fast`].
    #[error("the ECS kernel flies every aircraft with the model's own exact step (fast precision needs the lanes kernel)")]
    EcsNeedsExact,
    /// The lanes kernel was asked to start elsewhere than the demonstration fleet.
    #[error("the lanes kernel flies the demonstration fleet only (initial conditions and trim need the ECS kernel)")]
    LanesNeedDemonstration,
    /// The lanes kernel has not this precision.
    #[error(transparent)]
    Precision(KernelError),
    /// No aircraft.
    #[error("a fleet needs at least one aircraft")]
    NoAircraft,
    /// More aircraft than this machine can address.
    #[error("{0} aircraft do not fit in memory")]
    TooMany(u64),
    /// `threads` was 0.
    #[error("a fleet needs at least one thread")]
    NoThreads,
    /// The fleet does not fit in the memory this process can allocate.
    #[error(transparent)]
    Memory(#[from] MemoryRefused),
    /// The frame rate is not one the ECS accepts.
    #[error(transparent)]
    Fps(#[from] EcsError),
    /// The thread pool could not be built.
    #[error("building the thread pool")]
    ThreadPool(#[source] rayon::ThreadPoolBuildError),
    /// The model cannot start where the scenario says.
    #[error(transparent)]
    Start(#[from] StartRefused),
    /// The lanes kernel failed (building the fleet or flying it).
    #[error(transparent)]
    Kernel(KernelError),
    /// The DIS output could not start.
    #[cfg(feature = "dis")]
    #[error(transparent)]
    Dis(#[from] crate::dis::DisError),
    /// An attached output failed (its message, and its cause as
    /// `source()`).
    #[error(transparent)]
    Output(crate::output::OutputError),
    /// Flying or streaming a watched fleet failed.
    #[error(transparent)]
    Multiplayer(#[from] crate::multiplayer::MultiplayerError),
}

/// The aircraft and how they are stepped.
enum Flyer<M: FleetModel> {
    /// Flying-only entities of one world.
    Ecs {
        sim: Box<Simulation>,
        execution: Execution,
        /// The aircraft in the order the outputs number them (filled when
        /// the first output is attached).
        entities: Vec<Entity>,
    },
    /// The model's structure-of-arrays kernel.
    Lanes {
        fleet: M::Lanes,
        precision: Precision,
        /// The demonstration fleet's aircraft (the fleet's views).
        aircraft: M::Aircraft,
        /// Each aircraft's last state DIS published (its screen's memory:
        /// [`crate::dis::FleetDis::fly_and_publish_lanes`]).
        #[cfg(feature = "dis")]
        dis_last: Vec<Option<M::State>>,
    },
}

/// A fleet of model `M` flying: build it from a [`FleetScenario`]
/// ([`FleetRun::new`]), attach outputs, fly it frame by frame or to the end,
/// [`FleetRun::finish`] it and read its [`FleetReport`].
pub struct FleetRun<M: FleetModel> {
    flyer: Flyer<M>,
    pool: rayon::ThreadPool,
    scenario: FleetScenario,
    threads: usize,
    /// Aircraft in the fleet (read by the DIS output only).
    #[cfg_attr(not(feature = "dis"), allow(dead_code))]
    n: usize,
    origin: GeodeticOrigin,
    flown: u64,
    seconds: f64,
    estimated_bytes_per_aircraft: u64,
    measured_bytes_per_aircraft: Option<f64>,
    pacer: Option<FramePacer>,
    outputs: Vec<Box<dyn FleetOutput<M>>>,
    #[cfg(feature = "dis")]
    dis: Option<crate::dis::FleetDis>,
}

impl<M: FleetModel> std::fmt::Debug for FleetRun<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FleetRun")
            .field("model", &M::NAME)
            .field("scenario", &self.scenario)
            .field("threads", &self.threads)
            .field("flown", &self.flown)
            .finish_non_exhaustive()
    }
}

impl<M: FleetModel> FleetRun<M> {
    /// Checks the scenario, refuses a fleet that does not fit in memory
    /// ([`memory::check_fleet`] against [`memory::available_bytes`]), builds
    /// the thread pool, spawns the fleet (calling `progress(done, total)`
    /// with the aircraft spawned so far while the ECS kernel spawns the
    /// demonstration fleet, from `done` = 0), and opens the DIS output. The
    /// real-time clock starts now.
    ///
    /// # Errors
    /// [`FleetError`]: a scenario the kernel cannot fly, a fleet too large,
    /// a start the model refuses, a thread pool or DIS socket that cannot be
    /// made.
    pub fn new(
        scenario: FleetScenario,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<Self, FleetError> {
        if scenario.kernel == Kernel::Ecs {
            scenario.check_kernel::<M>()?;
        }
        if scenario.aircraft == 0 {
            return Err(FleetError::NoAircraft);
        }
        #[cfg(feature = "dis")]
        if let Some(dis) = &scenario.dis {
            let s = &dis.settings;
            crate::dis::fleet_identity(
                s.site,
                s.application,
                dis.entity_base,
                scenario.aircraft - 1,
            )?;
        }
        let n = usize::try_from(scenario.aircraft)
            .map_err(|_| FleetError::TooMany(scenario.aircraft))?;
        let fps = f64::from(scenario.fps);
        let resources = Resources::new(fps)?;
        let before;
        let (flyer, threads, pool, estimated) = match scenario.kernel {
            Kernel::Ecs => {
                let threads = scenario.thread_count()?;
                let pool = thread_pool(threads)?;
                let execution = if threads == 1 {
                    Execution::Sequential
                } else {
                    Execution::Parallel
                };
                let estimated = memory::estimated_bytes_per_aircraft::<M>();
                memory::check_fleet(
                    M::NAME,
                    scenario.aircraft,
                    estimated,
                    memory::available_bytes(),
                )?;
                before = memory::resident_bytes();
                let resources = resources.with_execution(execution);
                let sim = if scenario.start.is_thesis() {
                    spawn_demonstration::<M>(n, resources, progress)
                } else {
                    spawn_at::<M>(n, resources, &scenario.start)?
                };
                let flyer = Flyer::Ecs {
                    sim: Box::new(sim),
                    execution,
                    entities: Vec::new(),
                };
                (flyer, threads, pool, estimated)
            }
            Kernel::Lanes => {
                scenario.check_kernel::<M>()?;
                let estimated = M::Lanes::bytes_per_aircraft() as u64;
                memory::check_fleet(
                    M::NAME,
                    scenario.aircraft,
                    estimated,
                    memory::available_bytes(),
                )?;
                let threads = scenario.thread_count()?;
                let pool = thread_pool(threads)?;
                before = memory::resident_bytes();
                let fleet = M::Lanes::demonstration(n).map_err(FleetError::Kernel)?;
                let flyer = Flyer::Lanes {
                    fleet,
                    precision: scenario.precision,
                    aircraft: M::default_aircraft(),
                    #[cfg(feature = "dis")]
                    dis_last: Vec::new(),
                };
                (flyer, threads, pool, estimated)
            }
        };
        let after = memory::resident_bytes();
        #[allow(clippy::cast_precision_loss)] // a ratio of byte counts
        let measured_bytes_per_aircraft = before
            .zip(after)
            .map(|(b, a)| a.saturating_sub(b) as f64 / scenario.aircraft as f64);
        let origin = match &flyer {
            Flyer::Ecs { sim, .. } => sim.resources().origin,
            Flyer::Lanes { .. } => GeodeticOrigin::default(),
        };
        let mut run = Self {
            flyer,
            pool,
            threads,
            n,
            origin,
            flown: 0,
            seconds: 0.0,
            estimated_bytes_per_aircraft: estimated,
            measured_bytes_per_aircraft,
            pacer: None,
            outputs: Vec::new(),
            #[cfg(feature = "dis")]
            dis: None,
            scenario,
        };
        #[cfg(feature = "dis")]
        run.open_dis()?;
        run.pacer = run
            .scenario
            .realtime
            .then(|| FramePacer::new(FramePacer::period_for(run.scenario.fps), Instant::now()));
        Ok(run)
    }

    /// The DIS output of [`FleetScenario::dis`]: a tracker per aircraft.
    #[cfg(feature = "dis")]
    fn open_dis(&mut self) -> Result<(), FleetError> {
        use crate::dis::FleetDis;
        let Some(config) = &self.scenario.dis else {
            return Ok(());
        };
        self.dis = Some(match &mut self.flyer {
            Flyer::Ecs { sim, .. } => {
                FleetDis::attach::<M>(sim.world_mut(), &config.settings, config.entity_base)?
            }
            Flyer::Lanes { dis_last, .. } => {
                *dis_last = vec![None; self.n];
                FleetDis::for_lanes::<M>(&config.settings, config.entity_base, self.n)?
            }
        });
        Ok(())
    }

    /// The scenario flown.
    #[must_use]
    pub fn scenario(&self) -> &FleetScenario {
        &self.scenario
    }

    /// Where the fleet's earth frame is on WGS-84 (the ACMI header's origin).
    #[must_use]
    pub fn origin(&self) -> GeodeticOrigin {
        self.origin
    }

    /// Frames flown so far.
    #[must_use]
    pub fn flown(&self) -> u64 {
        self.flown
    }

    /// Whether [`FleetScenario::frames`] are flown.
    #[must_use]
    pub fn is_done(&self) -> bool {
        self.flown >= self.scenario.frames
    }

    /// Attaches an output: it is handed the current frame now and every
    /// flown frame after (an ACMI writer: every aircraft's track, numbered
    /// as the fleet is; crashed and diverged aircraft removed), and finished
    /// by [`Self::finish`].
    ///
    /// # Errors
    /// [`FleetError::Output`] when the output fails on the current frame
    /// (it is not attached then).
    pub fn attach(&mut self, output: impl FleetOutput<M> + 'static) -> Result<(), FleetError> {
        if let Flyer::Ecs { sim, entities, .. } = &mut self.flyer {
            if entities.is_empty() {
                *entities = sim.world().iter().map(|e| e.entity()).collect();
            }
        }
        let mut output = Box::new(output);
        output.frame(&self.frame()).map_err(FleetError::Output)?;
        self.outputs.push(output);
        Ok(())
    }

    /// Whether anything happens between frames (outputs, pacing): then
    /// [`Self::run_to_end`] flies frame by frame.
    fn has_outputs(&self) -> bool {
        #[cfg(feature = "dis")]
        if self.dis.is_some() {
            return true;
        }
        self.pacer.is_some() || !self.outputs.is_empty()
    }

    /// Flies one frame (timed), then hands it to the outputs (the attached
    /// [`FleetOutput`]s, then DIS) and with real-time pacing waits for the
    /// frame's end. A lanes fleet's DIS output publishes each piece of the
    /// fleet right after its step instead, within the frame
    /// (`dis::FleetDis::fly_and_publish_lanes`, feature `dis`), before the
    /// attached outputs see it.
    ///
    /// # Errors
    /// [`FleetError::Kernel`] when the lanes kernel fails,
    /// [`FleetError::Output`] when an output fails.
    pub fn step_frame(&mut self) -> Result<(), FleetError> {
        let fps = f64::from(self.scenario.fps);
        match &mut self.flyer {
            Flyer::Ecs { sim, execution, .. } => {
                self.seconds += fly_frames::<M>(sim, 1, *execution, &self.pool);
            }
            #[cfg(feature = "dis")]
            Flyer::Lanes {
                fleet,
                precision,
                dis_last,
                ..
            } if self.dis.is_some() => {
                // Each piece of the fleet is published right after its
                // step, on the thread that stepped it, while its states
                // are in that core's cache.
                if let Some(dis) = self.dis.as_mut() {
                    let origin = &self.origin;
                    self.seconds += self
                        .pool
                        .install(|| {
                            dis.fly_and_publish_lanes::<M>(fleet, fps, *precision, dis_last, origin)
                        })
                        .map_err(FleetError::Kernel)?;
                }
            }
            Flyer::Lanes {
                fleet, precision, ..
            } => {
                let start = Instant::now();
                self.pool
                    .install(|| fleet.par_fly(fps, *precision))
                    .map_err(FleetError::Kernel)?;
                self.seconds += start.elapsed().as_secs_f64();
            }
        }
        self.flown += 1;
        self.write_outputs()?;
        #[cfg(feature = "dis")]
        self.publish_dis();
        if let Some(pacer) = self.pacer.as_mut() {
            pacer.pace();
        }
        Ok(())
    }

    /// Flies the frames left of [`FleetScenario::frames`], asking `stop`
    /// before each frame (or, without outputs and pacing, before each second
    /// of flight) whether to stop early, and handing `warn` each output's
    /// first failure (a DIS send; never fatal).
    ///
    /// # Errors
    /// As [`Self::step_frame`].
    pub fn run_to_end(
        &mut self,
        mut stop: impl FnMut() -> bool + Send,
        mut warn: impl FnMut(&str),
    ) -> Result<(), FleetError> {
        let frames = self.scenario.frames;
        if self.has_outputs() {
            while self.flown < frames {
                if stop() {
                    break;
                }
                self.step_frame()?;
                if let Some(message) = self.take_warning() {
                    warn(&message);
                }
            }
            return Ok(());
        }
        let fps = self.scenario.fps;
        let flown = &mut self.flown;
        match &mut self.flyer {
            Flyer::Ecs { sim, execution, .. } => {
                while *flown < frames && !stop() {
                    let chunk = (frames - *flown).min(u64::from(fps));
                    self.seconds += fly_frames::<M>(sim, chunk, *execution, &self.pool);
                    *flown += chunk;
                }
            }
            Flyer::Lanes {
                fleet, precision, ..
            } => {
                let start = Instant::now();
                let result = self.pool.install(|| {
                    while *flown < frames && !stop() {
                        fleet.par_fly(f64::from(fps), *precision)?;
                        *flown += 1;
                    }
                    Ok(())
                });
                result.map_err(FleetError::Kernel)?;
                self.seconds += start.elapsed().as_secs_f64();
            }
        }
        Ok(())
    }

    /// The first failure of an output since the last call (a DIS send
    /// failure), once; sends are counted, never fatal.
    pub fn take_warning(&mut self) -> Option<String> {
        #[cfg(feature = "dis")]
        if let Some(dis) = self.dis.as_mut() {
            return dis.take_failure();
        }
        None
    }

    /// Completes the outputs (e.g. an ACMI file's last bytes), each once.
    ///
    /// # Errors
    /// [`FleetError::Output`]: the first output that fails (the others are
    /// still finished).
    pub fn finish(&mut self) -> Result<(), FleetError> {
        let mut first = None;
        for mut output in std::mem::take(&mut self.outputs) {
            if let Err(e) = output.finish() {
                first.get_or_insert(e);
            }
        }
        first.map_or(Ok(()), |e| Err(FleetError::Output(e)))
    }

    /// How many aircraft are in each flight status now.
    #[must_use]
    pub fn statuses(&self) -> StatusCounts {
        match &self.flyer {
            Flyer::Ecs { sim, .. } => {
                StatusCounts::of(sim.world().query::<&FlightStatus>().iter().copied())
            }
            Flyer::Lanes { fleet, .. } => {
                StatusCounts::of((0..fleet.len()).filter_map(|i| fleet.status(i)))
            }
        }
    }

    /// What the run measured so far (frames: those flown).
    #[must_use]
    pub fn report(&self) -> FleetReport {
        let s = &self.scenario;
        let lanes = match &self.flyer {
            Flyer::Ecs { .. } => None,
            Flyer::Lanes {
                fleet, precision, ..
            } => Some((*precision, fleet.instruction_set())),
        };
        #[allow(clippy::cast_precision_loss)] // a rate: 53 bits are plenty
        let steps = s.aircraft as f64 * self.flown as f64;
        let aircraft_steps_per_s = steps / self.seconds;
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        // floor of a positive rate
        let aircraft_at_30hz = (aircraft_steps_per_s / f64::from(REFERENCE_FPS)).floor() as u64;
        let statuses = self.statuses();
        FleetReport {
            model: M::NAME,
            kernel: s.kernel.name(),
            precision: lanes.map_or("exact", |(p, _)| p.name()),
            instruction_set: lanes.map(|(_, set)| set),
            aircraft: s.aircraft,
            frames: self.flown,
            threads: self.threads,
            seconds: self.seconds,
            aircraft_steps_per_s,
            aircraft_at_30hz,
            dt_s: M::time_step(f64::from(s.fps)).into(),
            estimated_bytes_per_aircraft: self.estimated_bytes_per_aircraft,
            measured_bytes_per_aircraft: self.measured_bytes_per_aircraft,
            diverged: statuses.diverged,
            statuses,
            #[cfg(feature = "dis")]
            dis: self.dis.as_ref().map(|d| d.report(s.fps)),
            realtime: self.pacer.as_ref().map(FramePacer::report),
        }
    }

    /// The current frame as the outputs see it.
    fn frame(&self) -> FleetFrame<'_> {
        FleetFrame {
            flown: self.flown,
            fps: self.scenario.fps,
            origin: &self.origin,
            source: &self.flyer,
        }
    }

    /// The current frame to every attached output.
    fn write_outputs(&mut self) -> Result<(), FleetError> {
        let frame = FleetFrame {
            flown: self.flown,
            fps: self.scenario.fps,
            origin: &self.origin,
            source: &self.flyer,
        };
        for output in &mut self.outputs {
            output.frame(&frame).map_err(FleetError::Output)?;
        }
        Ok(())
    }

    /// The current frame to the DIS output of an ECS fleet, if there is one
    /// (a lanes fleet's is published with its steps, in
    /// [`Self::step_frame`]).
    #[cfg(feature = "dis")]
    fn publish_dis(&mut self) {
        let Some(dis) = self.dis.as_mut() else {
            return;
        };
        let origin = &self.origin;
        if let Flyer::Ecs { sim, execution, .. } = &mut self.flyer {
            let world = sim.world_mut();
            match execution {
                Execution::Sequential => dis.publish::<M>(world, origin, false),
                Execution::Parallel => {
                    self.pool.install(|| dis.publish::<M>(world, origin, true));
                }
            }
        }
    }
}

impl<M: FleetModel> ViewSource for Flyer<M> {
    fn views(&self) -> Views<'_> {
        match self {
            Self::Ecs { sim, entities, .. } => Box::new(
                entities
                    .iter()
                    .map(|&e| sim.view::<M>(e).zip(sim.status(e))),
            ),
            Self::Lanes {
                fleet, aircraft, ..
            } => Box::new((0..fleet.len()).map(|i| {
                let state = fleet.state(i)?;
                let (controls, _) = M::fleet_member(i);
                Some((M::view(aircraft, &controls, &state), fleet.status(i)?))
            })),
        }
    }
}

/// A rayon pool of `threads` threads.
fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, FleetError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(FleetError::ThreadPool)
}

/// Spawns `n` aircraft of model `M`'s demonstration fleet
/// ([`Model::fleet_member`]) into a new simulation with `resources`. They
/// only fly ([`FleetOutputs::None`]): no FlightGear packets.
fn spawn_demonstration<M: Model>(
    n: usize,
    resources: Resources,
    progress: &mut dyn FnMut(u64, u64),
) -> Simulation {
    let mut sim = Simulation::new(resources);
    let aircraft = Arc::new(M::default_aircraft());
    let total = n as u64;
    progress(0, total);
    let mut done = 0;
    while done < n {
        let next = (done + SPAWN_CHUNK).min(n);
        sim.spawn_fleet::<M>(&aircraft, done..next, FleetOutputs::None);
        done = next;
        progress(done as u64, total);
    }
    sim
}

/// Spawns `n` aircraft of model `M`, every one starting from `start`
/// ([`StartOptions::start`]; trimmed with `trim`), flying only, into a new
/// simulation with `resources`. They share one start (the same place): the
/// fleet measures throughput, not traffic.
fn spawn_at<M: Model>(
    n: usize,
    resources: Resources,
    start: &StartOptions,
) -> Result<Simulation, StartRefused> {
    let (start, _) = start.start::<M>(M::default_aircraft(), M::initial_controls())?;
    let aircraft = Arc::new(start.aircraft);
    let mut sim = Simulation::new(resources);
    for _ in 0..n {
        sim.spawn_member::<M>(&aircraft, start.controls, start.state, FleetOutputs::None);
    }
    Ok(sim)
}

/// Runs `frames` frames of EquationsOfMotion on the fleet in `sim` (on
/// `pool` when parallel), each followed by the FlightStatus system. Returns
/// the seconds the EquationsOfMotion frames took (the status updates are not
/// timed).
fn fly_frames<M: Model>(
    sim: &mut Simulation,
    frames: u64,
    execution: Execution,
    pool: &rayon::ThreadPool,
) -> f64 {
    let resources = *sim.resources();
    let world = sim.world_mut();
    let mut seconds = 0.0;
    for _ in 0..frames {
        let start = Instant::now();
        match execution {
            Execution::Sequential => equations_of_motion_sequential::<M>(world, &resources),
            Execution::Parallel => {
                pool.install(|| equations_of_motion_parallel::<M>(world, &resources));
            }
        }
        seconds += start.elapsed().as_secs_f64();
        flight_status::<M>(world, &resources);
    }
    seconds
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::{Palmer, PalmerState};

    /// Member `i` of the demonstration fleet flown alone for `frames`
    /// frames by the core's whole frame, `fdm_core::model::fly`.
    fn alone<M: Model>(i: usize, frames: u64) -> (M::State, FlightStatus) {
        let aircraft = M::default_aircraft();
        let dt = M::time_step(f64::from(FLEET_FPS));
        let (controls, mut state) = M::fleet_member(i);
        let mut status = FlightStatus::initial(M::height_m(&state));
        for _ in 0..frames {
            (state, status) = fdm_core::model::fly::<M>(&aircraft, &controls, status, &state, dt);
        }
        (state, status)
    }

    fn resources(execution: Execution) -> Resources {
        Resources::new(f64::from(FLEET_FPS))
            .unwrap()
            .with_execution(execution)
    }

    /// Each aircraft of the fleet a run flies ends where the same member
    /// flown alone, by the core's `fly`, ends, with the same status: bit for
    /// bit, sequential and parallel, both models, both kernels.
    #[test]
    fn each_fleet_member_ends_as_if_flown_alone() {
        fn check<M: FleetModel>(execution: Execution, threads: usize) {
            let pool = thread_pool(threads).unwrap();
            let (n, frames) = (23, 40);
            let mut sim = spawn_demonstration::<M>(n, resources(execution), &mut |_, _| {});
            fly_frames::<M>(&mut sim, frames, execution, &pool);
            let fleet: Vec<(M::State, FlightStatus)> = sim
                .world()
                .query::<(&M::State, &FlightStatus)>()
                .iter()
                .map(|(s, f)| (*s, *f))
                .collect();
            assert_eq!(fleet.len(), n);
            let mut lanes = M::Lanes::demonstration(n).unwrap();
            for _ in 0..frames {
                pool.install(|| lanes.par_fly(f64::from(FLEET_FPS), Precision::Exact))
                    .unwrap();
            }
            for (i, got) in fleet.iter().enumerate() {
                let want = alone::<M>(i, frames);
                // Debug prints every float in shortest round-trip form, so
                // equal text is equal bits here.
                assert_eq!(format!("{got:?}"), format!("{want:?}"), "{} #{i}", M::NAME);
                let start = M::fleet_member(i).1;
                assert_ne!(
                    format!("{:?}", got.0),
                    format!("{start:?}"),
                    "{} #{i}",
                    M::NAME
                );
                let lane = (lanes.state(i).unwrap(), lanes.status(i).unwrap());
                assert_eq!(
                    format!("{lane:?}"),
                    format!("{want:?}"),
                    "{} lanes #{i}",
                    M::NAME
                );
            }
        }
        for (execution, threads) in [(Execution::Sequential, 1), (Execution::Parallel, 2)] {
            check::<fdm_core::palmer::Palmer>(execution, threads);
            check::<fdm_core::bourg::Bourg>(execution, threads);
        }
    }

    #[test]
    fn a_fleet_can_start_trimmed_in_cruise() {
        let start = StartOptions {
            altitude_ft: Some(2000.0),
            speed_kt: Some(100.0),
            heading_deg: None,
            trim: true,
        };
        let mut sim = spawn_at::<Palmer>(3, resources(Execution::Sequential), &start).unwrap();
        let res = *sim.resources();
        for _ in 0..30 {
            equations_of_motion_sequential::<Palmer>(sim.world_mut(), &res);
        }
        for s in sim.world().query::<&PalmerState>().iter() {
            assert!((s.position_m.z - 609.6).abs() < 0.01, "{s:?}");
        }
        let bad = StartOptions {
            speed_kt: Some(20.0),
            ..start
        };
        assert!(spawn_at::<Palmer>(3, resources(Execution::Sequential), &bad).is_err());
        // Through a run: the model's refusal, typed.
        let mut scenario = FleetScenario::new(3, 1);
        scenario.kernel = Kernel::Ecs;
        scenario.start = bad;
        assert!(matches!(
            FleetRun::<Palmer>::new(scenario, &mut |_, _| {}),
            Err(FleetError::Start(_))
        ));
    }

    #[test]
    fn the_fleet_really_flies() {
        let mut sim =
            spawn_demonstration::<Palmer>(4, resources(Execution::Parallel), &mut |_, _| {});
        let before: Vec<PalmerState> = sim
            .world()
            .query::<&PalmerState>()
            .iter()
            .copied()
            .collect();
        let res = *sim.resources();
        equations_of_motion_parallel::<Palmer>(sim.world_mut(), &res);
        let after: Vec<PalmerState> = sim
            .world()
            .query::<&PalmerState>()
            .iter()
            .copied()
            .collect();
        assert_eq!(after.len(), 4);
        for (b, a) in before.iter().zip(&after) {
            assert_eq!(a.time_s, 1.0 / 30.0);
            assert!(a.position_m.x > b.position_m.x);
        }
    }

    /// A plugin output sees the frame it is attached at and every flown
    /// frame after, every aircraft each time (either kernel), and is
    /// finished once; its failure stops the run, typed.
    #[test]
    fn outputs_are_plugins() {
        use std::sync::{Arc, Mutex};
        #[derive(Default)]
        struct Seen {
            frames: Vec<(u64, usize, usize)>,
            finished: u32,
        }
        struct Counter(Arc<Mutex<Seen>>, Option<u64>);
        impl FleetOutput<Palmer> for Counter {
            fn frame(&mut self, frame: &FleetFrame<'_>) -> Result<(), crate::OutputError> {
                if Some(frame.flown) == self.1 {
                    return Err("full".into());
                }
                let views: Vec<_> = frame.views().collect();
                let airborne = views
                    .iter()
                    .filter(|v| v.is_some_and(|(_, s)| s == FlightStatus::Airborne))
                    .count();
                let mut seen = self.0.lock().unwrap();
                seen.frames.push((frame.flown, views.len(), airborne));
                Ok(())
            }
            fn finish(&mut self) -> Result<(), crate::OutputError> {
                self.0.lock().unwrap().finished += 1;
                Ok(())
            }
        }
        for kernel in [Kernel::Ecs, Kernel::Lanes] {
            let mut scenario = FleetScenario::new(4, 3);
            scenario.kernel = kernel;
            scenario.threads = Some(1);
            let mut run = FleetRun::<Palmer>::new(scenario.clone(), &mut |_, _| {}).unwrap();
            let seen = Arc::new(Mutex::new(Seen::default()));
            run.attach(Counter(Arc::clone(&seen), None)).unwrap();
            run.run_to_end(|| false, |_| {}).unwrap();
            run.finish().unwrap();
            run.finish().unwrap();
            let seen = seen.lock().unwrap();
            assert_eq!(
                seen.frames,
                [(0, 4, 4), (1, 4, 4), (2, 4, 4), (3, 4, 4)],
                "{kernel:?}"
            );
            assert_eq!(seen.finished, 1);

            let mut run = FleetRun::<Palmer>::new(scenario, &mut |_, _| {}).unwrap();
            run.attach(Counter(Arc::default(), Some(2))).unwrap();
            let err = run.run_to_end(|| false, |_| {}).unwrap_err();
            assert!(matches!(err, FleetError::Output(_)), "{err}");
            assert_eq!((err.to_string(), run.flown()), ("full".to_owned(), 2));
        }
    }

    /// Frame by frame or to the end, a run flies the same fleet: the same
    /// statuses and frame count, and the report's rates follow from its
    /// counts. Scenarios a kernel cannot fly are typed errors.
    #[test]
    fn runs_driven_frame_by_frame_or_to_the_end_agree() {
        for kernel in [Kernel::Ecs, Kernel::Lanes] {
            let mut scenario = FleetScenario::new(10, 5);
            scenario.kernel = kernel;
            scenario.threads = Some(2);
            let mut whole = FleetRun::<Palmer>::new(scenario.clone(), &mut |_, _| {}).unwrap();
            whole.run_to_end(|| false, |_| {}).unwrap();
            whole.finish().unwrap();
            let mut stepped = FleetRun::<Palmer>::new(scenario, &mut |_, _| {}).unwrap();
            while !stepped.is_done() {
                stepped.step_frame().unwrap();
            }
            let (a, b) = (whole.report(), stepped.report());
            assert_eq!((a.frames, b.frames), (5, 5));
            assert_eq!(a.statuses, b.statuses);
            assert_eq!(a.statuses.airborne, 10);
            assert_eq!(a.kernel, kernel.name());
            let rate = 50.0 / a.seconds;
            assert!((a.aircraft_steps_per_s - rate).abs() <= 1e-9 * rate);
        }
        let mut stopped =
            FleetRun::<Palmer>::new(FleetScenario::new(3, 100), &mut |_, _| {}).unwrap();
        let mut asked = 0;
        stopped
            .run_to_end(
                || {
                    asked += 1;
                    asked > 2
                },
                |_| {},
            )
            .unwrap();
        assert_eq!(stopped.flown(), 2);

        let mut fast_ecs = FleetScenario::new(3, 1);
        fast_ecs.kernel = Kernel::Ecs;
        fast_ecs.precision = Precision::Fast;
        assert!(matches!(
            fast_ecs.check_kernel::<Palmer>(),
            Err(FleetError::EcsNeedsExact)
        ));
        let mut lanes_start = FleetScenario::new(3, 1);
        lanes_start.start.trim = true;
        assert!(matches!(
            FleetRun::<Palmer>::new(lanes_start, &mut |_, _| {}),
            Err(FleetError::LanesNeedDemonstration)
        ));
        for (aircraft, threads) in [(0, None), (3, Some(0))] {
            let mut bad = FleetScenario::new(aircraft, 1);
            bad.threads = threads;
            assert!(FleetRun::<Palmer>::new(bad, &mut |_, _| {}).is_err());
        }
    }
}
