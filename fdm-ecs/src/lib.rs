//! The thin Entity-Component-System shell around `fdm-core` (thesis chapter III):
//! hecs components for aircraft parameters, state, controls and FlightGear
//! packets; the FlightControl → EquationsOfMotion → MakePacket → SendPacket
//! systems run in a fixed order; geodesy from the model's earth frame to WGS-84;
//! many aircraft of both models per world, stepped in parallel.
//!
//! * [`components`]: what an aircraft entity is made of (shared parameters,
//!   controls, state, frame input, geodetic position, attitude, packet,
//!   optional FlightGear link).
//! * [`Resources`]: frame rate and both time steps, Bourg's thrust limits,
//!   the geodetic origin, the frame counter, sequential or parallel execution.
//! * [`systems`]: the four systems, each documenting what it reads and writes.
//! * [`Schedule`]: their fixed order.
//! * [`Simulation`]: all of it behind `spawn_*`, `push_input`, `set_script`,
//!   `run_frame` and accessors.
//! * [`geodesy`]: model frame → WGS-84 and FlightGear attitude.
//!
//! Stepping through the ECS gives the same bits as calling `fdm-core`
//! directly (`tests/ecs_parity.rs`), in either execution mode.
//!
//! # The thesis's names
//!
//! | thesis (figures 10–12) | here |
//! |---|---|
//! | `DataFDM` (one component per aircraft) | split: [`components::PalmerParams`] / [`components::BourgParams`] (shared), `PalmerControls` / `BourgControls`, `PalmerState` / `BourgState` |
//! | `KeyboardState` | [`components::FrameInput`] (+ [`components::ScriptInput`]) |
//! | `FGNetFDM` | `fgnet::FgNetFdm`, plus [`components::Geodetic`] and [`components::Attitude`] |
//! | (socket opened in SendPacket) | [`FlightGearLink`], optional per entity |
//! | `DeltaTime`, `MaxThrust`, `DeltaThrust` | [`Resources::dt_palmer_s`], [`Resources::dt_bourg_s`], [`Resources::max_thrust_lb`], [`Resources::delta_thrust_lb`] |
//! | FlightControl → EquationsOfMotion → MakePacket → SendPacket | [`systems::flight_control`], [`systems::equations_of_motion`], [`systems::make_packet`], [`systems::send_packet`] in [`Schedule::thesis`] |
//!
//! # Example: two aircraft, one per model
//!
//! ```
//! use std::sync::Arc;
//! use fdm_core::bourg::{Aircraft, BourgAction, BourgControls, BourgState};
//! use fdm_core::palmer::{PalmerAction, PalmerAircraft, PalmerControls, PalmerState};
//! use fdm_core::script::Script;
//! use fdm_ecs::{Resources, Simulation};
//!
//! let mut sim = Simulation::new(Resources::new(30.0)?);
//! let palmer = sim.spawn_palmer(
//!     Arc::new(PalmerAircraft::cessna_172()),
//!     PalmerControls::default(),
//!     PalmerState::at_rest(),
//!     None, // or Some(FlightGearLink::connect("127.0.0.1:5500")?)
//! );
//! let bourg = sim.spawn_bourg(
//!     Arc::new(Aircraft::bourg_default()),
//!     BourgControls::initial(),
//!     BourgState::initial(),
//!     None,
//! );
//! // Bourg flies a script; Palmer gets key presses.
//! sim.set_script(bourg, Arc::new(Script::<BourgAction>::parse("1-5 thrust-up\n")?))?;
//! for _ in 0..20 {
//!     sim.push_input(palmer, PalmerAction::ThrottleUp)?;
//! }
//! sim.run_frames(60);
//!
//! assert_eq!(sim.palmer_controls(palmer).unwrap().throttle, 1.0);
//! assert_eq!(sim.bourg_controls(bourg).unwrap().thrust_lb, 1000.0);
//! let cessna = sim.palmer_state(palmer).unwrap();
//! assert!(cessna.velocity_mps.x > 0.0);
//! // Where FlightGear would draw it: due north of the runway origin.
//! let here = sim.geodetic(palmer).unwrap();
//! assert!(here.lat_deg > 39.8264);
//! assert!(sim.send_stats(palmer).is_none()); // no link, nothing sent
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod components;
/// Geodesy lives in `fdm-core` (pure maths); re-exported here for the shell's users.
pub use fdm_core::geodesy;
mod resources;
mod schedule;
mod simulation;
pub mod systems;

pub use components::FlightGearLink;
/// The ECS crate this shell is built on (for `Entity`, `World` and queries).
pub use hecs;
pub use hecs::{Entity, World};
pub use resources::{Execution, Resources};
pub use schedule::{Schedule, System};
pub use simulation::Simulation;

/// Errors of this crate: a bad frame rate, or an entity that is not (or no
/// longer) an aircraft of the model an operation needs.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum EcsError {
    /// The frame rate is not a finite number above 0 frames per second.
    #[error("the frame rate must be a finite number of frames per second above 0, got {fps}")]
    InvalidFps {
        /// The rate given.
        fps: f64,
    },
    /// The entity does not exist (never spawned here, or despawned).
    #[error("no such entity")]
    NoSuchEntity,
    /// The entity lacks a component the operation needs, i.e. it is an
    /// aircraft of the other model (e.g. a Bourg action pushed to a Palmer
    /// aircraft).
    #[error("the entity has no `{component}` component: it is not an aircraft of that model")]
    MissingComponent {
        /// The missing component's type name.
        component: &'static str,
    },
}

impl EcsError {
    /// [`EcsError::MissingComponent`] for component `T`.
    #[must_use]
    pub fn missing<T: ?Sized>() -> Self {
        Self::MissingComponent {
            component: std::any::type_name::<T>(),
        }
    }

    /// Maps a hecs lookup error about component `T`.
    fn component<T: ?Sized>(error: &hecs::ComponentError) -> Self {
        match error {
            hecs::ComponentError::NoSuchEntity => Self::NoSuchEntity,
            hecs::ComponentError::MissingComponent(_) => Self::missing::<T>(),
        }
    }
}
