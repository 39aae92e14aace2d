//! The systems run in the declared order, FlightControl → EquationsOfMotion →
//! MakePacket → SendPacket, every frame, and each sees the data the one before
//! it wrote in the same frame: checked by observing the world after every
//! system of a frame, and by the datagram a linked entity sends.

use std::net::UdpSocket;
use std::sync::Arc;
use std::time::Duration;

use fdm_suite::fdm_core::bourg::{self, Aircraft, BourgAction, BourgControls, BourgState};
use fdm_suite::fdm_core::palmer::{
    self, PalmerAction, PalmerAircraft, PalmerControls, PalmerState,
};
use fdm_suite::fdm_core::script::Script;
use fdm_suite::fdm_ecs::components::{BourgInput, FgNetFdm, FlightGearLink, Geodetic, PalmerInput};
use fdm_suite::fdm_ecs::systems::{bourg_display, palmer_display};
use fdm_suite::fdm_ecs::{Entity, World};
use fdm_suite::fdm_ecs::{Resources, Schedule, Simulation};
use fdm_suite::fgnet::DATAGRAM_LEN;

fn receiver() -> (UdpSocket, String) {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let addr = socket.local_addr().unwrap().to_string();
    (socket, addr)
}

fn get<T: fdm_suite::fdm_ecs::hecs::Component + Clone>(world: &World, e: Entity) -> T {
    (*world.get::<&T>(e).unwrap()).clone()
}

#[test]
fn the_thesis_schedule_declares_the_four_systems_in_order() {
    let names: Vec<_> = Schedule::thesis()
        .systems()
        .iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(
        names,
        [
            "FlightControl",
            "EquationsOfMotion",
            "MakePacket",
            "SendPacket"
        ]
    );
    assert_eq!(
        Schedule::default().systems().len(),
        Schedule::thesis().systems().len()
    );
}

/// Runs frames with an observer that checks, after each system, that exactly
/// the data that system writes has changed and that it was computed from what
/// the previous systems of the same frame wrote.
#[test]
fn each_system_sees_what_the_previous_one_wrote_in_the_same_frame() {
    let (fg, addr) = receiver();
    let res = Resources::new(30.0).unwrap();
    let palmer_aircraft = PalmerAircraft::cessna_172();
    let bourg_aircraft = Aircraft::bourg_default();
    let mut sim = Simulation::new(res);
    let p = sim.spawn_palmer(
        Arc::new(palmer_aircraft),
        PalmerControls::default(),
        PalmerState::at_rest(),
        None,
    );
    let b = sim.spawn_bourg(
        Arc::new(bourg_aircraft),
        BourgControls::initial(),
        BourgState::initial(),
        Some(FlightGearLink::connect(&addr).unwrap()),
    );
    // Frames 1-3 pitch up by script, plus key presses queued below.
    sim.set_script(
        b,
        Arc::new(Script::<BourgAction>::parse("1-3 pitch-up\n").unwrap()),
    )
    .unwrap();

    let origin = sim.resources().origin;

    for frame in 1..=3u64 {
        sim.push_input(p, PalmerAction::ThrottleUp).unwrap();
        sim.push_input(b, BourgAction::ThrustUp).unwrap();

        let world = sim.world();
        let p_controls0: PalmerControls = get(world, p);
        let p_state0: PalmerState = get(world, p);
        let b_controls0: BourgControls = get(world, b);
        let b_state0: BourgState = get(world, b);
        let b_packet0: FgNetFdm = get(world, b);
        let sent0 = sim.send_stats(b).unwrap().sent;

        let mut trace = Vec::new();
        sim.run_frame_observed(|name, world| {
            trace.push(name);
            let p_controls: PalmerControls = get(world, p);
            let p_state: PalmerState = get(world, p);
            let b_controls: BourgControls = get(world, b);
            let b_state: BourgState = get(world, b);
            let b_packet: FgNetFdm = get(world, b);
            let sent = world.get::<&FlightGearLink>(b).unwrap().stats().sent;
            match name {
                "FlightControl" => {
                    // Controls updated from this frame's input; nothing else yet.
                    assert_eq!(p_controls, p_controls0.apply(PalmerAction::ThrottleUp));
                    let want = b_controls0
                        .neutralize_surfaces()
                        .apply(BourgAction::PitchUp)
                        .apply(BourgAction::ThrustUp);
                    assert_eq!(b_controls, want);
                    assert!(world.get::<&PalmerInput>(p).unwrap().is_empty());
                    assert!(world.get::<&BourgInput>(b).unwrap().is_empty());
                    assert_eq!((p_state, b_state), (p_state0, b_state0));
                    assert_eq!(b_packet, b_packet0);
                }
                "EquationsOfMotion" => {
                    // Stepped with the controls FlightControl just wrote.
                    let dt = 1.0 / 30.0;
                    assert_eq!(
                        p_state,
                        palmer::step(&palmer_aircraft, &p_controls, &p_state0, dt)
                    );
                    assert_eq!(
                        b_state,
                        bourg::step(&bourg_aircraft, &b_controls, &b_state0, 1.0f32 / 30.0)
                    );
                    assert_eq!(b_packet, b_packet0);
                    assert_eq!(sent, sent0);
                }
                "MakePacket" => {
                    // Built from the state EquationsOfMotion just wrote.
                    let want = bourg_display(&b_controls, &b_state, &origin);
                    assert_eq!(b_packet, want.packet);
                    assert_ne!(b_packet, b_packet0);
                    let want = palmer_display(&palmer_aircraft, &p_controls, &p_state, &origin);
                    assert_eq!(get::<FgNetFdm>(world, p), want.packet);
                    assert_eq!(get::<Geodetic>(world, p), want.geodetic);
                    assert_eq!(sent, sent0);
                }
                "SendPacket" => assert_eq!(sent, sent0 + 1),
                other => panic!("unexpected system {other}"),
            }
        });
        assert_eq!(
            trace,
            [
                "FlightControl",
                "EquationsOfMotion",
                "MakePacket",
                "SendPacket"
            ]
        );
        assert_eq!(sim.frame(), frame);

        // What went out this frame is the packet of this frame's step.
        let mut buf = [0u8; 1024];
        let len = fg.recv(&mut buf).unwrap();
        assert_eq!(len, DATAGRAM_LEN);
        assert_eq!(&buf[..len], &sim.packet(b).unwrap().encode()[..]);
    }
}

#[test]
fn frame_counter_numbers_frames_from_one_for_scripts() {
    let mut sim = Simulation::new(Resources::new(30.0).unwrap());
    assert_eq!(sim.frame(), 0);
    let e = sim.spawn_bourg(
        Arc::new(Aircraft::bourg_default()),
        BourgControls::initial(),
        BourgState::initial(),
        None,
    );
    // A single-frame rule on frame 1 and one on frame 3.
    let script =
        Script::<BourgAction>::parse("1-1 thrust-up\n3-3 thrust-down\n3-3 thrust-down\n").unwrap();
    sim.set_script(e, Arc::new(script)).unwrap();
    let mut thrust = Vec::new();
    for _ in 0..4 {
        sim.run_frame();
        thrust.push(sim.bourg_controls(e).unwrap().thrust_lb);
    }
    assert_eq!(sim.frame(), 4);
    assert_eq!(thrust, [600.0, 600.0, 400.0, 400.0]);
}

#[test]
fn script_actions_come_before_queued_keys() {
    let mut sim = Simulation::new(Resources::new(10.0).unwrap());
    let p = sim.spawn_palmer(
        Arc::new(PalmerAircraft::cessna_172()),
        PalmerControls {
            alpha_deg: 19.0,
            ..PalmerControls::default()
        },
        PalmerState::at_rest(),
        None,
    );
    // Script first: 19 +1 (script) = 20, +1 (key) = 20 (limit), -1 (key) = 19.
    // Keys first would give 19 +1 = 20, -1 = 19, +1 (script) = 20.
    sim.set_script(
        p,
        Arc::new(Script::<PalmerAction>::parse("1-1 alpha-up\n").unwrap()),
    )
    .unwrap();
    sim.push_input(p, PalmerAction::AlphaUp).unwrap();
    sim.push_input(p, PalmerAction::AlphaDown).unwrap();
    sim.run_frame();
    assert_eq!(sim.palmer_controls(p).unwrap().alpha_deg, 19.0);
}
