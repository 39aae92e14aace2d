//! The screened DIS publishing of a lanes fleet (`FleetDis::publish_lanes`
//! over `FleetPublisher::publish_screened` and `palmer_rough` or
//! `bourg_rough`) against the
//! path it replaced (`FleetPublisher::publish` of every aircraft's full
//! view): the same datagrams, byte for byte, frame by frame, over loopback
//! UDP, for Palmer's and Bourg's fleets; Palmer's rough attitude matrices
//! within their tolerance and Bourg's the view's own.

use std::net::UdpSocket;

use fdm_core::bourg::{ops, Bourg, BourgState, Quaternion};
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerState};
use fdm_dis::{
    DisVersion, DrAlgorithm, DrThresholds, FleetPublisher, Placement, Rough, UdpSender,
    ROUGH_TOLERANCE,
};
use fdm_fleet::{LaneFleet, Precision};
use fdm_run::dis::{callsign, fleet_identity, DisSettings};
use fdm_run::fleet::{FleetDisConfig, FleetRun, FleetScenario};
use fdm_run::model::bourg::bourg_rough;
use fdm_run::model::palmer::palmer_rough;
use fdm_run::FleetModel;
use nalgebra::Vector3;

/// Every datagram waiting on `socket` (non-blocking), sorted: the order
/// within a frame depends on the threads.
fn drain(socket: &UdpSocket) -> Vec<Vec<u8>> {
    let mut buf = [0u8; 2048];
    let mut got = Vec::new();
    while let Ok(n) = socket.recv(&mut buf) {
        got.push(buf[..n].to_vec());
    }
    got.sort();
    got
}

fn sink() -> UdpSocket {
    let socket = fdm_dis::listen::bind("127.0.0.1:0").expect("a loopback socket");
    socket.set_nonblocking(true).expect("non-blocking");
    socket
}

/// A `FleetRun` of `n` aircraft of `M`'s demonstration fleet publishing DIS
/// with `settings` (entities from `entity_base`), against the old path (the
/// same fleet flown beside it, every aircraft's full view published by a
/// `FleetPublisher`), for `frames` frames: every frame's datagrams the same,
/// byte for byte, and as many as the old path counted. Returns the run's
/// report and the datagrams sent.
fn against_the_old_path<M: FleetModel>(
    n: usize,
    frames: u64,
    settings: impl Fn(std::net::SocketAddr) -> DisSettings,
    entity_base: u16,
) -> (fdm_run::fleet::FleetReport, usize) {
    let new_sink = sink();
    let old_sink = sink();
    let mut scenario = FleetScenario::new(n as u64, frames);
    scenario.threads = Some(2);
    scenario.dis = Some(FleetDisConfig {
        settings: settings(new_sink.local_addr().unwrap()),
        entity_base,
    });
    let mut run = FleetRun::<M>::new(scenario, &mut |_, _| {}).unwrap();

    // The old path: the same fleet, every aircraft's full view.
    let old_settings = settings(old_sink.local_addr().unwrap());
    let trackers = (0..n as u64)
        .map(|i| {
            let id = fleet_identity(old_settings.site, old_settings.application, entity_base, i)
                .unwrap();
            old_settings
                .tracker::<M>(id, &callsign(M::CALLSIGN, u64::from(entity_base) + i))
                .unwrap()
        })
        .collect();
    let mut old = FleetPublisher::new(trackers);
    let sender = UdpSender::new(old_sink.local_addr().unwrap(), false).unwrap();
    let mut fleet = <M as FleetModel>::Lanes::demonstration(n).unwrap();
    let placement = Placement::new(GeodeticOrigin::default());
    let aircraft = M::default_aircraft();

    let mut sent = 0;
    for frame in 0..frames {
        run.step_frame().unwrap();
        LaneFleet::par_fly(&mut fleet, 30.0, Precision::Exact).unwrap();
        let tally = old.publish(&sender, &placement, |i| {
            let s = LaneFleet::state(&fleet, i)?;
            Some(M::view(&aircraft, &M::fleet_member(i).0, &s))
        });
        let new = drain(&new_sink);
        let expected = drain(&old_sink);
        assert_eq!(new.len() as u64, tally.pdus, "{}: frame {frame}", M::NAME);
        assert!(
            new == expected,
            "{} {:?} {:?}: frame {frame} differs",
            M::NAME,
            old_settings.dr,
            old_settings.thresholds
        );
        sent += new.len();
    }
    (run.report(), sent)
}

/// 200 aircraft of the demonstration fleet for 11 s (330 frames: the first
/// PDUs, position and orientation errors, heartbeats), with DRM(R,V,W)
/// and DRM(F,P,W) and a tight threshold set: every frame's datagrams are
/// the old path's.
#[test]
fn screened_fleet_sends_the_old_paths_datagrams() {
    let reasons = screened_fleet_against_the_old_path::<Palmer>();
    assert!(reasons.0 > 0 && reasons.1 > 0, "{reasons:?}");
}

/// The same for Bourg's demonstration fleet (its rough frames are
/// `bourg_rough`'s): its aircraft keep sending for position and
/// orientation, so no heartbeat falls due in these 11 s (the screen's
/// heartbeat test is Palmer's above; the screen does not depend on the model).
#[test]
fn screened_bourg_fleet_sends_the_old_paths_datagrams() {
    let reasons = screened_fleet_against_the_old_path::<Bourg>();
    assert!(reasons.0 > 0, "{reasons:?}");
}

/// The screened publishing of `M`'s demonstration fleet through `FleetRun`
/// against the old path, frame by frame, under the three settings of
/// [`screened_fleet_sends_the_old_paths_datagrams`]; the orientation errors
/// and heartbeats sent over the three runs.
fn screened_fleet_against_the_old_path<M: FleetModel>() -> (u64, u64) {
    const N: usize = 200;
    const FRAMES: u64 = 330;
    // Orientation errors and heartbeats sent, over the three runs.
    let mut reasons = (0, 0);
    for (dr, thresholds) in [
        (DrAlgorithm::Rvw, DrThresholds::default()),
        (DrAlgorithm::Fpw, DrThresholds::default()),
        (
            DrAlgorithm::Rvw,
            DrThresholds {
                position_m: 0.1,
                orientation_deg: 0.5,
                heartbeat_s: 2.0,
            },
        ),
    ] {
        let settings = |target| DisSettings {
            target,
            site: 3,
            application: 4,
            exercise: 5,
            version: DisVersion::V7,
            dr,
            thresholds,
            every_frame: false,
        };
        let (report, sent) = against_the_old_path::<M>(N, FRAMES, settings, 11);
        let dis = report.dis.unwrap();
        assert_eq!(dis.pdus as usize, sent);
        assert_eq!(dis.reasons.first, N as u64);
        assert!(dis.reasons.position > 0, "{dis:?}");
        reasons.0 += dis.reasons.orientation;
        reasons.1 += dis.reasons.heartbeat;
    }
    reasons
}

/// A fleet of several pieces (each published right after its step, on the
/// thread that stepped it: `FleetDis::fly_and_publish_lanes`, pieces of
/// 1 024 aircraft, the last one short) sends the old path's datagrams frame
/// by frame, Palmer and Bourg, on two threads; the report splits the
/// frames' time between the steps and DIS and says what each piece's
/// thread spent on each.
#[test]
fn a_fleet_published_piece_by_piece_sends_the_old_paths_datagrams() {
    fn check<M: FleetModel>() {
        const N: usize = 2 * 1024 + 300;
        const FRAMES: u64 = 75;
        let settings = |target| DisSettings {
            target,
            site: 2,
            application: 1,
            exercise: 9,
            version: DisVersion::V6,
            dr: DrAlgorithm::Rvw,
            thresholds: DrThresholds {
                position_m: 0.1,
                orientation_deg: 0.5,
                heartbeat_s: 1.5,
            },
            every_frame: false,
        };
        let (report, sent) = against_the_old_path::<M>(N, FRAMES, settings, 1);
        let dis = report.dis.unwrap();
        assert_eq!((dis.pdus as usize, dis.reasons.first), (sent, N as u64));
        assert!(dis.reasons.position + dis.reasons.orientation + dis.reasons.heartbeat > 0);
        let (step, publish) = (
            dis.step_thread_seconds.unwrap(),
            dis.publish_thread_seconds.unwrap(),
        );
        assert!(step > 0.0 && publish > 0.0, "{step} {publish}");
        assert!(report.seconds > 0.0 && dis.publish_seconds.unwrap() > 0.0);
    }
    check::<Palmer>();
    check::<Bourg>();
}

/// Palmer's rough body-to-NED matrices against the exact path's (the view's
/// Euler angles made a matrix again): within 1e-11 in every element, a
/// hundredth of the tolerance, over the demonstration fleet's controls and
/// velocities in every direction, near the vertical and at the limits of
/// the range; the time, position and velocity bit for bit. Past the limits
/// (velocities too small or too large, not finite) there is no rough frame.
#[test]
fn palmer_rough_is_within_the_tolerance() {
    let aircraft = Palmer::default_aircraft();
    let mut x: u64 = 0x1234_5678_9abc_def1;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut velocities: Vec<Vector3<f64>> = (0..20_000)
        .map(|_| Vector3::new(next(), next(), next()) * 80.0)
        .collect();
    // Near the vertical (climb ±90° less a little), at the range's ends.
    for k in 0..2_000 {
        let small = 10f64.powi(-(k % 12)) * next();
        velocities.push(Vector3::new(small, small * next(), 50.0 * next().signum()));
    }
    for m in [1e-99, 2e-100, 1e99, 5e99] {
        velocities.push(Vector3::new(m, -m, m));
        velocities.push(Vector3::new(m, 0.0, 0.0));
    }
    velocities.push(Vector3::new(0.0, 0.0, 0.0));
    let mut rough_made = 0;
    let mut worst: f64 = 0.0;
    let n = velocities.len();
    let states: Vec<Option<PalmerState>> = velocities
        .iter()
        .enumerate()
        .map(|(i, v)| {
            Some(PalmerState {
                time_s: i as f64 * 0.25,
                position_m: Vector3::new(i as f64, -3.0, 400.0),
                velocity_mps: *v,
            })
        })
        .collect();
    let mut out = vec![None; n];
    palmer_rough(0, &states, &mut out);
    for (i, (s, r)) in states.iter().zip(&out).enumerate() {
        let s = s.unwrap();
        let Some(r) = r else { continue };
        rough_made += 1;
        let view = Palmer::view(&aircraft, &Palmer::fleet_member(i).0, &s);
        let Rough {
            time_s,
            position_m,
            velocity_mps,
            body_to_ned,
        } = *r;
        assert_eq!(time_s.to_bits(), view.time_s.to_bits());
        assert_eq!(position_m, view.position_m);
        assert_eq!(velocity_mps, view.velocity_mps);
        worst = worst.max((body_to_ned - view.attitude.body_to_ned()).amax());
    }
    assert!(worst <= ROUGH_TOLERANCE / 100.0, "worst element {worst:e}");
    assert!(rough_made > n * 9 / 10, "{rough_made} of {n}");
    for v in [
        Vector3::new(1e-101, 0.0, 0.0),
        Vector3::new(1e101, 0.0, 0.0),
        Vector3::new(f64::NAN, 0.0, 0.0),
        Vector3::new(40.0, f64::INFINITY, 0.0),
    ] {
        let s = PalmerState {
            time_s: 0.0,
            position_m: Vector3::zeros(),
            velocity_mps: v,
        };
        let mut out = [None];
        palmer_rough(10, &[Some(s)], &mut out);
        assert!(out[0].is_none(), "{v}");
    }
}

/// Bourg's rough frames against its views, bit for bit (time, position,
/// velocity and the attitude matrix), over orientations in every direction
/// (random quaternions, normalised or a little off, as the step leaves
/// them), banked, inverted, turning and near or at the vertical (the
/// Euler angles' gimbal-lock branch): a rough frame for every finite state,
/// none for a non-finite one. The matrix straight from the quaternion is
/// measured too: the view's `f32` Euler angles move the view's matrix from
/// it by more than `ROUGH_TOLERANCE`, which is why `bourg_rough` does not
/// use it.
#[test]
fn bourg_rough_is_the_views_frame() {
    let aircraft = Bourg::default_aircraft();
    let mut x: u64 = 0x0fed_cba9_8765_4321;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut orientations: Vec<Quaternion<f32>> = Vec::new();
    for k in 0..20_000 {
        let q = Quaternion::new(next() as f32, next() as f32, next() as f32, next() as f32);
        let n = q.norm();
        // Normalised, or off by up to a few 1e-6 as integration leaves it.
        let scale = if k % 2 == 0 {
            1.0
        } else {
            1.0 + 4e-6 * next() as f32
        };
        orientations.push(Quaternion::from_vector(q.coords.map(|c| c / n * scale)));
    }
    // Euler angles (roll, pitch nose-down, yaw): banked, inverted, turning,
    // near and at the vertical.
    for k in 0..4_000 {
        let pitch = match k % 4 {
            0 => 90.0 - 10f64.powi(-(k % 9)) * next().abs(),
            1 => -90.0 + 10f64.powi(-(k % 9)) * next().abs(),
            2 => 89.0 * next(),
            _ => 90.0 * next().signum(),
        };
        let euler = nalgebra::Vector3::new(180.0 * next(), pitch, 180.0 * next()).map(|c| c as f32);
        orientations.push(ops::quat_from_euler_deg(&euler));
    }
    for roll in [0.0f32, 45.0, 90.0, 135.0, 180.0, -180.0, -60.0] {
        for yaw in [0.0f32, 30.0, 90.0, -170.0, 180.0] {
            orientations.push(ops::quat_from_euler_deg(&nalgebra::Vector3::new(
                roll, 5.0, yaw,
            )));
        }
    }
    let n = orientations.len();
    let states: Vec<Option<BourgState>> = orientations
        .iter()
        .enumerate()
        .map(|(i, q)| {
            let mut s = BourgState::initial();
            s.time_s = i as f64 / 30.0;
            s.position_ft = nalgebra::Vector3::new(i as f32 * 1.7, -3.3, 2000.0 + next() as f32);
            s.velocity_ftps =
                nalgebra::Vector3::new(next(), next(), next()).map(|c| (c * 300.0) as f32);
            s.orientation = *q;
            s.velocity_body_ftps = ops::qv_rotate(&ops::conjugate(q), &s.velocity_ftps);
            s.angular_velocity_radps =
                nalgebra::Vector3::new(next(), next(), next()).map(|c| c as f32);
            Some(s)
        })
        .collect();
    let mut out = vec![None; n];
    bourg_rough(&states, &mut out);
    // Model (x north, y west, z up) and body (forward, left, up) axes to
    // north-east-down and forward-right-down.
    let flip = nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, -1.0, -1.0));
    let mut from_quaternion: f64 = 0.0;
    for (i, (s, r)) in states.iter().zip(&out).enumerate() {
        let s = s.unwrap();
        let r = r.expect("a rough frame for every finite state");
        let view = Bourg::view(&aircraft, &Bourg::fleet_member(i).0, &s);
        assert_eq!(r.time_s.to_bits(), view.time_s.to_bits());
        let bits = |v: nalgebra::Vector3<f64>| v.map(f64::to_bits);
        assert_eq!(bits(r.position_m), bits(view.position_m));
        assert_eq!(bits(r.velocity_mps), bits(view.velocity_mps));
        let exact = view.attitude.body_to_ned();
        assert_eq!(
            r.body_to_ned.map(f64::to_bits),
            exact.map(f64::to_bits),
            "{:?}",
            s.orientation
        );
        let q = Quaternion::from_vector(s.orientation.coords.map(f64::from));
        let q = nalgebra::UnitQuaternion::from_quaternion(q);
        let straight = flip * q.to_rotation_matrix().into_inner() * flip;
        from_quaternion = from_quaternion.max((straight - exact).amax());
    }
    assert!(
        from_quaternion > ROUGH_TOLERANCE * 10.0,
        "{from_quaternion:e}"
    );
    for bad in [
        |s: &mut BourgState| s.time_s = f64::NAN,
        |s: &mut BourgState| s.position_ft.x = f32::INFINITY,
        |s: &mut BourgState| s.velocity_ftps.z = f32::NAN,
        |s: &mut BourgState| s.orientation.coords.w = f32::NAN,
    ] {
        let mut s = BourgState::initial();
        bad(&mut s);
        let mut out = [None];
        bourg_rough(&[Some(s)], &mut out);
        assert!(out[0].is_none(), "{s:?}");
    }
    let mut out = [None];
    bourg_rough(&[None], &mut out);
    assert!(out[0].is_none());
}

/// Palmer's rough frames made lane by lane (`palmer_rough_lanes`, what the
/// fleet's screen runs, through `FleetModel::dis_rough_lanes`) are
/// `palmer_rough`'s, bit for bit, in every field, and `None` exactly where
/// `palmer_rough` makes none: velocities in every direction, near the
/// vertical, at and past the range's limits, zero, not finite, aircraft
/// without a state, groups of fewer than eight, at several fleet indices
/// (so every control of the demonstration fleet). Bourg's default lanes
/// (its `bourg_rough` put in the lanes) likewise.
#[test]
fn palmer_rough_lanes_is_palmer_rough() {
    let mut x: u64 = 0x0bad_cafe_1234_5678;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut velocities: Vec<Vector3<f64>> = (0..20_000)
        .map(|_| Vector3::new(next(), next(), next()) * 80.0)
        .collect();
    for k in 0..2_000 {
        let small = 10f64.powi(-(k % 12)) * next();
        velocities.push(Vector3::new(small, small * next(), 50.0 * next().signum()));
    }
    for m in [1e-99, 1e-100, 2e-100, 1e-101, 1e99, 1e100, 5e99, 1e101] {
        velocities.push(Vector3::new(m, -m, m));
        velocities.push(Vector3::new(m, 0.0, 0.0));
        velocities.push(Vector3::new(0.0, -m, 0.0));
        velocities.push(Vector3::new(0.0, 0.0, m));
    }
    for v in [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(-0.0, 0.0, -0.0),
        Vector3::new(f64::NAN, 1.0, 0.0),
        Vector3::new(40.0, f64::INFINITY, 0.0),
        Vector3::new(40.0, 1.0, f64::NEG_INFINITY),
        Vector3::new(0.0, 0.0, -30.0),
    ] {
        velocities.push(v);
    }
    let states: Vec<Option<PalmerState>> = velocities
        .iter()
        .enumerate()
        .map(|(i, v)| {
            (i % 17 != 3).then(|| PalmerState {
                time_s: i as f64 * 0.25,
                position_m: Vector3::new(i as f64, -3.0, 400.0 + next()),
                velocity_mps: *v,
            })
        })
        .collect();
    let bits = |r: &Rough| {
        let mut b = vec![r.time_s.to_bits()];
        b.extend(r.position_m.iter().map(|x| x.to_bits()));
        b.extend(r.velocity_mps.iter().map(|x| x.to_bits()));
        b.extend(r.body_to_ned.iter().map(|x| x.to_bits()));
        b
    };
    let (mut made, mut none) = (0, 0);
    for first in [0usize, 3, 1000, 123_457] {
        let mut want = vec![None; states.len()];
        palmer_rough(first, &states, &mut want);
        // Groups of eight, and a last group of fewer.
        for (g, group) in states.chunks(fdm_dis::ROUGH_LANES).enumerate() {
            let at = g * fdm_dis::ROUGH_LANES;
            let mut lanes = fdm_dis::RoughLanes::default();
            Palmer::dis_rough_lanes(first + at, group, &mut lanes);
            for k in 0..fdm_dis::ROUGH_LANES {
                let got = lanes.get(k);
                let want = want.get(at + k).copied().flatten();
                match (&got, &want) {
                    (Some(g), Some(w)) => {
                        assert_eq!(bits(g), bits(w), "aircraft {}", first + at + k);
                        made += 1;
                    }
                    (None, None) => none += 1,
                    _ => panic!("aircraft {}: {got:?} against {want:?}", first + at + k),
                }
            }
        }
        // A short group on its own.
        let mut lanes = fdm_dis::RoughLanes::default();
        Palmer::dis_rough_lanes(first + 8, &states[8..11], &mut lanes);
        for k in 0..3 {
            assert_eq!(
                lanes.get(k).map(|r| bits(&r)),
                want[8 + k].map(|r| bits(&r))
            );
        }
        assert!((3..8).all(|k| !lanes.ok[k]));
    }
    assert!(made > 80_000 && none > 5_000, "{made} made, {none} none");

    // Bourg's lanes: its rough frames as they are.
    let bourg: Vec<Option<BourgState>> = (0..21)
        .map(|i| (i % 5 != 1).then(|| Bourg::fleet_member(i).1))
        .collect();
    let mut want = vec![None; bourg.len()];
    bourg_rough(&bourg, &mut want);
    for (g, group) in bourg.chunks(fdm_dis::ROUGH_LANES).enumerate() {
        let mut lanes = fdm_dis::RoughLanes::default();
        Bourg::dis_rough_lanes(g * 8, group, &mut lanes);
        for k in 0..group.len() {
            assert_eq!(
                lanes.get(k),
                want[g * 8 + k],
                "Bourg aircraft {}",
                g * 8 + k
            );
        }
    }
}

/// Bourg's rough frames made lane by lane (`bourg_rough_lanes`, the Euler
/// angles' `atan2`s eight at a time, what the fleet's screen runs through
/// `FleetModel::dis_rough_lanes`) are `bourg_rough`'s, bit for bit in every
/// field, and `None` exactly where it makes none: random orientations
/// (normalised or off by up to 4e-6), banked, inverted, near and at the
/// vertical (the Euler angles' gimbal-lock branch, which each lane takes on
/// its own), states that are not finite and aircraft without a state, in
/// groups of eight and shorter.
#[test]
fn bourg_rough_lanes_is_bourg_rough() {
    let mut x: u64 = 0x5eed_b0b0_1234_abcd;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut orientations: Vec<Quaternion<f32>> = Vec::new();
    for k in 0..12_000 {
        let q = Quaternion::new(next() as f32, next() as f32, next() as f32, next() as f32);
        let n = q.norm();
        let scale = if k % 2 == 0 {
            1.0
        } else {
            1.0 + 4e-6 * next() as f32
        };
        orientations.push(Quaternion::from_vector(q.coords.map(|c| c / n * scale)));
    }
    for k in 0..4_000 {
        let pitch = match k % 4 {
            0 => 90.0 - 10f64.powi(-(k % 9)) * next().abs(),
            1 => -90.0 + 10f64.powi(-(k % 9)) * next().abs(),
            2 => 89.0 * next(),
            _ => 90.0 * next().signum(),
        };
        let euler = nalgebra::Vector3::new(180.0 * next(), pitch, 180.0 * next()).map(|c| c as f32);
        orientations.push(ops::quat_from_euler_deg(&euler));
    }
    let states: Vec<Option<BourgState>> = orientations
        .iter()
        .enumerate()
        .map(|(i, q)| {
            (i % 13 != 5).then(|| {
                let mut s = BourgState::initial();
                s.time_s = i as f64 / 30.0;
                s.position_ft =
                    nalgebra::Vector3::new(i as f32 * 1.7, -3.3, 2000.0 + next() as f32);
                s.velocity_ftps =
                    nalgebra::Vector3::new(next(), next(), next()).map(|c| (c * 300.0) as f32);
                s.orientation = *q;
                match i % 101 {
                    7 => s.position_ft.x = f32::NAN,
                    8 => s.angular_velocity_radps.y = f32::INFINITY,
                    9 => s.orientation.coords.z = f32::NAN,
                    _ => {}
                }
                s
            })
        })
        .collect();
    let bits = |r: &Rough| {
        let mut b = vec![r.time_s.to_bits()];
        b.extend(r.position_m.iter().map(|x| x.to_bits()));
        b.extend(r.velocity_mps.iter().map(|x| x.to_bits()));
        b.extend(r.body_to_ned.iter().map(|x| x.to_bits()));
        b
    };
    let mut want = vec![None; states.len()];
    bourg_rough(&states, &mut want);
    let (mut made, mut none) = (0, 0);
    for (g, group) in states.chunks(fdm_dis::ROUGH_LANES).enumerate() {
        let at = g * fdm_dis::ROUGH_LANES;
        let mut lanes = fdm_dis::RoughLanes::default();
        Bourg::dis_rough_lanes(at, group, &mut lanes);
        for k in 0..fdm_dis::ROUGH_LANES {
            let want = want.get(at + k).copied().flatten();
            match (lanes.get(k), want) {
                (Some(g), Some(w)) => {
                    assert_eq!(bits(&g), bits(&w), "aircraft {}", at + k);
                    made += 1;
                }
                (None, None) => none += 1,
                (got, want) => panic!("aircraft {}: {got:?} against {want:?}", at + k),
            }
        }
    }
    let mut lanes = fdm_dis::RoughLanes::default();
    Bourg::dis_rough_lanes(3, &states[3..6], &mut lanes);
    for k in 0..3 {
        assert_eq!(
            lanes.get(k).map(|r| bits(&r)),
            want[3 + k].map(|r| bits(&r))
        );
    }
    assert!((3..8).all(|k| !lanes.ok[k]));
    assert!(made > 14_000 && none > 1_000, "{made} made, {none} none");
}
