//! The components of an aircraft entity.
//!
//! The thesis's single `DataFDM` component (parameters, mass properties, state
//! and controls in one struct, copied into every entity) is split, as its
//! future-work section suggests, into pieces each system takes only what it
//! needs of:
//!
//! | component | Palmer entity | Bourg entity | written by |
//! |---|---|---|---|
//! | shared parameters | [`PalmerParams`] | [`BourgParams`] | spawn only |
//! | controls | [`PalmerControls`] | [`BourgControls`] | FlightControl |
//! | state | [`PalmerState`] | [`BourgState`] | EquationsOfMotion |
//! | this frame's input | [`PalmerInput`] | [`BourgInput`] | the caller (keyboard), emptied by FlightControl |
//! | scripted input (optional) | [`ScriptInput<PalmerAction>`] | [`ScriptInput<BourgAction>`] | spawn / the caller |
//! | geodetic position | [`Geodetic`] | [`Geodetic`] | MakePacket |
//! | attitude as sent to FlightGear | [`Attitude`] | [`Attitude`] | MakePacket |
//! | the datagram | [`FgNetFdm`] | [`FgNetFdm`] | MakePacket |
//! | where it goes (optional) | [`FlightGearLink`] | [`FlightGearLink`] | SendPacket (its counters) |
//!
//! An entity's model is given by which parameter component it has. State,
//! controls, position, attitude and packet are the plain types of `fdm-core`,
//! the geodesy module and `fgnet`, used as components directly.
//!
//! # Shared parameters: `Arc`, not a copy and not a table index
//!
//! [`PalmerParams`] and [`BourgParams`] hold an [`Arc`] of the model's
//! parameters, so every aircraft of one type points at the same data: 8 bytes
//! per entity instead of a copy (a Bourg [`Aircraft`] with its mass properties
//! is 680 bytes, a [`PalmerAircraft`] 128, against an 84-byte Bourg and a
//! 56-byte Palmer state),
//! and the one shared copy stays in the cache while a fleet is stepped. An
//! index into a per-type table in the resources would be as small, but every
//! system would then need the table, spawning would need to register it, and
//! the index could dangle; the `Arc` keeps each entity self-contained and
//! allows any number of aircraft types in one world. The reference count is
//! touched only at spawn and despawn, never per frame. The
//! `benches/ecs_fleet.rs` comparison against a plain loop over a `Vec` with a
//! single `&Aircraft` measures what the indirection costs.

use std::io;
use std::ops::Deref;
use std::sync::Arc;

use fdm_core::bourg::{Aircraft, BourgAction};
use fdm_core::palmer::{PalmerAction, PalmerAircraft};
use fdm_core::script::Script;
use fgnet::{SendOutcome, Sender, SenderError, SenderStats};

pub use crate::geodesy::{Attitude, Geodetic};
pub use fdm_core::bourg::{BourgControls, BourgState};
pub use fdm_core::palmer::{PalmerControls, PalmerState};
pub use fgnet::FgNetFdm;

/// The Palmer parameters of an entity (wing, mass, engine, propeller), shared
/// by every aircraft of the same type. Its presence makes an entity a Palmer
/// aircraft.
#[derive(Debug, Clone, PartialEq)]
pub struct PalmerParams(pub Arc<PalmerAircraft>);

impl Deref for PalmerParams {
    type Target = PalmerAircraft;

    fn deref(&self) -> &PalmerAircraft {
        &self.0
    }
}

/// The Bourg airframe with its mass properties, shared by every aircraft of
/// the same type. Its presence makes an entity a Bourg aircraft.
#[derive(Debug, Clone, PartialEq)]
pub struct BourgParams(pub Arc<Aircraft>);

impl Deref for BourgParams {
    type Target = Aircraft;

    fn deref(&self) -> &Aircraft {
        &self.0
    }
}

/// The control actions of one frame (the thesis's `KeyboardState`): what the
/// keyboard or another caller pushed since the last frame, in order.
///
/// FlightControl applies the frame's script actions (if the entity has a
/// [`ScriptInput`]) and then these, as if each key had been pressed once, and
/// empties the list. Pushing the same action twice presses it twice.
///
/// An empty `FrameInput` does not allocate; once used, it keeps its capacity.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameInput<A> {
    actions: Vec<A>,
}

impl<A> FrameInput<A> {
    /// An empty input.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            actions: Vec::new(),
        }
    }

    /// Queues `action` for the next frame, after those already queued.
    pub fn push(&mut self, action: A) {
        self.actions.push(action);
    }

    /// The queued actions, in the order they will be applied.
    #[must_use]
    pub fn actions(&self) -> &[A] {
        &self.actions
    }

    /// Whether nothing is queued.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.actions.is_empty()
    }

    /// Removes and returns the queued actions in order, keeping the capacity.
    pub fn drain(&mut self) -> std::vec::Drain<'_, A> {
        self.actions.drain(..)
    }
}

impl<A> Default for FrameInput<A> {
    fn default() -> Self {
        Self::new()
    }
}

/// Input of a Palmer aircraft.
pub type PalmerInput = FrameInput<PalmerAction>;
/// Input of a Bourg aircraft.
pub type BourgInput = FrameInput<BourgAction>;

/// A control script driving an entity: on frame `n` (1-based,
/// [`Resources::frame`](crate::Resources::frame)) FlightControl applies
/// [`Script::actions_at`]`(n)` before the frame's [`FrameInput`].
///
/// The script is shared (`Arc`), so a fleet can fly one script without copies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptInput<A>(pub Arc<Script<A>>);

/// Where an entity's FlightGear datagrams go: a connected [`fgnet::Sender`],
/// with the error of its first failed send kept for the caller to report.
///
/// Entities without a link are simulated and get their [`FgNetFdm`] built,
/// but SendPacket sends nothing for them.
#[derive(Debug)]
pub struct FlightGearLink {
    sender: Sender,
    first_failure: Option<io::Error>,
}

impl FlightGearLink {
    /// Opens a UDP socket sending to `addr` (`"HOST:PORT"`, e.g.
    /// `"127.0.0.1:5500"`); see [`Sender::connect`]. Nothing is sent yet, so
    /// this succeeds whether or not FlightGear listens.
    ///
    /// # Errors
    /// [`SenderError`] when the address does not resolve or the socket cannot
    /// be set up.
    pub fn connect(addr: &str) -> Result<Self, SenderError> {
        Sender::connect(addr).map(Self::new)
    }

    /// A link using an existing sender.
    #[must_use]
    pub const fn new(sender: Sender) -> Self {
        Self {
            sender,
            first_failure: None,
        }
    }

    /// Sends one datagram (called by SendPacket). A failure is counted in
    /// [`stats`](Self::stats); the first one's error is kept for
    /// [`take_first_failure`](Self::take_first_failure).
    pub fn send(&mut self, packet: &FgNetFdm) {
        if let SendOutcome::FirstFailure(error) = self.sender.send(packet) {
            self.first_failure = Some(error);
        }
    }

    /// Datagrams sent and failed so far.
    #[must_use]
    pub fn stats(&self) -> SenderStats {
        self.sender.stats()
    }

    /// The error of the first failed send, once (later calls return `None`;
    /// later failures are only counted).
    pub fn take_first_failure(&mut self) -> Option<io::Error> {
        self.first_failure.take()
    }

    /// The sender.
    #[must_use]
    pub fn sender(&self) -> &Sender {
        &self.sender
    }
}
