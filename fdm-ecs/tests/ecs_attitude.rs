//! The placement Place computes, and the datagram the run library's
//! FlightGear output makes from it (`fgnet::bridge::packet_at`), follow
//! `docs/cli.md`: heading
//! clockwise from true north equal to the direction of travel over the ground,
//! roll positive right wing down, pitch positive nose up. Checked through the
//! ECS for both models against quantities computed from the successive
//! geodetic positions it produces (Karney's geodesics from geographiclib-rs
//! for the direction of travel), not from the model frame.

use fdm_core::bourg::Bourg;
use fdm_core::palmer::Palmer;
use std::sync::Arc;

use fdm_core::bourg::ops::quat_from_euler_deg;
use fdm_core::bourg::{BourgAction, BourgAircraft, BourgControls, BourgState, Vector3};
use fdm_core::palmer::{PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
use fdm_core::script::Script;
use fdm_ecs::components::{Attitude, Geodetic};
use fdm_ecs::geodesy::{ground_track_deg, palmer_attitude, GeodeticOrigin, WGS84_A_M, WGS84_F};
use fdm_ecs::{Entity, Resources, Simulation};
use fgnet::FgNetFdm;
use geographiclib_rs::{Geodesic, InverseGeodesic};

/// Signed difference of two angles in degrees, in (-180, 180].
fn angle_diff_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 {
        d - 360.0
    } else {
        d
    }
}

/// Direction of travel over the ground between two geodetic positions, at
/// their middle: the mean of the geodesic's azimuths at either end (Karney's
/// inverse problem on WGS-84), degrees in [0, 360).
fn travel_bearing_deg(a: Geodetic, b: Geodetic) -> f64 {
    let (azi1, azi2, _): (f64, f64, f64) =
        Geodesic::wgs84().inverse(a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg);
    let (s, c) = (
        azi1.to_radians().sin() + azi2.to_radians().sin(),
        azi1.to_radians().cos() + azi2.to_radians().cos(),
    );
    s.atan2(c).to_degrees().rem_euclid(360.0)
}

/// Flight-path angle between two nearby geodetic positions, degrees: height
/// change over the horizontal distance (the local radii of curvature of
/// WGS-84 at their mean latitude).
fn climb_angle_deg(a: Geodetic, b: Geodetic) -> f64 {
    let lat = (0.5 * (a.lat_deg + b.lat_deg)).to_radians();
    let e2 = WGS84_F * (2.0 - WGS84_F);
    let w = (1.0 - e2 * lat.sin().powi(2)).sqrt();
    let h = 0.5 * (a.alt_m + b.alt_m);
    let north = (WGS84_A_M * (1.0 - e2) / (w * w * w) + h) * (b.lat_deg - a.lat_deg).to_radians();
    let east = (WGS84_A_M / w + h) * lat.cos() * angle_diff_deg(b.lon_deg, a.lon_deg).to_radians();
    (b.alt_m - a.alt_m).atan2(north.hypot(east)).to_degrees()
}

/// The heading in a datagram, degrees in [0, 360).
fn packet_heading_deg(packet: &FgNetFdm) -> f64 {
    f64::from(packet.psi).to_degrees().rem_euclid(360.0)
}

/// The datagram FlightGear is sent for `e` (a Palmer or a Bourg aircraft):
/// made from its view and this frame's placement, as `fdm_run`'s FlightGear
/// output makes it.
fn packet(sim: &Simulation, e: Entity) -> FgNetFdm {
    let view = sim
        .view::<Palmer>(e)
        .or_else(|| sim.view::<Bourg>(e))
        .unwrap();
    let origin = sim.resources().origin;
    fgnet::bridge::packet_at(
        &view,
        &origin,
        sim.geodetic(e).unwrap(),
        sim.attitude(e).unwrap(),
    )
}

/// Per frame (index 0 = frame 1) and entity: position, attitude, packet.
type History = Vec<Vec<(Geodetic, Attitude, FgNetFdm)>>;

fn fly(sim: &mut Simulation, entities: &[Entity], frames: usize) -> History {
    (0..frames)
        .map(|_| {
            sim.run_frame();
            entities
                .iter()
                .map(|&e| {
                    (
                        sim.geodetic(e).unwrap(),
                        sim.attitude(e).unwrap(),
                        packet(sim, e),
                    )
                })
                .collect()
        })
        .collect()
}

/// A Bourg state flying towards compass heading `heading_deg` (wings level,
/// nose along the velocity): the original's initial state turned about the
/// vertical.
fn bourg_heading(heading_deg: f32) -> BourgState {
    let mut s = BourgState::initial();
    // The model's yaw is positive to the left of north.
    s.orientation = quat_from_euler_deg(&Vector3::new(0.0, 0.0, -heading_deg));
    let (sin, cos) = heading_deg.to_radians().sin_cos();
    s.velocity_ftps = Vector3::new(s.speed_ftps() * cos, -s.speed_ftps() * sin, 0.0); // y is west
    s
}

#[test]
fn heading_sent_is_the_direction_of_travel_over_the_ground() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let cessna = Arc::new(PalmerAircraft::cessna_172());
    let bourg = Arc::new(BourgAircraft::bourg_default());

    // Palmer: wings level, zero angle of attack (nose along the velocity),
    // fast enough to fly nearly level; 50 km east of the origin, where model
    // north differs from true north by 0.375°, and 50 km north-west.
    let palmer_cases = [
        (30.0_f64, [0.0, -50_000.0, 500.0]),
        (200.0, [35_000.0, 35_000.0, 800.0]),
        (350.0, [0.0, -50_000.0, 500.0]),
    ];
    let mut entities: Vec<Entity> = palmer_cases
        .iter()
        .map(|&(heading, position)| {
            let (sin, cos) = heading.to_radians().sin_cos();
            let speed = 79.0;
            sim.spawn::<Palmer>(
                Arc::clone(&cessna),
                PalmerControls {
                    throttle: 1.0,
                    ..PalmerControls::default()
                },
                PalmerState {
                    time_s: 0.0,
                    position_m: position.into(),
                    velocity_mps: [speed * cos, -speed * sin, 0.0].into(),
                },
            )
        })
        .collect();
    // Bourg: its initial state turned to three headings (1.5 km south of the
    // origin; f32 positions in feet limit the precision further out).
    let bourg_headings = [30.0_f32, 250.0, 340.0];
    entities.extend(bourg_headings.iter().map(|&h| {
        sim.spawn::<Bourg>(
            Arc::clone(&bourg),
            BourgControls::initial(),
            bourg_heading(h),
        )
    }));

    let history = fly(&mut sim, &entities, 70);
    for n in (10..=60).step_by(10) {
        for (i, &(heading, _)) in palmer_cases.iter().enumerate() {
            // Central difference over ±1 frame (5 m).
            let bearing = travel_bearing_deg(history[n - 1][i].0, history[n + 1][i].0);
            let (_, attitude, packet) = history[n][i];
            let climb = climb_angle_deg(history[n - 1][i].0, history[n + 1][i].0);
            assert!(climb.abs() < 2.0, "level flight: climb {climb}");
            // Karney's bearing is on the ellipsoid, the aircraft ~1 km above
            // it: they may differ by up to e² h / 2a (2e-5° here).
            let err = angle_diff_deg(attitude.heading_deg, bearing);
            assert!(
                err.abs() < 3e-5,
                "palmer {heading} frame {n}: {attitude:?} vs {bearing}"
            );
            let err = angle_diff_deg(packet_heading_deg(&packet), bearing);
            assert!(
                err.abs() < 1e-4,
                "palmer {heading} frame {n}: packet off by {err}"
            );
            // The model's own track (relative to north at the origin) is not
            // what FlightGear needs here: the correction is being tested.
            let state = sim.state::<Palmer>(entities[i]).unwrap();
            let raw = angle_diff_deg(ground_track_deg(state.velocity_mps), bearing);
            assert!(raw.abs() > 0.2, "raw track off by only {raw}");
        }
        for (j, &heading) in bourg_headings.iter().enumerate() {
            let i = palmer_cases.len() + j;
            // ±6 frames (about 25 ft): f32 positions in feet are coarse.
            let bearing = travel_bearing_deg(history[n - 6][i].0, history[n + 6][i].0);
            let (_, attitude, packet) = history[n][i];
            let err = angle_diff_deg(attitude.heading_deg, bearing);
            assert!(
                err.abs() < 0.01,
                "bourg {heading} frame {n}: {attitude:?} vs {bearing}"
            );
            let err = angle_diff_deg(packet_heading_deg(&packet), bearing);
            assert!(
                err.abs() < 0.01,
                "bourg {heading} frame {n}: packet off by {err}"
            );
        }
    }
}

#[test]
fn positive_roll_is_right_wing_down_and_turns_right() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let palmer = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        },
        PalmerState {
            velocity_mps: [50.0, 0.0, 0.0].into(),
            position_m: [0.0, 0.0, 300.0].into(),
            ..PalmerState::at_rest()
        },
    );
    for _ in 0..10 {
        sim.push_input(palmer, PalmerAction::BankRight).unwrap();
    }
    // Bourg's `roll` reference scenario: climb, then roll right on 247-307.
    let bourg = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
    );
    let script = "1-5 thrust-up\n6-246 pitch-up\n247-307 roll-right\n";
    sim.set_script(
        bourg,
        Arc::new(Script::<BourgAction>::parse(script).unwrap()),
    )
    .unwrap();

    let history = fly(&mut sim, &[palmer, bourg], 420);
    let track = |n: usize, i: usize| travel_bearing_deg(history[n - 2][i].0, history[n + 2][i].0);

    // Palmer banked 10° right: roll sent about +10, and it turns right
    // (clockwise seen from above): the track's compass bearing grows.
    for n in [30, 60, 90, 120] {
        let (_, attitude, packet) = history[n][0];
        assert!(
            attitude.roll_deg > 9.5 && attitude.roll_deg < 10.5,
            "{attitude:?}"
        );
        assert!(packet.phi > 0.0);
        assert!(angle_diff_deg(track(n + 20, 0), track(n, 0)) > 0.5);
    }
    // Flying north from the origin and turning right: it goes east.
    assert!(history[150][0].0.lon_deg > history[0][0].0.lon_deg);

    // Bourg: wings level before the roll, right wing down after it, and
    // then turning right.
    assert!(history[240][1].1.roll_deg.abs() < 0.1);
    let (_, attitude, packet) = history[310][1];
    assert!(attitude.roll_deg > 20.0, "{attitude:?}");
    assert!(packet.phi > 0.0);
    for n in [320, 350, 380] {
        assert!(angle_diff_deg(track(n + 20, 1), track(n, 1)) > 1.0);
    }
}

#[test]
fn positive_pitch_is_nose_up() {
    // Wings level, no sideslip: pitch = flight-path angle + angle of attack.
    // The flight-path angle comes from the geodetic positions; the angle of
    // attack is Palmer's control and Bourg's from its body velocity (the
    // datagram's `alpha`). A reversed pitch sign breaks the identity.
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    let palmer = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        },
        PalmerState {
            velocity_mps: [45.0, 0.0, 0.0].into(),
            position_m: [0.0, 0.0, 300.0].into(),
            ..PalmerState::at_rest()
        },
    );
    // Bourg's `pitch` reference scenario: pitch up all the way.
    let bourg = sim.spawn::<Bourg>(
        Arc::new(BourgAircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
    );
    let script = "1-5 thrust-up\n1-900 pitch-up\n";
    sim.set_script(
        bourg,
        Arc::new(Script::<BourgAction>::parse(script).unwrap()),
    )
    .unwrap();

    let history = fly(&mut sim, &[palmer, bourg], 300);
    let mut bourg_pitch = Vec::new();
    for n in (10..290).step_by(10) {
        // Centred on frame n: RK4 positions sample the path, so frames n ± 2;
        // Bourg's Euler step moves by the new velocity (x_n = x_{n-1} + v_n dt),
        // so the chord from frame n - 3 to n + 2 is the sum of v_{n-2} .. v_{n+2}.
        let palmer_climb = climb_angle_deg(history[n - 2][0].0, history[n + 2][0].0);
        let bourg_climb = climb_angle_deg(history[n - 3][1].0, history[n + 2][1].0);

        let (_, attitude, packet) = history[n][0];
        assert!(attitude.roll_deg.abs() < 0.01);
        let err = attitude.pitch_deg - (palmer_climb + 4.0);
        assert!(
            err.abs() < 1e-3,
            "palmer frame {n}: {attitude:?}, climb {palmer_climb}"
        );
        assert!(packet.theta > 0.0, "nose up in a climb at 4° alpha");

        let (_, attitude, packet) = history[n][1];
        assert!(attitude.roll_deg.abs() < 0.1);
        let alpha_deg = f64::from(packet.alpha).to_degrees();
        let err = attitude.pitch_deg - (bourg_climb + alpha_deg);
        assert!(
            err.abs() < 0.05,
            "bourg frame {n}: {attitude:?}, climb {bourg_climb}, alpha {alpha_deg}"
        );
        bourg_pitch.push(attitude.pitch_deg);
    }
    // Holding pitch-up, the nose ends up well above the horizon.
    assert!(*bourg_pitch.last().unwrap() > 20.0, "{bourg_pitch:?}");
}

#[test]
fn place_rotation_is_the_geodesy_modules_bit_for_bit() {
    // Place reuses the geodetic position it has just computed instead of
    // converting again inside `GeodeticOrigin::model_ned_to_local_ned`.
    let origins = [
        GeodeticOrigin::default(),
        GeodeticOrigin::new(65.0, 25.0, 10.0).unwrap(),
        GeodeticOrigin::new(-33.9, 151.2, 0.0).unwrap(),
        GeodeticOrigin::new(89.9, -179.9, 3000.0).unwrap(),
    ];
    for origin in &origins {
        for i in 0..200 {
            let k = f64::from(i);
            let position_m = Vector3::new(
                (k * 7919.0) % 200_000.0 - 100_000.0,
                (k * 104_729.0) % 200_000.0 - 100_000.0,
                (k * 37.0) % 12_000.0,
            );
            let here = origin.model_to_geodetic(position_m);
            let ours = origin.model_ned_to_local_ned_at(&here);
            let theirs = origin.model_ned_to_local_ned(position_m);
            assert_eq!(
                ours.map(f64::to_bits),
                theirs.map(f64::to_bits),
                "{origin:?} {position_m}"
            );
        }
    }

    // And so the attitude and position in the world are `attitude_at`'s.
    let origin = origins[1];
    let mut sim = Simulation::new(Resources::new(30.0).unwrap().with_origin(origin));
    let controls = PalmerControls {
        throttle: 1.0,
        alpha_deg: 6.0,
        bank_deg: -12.0,
        ..PalmerControls::default()
    };
    let e = sim.spawn::<Palmer>(
        Arc::new(PalmerAircraft::cessna_172()),
        controls,
        PalmerState {
            position_m: [30_000.0, 60_000.0, 900.0].into(),
            velocity_mps: [40.0, -20.0, 3.0].into(),
            ..PalmerState::at_rest()
        },
    );
    sim.run_frames(5);
    let state = sim.state::<Palmer>(e).unwrap();
    let want = origin.attitude_at(
        state.position_m,
        palmer_attitude(state.velocity_mps, controls.alpha_deg, controls.bank_deg),
    );
    assert_eq!(sim.attitude(e).unwrap(), want);
    assert_eq!(
        sim.geodetic(e).unwrap(),
        origin.model_to_geodetic(state.position_m)
    );
}
