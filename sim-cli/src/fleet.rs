//! `sim-cli fleet`: many aircraft of one model flown headless through fdm-ecs,
//! to measure how many this machine can fly.
//!
//! The fleet is spawned into an fdm-ecs [`Simulation`] (each aircraft a full
//! entity, as `sim-cli palmer`/`bourg` would spawn it), then the
//! EquationsOfMotion system runs `frames` times at 30 frames per second:
//! in parallel on a rayon pool of `threads` threads
//! ([`equations_of_motion_parallel`]), or on this thread when `threads` is 1
//! ([`equations_of_motion_sequential`]). Only those frames are timed; after
//! each, untimed, the FlightStatus system ([`flight_status`]) updates every
//! aircraft's status and ground contact, so each aircraft ends as
//! [`fdm_core::model::fly`] leaves it. With `--kernel lanes` the
//! structure-of-arrays kernels ([`LaneFleet::par_fly`]) fly the same frames,
//! status included (it is part of their timed frame). The
//! other systems (keyboard input, FlightGear packets) are per-aircraft I/O
//! that a headless fleet does not need, so the figure is the model's
//! throughput through the ECS: the same quantity as the `fleet` criterion
//! benchmark (`benches/fleet.rs`), which flies the very same fleets
//! (each model's [`Model::fleet_member`]).
//!
//! The report gives aircraft-steps per second, how many aircraft that
//! throughput could keep at 30 Hz (steps/s ÷ 30), and how many aircraft end
//! in each flight status ([`StatusCounts`]).
//!
//! With `--dis` every aircraft is also published as a DIS entity after every
//! frame ([`fdm_run::dis::FleetDis`]; the time that takes is reported apart, in
//! `dis.publish_seconds`), and `--realtime` paces the frames at 1/30 s of
//! wall-clock time.

use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;
use fdm_core::model::{FlightStatus, Model};
use fdm_ecs::components::{FrameInput, Params};
use fdm_ecs::systems::{
    equations_of_motion_parallel, equations_of_motion_sequential, flight_status,
};
use fdm_ecs::{Execution, FleetOutputs, Resources, Simulation};
use serde::Serialize;

use crate::args::{FleetArgs, FleetKernel, FleetPrecision};
use crate::error::CliError;
use crate::models::{CliModel, WithModel};
use crate::pacer::FramePacer;
use crate::progress::StderrProgress;
use crate::report::RealtimeReport;
use fdm_fleet::{LaneFleet, Precision};
use fdm_run::acmi::AcmiWriter;
use fdm_run::dis::{DisReport, FleetDis};

/// The frame rate the fleet flies at and the one "could fly" refers to.
pub use crate::args::FLEET_FPS;

/// Aircraft spawned between two progress updates.
const SPAWN_CHUNK: usize = 50_000;

/// Spawns `n` aircraft of model `M` (its demonstration fleet,
/// [`Model::fleet_member`]) into a new simulation at [`FLEET_FPS`] with the
/// given execution mode. They only fly ([`FleetOutputs::None`]): the fleet
/// builds no FlightGear packets. On a terminal, stderr shows the progress.
#[must_use]
pub fn spawn_fleet<M: Model>(n: usize, execution: Execution) -> Simulation {
    let resources = Resources::new(f64::from(FLEET_FPS))
        .expect("30 frames per second is valid")
        .with_execution(execution);
    let mut sim = Simulation::new(resources);
    let aircraft = Arc::new(M::default_aircraft());
    let mut progress = StderrProgress::new(n as u64);
    let mut done = 0;
    while done < n {
        let next = (done + SPAWN_CHUNK).min(n);
        sim.spawn_fleet::<M>(&aircraft, done..next, FleetOutputs::None);
        done = next;
        progress.tick(done as u64);
    }
    progress.finish();
    sim
}

/// Spawns `n` aircraft of model `M`, every one starting from the
/// initial-condition options `start` ([`crate::start::start_for`]; with
/// `--trim`, trimmed), flying only ([`FleetOutputs::None`]), into a new
/// simulation at [`FLEET_FPS`]. They share one start (the same place): the
/// fleet measures throughput, not traffic.
///
/// # Errors
/// [`CliError::Usage`] when the model cannot start there.
pub fn spawn_fleet_at<M: Model>(
    n: usize,
    execution: Execution,
    start: &crate::start::StartArgs,
) -> Result<Simulation, CliError> {
    let resources = Resources::new(f64::from(FLEET_FPS))
        .expect("30 frames per second is valid")
        .with_execution(execution);
    let (start, _) =
        crate::start::start_for::<M>(M::default_aircraft(), M::initial_controls(), start)?;
    let aircraft = Arc::new(start.aircraft);
    let mut sim = Simulation::new(resources);
    for _ in 0..n {
        sim.spawn_member::<M>(&aircraft, start.controls, start.state, FleetOutputs::None);
    }
    Ok(sim)
}

/// Bytes one flying-only aircraft of model `M` takes in the world: its
/// components (parameters handle, controls, state, input queue, status) plus
/// hecs's per-entity bookkeeping (the entity id in the archetype and the
/// entity table, measured at about 16 bytes). The estimate the memory check
/// uses; `sim-cli fleet --json` reports the measured figure beside it.
#[must_use]
pub fn estimated_bytes_per_aircraft<M: Model>() -> u64 {
    let components = std::mem::size_of::<Params<M>>()
        + std::mem::size_of::<M::Controls>()
        + std::mem::size_of::<M::State>()
        + std::mem::size_of::<FrameInput<M::Action>>()
        + std::mem::size_of::<FlightStatus>();
    (components + 16) as u64
}

/// Bytes of memory this process can still allocate: the least of the
/// machine's available memory, the address-space limit (`ulimit -v`) less
/// the address space in use and the cgroup's memory limit less its use
/// ([`crate::memory::available_bytes`]); `None` where none is known.
#[must_use]
pub fn available_memory_bytes() -> Option<u64> {
    crate::memory::available_bytes()
}

/// This process's resident memory in bytes (`/proc/self/statm`); `None` where
/// that is not known.
#[must_use]
pub fn resident_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = text.split_whitespace().nth(1)?.parse().ok()?;
    // Linux pages are 4 KiB on the machines this runs on (x86-64, aarch64 default).
    pages.checked_mul(4096)
}

/// Refuses a fleet whose estimate (with room for the world's growth: hecs
/// doubles an archetype's columns as it fills, so up to twice the live size
/// is allocated for a moment) does not fit in the available memory.
///
/// # Errors
/// [`CliError::Usage`] saying how much the fleet needs and the machine has.
pub fn check_memory<M: Model>(n: u64, available: Option<u64>) -> Result<(), CliError> {
    check_fleet_memory(M::NAME, n, estimated_bytes_per_aircraft::<M>(), available)
}

/// Refuses a fleet of `n` aircraft of `model` at `per_aircraft` bytes each
/// when twice that (the arrays double as they grow) exceeds `available`.
fn check_fleet_memory(
    model: &str,
    n: u64,
    per_aircraft: u64,
    available: Option<u64>,
) -> Result<(), CliError> {
    let needed = n.saturating_mul(per_aircraft).saturating_mul(2);
    let refuse = |have: u64, why: &str| {
        CliError::usage(format!(
            "a fleet of {n} {model} aircraft needs about {} MiB ({per_aircraft} bytes each, twice \
             that while the fleet grows); this process has {} MiB available{why}",
            needed / (1024 * 1024),
            have / (1024 * 1024)
        ))
    };
    match available {
        Some(have) if needed > have => Err(refuse(have, "")),
        // The estimate fits: the allocator must also grant that much address
        // space (tried, never touched), or the fleet's own allocations would
        // abort the process instead of this refusal.
        Some(have) if !crate::memory::can_reserve(needed) => {
            Err(refuse(have, ", but the allocator refuses that much"))
        }
        _ => Ok(()),
    }
}

/// What `sim-cli fleet` measured (its `--json` output).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FleetReport {
    /// `"palmer"` or `"bourg"`.
    pub model: &'static str,
    /// `"lanes"` (structure-of-arrays SIMD kernels) or `"ecs"` (one entity per aircraft).
    pub kernel: &'static str,
    /// `"exact"` (bit-identical to the model's step) or `"fast"`.
    pub precision: &'static str,
    /// The instruction set the lanes kernel dispatched to (`null` for `ecs`).
    pub instruction_set: Option<&'static str>,
    /// Aircraft in the fleet.
    pub aircraft: u64,
    /// Frames flown (each aircraft stepped once per frame).
    pub frames: u64,
    /// Threads of the rayon pool (1: the sequential system on the main thread).
    pub threads: usize,
    /// Wall-clock time of the frames, seconds (spawning excluded).
    pub seconds: f64,
    /// `aircraft × frames / seconds`.
    pub aircraft_steps_per_s: f64,
    /// How many aircraft that throughput keeps at 30 Hz: steps/s ÷ 30, rounded down.
    pub aircraft_at_30hz: u64,
    /// The time step of each frame, seconds (`1/30`; Bourg's in f32, widened).
    pub dt_s: f64,
    /// Memory per aircraft, bytes: the estimate the memory check used.
    pub estimated_bytes_per_aircraft: u64,
    /// Memory per aircraft, bytes, measured as the growth of the resident set
    /// while the fleet was spawned (`null` where it cannot be read).
    pub measured_bytes_per_aircraft: Option<f64>,
    /// Aircraft whose state became non-finite during the run: from that
    /// frame on they are skipped (no longer stepped), and counted here instead
    /// of stopping the fleet (the same number as `statuses.diverged`).
    pub diverged: u64,
    /// How many aircraft end the run in each flight status.
    pub statuses: StatusCounts,
    /// DIS output, with `--dis`: every aircraft is published after every
    /// frame; that time is in `dis.publish_seconds`, not in `seconds`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dis: Option<DisReport>,
    /// Real-time pacing, with `--realtime`: frames that missed their deadline.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub realtime: Option<RealtimeReport>,
}

impl FleetReport {
    /// The human-readable summary (two lines).
    #[must_use]
    pub fn summary(&self) -> String {
        format!(
            "{} fleet: {} aircraft x {} frames on {} thread{} in {:.3} s\n\
             {:.2} M aircraft-steps/s: this machine could fly {} {} aircraft at 30 Hz",
            self.model,
            self.aircraft,
            self.frames,
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            self.seconds,
            self.aircraft_steps_per_s / 1e6,
            self.aircraft_at_30hz,
            self.model,
        ) + &if self.diverged > 0 {
            format!("\n{} aircraft diverged and were skipped", self.diverged)
        } else {
            String::new()
        } + &{
            let s = &self.statuses;
            let landed = s.landed_safe + s.landed_rough + s.crashed;
            if landed > 0 {
                format!("\n{landed} aircraft landed ({} crashed)", s.crashed)
            } else {
                String::new()
            }
        } + &self.dis.as_ref().map_or_else(String::new, |d| {
            let publish = d.publish_seconds.unwrap_or(0.0);
            format!("\n{}\ndis  {publish:.3} s publishing", d.summary())
        })
    }
}

/// How many aircraft of a fleet are in each [`FlightStatus`] (the JSON
/// report's `statuses`, keyed by [`FlightStatus::code`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct StatusCounts {
    /// On the ground, not flown yet.
    pub on_ground: u64,
    /// Above the ground plane.
    pub airborne: u64,
    /// Landed safely (and rolling).
    pub landed_safe: u64,
    /// Landed hard (and rolling).
    pub landed_rough: u64,
    /// Crashed: at rest where they came down.
    pub crashed: u64,
    /// Diverged: no longer stepped.
    pub diverged: u64,
}

impl StatusCounts {
    /// The counts of `statuses`.
    pub fn of(statuses: impl IntoIterator<Item = FlightStatus>) -> Self {
        use fdm_core::model::LandingState;
        let mut counts = Self::default();
        for status in statuses {
            let count = match status {
                FlightStatus::OnGround => &mut counts.on_ground,
                FlightStatus::Airborne => &mut counts.airborne,
                FlightStatus::Landed(LandingState::Safe) => &mut counts.landed_safe,
                FlightStatus::Landed(LandingState::Rough) => &mut counts.landed_rough,
                FlightStatus::Landed(LandingState::Crash) => &mut counts.crashed,
                FlightStatus::Diverged => &mut counts.diverged,
            };
            *count += 1;
        }
        counts
    }
}

/// [`measure`] for the model the arguments name.
struct Measure<'a>(&'a FleetArgs);

impl WithModel for Measure<'_> {
    type Output = Result<FleetReport, CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        // The first DIS failure, once, on stderr; never fatal.
        let mut warn = |m: &str| eprintln!("{}", crate::run::link_warning(m));
        match self.0.kernel {
            FleetKernel::Lanes => measure_lanes::<M>(self.0, &mut warn),
            FleetKernel::Ecs => measure_model::<M>(self.0, &mut warn),
        }
    }
}

/// Flies the fleet and measures it.
///
/// # Errors
/// [`CliError::Usage`] if the fleet does not fit this machine's address
/// space; [`CliError::Runtime`] if the thread pool cannot be built.
pub fn measure(args: &FleetArgs) -> Result<FleetReport, CliError> {
    args.model.with(Measure(args))
}

/// `--dis` settings, checked before anything is spawned: entity numbers for
/// the whole fleet must exist.
fn dis_settings(args: &FleetArgs) -> Result<Option<fdm_run::dis::DisSettings>, CliError> {
    let settings = args.dis.common.settings()?;
    if let Some(s) = &settings {
        fdm_run::dis::fleet_identity(
            s.site,
            s.application,
            args.dis.entity_base,
            args.aircraft - 1,
        )?;
    }
    Ok(settings)
}

/// Waits for the end of the frame when `pacer` paces.
fn pace(pacer: Option<&mut FramePacer>) {
    if let Some(pacer) = pacer {
        let sleep = pacer.finish_frame(Instant::now());
        if !sleep.is_zero() {
            std::thread::sleep(sleep);
        }
    }
}

fn new_pacer(args: &FleetArgs) -> Option<FramePacer> {
    args.show
        .realtime
        .then(|| FramePacer::new(FramePacer::period_for(FLEET_FPS), Instant::now()))
}

fn measure_model<M: CliModel>(
    args: &FleetArgs,
    warn: &mut dyn FnMut(&str),
) -> Result<FleetReport, CliError> {
    if args.precision == FleetPrecision::Fast {
        return Err(CliError::usage(
            "--precision fast needs --kernel lanes \
             (--kernel ecs flies every aircraft with the model's own exact step)",
        ));
    }
    let dis_settings = dis_settings(args)?;
    let n = usize::try_from(args.aircraft)
        .map_err(|_| CliError::usage(format!("{} aircraft do not fit in memory", args.aircraft)))?;
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from));
    let execution = if threads == 1 {
        Execution::Sequential
    } else {
        Execution::Parallel
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("building the thread pool")?;
    check_memory::<M>(args.aircraft, available_memory_bytes())?;
    let before = resident_bytes();
    let mut sim = if args.start.is_thesis() {
        spawn_fleet::<M>(n, execution)
    } else {
        spawn_fleet_at::<M>(n, execution, &args.start)?
    };
    let after = resident_bytes();
    #[allow(clippy::cast_precision_loss)] // a ratio of byte counts
    let measured_bytes_per_aircraft = before
        .zip(after)
        .map(|(b, a)| a.saturating_sub(b) as f64 / args.aircraft as f64);
    let mut dis = match &dis_settings {
        Some(s) => Some(FleetDis::attach::<M>(
            sim.world_mut(),
            s,
            args.dis.entity_base,
        )?),
        None => None,
    };
    let mut pacer = new_pacer(args);
    let origin = sim.resources().origin;
    let mut acmi = crate::acmi::create(
        args.acmi.acmi.as_deref(),
        args.acmi.acmi_reference_time.as_ref(),
        M::NAME,
        FLEET_FPS,
        &origin,
        &[],
    )?;
    let entities: Vec<_> = if acmi.is_some() {
        sim.world().iter().map(|e| e.entity()).collect()
    } else {
        Vec::new()
    };
    let write_acmi = |acmi: &mut Option<AcmiWriter>, sim: &Simulation, flown| match acmi {
        Some(w) => w
            .fleet_frame::<M>(
                flown,
                &origin,
                entities
                    .iter()
                    .map(|&e| sim.view::<M>(e).zip(sim.status(e))),
            )
            .context("--acmi"),
        None => Ok(()),
    };
    write_acmi(&mut acmi, &sim, 0)?;
    // Frames flown: all of them unless a signal stops the run early
    // (crate::signals; checked between frames, or every second of flight).
    let mut frames_flown = 0;
    let seconds = if dis.is_none() && pacer.is_none() && acmi.is_none() {
        let mut seconds = 0.0;
        while frames_flown < args.frames && crate::signals::stop_requested().is_none() {
            let chunk = (args.frames - frames_flown).min(u64::from(FLEET_FPS));
            seconds += fly_frames::<M>(&mut sim, chunk, execution, &pool);
            frames_flown += chunk;
        }
        seconds
    } else {
        // Frame by frame: step, publish, wait for the frame's deadline; only
        // the steps are timed.
        let mut seconds = 0.0;
        for flown in 1..=args.frames {
            if crate::signals::stop_requested().is_some() {
                break;
            }
            frames_flown = flown;
            seconds += fly_frames::<M>(&mut sim, 1, execution, &pool);
            write_acmi(&mut acmi, &sim, flown)?;
            if let Some(dis) = dis.as_mut() {
                let world = sim.world_mut();
                match execution {
                    Execution::Sequential => dis.publish::<M>(world, &origin, false),
                    Execution::Parallel => {
                        pool.install(|| dis.publish::<M>(world, &origin, true));
                    }
                }
                if let Some(message) = dis.take_failure() {
                    warn(&message);
                }
            }
            pace(pacer.as_mut());
        }
        seconds
    };
    if let Some(acmi) = acmi.as_mut() {
        acmi.finish().context("--acmi")?;
    }
    let statuses = StatusCounts::of(sim.world().query::<&FlightStatus>().iter().copied());
    let mut report = report::<M>(
        &FleetArgs {
            frames: frames_flown,
            ..args.clone()
        },
        threads,
        seconds,
        estimated_bytes_per_aircraft::<M>(),
        measured_bytes_per_aircraft,
        None,
        statuses,
    );
    report.dis = dis.map(|d| d.report(FLEET_FPS));
    report.realtime = pacer.map(|p| RealtimeReport {
        overruns: p.overruns(),
    });
    Ok(report)
}

/// The lanes kernel's precision for `--precision`.
fn precision(p: FleetPrecision) -> Precision {
    match p {
        FleetPrecision::Exact => Precision::Exact,
        FleetPrecision::Fast => Precision::Fast,
    }
}

/// The fleet flown by model `M`'s structure-of-arrays kernel
/// ([`CliModel::Lanes`]): the same demonstration fleet, the same frames.
fn measure_lanes<M: CliModel>(
    args: &FleetArgs,
    warn: &mut dyn FnMut(&str),
) -> Result<FleetReport, CliError> {
    let dis_settings = dis_settings(args)?;
    if !args.start.is_thesis() {
        return Err(CliError::usage(
            "--altitude-ft, --speed-kt, --heading-deg and --trim need --kernel ecs \
             (the lanes kernel flies the demonstration fleet only)",
        ));
    }
    let n = usize::try_from(args.aircraft)
        .map_err(|_| CliError::usage(format!("{} aircraft do not fit in memory", args.aircraft)))?;
    let precision = precision(args.precision);
    M::Lanes::check_precision(precision)
        .map_err(|e| CliError::usage(format!("--precision: {e}")))?;
    let per_aircraft = M::Lanes::bytes_per_aircraft() as u64;
    check_fleet_memory(
        M::NAME,
        args.aircraft,
        per_aircraft,
        available_memory_bytes(),
    )?;
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("building the thread pool")?;
    let before = resident_bytes();
    let mut fleet = M::Lanes::demonstration(n).map_err(|e| CliError::runtime(e.to_string()))?;
    let after = resident_bytes();
    #[allow(clippy::cast_precision_loss)] // a ratio of byte counts
    let measured_bytes_per_aircraft = before
        .zip(after)
        .map(|(b, a)| a.saturating_sub(b) as f64 / args.aircraft as f64);
    let fps = f64::from(FLEET_FPS);
    let mut dis = match &dis_settings {
        Some(s) => Some(FleetDis::for_lanes::<M>(s, args.dis.entity_base, n)?),
        None => None,
    };
    let mut pacer = new_pacer(args);
    let origin = fdm_ecs::geodesy::GeodeticOrigin::default();
    let mut acmi = crate::acmi::create(
        args.acmi.acmi.as_deref(),
        args.acmi.acmi_reference_time.as_ref(),
        M::NAME,
        FLEET_FPS,
        &origin,
        &[],
    )?;
    let aircraft = M::default_aircraft();
    let write_acmi = |acmi: &mut Option<AcmiWriter>, fleet: &M::Lanes, flown| match acmi {
        Some(w) => w
            .fleet_frame::<M>(
                flown,
                &origin,
                (0..n).map(|i| {
                    let state = fleet.state(i)?;
                    let (controls, _) = M::fleet_member(i);
                    Some((M::view(&aircraft, &controls, &state), fleet.status(i)?))
                }),
            )
            .context("--acmi"),
        None => Ok(()),
    };
    write_acmi(&mut acmi, &fleet, 0)?;
    // Frames flown: all of them unless a signal stops the run early
    // (crate::signals; checked between frames).
    let mut frames_flown = 0;
    let seconds = if dis.is_none() && pacer.is_none() && acmi.is_none() {
        let start = Instant::now();
        pool.install(|| {
            while frames_flown < args.frames && crate::signals::stop_requested().is_none() {
                fleet.par_fly(fps, precision)?;
                frames_flown += 1;
            }
            Ok::<(), fdm_fleet::FleetError>(())
        })
        .map_err(|e| CliError::runtime(e.to_string()))?;
        start.elapsed().as_secs_f64()
    } else {
        let mut seconds = 0.0;
        let mut states = Vec::with_capacity(if dis.is_some() { n } else { 0 });
        for flown in 1..=args.frames {
            if crate::signals::stop_requested().is_some() {
                break;
            }
            frames_flown = flown;
            let start = Instant::now();
            pool.install(|| fleet.par_fly(fps, precision))
                .map_err(|e| CliError::runtime(e.to_string()))?;
            seconds += start.elapsed().as_secs_f64();
            write_acmi(&mut acmi, &fleet, flown)?;
            if let Some(dis) = dis.as_mut() {
                // The kernel's arrays are not shareable across threads; the
                // states are copied out once per frame (a few MB at 100 000).
                // A diverged aircraft is no longer sent, as with the ECS.
                states.clear();
                states.extend((0..n).map(|i| {
                    fleet
                        .state(i)
                        .filter(|_| fleet.status(i) != Some(FlightStatus::Diverged))
                }));
                let states = &states;
                pool.install(|| dis.publish_lanes::<M>(|i| states[i], &origin));
                if let Some(message) = dis.take_failure() {
                    warn(&message);
                }
            }
            pace(pacer.as_mut());
        }
        seconds
    };
    if let Some(acmi) = acmi.as_mut() {
        acmi.finish().context("--acmi")?;
    }
    let statuses = StatusCounts::of((0..fleet.len()).filter_map(|i| fleet.status(i)));
    let mut report = report::<M>(
        &FleetArgs {
            frames: frames_flown,
            ..args.clone()
        },
        threads,
        seconds,
        per_aircraft,
        measured_bytes_per_aircraft,
        Some((precision, fleet.instruction_set())),
        statuses,
    );
    report.dis = dis.map(|d| d.report(FLEET_FPS));
    report.realtime = pacer.map(|p| RealtimeReport {
        overruns: p.overruns(),
    });
    Ok(report)
}

/// The report of a measured fleet (`args.frames`: the frames flown).
fn report<M: Model>(
    args: &FleetArgs,
    threads: usize,
    seconds: f64,
    estimated_bytes_per_aircraft: u64,
    measured_bytes_per_aircraft: Option<f64>,
    lanes: Option<(Precision, &'static str)>,
    statuses: StatusCounts,
) -> FleetReport {
    #[allow(clippy::cast_precision_loss)] // a rate: 53 bits are plenty
    let steps = args.aircraft as f64 * args.frames as f64;
    let aircraft_steps_per_s = steps / seconds;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // floor of a positive rate
    let aircraft_at_30hz = (aircraft_steps_per_s / f64::from(FLEET_FPS)).floor() as u64;
    FleetReport {
        model: M::NAME,
        kernel: if lanes.is_some() { "lanes" } else { "ecs" },
        precision: lanes.map_or("exact", |(p, _)| p.name()),
        instruction_set: lanes.map(|(_, set)| set),
        aircraft: args.aircraft,
        frames: args.frames,
        threads,
        seconds,
        aircraft_steps_per_s,
        aircraft_at_30hz,
        dt_s: M::time_step(f64::from(FLEET_FPS)).into(),
        estimated_bytes_per_aircraft,
        measured_bytes_per_aircraft,
        diverged: statuses.diverged,
        statuses,
        dis: None,
        realtime: None,
    }
}

/// Runs `frames` frames of EquationsOfMotion on the fleet in `sim` (on
/// `pool` when parallel), each followed by the FlightStatus system: what
/// [`measure`] flies. Returns the seconds the EquationsOfMotion frames took
/// (the status updates are not timed).
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

/// `sim-cli fleet`: [`measure`], then the summary or (`--json`) the report
/// as one JSON object on stdout.
///
/// # Errors
/// See [`measure`]; writing to stdout can fail too (exit status 1).
pub fn run(args: &FleetArgs) -> Result<(), CliError> {
    if args.show.fg_mp.is_some() && args.acmi.acmi.is_some() {
        return Err(CliError::usage(
            "--acmi cannot be combined with --fg-mp (fly the fleet without --fg-mp to write it)",
        ));
    }
    if let Some(text) = crate::fleet_mp::run_show(args)? {
        return print_line(&text);
    }
    let report = measure(args)?;
    let text = if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.summary()
    };
    print_line(&text)
}

/// `text` and a newline on stdout.
fn print_line(text: &str) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .context("writing to stdout")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::ModelKind;
    use fdm_core::palmer::{Palmer, PalmerState};

    #[test]
    fn a_small_fleet_reports_consistent_numbers() {
        for (model, threads, kernel) in [
            (ModelKind::Palmer, 2, FleetKernel::Ecs),
            (ModelKind::Bourg, 1, FleetKernel::Ecs),
            (ModelKind::Palmer, 2, FleetKernel::Lanes),
            (ModelKind::Bourg, 1, FleetKernel::Lanes),
        ] {
            let args = FleetArgs {
                model,
                aircraft: 10,
                frames: 3,
                threads: Some(threads),
                kernel,
                precision: FleetPrecision::Exact,
                json: true,
                start: crate::start::StartArgs::default(),
                dis: crate::dis::FleetDisArgs::default(),
                show: crate::args::FleetShowArgs::default(),
                acmi: crate::args::AcmiArgs::default(),
            };
            let report = measure(&args).unwrap();
            assert_eq!(report.model, model.name());
            assert_eq!((report.aircraft, report.frames), (10, 3));
            assert_eq!(report.threads, threads);
            assert!(report.seconds > 0.0);
            let rate = 30.0 / report.seconds;
            assert!((report.aircraft_steps_per_s - rate).abs() <= 1e-9 * rate);
            assert_eq!(
                report.aircraft_at_30hz,
                (report.aircraft_steps_per_s / 30.0).floor() as u64
            );
            assert!(report.summary().contains("aircraft at 30 Hz"));
            assert_eq!(report.statuses.airborne, 10, "{:?}", report.statuses);
            assert_eq!(report.diverged, 0);
        }
    }

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

    /// Each aircraft of the fleet `measure` flies ends where the same member
    /// flown alone, by the core's `fly`, ends, with the same status: bit for
    /// bit, sequential and parallel, both models, both kernels.
    #[test]
    fn each_fleet_member_ends_as_if_flown_alone() {
        fn check<M: CliModel>(execution: Execution, threads: usize) {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (n, frames) = (23, 40);
            let mut sim = spawn_fleet::<M>(n, execution);
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
    fn fleets_that_do_not_fit_are_refused_saying_how_much() {
        let gib = 1024 * 1024 * 1024;
        let err = check_memory::<Palmer>(10_000_000, Some(gib)).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        let message = err.to_string();
        let per = estimated_bytes_per_aircraft::<Palmer>();
        let need_mib = 10_000_000 * per * 2 / (1024 * 1024);
        assert!(
            message.contains(&format!("needs about {need_mib} MiB"))
                && message.contains("has 1024 MiB available"),
            "{message}"
        );
        assert!(check_memory::<Palmer>(1_000, Some(gib)).is_ok());
        // Unknown available memory: nothing to check against.
        assert!(check_memory::<Palmer>(10_000_000, None).is_ok());
        // A lean entity: a few dozen bytes of state and controls, well under
        // the kilobyte a full aircraft with its datagram takes.
        assert!((100..200).contains(&per), "{per}");
    }

    #[test]
    fn a_fleet_can_start_trimmed_in_cruise() {
        let start = crate::start::StartArgs {
            altitude_ft: Some(2000.0),
            speed_kt: Some(100.0),
            heading_deg: None,
            trim: true,
        };
        let mut sim = spawn_fleet_at::<Palmer>(3, Execution::Sequential, &start).unwrap();
        let res = *sim.resources();
        for _ in 0..30 {
            equations_of_motion_sequential::<Palmer>(sim.world_mut(), &res);
        }
        for s in sim.world().query::<&PalmerState>().iter() {
            assert!((s.position_m.z - 609.6).abs() < 0.01, "{s:?}");
        }
        let bad = crate::start::StartArgs {
            speed_kt: Some(20.0),
            ..start
        };
        let err = spawn_fleet_at::<Palmer>(3, Execution::Sequential, &bad).unwrap_err();
        assert_eq!(err.exit_code(), 2);
    }

    #[test]
    fn the_fleet_really_flies() {
        let mut sim = spawn_fleet::<Palmer>(4, Execution::Parallel);
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
}
