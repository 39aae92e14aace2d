//! The third model of `examples/third_model.rs`, written outside the library
//! crates against the `Model` trait alone, flies in one world with Palmer and
//! Bourg, steps exactly as its own `step` says, and its datagrams decode.

#[path = "../examples/third_model.rs"]
mod third_model;

use fdm_core::bourg::Bourg;
use fdm_core::model::Model;
use fdm_core::palmer::Palmer;
use fgnet::FgNetFdm;
use third_model::{datagram, fly_glider_fleet, fly_mixed_fleet, Glider, GliderAction};

#[test]
fn a_third_model_flies_in_a_mixed_fleet_and_reaches_flightgear() {
    let frames = 90;
    let fleet = fly_mixed_fleet(frames).unwrap();
    let sim = &fleet.sim;
    assert_eq!(sim.frame(), frames);
    // Its systems joined the schedule when it was spawned: one more of each
    // phase (4 phases for 3 models; the FlightGear datagram is an output of
    // the run library now, not a SendPacket system).
    assert_eq!(sim.schedule().systems().len(), 12);

    // The glider flew exactly its own model, driven by its own script.
    let aircraft = Glider::default_aircraft();
    let mut controls = Glider::initial_controls();
    let mut state = Glider::initial_state();
    let dt = Glider::time_step(30.0);
    for frame in 1..=frames {
        if frame <= 6 {
            controls = Glider::apply(&aircraft, controls, GliderAction::BankRight);
        }
        state = Glider::step(&aircraft, &controls, &state, dt);
    }
    assert_eq!(sim.state::<Glider>(fleet.glider), Some(state));
    assert_eq!(sim.controls::<Glider>(fleet.glider).unwrap().bank_deg, 30.0);
    // Banked right, it turned toward the east (heading past north, clockwise).
    let heading = sim.attitude(fleet.glider).unwrap().heading_deg;
    assert!(heading > 1.0 && heading < 180.0, "{heading}");

    // The other two flew as alone (their states are the models' own).
    let mut p = Palmer::fleet_member(0).1;
    let pc = Palmer::fleet_member(0).0;
    let mut b = Bourg::initial_state();
    let bc = Bourg::initial_controls();
    for _ in 0..frames {
        p = Palmer::step(
            &Palmer::default_aircraft(),
            &pc,
            &p,
            Palmer::time_step(30.0),
        );
        b = Bourg::step(&Bourg::default_aircraft(), &bc, &b, Bourg::time_step(30.0));
    }
    assert_eq!(sim.state::<Palmer>(fleet.palmer), Some(p));
    assert_eq!(sim.state::<Bourg>(fleet.bourg), Some(b));

    // Every aircraft's datagram is a valid FGNetFDM v24 datagram carrying its
    // own geodetic position.
    for (entity, view) in [
        (fleet.glider, sim.view::<Glider>(fleet.glider)),
        (fleet.palmer, sim.view::<Palmer>(fleet.palmer)),
        (fleet.bourg, sim.view::<Bourg>(fleet.bourg)),
    ] {
        let packet = datagram(sim, entity, &view.unwrap()).unwrap();
        let bytes = packet.encode();
        assert_eq!(bytes.len(), fgnet::DATAGRAM_LEN);
        let decoded = FgNetFdm::decode(&bytes).unwrap();
        assert_eq!(decoded, packet);
        let here = sim.geodetic(entity).unwrap();
        assert_eq!(decoded.latitude, here.lat_deg.to_radians());
        assert_eq!(decoded.altitude, here.alt_m);
    }
    // The glider started 300 m west of the origin, 600 m up, and is gliding down.
    let glider_alt = sim.geodetic(fleet.glider).unwrap().alt_m;
    let origin_alt = sim.resources().origin.geodetic().alt_m;
    assert!(
        glider_alt > origin_alt + 500.0 && glider_alt < origin_alt + 600.0,
        "{glider_alt}"
    );
}

/// The glider's one step flies one aircraft in the ECS and many in a fleet
/// of lanes, bit for bit: every glider of a fleet of 21 (two whole blocks of
/// 8 and a partial one) ends where the scalar step takes it alone, and the
/// first ends where the ECS's glider ends (same script, same frames).
#[test]
fn the_glider_flies_in_lanes_as_alone_and_as_in_the_ecs() {
    let frames = 90;
    let (alone, lanes) = fly_glider_fleet(21, frames).unwrap();
    assert_eq!(alone.len(), 21);
    for (i, (a, l)) in alone.iter().zip(&lanes).enumerate() {
        assert_eq!(a, l, "glider {i}");
    }
    // Their flights differ from each other (the test is not vacuous).
    assert_ne!(alone[1], alone[2]);
    let fleet = fly_mixed_fleet(frames).unwrap();
    assert_eq!(fleet.sim.state::<Glider>(fleet.glider), Some(lanes[0]));
}
