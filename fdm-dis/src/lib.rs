//! DIS (IEEE 1278.1) Entity State output for the flight models, built on
//! the [`dis_rs`] crate (0.14, DIS 6 and 7).
//!
//! A shell that flies one or more aircraft gives each of them an
//! [`EntityPublisher`] and calls [`EntityPublisher::update`] once per frame
//! with an [`AircraftState`]. When the sender-side dead-reckoning model says
//! receivers' pictures have drifted too far (or the heartbeat is due), the
//! call returns the bytes of one Entity State PDU, ready for one UDP datagram
//! ([`UdpSender`]). The [`Listener`] is the other end: it decodes datagrams,
//! counts them and keeps each entity's last state in geodetic terms.
//!
//! ```
//! use fdm_dis::geodesy::{Attitude, Geodetic};
//! use fdm_dis::{AircraftKind, AircraftState, DrThresholds, EntityConfig, EntityIdentity,
//!               EntityPublisher, Listener, Marking};
//! use nalgebra::Vector3;
//!
//! let config = EntityConfig::new(
//!     EntityIdentity::new(1, 1, 1)?,        // site, application, entity
//!     AircraftKind::CESSNA_172_SKYHAWK,              // entity type 1.2.225.85.11.1.0
//!     Marking::new("N172SP")?,              // callsign, ≤ 11 ASCII characters
//! );                                        // DIS 7, DRM(R,V,W), Friendly, exercise 1
//! let mut out = EntityPublisher::new(config, DrThresholds::default())?;
//! let mut listener = Listener::new();
//!
//! for k in 0..=600 {
//!     let t = f64::from(k) / 60.0; // 10 s at 60 Hz, flying north at 50 m/s
//!     let state = AircraftState::new(
//!         t,
//!         Geodetic { lat_deg: 39.8264 + 50.0 * t / 111_030.0, lon_deg: -84.0483, alt_m: 600.0 },
//!         Attitude { heading_deg: 0.0, pitch_deg: 2.0, roll_deg: 0.0 },
//!         Vector3::new(50.0, 0.0, 0.0),
//!     );
//!     if let Some(due) = out.update(&state)? {
//!         // udp.send(due.bytes)?;
//!         listener.ingest(due.bytes)?;
//!     }
//! }
//! // Straight and level: the first PDU and two heartbeats (t = 5 s, 10 s).
//! assert_eq!(out.counts().sent, 3);
//! assert_eq!(listener.entity_count(), 1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # What is sent
//!
//! One Entity State PDU per aircraft, 144 bytes (no variable parameters),
//! written by dis-rs in DIS 7 (IEEE 1278.1-2012) by default or DIS 6
//! (IEEE 1278.1a-1998) on request ([`DisVersion`]):
//!
//! | field | value |
//! | --- | --- |
//! | header | protocol version 7 (or 6), exercise id (default 1), PDU type 1, family 1, timestamp, length 144 |
//! | entity id | site, application, entity ([`EntityIdentity`]) |
//! | force id | default Friendly (1) |
//! | entity type | per model, see below; alternative type all zero |
//! | linear velocity | ECEF, m/s (`f32`) |
//! | location | ECEF, m (`f64`) |
//! | orientation | ψ, θ, φ, radians (`f32`), body relative to ECEF |
//! | appearance | 0 (air platform, nothing special) |
//! | dead reckoning | algorithm (default DRM(R,V,W) = 4), 15 zero bytes of "other parameters", linear acceleration (ECEF, m/s²) and angular velocity (body axes, rad/s), each zero when the algorithm does not use it |
//! | marking | character set 1 (ASCII), the callsign padded with spaces to 11 |
//! | capabilities | 0 |
//!
//! The timestamp counts simulation time (not wall-clock time) within the
//! hour in units of 3600 s / 2³¹, flagged *relative* ([`dis_timestamp`]).
//!
//! # Entity types (SISO-REF-010)
//!
//! Kind.domain.country.category.subcategory.specific.extra, from the DIS
//! enumerations document SISO-REF-010 (version 35, the one dis-rs 0.14 is
//! generated from):
//!
//! * Palmer's Cessna 172: **1.2.225.85.11.1.0**: platform, air, USA,
//!   "Civilian Fixed Wing Aircraft, Small (up to 12,500 lbs / 5,670 kg)",
//!   "Single Piston Engine", "Cessna 172 Skyhawk". (The document also has a
//!   Cessna 172 under "Trainer", 1.2.225.40.1: the military T-41; the civil
//!   entry is the right one for a civil Skyhawk.)
//! * Bourg's generic aircraft: **1.2.0.85.0.0.0**: platform, air, country
//!   "Other", small civil fixed-wing, subcategory "Other". It is no real type
//!   and no nation's design, so only its class is stated.
//!
//! Other types can be set directly in [`EntityConfig::entity_type`].
//!
//! # Frames
//!
//! The input is what a flight model shell has ([`AircraftState`]): WGS-84
//! latitude/longitude (degrees) and height above the ellipsoid (metres);
//! heading (clockwise from true north), pitch (nose up +) and roll (right
//! wing down +) relative to local north-east-down; velocity (and optionally
//! acceleration) in local NED; optionally the body angular velocity.
//!
//! DIS works in the Earth-centred, Earth-fixed frame (x to 0°/0°, y to
//! 0°/90° E, z to the north pole). The location is the exact closed-form
//! geodetic → ECEF conversion of the project's geodesy. The orientation is
//! the rotation from body axes (x forward, y right wing, z down) to ECEF,
//! `C_ecef←body = C_ecef←ned(lat, lon) · C_ned←body(heading, pitch, roll)`,
//! written as DIS's Z-Y-X Euler angles: `C_ecef←body = Rz(ψ) Ry(θ) Rx(φ)`
//! ([`DisEuler::from_body_to_ecef`]). Velocity and acceleration are rotated
//! by `C_ecef←ned`; the angular velocity stays in body axes, as DIS wants it.
//! A level aircraft heading north on the equator at 0° longitude has its
//! nose along ECEF +z: ψ = 0, θ = -90°, φ = 0. At θ = ±90° the standard's
//! angles are degenerate; φ is then 0 and the rotation about z goes into ψ
//! (it is still the same rotation). The [`frames`] module has the inverse
//! used by the listener.
//!
//! # Dead reckoning
//!
//! Receivers extrapolate each entity between PDUs with the algorithm the PDU
//! names. This crate supports the four with world-frame rates:
//! DRM(F,P,W) (2), DRM(R,P,W) (3), DRM(R,V,W) (4, default) and DRM(F,V,W)
//! (5) ([`DrAlgorithm`]): P models move the last position along the last
//! velocity, V models add half the acceleration times Δt²; R models turn
//! the last orientation at the last body angular velocity, F models hold it.
//!
//! The sender runs the very same extrapolation on exactly what it sent last
//! (the `f32`-rounded values, [`WireState`]) and sends a new PDU only when
//!
//! * the extrapolated position is more than 1 m from the true one, or
//! * the extrapolated orientation is more than 3° from the true one (the
//!   angle of the single rotation between them), or
//! * 5 s have passed since the last PDU (the heartbeat, so late joiners and
//!   receivers that lost a datagram catch up),
//!
//! plus the first PDU and after the simulation clock went backwards. The
//! three numbers are configurable per entity ([`DrThresholds`]). Straight
//! and level flight then costs one PDU per 5 s; a 30° banked turn at 60 m/s
//! about one per 0.55 s with DRM(F,P,W) and one per 2.2 s with DRM(R,V,W)
//! (see `tests/dead_reckoning.rs`).
//!
//! # Receiving
//!
//! [`Listener::ingest`] takes any bytes. It splits a datagram on the PDU
//! lengths in the headers (checking each against what is left), hands each
//! PDU to dis-rs, and applies the datagram only if every PDU decoded;
//! otherwise the datagram is counted as malformed and skipped. It never
//! panics: dis-rs 0.14 itself can (fuzzing found malformed Signal PDUs that
//! make it slice out of range, and Transmitter PDUs that make it subtract
//! with overflow), so it is called under `catch_unwind` and a
//! panic there is counted as a malformed datagram and separately
//! (`decoder_panics`); this relies on the default `panic = "unwind"`. It counts datagrams, bytes, PDUs, Entity State
//! PDUs, malformed datagrams and distinct entities, and keeps each entity's
//! last location and orientation, converted back to latitude, longitude,
//! height and heading, pitch, roll ([`EntityRecord`]).

pub mod dead_reckoning;
pub mod entity;
pub mod error;
pub mod fleet;
pub mod frames;
pub mod listen;
pub mod listener;
pub mod publisher;
mod screen;
pub mod tracker;

/// The project's WGS-84 geodesy (the one place this crate names its home).
pub use fdm_core::geodesy;

pub use dead_reckoning::{extrapolate, DeadReckoner, DrError, DrThresholds, SendReason};
pub use entity::{
    dis_timestamp, encode_entity_state, entity_state_pdu, type_label, AircraftKind, DisVersion,
    DrAlgorithm, EntityConfig, EntityIdentity, Marking, WireState, ENTITY_STATE_PDU_LEN,
};
pub use error::DisOutputError;
pub use fleet::{FleetPublisher, ScreenedPiece, FLEET_BATCH};
pub use frames::{
    ecef_vector_to_ned, local_from_ecef, ned_to_ecef_rotation, rotation_angle_between,
    AircraftState, DisEuler, EcefState,
};
pub use listener::{decode_datagram, DecodeError, EntityRecord, Listener, ListenerStats};
pub use publisher::{Due, EntityPublisher, PublisherCounts, UdpSender};
pub use screen::{RoughFrames, RoughLanes, ROUGH_LANES, ROUGH_TOLERANCE};
pub use tracker::{rotation_vector, Placed, Placement, ReasonCounts, Rough, Tally, Tracker};

/// The dis-rs crate, for its enumerations (`ForceId`, `Country`, …) and PDU
/// model.
pub use dis_rs;

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
