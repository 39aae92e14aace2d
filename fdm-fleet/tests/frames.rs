//! The `_frames` methods (`Fleet::step_frames_with`, `fly_frames_with` and
//! their parallel forms), which fly several frames of each cache-sized run of
//! blocks before the next, against as many calls of the one-frame methods
//! over the whole fleet.
//!
//! Tolerance: none. Every aircraft's state (its `Debug` text: every digit,
//! the sign of zeros) and status must be the same, for fleets of several
//! runs of blocks with a partly filled last block, in every precision the
//! model has, with some aircraft near the ground (touchdowns and crashes
//! during the frames).

use fdm_core::bourg::Bourg;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::Palmer;
use fdm_fleet::{Fleet, FleetKernel, LaneFleet, Precision};

/// Every aircraft's state and status, as text.
fn snapshot<M: FleetKernel>(fleet: &Fleet<M>) -> Vec<(String, FlightStatus)> {
    fleet
        .states()
        .zip(fleet.statuses())
        .map(|(s, st)| (format!("{s:?}"), st))
        .collect()
}

/// The model's demonstration fleet of `n` aircraft, every seventh moved
/// down to `height` (model units) so that it reaches the ground during the
/// frames.
fn fleet<M: FleetKernel>(n: usize, lower: impl Fn(&mut M::State)) -> Fleet<M>
where
    Fleet<M>: LaneFleet<Model = M>,
{
    let mut fleet = <Fleet<M> as LaneFleet>::demonstration(n).expect("demonstration fleet");
    for i in (0..n).step_by(7) {
        let mut state = fleet.state(i).expect("in the fleet");
        lower(&mut state);
        fleet.set_state(i, &state).expect("in the fleet");
    }
    fleet
}

/// `frames` frames in one call of each `_frames` method against `frames`
/// calls of its one-frame method, in each precision.
fn check<M: FleetKernel + Model>(fleet: &Fleet<M>, dt: M::TimeStep, frames: usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool");
    for precision in [Precision::Exact, Precision::Fast] {
        if Fleet::<M>::check_precision(precision).is_err() {
            continue;
        }
        type Once<M> = fn(
            &mut Fleet<M>,
            <M as Model>::TimeStep,
            Precision,
        ) -> Result<(), fdm_fleet::FleetError>;
        type Many<M> = fn(
            &mut Fleet<M>,
            <M as Model>::TimeStep,
            Precision,
            usize,
        ) -> Result<(), fdm_fleet::FleetError>;
        let pairs: [(&str, Once<M>, Many<M>); 4] = [
            ("step", Fleet::step_with, Fleet::step_frames_with),
            (
                "par_step",
                Fleet::par_step_with,
                Fleet::par_step_frames_with,
            ),
            ("fly", Fleet::fly_with, Fleet::fly_frames_with),
            ("par_fly", Fleet::par_fly_with, Fleet::par_fly_frames_with),
        ];
        for (name, once, many) in pairs {
            let (mut a, mut b) = (fleet.clone(), fleet.clone());
            pool.install(|| {
                for _ in 0..frames {
                    once(&mut a, dt, precision).expect("precision checked");
                }
                many(&mut b, dt, precision, frames).expect("precision checked");
            });
            assert!(
                snapshot(&a) == snapshot(&b),
                "{name} in {precision:?}: {frames} frames differ"
            );
        }
        // No frame at all.
        let mut c = fleet.clone();
        c.fly_frames_with(dt, precision, 0)
            .expect("precision checked");
        assert!(snapshot(&c) == snapshot(fleet));
    }
}

#[test]
fn several_bourg_frames_in_cache_are_as_many_frames() {
    // 5,003 aircraft: three 256 kB runs of Bourg's blocks, the last block
    // partly filled.
    let fleet = fleet::<Bourg>(5_003, |s| {
        s.position_ft.z = 2.0;
        s.velocity_ftps.z = -30.0;
    });
    check(&fleet, 1.0 / 30.0, 9);
}

#[test]
fn several_palmer_frames_in_cache_are_as_many_frames() {
    // 4,001 aircraft: three 256 kB runs of Palmer's blocks, the last block
    // partly filled; exact and fast maths.
    let fleet = fleet::<Palmer>(4_001, |s| {
        s.position_m.z = 0.5;
        s.velocity_mps.z = -8.0;
    });
    check(&fleet, 0.1, 6);
}
