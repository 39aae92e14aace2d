//! Palmer's step in lanes: the [`LaneModel`] seam a structure-of-arrays fleet
//! flies it through. The physics is [`super::dynamics`]'s `rk4`, the one
//! source of the scalar [`step`](super::step), instantiated with lane vectors.
//!
//! | fleet block | lanes | read by the step | written by the step |
//! |---|---|---|---|
//! | `Vars` | `[vx, x, vy, y, vz, z]`, one [`PalmerLanes`] each | all six | all six |
//! | `Terms` | [`ControlTerms`] of each lane's controls | all | never (set with the controls) |
//! | `Shared` | [`AircraftTerms`] and the aircraft | all | never |

use nalgebra::Vector3;

use super::dynamics::{bank_rad, flaps_lift, rk4, AircraftTerms, ControlParts, ControlTerms};
use super::{AircraftError, Flaps, Palmer, PalmerAircraft, PalmerControls, PalmerState};
use crate::real::{F64s, LaneMask, LaneModel, Maths, Real};

/// Aircraft per block of a Palmer fleet: 8 `f64` lanes (one AVX-512 register,
/// two AVX2 registers or four SSE2 registers).
pub const LANES: usize = 8;

/// The lane vector of a Palmer fleet.
pub type PalmerLanes = F64s<LANES>;

impl LaneModel for Palmer {
    type Lanes = PalmerLanes;
    type Shared = AircraftTerms;
    type Vars = [PalmerLanes; 6];
    type Terms = ControlTerms<PalmerLanes>;
    type AircraftError = AircraftError;
    const HAS_FAST: bool = true;
    /// `3 · 1e150² < f64::MAX`: the airspeed of a state whose components
    /// are all below it cannot overflow.
    const SUSPECT: f64 = 1e150;

    fn check_aircraft(aircraft: &PalmerAircraft) -> Result<(), AircraftError> {
        aircraft.validate()
    }

    fn shared(aircraft: &PalmerAircraft) -> AircraftTerms {
        AircraftTerms::new(aircraft)
    }

    fn idle(aircraft: &PalmerAircraft) -> (Self::Vars, Self::Terms) {
        let at = AircraftTerms::new(aircraft);
        let controls = ControlTerms::new(aircraft, &at, &PalmerControls::default());
        ([F64s::splat_zero(); 6], ControlTerms::splat(&controls))
    }

    #[inline]
    fn state(vars: &Self::Vars, time_s: f64, lane: usize) -> PalmerState {
        let q = |j: usize| vars[j].0[lane];
        PalmerState {
            time_s,
            position_m: Vector3::new(q(1), q(3), q(5)),
            velocity_mps: Vector3::new(q(0), q(2), q(4)),
        }
    }

    #[inline]
    fn set_state(vars: &mut Self::Vars, lane: usize, s: &PalmerState) -> f64 {
        let (p, v) = (&s.position_m, &s.velocity_mps);
        for (field, value) in vars.iter_mut().zip([v.x, p.x, v.y, p.y, v.z, p.z]) {
            field.0[lane] = value;
        }
        s.time_s
    }

    fn set_controls(
        terms: &mut Self::Terms,
        lane: usize,
        aircraft: &PalmerAircraft,
        shared: &AircraftTerms,
        controls: &PalmerControls,
    ) {
        terms.set_lane(lane, &ControlTerms::new(aircraft, shared, controls));
    }

    /// A whole block's terms computed lane-wise: the bank sines and cosines
    /// at once ([`crate::math::sin_cos_lanes`], the bits of the scalar
    /// `sin_cos`) and the rest by [`ControlTerms::from_parts`], the scalar
    /// terms' one source, with lanes.
    /// Always inlined (into a caller with a wider instruction set too).
    #[inline(always)]
    fn set_controls_lanes(
        terms: &mut Self::Terms,
        count: usize,
        aircraft: &PalmerAircraft,
        shared: &AircraftTerms,
        controls: &[PalmerControls; LANES],
    ) {
        if count < LANES {
            for (lane, c) in controls.iter().enumerate().take(count) {
                Self::set_controls(terms, lane, aircraft, shared, c);
            }
            return;
        }
        // Each field's lanes built whole (`from_fn`, not lane by lane into
        // an array read back as a vector: a load that a narrower store must
        // forward stalls).
        let bank_deg = F64s(core::array::from_fn(|l| controls[l].bank_deg));
        let (sin, cos) = crate::math::sin_cos_lanes(bank_rad(bank_deg).0);
        let parts = ControlParts {
            alpha_deg: F64s(core::array::from_fn(|l| controls[l].alpha_deg)),
            flaps_up: LaneMask(core::array::from_fn(|l| controls[l].flaps == Flaps::Up)),
            flaps_lift: F64s(core::array::from_fn(|l| flaps_lift(controls[l].flaps))),
            throttle: F64s(core::array::from_fn(|l| controls[l].throttle)),
            brakes: LaneMask(core::array::from_fn(|l| controls[l].brakes)),
        };
        *terms = ControlTerms::from_parts(aircraft, shared, &parts, (F64s(sin), F64s(cos)));
    }

    #[inline(always)]
    fn step_lanes<F: Maths>(
        aircraft: &PalmerAircraft,
        shared: &AircraftTerms,
        terms: &Self::Terms,
        vars: &Self::Vars,
        dt: f64,
    ) -> Self::Vars {
        rk4::<PalmerLanes, F>(aircraft, shared, terms, vars, dt)
    }

    #[inline(always)]
    fn for_each_component(vars: &Self::Vars, f: impl FnMut(PalmerLanes)) {
        vars.iter().copied().for_each(f);
    }

    #[inline(always)]
    fn above_ground(vars: &Self::Vars) -> LaneMask<LANES> {
        vars[5].gt(0.0)
    }

    #[inline]
    fn position_m(state: &PalmerState) -> Vector3<f64> {
        state.position_m
    }

    /// The provided body, written out (and not inlined) so that this
    /// model's fleet kernel is compiled once, in this crate
    /// ([`crate::real::kernel`]).
    #[cfg(feature = "std")]
    fn run_blocks(
        blocks: &mut [crate::real::kernel::Block<Self>],
        aircraft: &Self::Aircraft,
        shared: &Self::Shared,
        dt: Self::TimeStep,
        arch: pulp::Arch,
        fast: bool,
        fly: bool,
    ) {
        crate::real::kernel::run_blocks::<Self>(blocks, aircraft, shared, dt, arch, fast, fly);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of every lane as bits (`-0.0` and `0.0` differ).
    fn bits(t: &ControlTerms<PalmerLanes>) -> [[u64; LANES]; 7] {
        [
            t.cos_w,
            t.sin_w,
            t.cl_without_ground_effect,
            t.half_cl_without_ground_effect,
            t.half_cd_without_ground_effect,
            t.throttle,
            t.wheel_friction,
        ]
        .map(|field| field.0.map(f64::to_bits))
    }

    fn controls() -> [PalmerControls; LANES] {
        core::array::from_fn(|l| PalmerControls {
            throttle: 0.1 * l as f64,
            alpha_deg: l as f64 - 2.0,
            bank_deg: 11.0 * l as f64 - 30.0,
            flaps: [Flaps::Up, Flaps::Deg20, Flaps::Deg40][l % 3],
            brakes: l % 2 == 1,
        })
    }

    /// The block path and the lane-by-lane path write the same bits, and a
    /// partial block (`count < LANES`, the fleet's last block) leaves the
    /// lanes past `count` as they were: they belong to no aircraft.
    #[test]
    fn block_controls_are_the_lane_by_lane_bits_and_stop_at_count() {
        let aircraft = PalmerAircraft::cessna_172();
        let shared = AircraftTerms::new(&aircraft);
        let controls = controls();
        let (_, idle) = Palmer::idle(&aircraft);
        for count in 0..=LANES {
            let mut block = idle;
            Palmer::set_controls_lanes(&mut block, count, &aircraft, &shared, &controls);
            let mut by_lane = idle;
            for (lane, c) in controls.iter().enumerate().take(count) {
                Palmer::set_controls(&mut by_lane, lane, &aircraft, &shared, c);
            }
            assert_eq!(bits(&block), bits(&by_lane), "count {count}");
        }
    }
}
