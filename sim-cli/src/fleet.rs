//! `sim-cli fleet`: many aircraft of one model flown headless through fdm-ecs,
//! to measure how many this machine can fly.
//!
//! The fleet is spawned into an fdm-ecs [`Simulation`] (each aircraft a full
//! entity, as `sim-cli palmer`/`bourg` would spawn it), then the
//! EquationsOfMotion system runs `frames` times at 30 frames per second:
//! in parallel on a rayon pool of `threads` threads
//! ([`equations_of_motion_parallel`]), or on this thread when `threads` is 1
//! ([`equations_of_motion_sequential`]). Only those frames are timed. The
//! other systems (keyboard input, FlightGear packets) are per-aircraft I/O
//! that a headless fleet does not need, so the figure is the model's
//! throughput through the ECS: the same quantity as the `fleet` criterion
//! benchmark (`benches/fleet.rs`), which flies the very same fleets
//! (each model's [`Model::fleet_member`]).
//!
//! The report gives aircraft-steps per second and how many aircraft that
//! throughput could keep at 30 Hz (steps/s ÷ 30).

use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;
use fdm_core::model::Model;
use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_ecs::{Execution, Resources, Simulation};
use serde::Serialize;

use crate::args::FleetArgs;
use crate::error::CliError;
use crate::models::{CliModel, WithModel};

/// The frame rate the fleet flies at and the one "could fly" refers to.
pub const FLEET_FPS: u32 = 30;

/// Spawns `n` aircraft of model `M` (its demonstration fleet,
/// [`Model::fleet_member`]) into a new simulation at [`FLEET_FPS`] with the
/// given execution mode.
#[must_use]
pub fn spawn_fleet<M: Model>(n: usize, execution: Execution) -> Simulation {
    let resources = Resources::new(f64::from(FLEET_FPS))
        .expect("30 frames per second is valid")
        .with_execution(execution);
    let mut sim = Simulation::new(resources);
    sim.spawn_fleet::<M>(&Arc::new(M::default_aircraft()), n);
    sim
}

/// What `sim-cli fleet` measured (its `--json` output).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FleetReport {
    /// `"palmer"` or `"bourg"`.
    pub model: &'static str,
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
        )
    }
}

/// [`measure`] for the model the arguments name.
struct Measure<'a>(&'a FleetArgs);

impl WithModel for Measure<'_> {
    type Output = Result<FleetReport, CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        measure_model::<M>(self.0)
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

fn measure_model<M: Model>(args: &FleetArgs) -> Result<FleetReport, CliError> {
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
    let (sim, seconds) = fly_fleet::<M>(n, args.frames, execution, &pool);
    let resources = *sim.resources();

    #[allow(clippy::cast_precision_loss)] // a rate: 53 bits are plenty
    let steps = args.aircraft as f64 * args.frames as f64;
    let aircraft_steps_per_s = steps / seconds;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // floor of a positive rate
    let aircraft_at_30hz = (aircraft_steps_per_s / f64::from(FLEET_FPS)).floor() as u64;
    Ok(FleetReport {
        model: M::NAME,
        aircraft: args.aircraft,
        frames: args.frames,
        threads,
        seconds,
        aircraft_steps_per_s,
        aircraft_at_30hz,
        dt_s: resources.time_step::<M>().into(),
    })
}

/// Spawns the fleet of `n` aircraft and runs `frames` frames of
/// EquationsOfMotion on it (on `pool` when parallel): what [`measure`]
/// times. Returns the flown simulation and the seconds the frames took.
fn fly_fleet<M: Model>(
    n: usize,
    frames: u64,
    execution: Execution,
    pool: &rayon::ThreadPool,
) -> (Simulation, f64) {
    let mut sim = spawn_fleet::<M>(n, execution);
    let resources = *sim.resources();
    let world = sim.world_mut();

    let start = Instant::now();
    match execution {
        Execution::Sequential => {
            for _ in 0..frames {
                equations_of_motion_sequential::<M>(world, &resources);
            }
        }
        Execution::Parallel => pool.install(|| {
            for _ in 0..frames {
                equations_of_motion_parallel::<M>(world, &resources);
            }
        }),
    }
    let seconds = start.elapsed().as_secs_f64();
    (sim, seconds)
}

/// `sim-cli fleet`: [`measure`], then the summary or (`--json`) the report
/// as one JSON object on stdout.
///
/// # Errors
/// See [`measure`]; writing to stdout can fail too (exit status 1).
pub fn run(args: &FleetArgs) -> Result<(), CliError> {
    let report = measure(args)?;
    let text = if args.json {
        serde_json::to_string(&report).context("encoding the report")?
    } else {
        report.summary()
    };
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
        for (model, threads) in [(ModelKind::Palmer, 2), (ModelKind::Bourg, 1)] {
            let args = FleetArgs {
                model,
                aircraft: 10,
                frames: 3,
                threads: Some(threads),
                json: true,
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
        }
    }

    /// Each aircraft of the fleet `measure` flies ends where the same member
    /// flown alone, by the core step, ends: bit for bit, sequential and
    /// parallel, both models.
    #[test]
    fn each_fleet_member_ends_as_if_flown_alone() {
        fn check<M: Model>(execution: Execution, threads: usize) {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (n, frames) = (23, 40);
            let (sim, _) = fly_fleet::<M>(n, frames, execution, &pool);
            let fleet: Vec<M::State> = sim.world().query::<&M::State>().iter().copied().collect();
            assert_eq!(fleet.len(), n);
            let aircraft = M::default_aircraft();
            let dt = M::time_step(f64::from(FLEET_FPS));
            for (i, got) in fleet.iter().enumerate() {
                let (controls, mut alone) = M::fleet_member(i);
                let start = alone;
                for _ in 0..frames {
                    alone = M::step(&aircraft, &controls, &alone, dt);
                }
                // Debug prints every float in shortest round-trip form, so
                // equal text is equal bits here.
                assert_eq!(format!("{got:?}"), format!("{alone:?}"), "{} #{i}", M::NAME);
                assert_ne!(format!("{got:?}"), format!("{start:?}"), "{} #{i}", M::NAME);
            }
        }
        for (execution, threads) in [(Execution::Sequential, 1), (Execution::Parallel, 2)] {
            check::<fdm_core::palmer::Palmer>(execution, threads);
            check::<fdm_core::bourg::Bourg>(execution, threads);
        }
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
