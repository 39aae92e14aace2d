//! The screened DIS publishing of a lanes fleet (`FleetDis::publish_lanes`
//! over `FleetPublisher::publish_screened` and `palmer_rough`) against the
//! path it replaced (`FleetPublisher::publish` of every aircraft's full
//! view): the same datagrams, byte for byte, frame by frame, over loopback
//! UDP; and Palmer's rough attitude matrices within their tolerance.

use std::net::UdpSocket;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fdm_core::palmer::{Palmer, PalmerState};
use fdm_dis::{
    DisVersion, DrAlgorithm, DrThresholds, FleetPublisher, Placement, Rough, UdpSender,
    ROUGH_TOLERANCE,
};
use fdm_fleet::{LaneFleet, Precision};
use fdm_run::dis::{callsign, fleet_identity, palmer_rough, DisSettings};
use fdm_run::fleet::{FleetDisConfig, FleetRun, FleetScenario};
use fdm_run::{FleetModel, RunModel};
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

/// 200 aircraft of the demonstration fleet for 11 s (330 frames: the first
/// PDUs, position and orientation errors, heartbeats), with DRM(R,V,W)
/// and DRM(F,P,W) and a tight threshold set: every frame's datagrams are
/// the old path's.
#[test]
fn screened_fleet_sends_the_old_paths_datagrams() {
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
        let new_sink = sink();
        let old_sink = sink();
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
        let mut scenario = FleetScenario::new(N as u64, FRAMES);
        scenario.threads = Some(2);
        scenario.dis = Some(FleetDisConfig {
            settings: settings(new_sink.local_addr().unwrap()),
            entity_base: 11,
        });
        let mut run = FleetRun::<Palmer>::new(scenario, &mut |_, _| {}).unwrap();

        // The old path: the same fleet, every aircraft's full view.
        let old_settings = settings(old_sink.local_addr().unwrap());
        let trackers = (0..N as u64)
            .map(|i| {
                let id = fleet_identity(3, 4, 11, i).unwrap();
                old_settings
                    .tracker::<Palmer>(id, &callsign(Palmer::CALLSIGN, 11 + i))
                    .unwrap()
            })
            .collect();
        let mut old = FleetPublisher::new(trackers);
        let sender = UdpSender::new(old_sink.local_addr().unwrap(), false).unwrap();
        let mut fleet = <Palmer as FleetModel>::Lanes::demonstration(N).unwrap();
        let placement = Placement::new(GeodeticOrigin::default());
        let aircraft = Palmer::default_aircraft();

        let mut sent = 0;
        for frame in 0..FRAMES {
            run.step_frame().unwrap();
            LaneFleet::par_fly(&mut fleet, 30.0, Precision::Exact).unwrap();
            let tally = old.publish(&sender, &placement, |i| {
                let s = LaneFleet::state(&fleet, i)?;
                Some(Palmer::view(&aircraft, &Palmer::fleet_member(i).0, &s))
            });
            let new = drain(&new_sink);
            let expected = drain(&old_sink);
            assert_eq!(new.len() as u64, tally.pdus, "{dr:?} frame {frame}");
            assert!(
                new == expected,
                "{dr:?} {thresholds:?}: frame {frame} differs"
            );
            sent += new.len();
        }
        let report = run.report();
        let dis = report.dis.unwrap();
        assert_eq!(dis.pdus as usize, sent);
        assert_eq!(dis.reasons.first, N as u64);
        assert!(dis.reasons.position > 0, "{dis:?}");
        reasons.0 += dis.reasons.orientation;
        reasons.1 += dis.reasons.heartbeat;
    }
    assert!(reasons.0 > 0 && reasons.1 > 0, "{reasons:?}");
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
