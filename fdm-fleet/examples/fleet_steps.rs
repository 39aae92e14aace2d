//! Steps a Palmer fleet for profiling (`perf record`, `valgrind --tool=callgrind`):
//!
//! ```sh
//! cargo run --release -p fdm-fleet --example fleet_steps -- fast 10000 100
//! ```
//!
//! Arguments: `scalar`, `exact`, `fast`, `exact-baseline` or `fast-baseline`
//! (Palmer), `bourg-scalar` or `bourg` (Bourg, 1/30 s steps), `bourg-demo`
//! (Bourg's demonstration fleet, `Model::fleet_member`, as `sim-cli fleet`
//! flies it; prints the aircraft-steps per second) or `bourg-demo-2t` (the
//! same on a 2-thread rayon pool, `par_step`);
//! the number of aircraft; the number of steps; `fly` to fly whole frames
//! with the flight status (`fly`) instead of bare steps (not for the scalar
//! kernels), or, for `bourg-demo` and `bourg-demo-2t`, `frames` to step all
//! the steps in one call of `step_frames_with` (`par_step_frames_with`: each
//! cache-sized run of blocks stepped every time before the next; the same
//! checksum). Prints the instruction set and
//! a checksum of the final positions (so the work cannot be optimised away).

use fdm_core::bourg::{self, Bourg, BourgAction, BourgAircraft, BourgControls, BourgState};
use fdm_core::palmer::{step, Palmer, PalmerAircraft, PalmerControls, PalmerState};
use fdm_fleet::{Fleet, LaneFleet, Precision};

/// Time this thread has spent on a CPU, ns (Linux's `/proc/thread-self/schedstat`):
/// unlike the wall clock, not inflated when other processes take the core.
fn on_cpu_ns() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    text.split_whitespace().next()?.parse().ok()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let what = args.first().map_or("fast", String::as_str);
    let n: usize = args.get(1).map_or(Ok(10_000), |s| s.parse())?;
    let steps: usize = args.get(2).map_or(Ok(100), |s| s.parse())?;
    let cessna = PalmerAircraft::cessna_172();
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 4.0,
        bank_deg: 5.0,
        ..PalmerControls::default()
    };
    let mut start = PalmerState::at_rest();
    start.position_m.z = 500.0;
    start.velocity_mps.x = 40.0;
    let checksum: f64 = if what == "bourg-demo" || what == "bourg-demo-2t" {
        let mut fleet = <Fleet<Bourg> as LaneFleet>::demonstration(n)?;
        println!("instruction set: {}", fleet.instruction_set());
        let dt = 1.0_f32 / 30.0;
        let threads = if what == "bourg-demo" { 1 } else { 2 };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        let fly = args.get(3).is_some_and(|a| a == "fly");
        let frames = args.get(3).is_some_and(|a| a == "frames");
        let run = |fleet: &mut Fleet<Bourg>| match (threads, fly) {
            (1, false) => fleet.step(dt),
            (1, true) => fleet.fly(dt),
            (_, false) => pool.install(|| fleet.par_step(dt)),
            (_, true) => pool.install(|| fleet.par_fly(dt)),
        };
        run(&mut fleet);
        let cpu = on_cpu_ns();
        let start = std::time::Instant::now();
        if frames && threads == 1 {
            fleet.step_frames_with(dt, Precision::Exact, steps)?;
        } else if frames {
            pool.install(|| fleet.par_step_frames_with(dt, Precision::Exact, steps))?;
        } else {
            for _ in 0..steps {
                run(&mut fleet);
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        #[allow(clippy::cast_precision_loss)] // a rate
        let (rate, cpu) = ((n * steps) as f64 / seconds, on_cpu_ns().zip(cpu));
        print!(
            "{:.2} M aircraft-steps/s on {threads} thread(s)",
            rate / 1e6
        );
        #[allow(clippy::cast_precision_loss)] // a rate
        if let (1, Some((after, before))) = (threads, cpu) {
            print!(
                ", {:.2} ns on the CPU per aircraft-step",
                (after - before) as f64 / (n * steps) as f64
            );
        }
        println!();
        fleet.states().map(|s| f64::from(s.position_ft.z)).sum()
    } else if what.starts_with("bourg") {
        let aircraft = BourgAircraft::bourg_default();
        let controls = BourgControls::initial()
            .apply(BourgAction::ThrustUp)
            .apply(BourgAction::PitchUp);
        let dt = 1.0_f32 / 30.0;
        let states: Vec<BourgState> = if what == "bourg-scalar" {
            let mut states = vec![BourgState::initial(); n];
            for _ in 0..steps {
                for s in &mut states {
                    *s = bourg::step(&aircraft, &controls, s, dt);
                }
            }
            states
        } else {
            let mut fleet = Fleet::<Bourg>::new(aircraft)?;
            for _ in 0..n {
                fleet.push(BourgState::initial(), controls);
            }
            for _ in 0..steps {
                fleet.step(dt);
            }
            fleet.states().collect()
        };
        states.iter().map(|s| f64::from(s.position_ft.z)).sum()
    } else if what == "scalar" {
        let mut states = vec![start; n];
        for _ in 0..steps {
            for s in &mut states {
                *s = step(&cessna, &controls, s, 0.1);
            }
        }
        states.iter().map(|s| s.position_m.z).sum()
    } else {
        let (precision, baseline) = match what {
            "exact" => (Precision::Exact, false),
            "fast" => (Precision::Fast, false),
            "exact-baseline" => (Precision::Exact, true),
            "fast-baseline" => (Precision::Fast, true),
            other => return Err(format!("unknown kernel `{other}`").into()),
        };
        let mut fleet = Fleet::<Palmer>::from_states(cessna, vec![(start, controls); n])?;
        println!("instruction set: {}", fleet.instruction_set());
        let fly = args.get(3).is_some_and(|a| a == "fly");
        let cpu = on_cpu_ns();
        for _ in 0..steps {
            match (baseline, fly) {
                (true, false) => fleet.step_baseline_with(0.1, precision)?,
                (true, true) => fleet.fly_baseline_with(0.1, precision)?,
                (false, false) => fleet.step_with(0.1, precision)?,
                (false, true) => fleet.fly_with(0.1, precision)?,
            }
        }
        if let Some((after, before)) = on_cpu_ns().zip(cpu) {
            #[allow(clippy::cast_precision_loss)] // a rate
            let ns = (after - before) as f64 / (n * steps) as f64;
            println!("{ns:.2} ns on the CPU per aircraft-step");
        }
        fleet.states().map(|s| s.position_m.z).sum()
    };
    println!("{what}: {n} aircraft, {steps} steps, checksum {checksum}");
    Ok(())
}
