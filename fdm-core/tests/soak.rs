//! Soak: one simulated hour of both models at 1, 5, 10, 30 and 100 frames per
//! second with random control inputs, through the model interface's
//! [`fly`] (the step, the ground contact, the divergence check). Every frame
//! ends either with a finite state (and a finite [`FlightView`]) at or above
//! the ground plane, or with the aircraft marked
//! [`FlightStatus::Diverged`], its state the last finite one; nothing else.
//!
//! Cost: one random run per model and frame rate by default (about
//! 1.05 million frames in all). `FDM_SOAK_RUNS=N` runs N random runs per
//! model and frame rate (docs/cli.md "Soak tests").

use fdm_core::bourg::Bourg;
use fdm_core::model::{fly, FlightStatus, Model, ScriptAction};
use fdm_core::palmer::Palmer;
use fdm_core::start::InitialConditions;

/// xorshift64*: deterministic, no extra crate.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// What a run ended with.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// All frames flown, finite.
    Finished,
    /// Diverged at this frame.
    Diverged(u64),
}

/// One simulated hour of `M` at `fps`, from the thesis's start or trimmed in
/// `cruise`, with random held inputs: each frame, a
/// 1 % chance to start holding a random action for 1 to 120 frames (at most
/// four at once, as if several keys were held).
fn soak<M: Model>(fps: u32, seed: u64, cruise: bool) -> Outcome {
    let mut rng = Rng(seed | 1);
    let aircraft = M::default_aircraft();
    let (mut controls, mut state) = if cruise {
        // Trimmed at 3000 ft and 100 kt (both models trim there).
        let ic = InitialConditions::from_feet_knots(3000.0, 100.0, 45.0);
        let t = M::trim(&aircraft, &M::initial_controls(), &ic).expect("trimmable");
        (t.controls, t.state)
    } else {
        (M::initial_controls(), M::initial_state())
    };
    let mut status = FlightStatus::initial(M::height_m(&state));
    let dt = M::time_step(f64::from(fps));
    let mut held: Vec<(M::Action, u64)> = Vec::new();
    let frames = 3600 * u64::from(fps);
    for frame in 1..=frames {
        if held.len() < 4 && rng.below(100) == 0 {
            let all = <M::Action as ScriptAction>::ALL;
            let action = all[usize::try_from(rng.below(all.len() as u64)).unwrap()];
            held.push((action, frame + rng.below(120)));
        }
        held.retain(|&(_, until)| until >= frame);
        controls = M::begin_frame(controls);
        for &(action, _) in &held {
            controls = M::apply(&aircraft, controls, action);
        }
        (state, status) = fly::<M>(&aircraft, &controls, status, &state, dt);
        if status == FlightStatus::Diverged {
            assert!(
                M::is_finite(&state),
                "{} frame {frame}: kept state",
                M::NAME
            );
            return Outcome::Diverged(frame);
        }
        assert!(M::is_finite(&state), "{} {fps} fps frame {frame}", M::NAME);
        let view = M::view(&aircraft, &controls, &state);
        assert!(
            view.is_finite(),
            "{} {fps} fps frame {frame}: {view:?}",
            M::NAME
        );
        assert!(
            M::height_m(&state) >= 0.0,
            "{} {fps} fps frame {frame}",
            M::NAME
        );
    }
    Outcome::Finished
}

fn runs() -> u64 {
    std::env::var("FDM_SOAK_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1)
}

fn soak_all<M: Model>(salt: u64) {
    for (i, fps) in [1_u32, 5, 10, 30, 100].into_iter().enumerate() {
        for run in 0..runs() {
            let seed = salt ^ (u64::from(fps) << 32) ^ run.wrapping_mul(0x9e37_79b9_7f4a_7c15);
            // Alternately from the thesis's start and trimmed in cruise.
            let cruise = (run + i as u64) % 2 == 1;
            let outcome = soak::<M>(fps, seed, cruise);
            println!(
                "{} {fps} fps run {run} (cruise {cruise}): {outcome:?}",
                M::NAME
            );
        }
    }
}

#[test]
fn palmer_one_hour_at_every_frame_rate() {
    soak_all::<Palmer>(0x5041_4c4d);
}

#[test]
fn bourg_one_hour_at_every_frame_rate() {
    soak_all::<Bourg>(0x424f_5552);
}
