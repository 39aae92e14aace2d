//! DIS traffic of a Palmer fleet: PDUs and bytes per second for N aircraft
//! cruising, in steady turns, and manoeuvring, with dead reckoning (DRM(R,V,W)
//! and DRM(F,P,W), the default thresholds 1 m / 3° / 5 s) and without (a PDU
//! every frame). It counts what `sim-cli fleet --dis` would send, through the
//! same code (`fdm_run::dis` and `fdm_dis::Tracker`: placement on WGS-84, rates from
//! consecutive frames, fdm-dis's publisher), without a socket: the count is
//! the traffic, the sending is measured separately (`benches/dis_publish.rs`).
//!
//! ```sh
//! cargo run --release -p afit-fdm-cli --example dis_traffic -- [AIRCRAFT] [WARMUP_S] [WINDOW_S] [SCENARIO|MODE...]
//! ```
//!
//! SCENARIO: `cruise`, `turns`, `manoeuvre` (default all); MODE: `rvw`,
//! `fpw`, `every` (default all).
//!
//! Defaults: 100 000 aircraft, 5 s of warm-up (the first PDU of every
//! aircraft and the start-up transient are not counted), a 30 s window, at
//! 30 frames per second, the fleet's default origin; all scenarios. One JSON
//! line per scenario and mode on stdout.
//!
//! Scenarios (aircraft `i` starts as `Palmer::fleet_member(i)`: 500 m up,
//! 45–54 m/s, throttle 0.5–1, alpha 2–6°, flaps up or 20°):
//!
//! * `cruise`: wings level (bank 0), controls held: straight, steady flight;
//! * `turns`: the demonstration fleet as `sim-cli fleet` flies it, banks
//!   from −10° to 10° held: 20 of 21 aircraft in steady turns;
//! * `manoeuvre`: continuous S-turns and pitching: bank 20°·sin(2π(t/40 s + i/97)),
//!   alpha the member's + 2°·sin(2π(t/25 s + i/89)), set every frame.

use std::f64::consts::TAU;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerControls};
use fdm_dis::{DisVersion, DrThresholds, EntityIdentity, SendReason};
use fdm_dis::{DrAlgorithm as DrChoice, Placement, Tracker};
use fdm_run::dis::{callsign, fleet_identity, DisSettings, ReasonCounts};
use rayon::prelude::*;

const FPS: u32 = 30;

#[derive(Clone, Copy, Debug)]
enum Scenario {
    Cruise,
    Turns,
    Manoeuvre,
}

impl Scenario {
    fn name(self) -> &'static str {
        match self {
            Self::Cruise => "cruise",
            Self::Turns => "turns",
            Self::Manoeuvre => "manoeuvre",
        }
    }

    fn controls(self, i: usize, base: PalmerControls, t: f64) -> PalmerControls {
        match self {
            Self::Cruise => PalmerControls {
                bank_deg: 0.0,
                ..base
            },
            Self::Turns => base,
            Self::Manoeuvre => {
                let (a, b) = (i as f64 / 97.0, i as f64 / 89.0);
                PalmerControls {
                    bank_deg: 20.0 * (TAU * (t / 40.0 + a)).sin(),
                    alpha_deg: base.alpha_deg + 2.0 * (TAU * (t / 25.0 + b)).sin(),
                    ..base
                }
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Mode {
    Dr(DrChoice),
    EveryFrame,
}

#[derive(Default, Clone, Copy)]
struct Count {
    pdus: u64,
    bytes: u64,
    reasons: ReasonCounts,
}

impl Count {
    fn add(mut self, o: Self) -> Self {
        self.pdus += o.pdus;
        self.bytes += o.bytes;
        self.reasons.first += o.reasons.first;
        self.reasons.position += o.reasons.position;
        self.reasons.orientation += o.reasons.orientation;
        self.reasons.heartbeat += o.reasons.heartbeat;
        self
    }
}

fn settings(mode: Mode) -> DisSettings {
    let (dr, every_frame) = match mode {
        Mode::Dr(dr) => (dr, false),
        Mode::EveryFrame => (DrChoice::Rvw, true),
    };
    DisSettings {
        // Never used: nothing is sent here.
        target: "127.0.0.1:3000".parse().expect("an address"),
        site: 1,
        application: 1,
        exercise: 1,
        version: DisVersion::V7,
        dr,
        thresholds: DrThresholds::default(),
        every_frame,
    }
}

/// Flies aircraft `i` for `frames` frames; counts the PDUs due after `warmup` frames.
fn fly(i: usize, scenario: Scenario, s: &DisSettings, frames: u64, warmup: u64) -> Count {
    let placement = Placement::new(GeodeticOrigin::default());
    let aircraft = Palmer::default_aircraft();
    let (base, mut state) = Palmer::fleet_member(i);
    let id: EntityIdentity = fleet_identity(1, 1, 1, i as u64).expect("in range");
    let mut tracker: Tracker = s
        .tracker::<Palmer>(id, &callsign("C172", i as u64 + 1))
        .expect("valid");
    let dt = Palmer::time_step(f64::from(FPS));
    let mut count = Count::default();
    for frame in 1..=frames {
        let controls = scenario.controls(i, base, state.time_s);
        state = Palmer::step(&aircraft, &controls, &state, dt);
        let view = Palmer::view(&aircraft, &controls, &state);
        if let Ok(Some(due)) = tracker.update(&view, &placement) {
            if frame > warmup {
                count.pdus += 1;
                count.bytes += due.bytes.len() as u64;
                match due.reason {
                    SendReason::First | SendReason::ClockReset => count.reasons.first += 1,
                    SendReason::PositionError => count.reasons.position += 1,
                    SendReason::OrientationError => count.reasons.orientation += 1,
                    SendReason::Heartbeat => count.reasons.heartbeat += 1,
                }
            }
        }
    }
    count
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |k: usize, default: f64| {
        args.get(k)
            .and_then(|a| a.parse::<f64>().ok())
            .unwrap_or(default)
    };
    let n = number(0, 100_000.0) as usize;
    let warmup_s = number(1, 5.0);
    let window_s = number(2, 30.0);
    let mut scenarios: Vec<Scenario> = args
        .iter()
        .skip(3)
        .filter_map(|a| match a.as_str() {
            "cruise" => Some(Scenario::Cruise),
            "turns" => Some(Scenario::Turns),
            "manoeuvre" => Some(Scenario::Manoeuvre),
            _ => None,
        })
        .collect();
    if scenarios.is_empty() {
        scenarios = vec![Scenario::Cruise, Scenario::Turns, Scenario::Manoeuvre];
    }
    let warmup = (warmup_s * f64::from(FPS)).round() as u64;
    let frames = warmup + (window_s * f64::from(FPS)).round() as u64;
    let mut modes: Vec<Mode> = args
        .iter()
        .skip(3)
        .filter_map(|a| match a.as_str() {
            "rvw" => Some(Mode::Dr(DrChoice::Rvw)),
            "fpw" => Some(Mode::Dr(DrChoice::Fpw)),
            "every" => Some(Mode::EveryFrame),
            _ => None,
        })
        .collect();
    if modes.is_empty() {
        modes = vec![
            Mode::Dr(DrChoice::Rvw),
            Mode::Dr(DrChoice::Fpw),
            Mode::EveryFrame,
        ];
    }
    for scenario in scenarios {
        for &mode in &modes {
            let s = settings(mode);
            let start = std::time::Instant::now();
            let c = (0..n)
                .into_par_iter()
                .map(|i| fly(i, scenario, &s, frames, warmup))
                .reduce(Count::default, Count::add);
            let wall = start.elapsed().as_secs_f64();
            let window = (frames - warmup) as f64 / f64::from(FPS);
            let line = serde_json::json!({
                "scenario": scenario.name(),
                "mode": match mode { Mode::Dr(d) => d.label(), Mode::EveryFrame => "every frame" },
                "aircraft": n,
                "fps": FPS,
                "window_s": window,
                "pdus": c.pdus,
                "bytes": c.bytes,
                "pdus_per_s": c.pdus as f64 / window,
                "bytes_per_s": c.bytes as f64 / window,
                "pdus_per_aircraft_per_s": c.pdus as f64 / window / n as f64,
                "reasons": c.reasons,
                "wall_s": wall,
            });
            println!("{line}");
        }
    }
}
