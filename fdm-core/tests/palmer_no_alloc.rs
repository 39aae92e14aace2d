//! `step`, `try_step`, the derived flight data, the touchdown detector and the
//! control updates never allocate. This file is its own test binary, so the
//! counting global allocator sees only this binary's allocations; it holds a
//! single test so no other test runs (and allocates) concurrently.
//!
//! The counter is `stats_alloc`'s wrapper around `std::alloc::System`: the
//! workspace forbids `unsafe` code, so a test cannot implement `GlobalAlloc`
//! itself.

use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;

use fdm_core::palmer::{
    step, try_step, Flaps, FlightPhase, PalmerAction, PalmerAircraft, PalmerControls, PalmerState,
};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

fn thousand_frames_allocate_nothing() {
    // The counter does count: a Vec allocates once.
    let region = Region::new(GLOBAL);
    let v = std::hint::black_box(vec![1_u8; 64]);
    assert_eq!(region.change().allocations, 1, "the counter missed a Vec");
    drop(v);

    let cessna = PalmerAircraft::cessna_172();
    let mut controls = PalmerControls {
        throttle: 0.0,
        alpha_deg: 0.0,
        bank_deg: 0.0,
        flaps: Flaps::Up,
        brakes: false,
    };
    let mut state = PalmerState::at_rest();
    let mut phase = FlightPhase::default();
    let mut checksum = 0.0;

    let region = Region::new(GLOBAL);
    for frame in 0..1000 {
        if frame < 20 {
            controls = controls.apply(PalmerAction::ThrottleUp);
        }
        if frame < 4 {
            controls = controls.apply(PalmerAction::AlphaUp);
        }
        if frame == 300 {
            controls = controls.apply(PalmerAction::BankRight);
        }
        // Two steps per frame: one unchecked, one checked.
        state = step(&cessna, &controls, &state, 1.0 / 30.0);
        state = try_step(&cessna, &controls, &state, 1.0 / 30.0).unwrap_or(state);
        let data = state.flight_data();
        let (next_phase, _landing) = phase.update(&state);
        phase = next_phase;
        checksum += data.airspeed_mps + data.compass_heading_deg;
    }
    let stats = region.change();

    assert_eq!(stats.allocations, 0, "{stats:?}");
    assert_eq!(stats.reallocations, 0, "{stats:?}");
    assert_eq!(stats.bytes_allocated, 0, "{stats:?}");
    // The loop did real work (and was not optimised away): 2000 steps of 1/30 s
    // at full power take off and climb.
    assert!(state.position_m.z > 0.0, "{state:?}");
    assert_eq!(phase, FlightPhase::Airborne);
    assert!(checksum.is_finite() && checksum > 0.0);
}

/// Runs without libtest (`harness = false` in the root `Cargo.toml`): libtest's
/// own threads allocate while a test runs (seen as 4 allocations of 900 bytes in
/// total, at random), which a process-wide counter cannot tell apart from the
/// model's. Here the measured code is the only thing running; a failed assertion
/// panics and exits non-zero.
fn main() {
    thousand_frames_allocate_nothing();
    println!("test thousand_frames_allocate_nothing ... ok");
    println!("1 passed, 0 failed");
}
