//! The deterministic per-frame order of the systems (the thesis's figure 12).
//!
//! The thesis found that its dispatcher, left to itself, could run the
//! systems in a different order from frame to frame; here the order is a list
//! run front to back, every frame.

use hecs::World;

use crate::resources::Resources;
use crate::systems::{equations_of_motion, flight_control, make_packet, send_packet};

/// A system: a named function over the world and the resources.
#[derive(Debug, Clone, Copy)]
pub struct System {
    /// The system's name, e.g. `"EquationsOfMotion"`.
    pub name: &'static str,
    /// The function run once per frame.
    pub run: fn(&mut World, &Resources),
}

/// Systems run one after the other, in a fixed order, once per frame.
#[derive(Debug, Clone)]
pub struct Schedule {
    systems: Vec<System>,
}

impl Schedule {
    /// The name of [`flight_control`].
    pub const FLIGHT_CONTROL: &'static str = "FlightControl";
    /// The name of [`equations_of_motion`].
    pub const EQUATIONS_OF_MOTION: &'static str = "EquationsOfMotion";
    /// The name of [`make_packet`].
    pub const MAKE_PACKET: &'static str = "MakePacket";
    /// The name of [`send_packet`].
    pub const SEND_PACKET: &'static str = "SendPacket";

    /// The thesis's order: FlightControl → EquationsOfMotion → MakePacket →
    /// SendPacket.
    #[must_use]
    pub fn thesis() -> Self {
        Self::new(vec![
            System {
                name: Self::FLIGHT_CONTROL,
                run: flight_control,
            },
            System {
                name: Self::EQUATIONS_OF_MOTION,
                run: equations_of_motion,
            },
            System {
                name: Self::MAKE_PACKET,
                run: make_packet,
            },
            System {
                name: Self::SEND_PACKET,
                run: send_packet,
            },
        ])
    }

    /// A schedule running `systems` in the given order.
    #[must_use]
    pub const fn new(systems: Vec<System>) -> Self {
        Self { systems }
    }

    /// The systems, in the order they run.
    #[must_use]
    pub fn systems(&self) -> &[System] {
        &self.systems
    }

    /// Runs one frame: increments [`Resources::frame`], then runs every system
    /// in order.
    pub fn run(&self, world: &mut World, res: &mut Resources) {
        self.run_observed(world, res, |_, _| {});
    }

    /// [`Schedule::run`], calling `observer` with each system's name and the
    /// world right after that system has run (for tracing and tests).
    pub fn run_observed(
        &self,
        world: &mut World,
        res: &mut Resources,
        mut observer: impl FnMut(&'static str, &World),
    ) {
        res.frame += 1;
        for system in &self.systems {
            (system.run)(world, res);
            observer(system.name, world);
        }
    }
}

impl Default for Schedule {
    /// [`Schedule::thesis`].
    fn default() -> Self {
        Self::thesis()
    }
}
