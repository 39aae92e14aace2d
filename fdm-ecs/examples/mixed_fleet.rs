//! A mixed fleet in one ECS world: 100 of Palmer's Cessnas and 100 of Bourg's
//! aircraft (the models' demonstration fleets, every member in a different
//! flying state) and 5 Cessnas gliding in to land, stepped in parallel for 20 s, with two systems of our own
//! added to the schedule:
//!
//! * `MaxHeight`, generic over the model like the built-in systems, placed
//!   right after FlightStatus with `Schedule::insert_after`: the highest
//!   height above the ground plane each aircraft has reached;
//! * `Touchdowns`, appended at the end of the frame with `Schedule::push`:
//!   counts aircraft that came back to the ground, from the `FlightStatus`
//!   component every model's aircraft carry.
//!
//! `cargo run -p fdm-ecs --example mixed_fleet`

use std::error::Error;
use std::sync::Arc;

use fdm_core::bourg::Bourg;
use fdm_core::model::{FlightStatus, Model};
use fdm_core::palmer::Palmer;
use fdm_ecs::components::Params;
use fdm_ecs::{Entity, Execution, FleetOutputs, Resources, Schedule, Simulation, System, World};

/// Aircraft per model.
const PER_MODEL: usize = 100;

/// Frames to fly at 30 frames per second (20 s).
const FRAMES: u64 = 600;

/// The highest height above the ground plane reached so far, m.
#[derive(Debug, Clone, Copy, PartialEq)]
struct MaxHeight(f64);

/// Set once an aircraft is back on the ground after flying, with the frame
/// it happened on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct TouchedDown {
    frame: u64,
}

/// Keeps [`MaxHeight`] up to date for the aircraft of model `M`. A system is a
/// plain `fn(&mut World, &Resources)`: one instantiation per model.
fn max_height<M: Model>(world: &mut World, _res: &Resources) {
    for (state, max) in world.query_mut::<(&M::State, &mut MaxHeight)>() {
        max.0 = max.0.max(M::height_m(state));
    }
}

/// Marks aircraft whose status says they have landed. Model-agnostic: every
/// aircraft entity has a [`FlightStatus`]. Structural changes (adding a
/// component) wait until the query is over.
fn touchdowns(world: &mut World, res: &Resources) {
    let landed: Vec<_> = world
        .query_mut::<(Entity, &FlightStatus)>()
        .without::<&TouchedDown>()
        .into_iter()
        .filter(|(_, status)| matches!(status, FlightStatus::Landed(_)))
        .map(|(entity, _)| entity)
        .collect();
    for entity in landed {
        // The entity came from the query just above, so it exists.
        let _ = world.insert_one(
            entity,
            TouchedDown {
                // During a frame, `frame` is that frame's 1-based number.
                frame: res.frame,
            },
        );
    }
}

/// The aircraft of model `M`: the entities with its [`Params`] component.
fn entities_of<M: Model>(world: &mut World) -> Vec<Entity> {
    world
        .query_mut::<(Entity, &Params<M>)>()
        .into_iter()
        .map(|(entity, _)| entity)
        .collect()
}

fn main() -> Result<(), Box<dyn Error>> {
    let resources = Resources::new(30.0)?.with_execution(Execution::Parallel);
    let mut sim = Simulation::new(resources);
    let cessna = Arc::new(Palmer::default_aircraft());
    // The demonstration fleets: full aircraft (with their FlightGear datagram).
    sim.spawn_fleet::<Palmer>(&cessna, 0..PER_MODEL, FleetOutputs::Placement);
    let bourg = Arc::new(Bourg::default_aircraft());
    sim.spawn_fleet::<Bourg>(&bourg, 0..PER_MODEL, FleetOutputs::Placement);
    let mut palmers = entities_of::<Palmer>(sim.world_mut());
    let bourgs = entities_of::<Bourg>(sim.world_mut());
    // Plus a few Cessnas on final approach: engine idle, 30 to 70 m up.
    for i in 0..5_u32 {
        let (mut controls, mut state) = Palmer::fleet_member(PER_MODEL + i as usize);
        controls.throttle = 0.0;
        state.position_m.z = 30.0 + 10.0 * f64::from(i);
        palmers.push(sim.spawn::<Palmer>(Arc::clone(&cessna), controls, state));
    }
    for &entity in palmers.iter().chain(&bourgs) {
        sim.world_mut().insert_one(entity, MaxHeight(0.0))?;
    }

    let schedule = sim.schedule_mut();
    for run in [
        max_height::<Palmer> as fn(&mut World, &Resources),
        max_height::<Bourg>,
    ] {
        let system = System {
            name: "MaxHeight",
            run,
        };
        if !schedule.insert_after(Schedule::FLIGHT_STATUS, system) {
            return Err("the schedule has no FlightStatus system".into());
        }
    }
    schedule.push(System {
        name: "Touchdowns",
        run: touchdowns,
    });
    let order: Vec<&str> = sim.schedule().systems().iter().map(|s| s.name).collect();
    println!("schedule: {}", order.join(" → "));

    sim.run_frames(FRAMES);

    for (title, fleet) in [(Palmer::TITLE, &palmers), (Bourg::TITLE, &bourgs)] {
        let world = sim.world();
        let highest = fleet
            .iter()
            .filter_map(|&e| world.get::<&MaxHeight>(e).ok().map(|m| m.0))
            .fold(f64::NEG_INFINITY, f64::max);
        let landed = fleet
            .iter()
            .filter(|&&e| world.get::<&TouchedDown>(e).is_ok())
            .count();
        let first = fleet
            .iter()
            .filter_map(|&e| world.get::<&TouchedDown>(e).ok().map(|t| t.frame))
            .min();
        println!(
            "{title}: {} aircraft, highest {highest:.0} m, {landed} touched down{}",
            fleet.len(),
            first.map_or_else(String::new, |f| format!(" (first on frame {f})")),
        );
    }
    println!(
        "{} frames, t = {:.2} s",
        sim.frame(),
        sim.frame() as f64 / 30.0
    );
    Ok(())
}
