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
//! ([`palmer_fleet`], [`bourg_fleet`]).
//!
//! The report gives aircraft-steps per second and how many aircraft that
//! throughput could keep at 30 Hz (steps/s ÷ 30).

use std::io::Write;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;
use fdm_core::bourg::{Aircraft, BourgControls, BourgState};
use fdm_core::palmer::{Flaps, PalmerAircraft, PalmerControls, PalmerState};
use fdm_ecs::systems::{equations_of_motion_parallel, equations_of_motion_sequential};
use fdm_ecs::{Execution, Resources, Simulation};
use serde::Serialize;

use crate::args::{FleetArgs, ModelKind};
use crate::error::CliError;

/// The frame rate the fleet flies at and the one "could fly" refers to.
pub const FLEET_FPS: u32 = 30;

/// `n` Palmer aircraft in distinct flying states: throttle 50..100 % in 11
/// steps, alpha 2..6°, bank -10..10°, flaps up or 20°, 45..54 m/s, 500 m up,
/// spaced 10 m apart along x. No two neighbours share all their controls.
#[must_use]
pub fn palmer_fleet(n: usize) -> Vec<(PalmerControls, PalmerState)> {
    (0..n)
        .map(|i| {
            let controls = PalmerControls {
                throttle: 0.5 + small(i % 11) / 20.0,
                alpha_deg: 2.0 + small(i % 5),
                bank_deg: small(i % 21) - 10.0,
                flaps: [Flaps::Up, Flaps::Deg20][i % 2],
            };
            let state = PalmerState {
                time_s: 0.0,
                position_m: [index_m(i, 10.0), 0.0, 500.0].into(),
                velocity_mps: [45.0 + small(i % 10), 0.0, 0.0].into(),
            };
            (controls, state)
        })
        .collect()
}

/// `n` Bourg aircraft in distinct flying states: thrust 500..2500 lb in 21
/// steps, landing flaps down on every third, flying level north at
/// 60..78 ft/s (body velocity set too, so the very first frame has its
/// aerodynamic loads) at 2000..2900 ft, spread 20 ft apart sideways (in rows
/// of 1000).
#[must_use]
pub fn bourg_fleet(n: usize) -> Vec<(BourgControls, BourgState)> {
    (0..n)
        .map(|i| {
            let mut controls = BourgControls::initial();
            controls.thrust_lb = 500.0 + small_f32(i % 21) * 100.0;
            controls.landing_flaps = i % 3 == 0;
            let mut state = BourgState::initial();
            state.position.y = small_f32(i % 1000) * 20.0;
            state.position.z = 2000.0 + small_f32(i % 10) * 100.0;
            state.velocity.x = 60.0 + small_f32(i % 7) * 3.0;
            state.speed = state.velocity.x;
            // Already flying: the body-frame velocity the loads read is the
            // earth-frame one (wings level, heading north). Left at zero, as
            // in `BourgState::initial`, the first frame would have no
            // aerodynamic forces and be much cheaper than the others.
            state.velocity_body = state.velocity;
            (controls, state)
        })
        .collect()
}

/// A small index (below 1000) as f64, exactly.
fn small(i: usize) -> f64 {
    f64::from(u16::try_from(i).expect("index below 1000"))
}

/// A small index (below 1000) as f32, exactly.
fn small_f32(i: usize) -> f32 {
    f32::from(u16::try_from(i).expect("index below 1000"))
}

/// `i * spacing` metres (exact for any fleet that fits in memory).
#[allow(clippy::cast_precision_loss)] // i < 2^53
fn index_m(i: usize, spacing: f64) -> f64 {
    i as f64 * spacing
}

/// Spawns the fleet of `model` with `n` aircraft into a new simulation at
/// [`FLEET_FPS`] with the given execution mode.
#[must_use]
pub fn spawn_fleet(model: ModelKind, n: usize, execution: Execution) -> Simulation {
    let resources = Resources::new(f64::from(FLEET_FPS))
        .expect("30 frames per second is valid")
        .with_execution(execution);
    let mut sim = Simulation::new(resources);
    match model {
        ModelKind::Palmer => {
            let cessna = Arc::new(PalmerAircraft::cessna_172());
            for (controls, state) in palmer_fleet(n) {
                sim.spawn_palmer(Arc::clone(&cessna), controls, state, None);
            }
        }
        ModelKind::Bourg => {
            let aircraft = Arc::new(Aircraft::bourg_default());
            for (controls, state) in bourg_fleet(n) {
                sim.spawn_bourg(Arc::clone(&aircraft), controls, state, None);
            }
        }
    }
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

/// Flies the fleet and measures it.
///
/// # Errors
/// [`CliError::Usage`] if the fleet does not fit this machine's address
/// space; [`CliError::Runtime`] if the thread pool cannot be built.
pub fn measure(args: &FleetArgs) -> Result<FleetReport, CliError> {
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
    let mut sim = spawn_fleet(args.model, n, execution);
    let resources = *sim.resources();
    let world = sim.world_mut();

    let start = Instant::now();
    match execution {
        Execution::Sequential => {
            for _ in 0..args.frames {
                equations_of_motion_sequential(world, &resources);
            }
        }
        Execution::Parallel => pool.install(|| {
            for _ in 0..args.frames {
                equations_of_motion_parallel(world, &resources);
            }
        }),
    }
    let seconds = start.elapsed().as_secs_f64();

    #[allow(clippy::cast_precision_loss)] // a rate: 53 bits are plenty
    let steps = args.aircraft as f64 * args.frames as f64;
    let aircraft_steps_per_s = steps / seconds;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // floor of a positive rate
    let aircraft_at_30hz = (aircraft_steps_per_s / f64::from(FLEET_FPS)).floor() as u64;
    let dt_s = match args.model {
        ModelKind::Palmer => resources.dt_palmer_s(),
        ModelKind::Bourg => f64::from(resources.dt_bourg_s()),
    };
    Ok(FleetReport {
        model: args.model.name(),
        aircraft: args.aircraft,
        frames: args.frames,
        threads,
        seconds,
        aircraft_steps_per_s,
        aircraft_at_30hz,
        dt_s,
    })
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

    #[test]
    fn fleets_are_spread_over_distinct_states() {
        let palmer = palmer_fleet(2310);
        assert_eq!(palmer.len(), 2310);
        // lcm(11, 5, 21, 2) = 2310 distinct control settings, all different.
        let mut controls: Vec<_> = palmer
            .iter()
            .map(|(c, _)| {
                (
                    c.throttle.to_bits(),
                    c.alpha_deg.to_bits(),
                    c.bank_deg.to_bits(),
                    c.flaps,
                )
            })
            .collect();
        controls.sort_by_key(|c| (c.0, c.1, c.2, u8::from(c.3)));
        controls.dedup();
        assert_eq!(controls.len(), 2310);
        assert!(palmer
            .iter()
            .all(|(c, _)| (0.5..=1.0).contains(&c.throttle)));
        assert_eq!(palmer[3].1.position_m.x, 30.0);

        let bourg = bourg_fleet(1000);
        assert!(bourg
            .iter()
            .all(|(c, _)| (500.0..=2500.0).contains(&c.thrust_lb)));
        assert_ne!(bourg[0].1, bourg[1].1);
        assert!(bourg
            .iter()
            .all(|(_, s)| s.speed == s.velocity.x && s.velocity_body == s.velocity));
    }

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

    #[test]
    fn the_fleet_really_flies() {
        let mut sim = spawn_fleet(ModelKind::Palmer, 4, Execution::Parallel);
        let before: Vec<PalmerState> = sim
            .world()
            .query::<&PalmerState>()
            .iter()
            .copied()
            .collect();
        let res = *sim.resources();
        equations_of_motion_parallel(sim.world_mut(), &res);
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
