//! The thin Entity-Component-System shell around `fdm-core` (thesis chapter
//! III): hecs components for any [`Model`](fdm_core::model::Model)'s
//! parameters, state, controls and placement on WGS-84; the FlightControl →
//! EquationsOfMotion → FlightStatus → Place systems, generic over the model,
//! run in a fixed order; aircraft of any number of models per world, stepped
//! in parallel. No wire format lives here: the FlightGear link, DIS and the
//! other outputs are the run library's (`fdm_run`), fed by the placement
//! Place computes once per frame.
//!
//! * [`components`]: what an aircraft entity is made of.
//! * [`Resources`]: frame rate, geodetic origin, frame counter, sequential or
//!   parallel execution.
//! * [`systems`]: the systems, each documenting what it reads and writes.
//! * [`Schedule`]: their fixed order; each model adds its instantiations.
//! * [`Simulation`]: all of it behind `spawn::<M>`, `push_input`,
//!   `set_script`, `run_frame` and accessors.
//!
//! Geodesy is pure maths and lives in `fdm_core::geodesy` (re-exported as
//! [`geodesy`]); [`systems::placement`] places a model's view with it; the
//! mapping of a view to FlightGear's fields is `fgnet::bridge`. Stepping through the ECS gives the same bits as calling
//! `fdm-core` directly (`tests/ecs_parity.rs`), in either execution mode.
//!
//! # The thesis's names
//!
//! | thesis (figures 10–12) | here |
//! |---|---|
//! | `DataFDM` (one component per aircraft) | split: [`components::Params<M>`] (shared), `M::Controls`, `M::State` |
//! | `KeyboardState` | [`components::FrameInput`] (+ [`components::ScriptInput`]) |
//! | `FGNetFDM` | [`components::Geodetic`] and [`components::Attitude`] here; the datagram is `fdm_run::flightgear`'s |
//! | (socket opened in SendPacket) | `fdm_run::flightgear::FlightGearOutput`, an output of the run |
//! | `DeltaTime` | [`Resources::time_step`] |
//! | `MaxThrust`, `DeltaThrust` | Bourg's aircraft parameters (`max_thrust_lb`, `delta_thrust_lb`) |
//! | FlightControl → EquationsOfMotion → MakePacket → SendPacket | [`systems::flight_control`], [`systems::equations_of_motion`], [`systems::flight_status`], [`systems::place`] in each model's [`Schedule::with_model`]; the packet is made and sent by `fdm_run::flightgear::FlightGearOutput` |
//!
//! # Example: two aircraft, one per model
//!
//! ```
//! use std::sync::Arc;
//! use fdm_core::bourg::{Bourg, BourgAction};
//! use fdm_core::model::Model;
//! use fdm_core::palmer::{Palmer, PalmerAction};
//! use fdm_core::script::Script;
//! use fdm_ecs::{Resources, Simulation};
//!
//! let mut sim = Simulation::new(Resources::new(30.0)?);
//! let palmer = sim.spawn::<Palmer>(
//!     Arc::new(Palmer::default_aircraft()),
//!     Palmer::initial_controls(),
//!     Palmer::initial_state(),
//! );
//! let bourg = sim.spawn::<Bourg>(
//!     Arc::new(Bourg::default_aircraft()),
//!     Bourg::initial_controls(),
//!     Bourg::initial_state(),
//! );
//! // Bourg flies a script; Palmer gets key presses.
//! sim.set_script(bourg, Arc::new(Script::<BourgAction>::parse("1-5 thrust-up\n")?))?;
//! for _ in 0..20 {
//!     sim.push_input(palmer, PalmerAction::ThrottleUp)?;
//! }
//! sim.run_frames(60);
//!
//! assert_eq!(sim.controls::<Palmer>(palmer).unwrap().throttle, 1.0);
//! assert_eq!(sim.controls::<Bourg>(bourg).unwrap().thrust_lb, 1000.0);
//! let cessna = sim.state::<Palmer>(palmer).unwrap();
//! assert!(cessna.velocity_mps.x > 0.0);
//! // Where FlightGear would draw it: due north of the runway origin.
//! let here = sim.geodetic(palmer).unwrap();
//! assert!(here.lat_deg > 39.8264);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod components;
/// Geodesy lives in `fdm-core` (pure maths); re-exported here for the shell's users.
pub use fdm_core::geodesy;
mod resources;
mod schedule;
mod simulation;
pub mod systems;

/// The ECS crate this shell is built on (for `Entity`, `World` and queries).
pub use hecs;
pub use hecs::{Entity, World};
pub use resources::{Execution, Resources};
pub use schedule::{Schedule, System};
pub use simulation::{FleetOutputs, Simulation};

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

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
