//! What a fleet run measured, as data: [`FleetReport`] (`sim-cli fleet
//! --json`) and the flight statuses it ends in, [`StatusCounts`].

use fdm_core::model::{FlightStatus, LandingState};
use serde::Serialize;

use crate::pacer::RealtimeReport;

/// What a fleet run measured ([`super::FleetRun::report`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FleetReport {
    /// The model's name, e.g. `"palmer"`.
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
    /// Threads of the rayon pool (1: the ECS kernel's sequential system on
    /// the calling thread).
    pub threads: usize,
    /// Wall-clock time of the frames, seconds (spawning and outputs
    /// excluded; with DIS on the lanes kernel, the steps' share of the
    /// frames, see `dis`).
    pub seconds: f64,
    /// `aircraft × frames / seconds`.
    pub aircraft_steps_per_s: f64,
    /// How many aircraft that throughput keeps at 30 Hz: steps/s ÷ 30, rounded down.
    pub aircraft_at_30hz: u64,
    /// The time step of each frame, seconds (`1/fps`; Bourg's in f32, widened).
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
    /// DIS output (feature `dis`): every aircraft is published after every
    /// frame; that time is in `dis.publish_seconds`, not in `seconds`. On
    /// the lanes kernel each piece of the fleet is published right after
    /// its step: the frames' wall clock is split between `seconds` and
    /// `dis.publish_seconds` in proportion to the threads' time in each
    /// (`dis.step_thread_seconds`, `dis.publish_thread_seconds`).
    #[cfg(feature = "dis")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dis: Option<crate::dis::DisReport>,
    /// Real-time pacing: frames that missed their deadline.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub realtime: Option<RealtimeReport>,
}

impl FleetReport {
    /// The human-readable summary (`sim-cli fleet` without `--json`): two
    /// lines, and one more for each of divergence, landings and DIS.
    #[must_use]
    pub fn summary(&self) -> String {
        let r = self;
        let mut text = format!(
            "{} fleet: {} aircraft x {} frames on {} thread{} in {:.3} s\n\
             {:.2} M aircraft-steps/s: this machine could fly {} {} aircraft at 30 Hz",
            r.model,
            r.aircraft,
            r.frames,
            r.threads,
            if r.threads == 1 { "" } else { "s" },
            r.seconds,
            r.aircraft_steps_per_s / 1e6,
            r.aircraft_at_30hz,
            r.model,
        );
        if r.diverged > 0 {
            text += &format!("\n{} aircraft diverged and were skipped", r.diverged);
        }
        let landed = r.statuses.landed();
        if landed > 0 {
            text += &format!(
                "\n{landed} aircraft landed ({} crashed)",
                r.statuses.crashed
            );
        }
        #[cfg(feature = "dis")]
        if let Some(d) = &r.dis {
            let publish = d.publish_seconds.unwrap_or(0.0);
            text += &format!("\n{}\ndis  {publish:.3} s publishing", d.summary());
        }
        text
    }
}

/// How many aircraft of a fleet are in each [`FlightStatus`] (a fleet
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

    /// Aircraft that came down: landed safely, hard, or crashed.
    #[must_use]
    pub fn landed(&self) -> u64 {
        self.landed_safe + self.landed_rough + self.crashed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_status_is_counted_in_its_own_field() {
        let counts = StatusCounts::of([
            FlightStatus::OnGround,
            FlightStatus::Airborne,
            FlightStatus::Airborne,
            FlightStatus::Landed(LandingState::Safe),
            FlightStatus::Landed(LandingState::Rough),
            FlightStatus::Landed(LandingState::Crash),
            FlightStatus::Diverged,
        ]);
        assert_eq!(
            counts,
            StatusCounts {
                on_ground: 1,
                airborne: 2,
                landed_safe: 1,
                landed_rough: 1,
                crashed: 1,
                diverged: 1,
            }
        );
        assert_eq!(counts.landed(), 3);
    }
}
