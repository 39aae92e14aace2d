//! The FlightGear native-FDM link as an output of a run (what the ECS's
//! SendPacket did until issue 22, moved here from `fdm-ecs/tests/ecs_flightgear.rs`):
//! a run with a `FlightGearOutput` sends exactly one 408-byte datagram per
//! flown frame (none when attached, none on a reset), the datagram of that
//! frame's view at the placement the ECS computed, the same bytes as
//! `fgnet::bridge::display` of the state; a diverged aircraft sends nothing
//! more; send failures are counted, reported once, and do not stop the run.

use std::io::ErrorKind;
use std::net::UdpSocket;
use std::time::Duration;

use fdm_core::bourg::{Bourg, BourgAction};
use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::{Palmer, PalmerControls, PalmerState};
use fdm_run::flightgear::FlightGearOutput;
use fdm_run::{LinkStats, Run, RunError, Scenario, SharedOutput, Start};
use fgnet::{FgNetFdm, DATAGRAM_LEN};
use nalgebra::Vector3;

fn receiver() -> (UdpSocket, String) {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let addr = socket.local_addr().unwrap().to_string();
    (socket, addr)
}

/// Receives one datagram, asserting it has the FGNetFDM size.
fn recv_packet(socket: &UdpSocket) -> Vec<u8> {
    let mut buf = [0u8; 2048];
    let len = socket.recv(&mut buf).unwrap();
    assert_eq!(len, DATAGRAM_LEN);
    buf[..len].to_vec()
}

/// Asserts nothing more is waiting on the socket.
fn assert_drained(socket: &UdpSocket) {
    socket.set_nonblocking(true).unwrap();
    let mut buf = [0u8; 2048];
    let err = socket.recv(&mut buf).unwrap_err();
    assert_eq!(
        err.kind(),
        ErrorKind::WouldBlock,
        "an extra datagram arrived"
    );
    socket.set_nonblocking(false).unwrap();
}

fn link(addr: &str, origin: GeodeticOrigin) -> SharedOutput<FlightGearOutput> {
    SharedOutput::new(FlightGearOutput::connect(addr, origin).unwrap())
}

fn stats(link: &SharedOutput<FlightGearOutput>) -> LinkStats {
    link.with(|o| o.map(|o| o.stats())).unwrap()
}

/// Every flown frame sends one datagram: `fgnet::bridge::display` of the
/// frame's state (the bytes MakePacket built in the ECS before), for both
/// models, away from the default origin too; attaching and resetting send
/// nothing.
#[test]
fn one_datagram_per_flown_frame_the_bridges_bytes() {
    let origin = GeodeticOrigin::new(47.5, 8.5, 430.0).unwrap();
    let (fg_palmer, palmer_addr) = receiver();
    let (fg_bourg, bourg_addr) = receiver();
    let start = Start::<Palmer> {
        controls: PalmerControls {
            throttle: 1.0,
            alpha_deg: 4.0,
            ..PalmerControls::default()
        },
        ..Start::thesis()
    };
    let mut palmer = Run::new(Scenario::new(start, 30, 0).unwrap().with_origin(origin)).unwrap();
    let palmer_link = link(&palmer_addr, origin);
    palmer.attach(palmer_link.clone()).unwrap();
    let mut bourg = Run::new(
        Scenario::<Bourg>::new(Start::thesis(), 30, 0)
            .unwrap()
            .with_origin(origin),
    )
    .unwrap();
    let bourg_link = link(&bourg_addr, origin);
    bourg.attach(bourg_link.clone()).unwrap();
    assert_drained(&fg_palmer);
    let frames = 40;
    for frame in 1..=frames {
        palmer.step_frame(&[]).unwrap();
        bourg.step_frame(&[BourgAction::PitchUp]).unwrap();
        let want = fgnet::bridge::display(&palmer.view(), &origin);
        assert_eq!(
            recv_packet(&fg_palmer),
            want.packet.encode(),
            "frame {frame}"
        );
        let placement = palmer.placement();
        assert_eq!(
            (placement.geodetic, placement.attitude),
            (want.geodetic, want.attitude)
        );
        let want = fgnet::bridge::display(&bourg.view(), &origin);
        assert_eq!(
            recv_packet(&fg_bourg),
            want.packet.encode(),
            "frame {frame}"
        );
        let last = bourg_link.with(|o| o.and_then(|o| o.last_packet().copied()));
        assert_eq!(last, Some(want.packet));
    }
    palmer.reset().unwrap();
    assert_drained(&fg_palmer);
    assert_drained(&fg_bourg);
    assert_eq!(
        stats(&palmer_link),
        LinkStats {
            sent: frames,
            failed: 0
        }
    );
    assert_eq!(
        stats(&bourg_link),
        LinkStats {
            sent: frames,
            failed: 0
        }
    );
    assert!(palmer_link
        .with(|o| o.and_then(FlightGearOutput::take_failure))
        .is_none());
    let decoded = FgNetFdm::decode(
        &FlightGearOutput::packet(&palmer.view(), &origin, &palmer.placement()).encode(),
    )
    .unwrap();
    assert_eq!(decoded.version, 24);
}

/// A huge but finite state whose first step overflows: the run stops with
/// `Diverged`, the output took the frame and sent nothing.
#[test]
fn a_diverged_aircraft_sends_nothing() {
    let (fg, addr) = receiver();
    let start = Start::<Palmer> {
        state: PalmerState {
            position_m: Vector3::new(0.0, 0.0, 30.0),
            velocity_mps: Vector3::new(1e150, 0.0, 0.0),
            ..PalmerState::at_rest()
        },
        ..Start::thesis()
    };
    assert!(fdm_core::model::FlightView::is_finite(&Palmer::view(
        &start.aircraft,
        &start.controls,
        &start.state
    )));
    let scenario = Scenario::new(start, 10, 0).unwrap();
    let origin = scenario.origin;
    let mut run = Run::new(scenario).unwrap();
    let out = link(&addr, origin);
    run.attach(out.clone()).unwrap();
    for _ in 0..3 {
        assert!(matches!(
            run.step_frame(&[]),
            Err(RunError::Diverged { .. })
        ));
    }
    assert_eq!(run.status(), FlightStatus::Diverged);
    assert_eq!(stats(&out).sent, 0);
    fg.set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let mut buf = [0u8; 1024];
    assert!(fg.recv(&mut buf).is_err(), "a datagram was sent");
}

/// A finite state with no geodetic position (1.7e308 m out): the ECS's
/// Place marks it diverged and the output sends nothing.
#[test]
fn a_state_too_far_out_to_be_placed_sends_nothing() {
    let (fg, addr) = receiver();
    let start = Start::<Palmer> {
        state: PalmerState {
            position_m: Vector3::new(1.7e308, 0.0, 1.7e308),
            velocity_mps: Vector3::new(45.0, 0.0, 0.0),
            ..PalmerState::at_rest()
        },
        ..Start::thesis()
    };
    let scenario = Scenario::new(start, 10, 0).unwrap();
    let origin = scenario.origin;
    let mut run = Run::new(scenario).unwrap();
    let out = link(&addr, origin);
    run.attach(out.clone()).unwrap();
    assert!(matches!(
        run.step_frame(&[]),
        Err(RunError::Diverged { .. })
    ));
    assert!(Palmer::is_finite(&run.state().unwrap()));
    assert_eq!(stats(&out).sent, 0);
    fg.set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let mut buf = [0u8; 1024];
    assert!(fg.recv(&mut buf).is_err(), "a datagram was sent");
}

/// Nobody listens: failures are counted with the sends, the first is kept
/// once as a message naming the target and the frame, and the run goes on.
#[test]
fn failures_are_counted_reported_once_and_do_not_stop_the_run() {
    let port = UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let addr = format!("127.0.0.1:{port}");
    let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 30).unwrap();
    let origin = scenario.origin;
    let mut run = Run::new(scenario).unwrap();
    let out = link(&addr, origin);
    run.attach(out.clone()).unwrap();
    assert_eq!(run.run_to_end().unwrap().frames, 30);
    let s = stats(&out);
    assert_eq!(s.sent + s.failed, 30);
    assert!(s.failed > 0, "{s:?}");
    let first = out
        .with(|o| o.and_then(FlightGearOutput::take_failure))
        .expect("first failure kept");
    assert!(
        first.starts_with(&format!("sending to {addr} failed on frame ")),
        "{first}"
    );
    assert!(
        first.ends_with("; the run goes on and counts failures"),
        "{first}"
    );
    assert!(out
        .with(|o| o.and_then(FlightGearOutput::take_failure))
        .is_none());
}
