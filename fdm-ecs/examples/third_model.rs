//! A third flight dynamics model, written outside the workspace's library
//! crates against `fdm_core::model::Model` alone, flown in one world with
//! Palmer's Cessna and Bourg's aircraft, and shown to FlightGear through the
//! same generic systems: nothing in `fdm-core`, `fdm-ecs` or `fgnet` knows it.
//!
//! The model is a point-mass glider: lift perpendicular to the velocity,
//! banked about it, drag from a parabolic polar, gravity; semi-implicit Euler
//! in `f64`, SI units. The pilot changes the lift coefficient and the bank.
//!
//! Its step is written once ([`glider_step`]), over `fdm_core::real`'s number
//! type: `f64` for one aircraft ([`Model::step`], what the ECS flies) and
//! lane vectors for a structure-of-arrays fleet (`fdm_fleet::Fleet<Glider>`,
//! through [`LaneModel`]), with nothing written twice and no hand-written
//! kernel; [`fly_glider_fleet`] flies both and the test checks the bits.
//! The model is the file `sim-cli --features glider` flies
//! (`sim-cli/src/models/glider/model.rs`, included below): the glider checked
//! here is the CLI's, written once.
//!
//! Run it with `cargo run -p fdm-ecs --example third_model`; the test
//! `fdm-ecs/tests/third_model.rs` runs [`fly_mixed_fleet`] and
//! [`fly_glider_fleet`] and checks them.

use std::sync::Arc;

use fdm_core::bourg::Bourg;
use fdm_core::model::{FlightView, Model};
use fdm_core::palmer::Palmer;
use fdm_ecs::{Entity, Resources, Simulation};
use fdm_fleet::{Fleet, Precision};

// The glider's model (types, step, `Model` and `LaneModel` impls, fleet
// kernel) is the file `sim-cli glider` flies, included here: one source for
// the example and the CLI. It uses only fdm-core, fdm-fleet, nalgebra and serde.
#[path = "../../sim-cli/src/models/glider/model.rs"]
mod glider;
pub use glider::*;

/// Flies `n` gliders for `frames` frames at 30 FPS two ways, each member
/// with its own lift coefficient and bank (the first banking right over
/// frames 1 to 6, as in [`fly_mixed_fleet`]): one aircraft at a time with
/// [`Model::step`], and all together in a `Fleet<Glider>` of lanes. Returns
/// both final states, in member order.
///
/// # Errors
/// If the fleet refuses the aircraft (it does not).
pub fn fly_glider_fleet(
    n: usize,
    frames: u64,
) -> Result<(Vec<GliderState>, Vec<GliderState>), Box<dyn std::error::Error>> {
    let aircraft = Glider::default_aircraft();
    let dt = Glider::time_step(30.0);
    let member = |i: usize| {
        let small = f64::from(u16::try_from(i % 100).unwrap_or(0));
        let mut c = Glider::initial_controls();
        c.lift_coefficient = 0.4 + 0.01 * small;
        c.bank_deg = -20.0 + 0.5 * small;
        if i == 0 {
            c = Glider::initial_controls();
        }
        let mut s = Glider::initial_state();
        s.position_m.y += 30.0 * small;
        (c, s)
    };
    let mut alone: Vec<(GliderControls, GliderState)> = (0..n).map(member).collect();
    let mut fleet =
        Fleet::<Glider>::from_states(aircraft.clone(), alone.iter().map(|&(c, s)| (s, c)))?;
    for frame in 1..=frames {
        if frame <= 6 {
            let (c, _) = &mut alone[0];
            *c = Glider::apply(&aircraft, *c, GliderAction::BankRight);
            fleet.set_controls(0, *c)?;
        }
        for (c, s) in &mut alone {
            *s = Glider::step(&aircraft, c, s, dt);
        }
        fleet.fly_with(dt, Precision::Exact)?;
    }
    Ok((
        alone.into_iter().map(|m| m.1).collect(),
        fleet.states().collect(),
    ))
}

/// What [`fly_mixed_fleet`] left behind.
pub struct MixedFleet {
    /// The world after the flight.
    pub sim: Simulation,
    /// The glider's entity.
    pub glider: Entity,
    /// The Cessna's entity.
    pub palmer: Entity,
    /// Bourg's aircraft's entity.
    pub bourg: Entity,
}

/// Spawns a glider, a Cessna and Bourg's aircraft in one world at 30 FPS,
/// banks the glider right for a second, and flies `frames` frames.
///
/// # Errors
/// If the ECS refuses an input (it does not, for these).
pub fn fly_mixed_fleet(frames: u64) -> Result<MixedFleet, Box<dyn std::error::Error>> {
    let mut sim = Simulation::new(Resources::new(30.0)?);
    let glider = sim.spawn::<Glider>(
        Arc::new(Glider::default_aircraft()),
        Glider::initial_controls(),
        Glider::initial_state(),
    );
    let palmer = sim.spawn::<Palmer>(
        Arc::new(Palmer::default_aircraft()),
        Palmer::fleet_member(0).0,
        Palmer::fleet_member(0).1,
    );
    let bourg = sim.spawn::<Bourg>(
        Arc::new(Bourg::default_aircraft()),
        Bourg::initial_controls(),
        Bourg::initial_state(),
    );
    let script = fdm_core::script::Script::<GliderAction>::parse("1-6 bank-right\n")?;
    sim.set_script(glider, Arc::new(script))?;
    sim.run_frames(frames);
    Ok(MixedFleet {
        sim,
        glider,
        palmer,
        bourg,
    })
}

#[allow(dead_code)] // the test includes this file as a module and calls only the library part
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let fleet = fly_mixed_fleet(300)?;
    let (alone, lanes) = fly_glider_fleet(21, 300)?;
    let same = alone.iter().zip(&lanes).filter(|(a, b)| a == b).count();
    println!(
        "glider fleet: {same} of {} gliders in lanes bit-identical to the scalar step after 300 frames",
        alone.len()
    );
    if fleet.sim.state::<Glider>(fleet.glider) != Some(lanes[0]) {
        return Err("the ECS glider differs from the fleet's first glider".into());
    }
    for (name, entity, view) in [
        (
            "glider",
            fleet.glider,
            fleet.sim.view::<Glider>(fleet.glider),
        ),
        (
            "palmer",
            fleet.palmer,
            fleet.sim.view::<Palmer>(fleet.palmer),
        ),
        ("bourg", fleet.bourg, fleet.sim.view::<Bourg>(fleet.bourg)),
    ] {
        let here = fleet.sim.geodetic(entity).ok_or("no position")?;
        let packet = datagram(&fleet.sim, entity, &view.ok_or("no view")?).ok_or("no placement")?;
        println!(
            "{name:7} lat {:.6} lon {:.6} alt {:7.1} m  heading {:5.1}  datagram {} bytes",
            here.lat_deg,
            here.lon_deg,
            here.alt_m,
            fleet.sim.attitude(entity).ok_or("no attitude")?.heading_deg,
            packet.encode().len()
        );
    }
    Ok(())
}

/// The FlightGear datagram of an aircraft seen through `view`, from the
/// placement the ECS computed this frame (what `fdm_run`'s FlightGear output
/// sends): the glider needs nothing FlightGear-specific.
pub fn datagram(sim: &Simulation, entity: Entity, view: &FlightView) -> Option<fgnet::FgNetFdm> {
    let origin = sim.resources().origin;
    Some(fgnet::bridge::packet_at(
        view,
        &origin,
        sim.geodetic(entity)?,
        sim.attitude(entity)?,
    ))
}
