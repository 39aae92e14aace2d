//! DIS (IEEE 1278.1) Entity State output for the flight models, built on
//! the `dis-rs` crate.
//!
//! (Full description below is completed in the crate docs.)

pub mod dead_reckoning;
pub mod entity;
pub mod error;
pub mod frames;
pub mod listener;
pub mod publisher;

/// The project's WGS-84 geodesy (the one place this crate names its home).
pub use fdm_ecs::geodesy;

pub use dead_reckoning::{extrapolate, DeadReckoner, DrError, DrThresholds, SendReason};
pub use entity::{
    dis_timestamp, encode_entity_state, entity_state_pdu, AircraftKind, DisVersion, DrAlgorithm,
    EntityConfig, EntityIdentity, Marking, WireState, ENTITY_STATE_PDU_LEN,
};
pub use error::DisOutputError;
pub use frames::{
    ecef_vector_to_ned, local_from_ecef, ned_to_ecef_rotation, rotation_angle_between,
    AircraftState, DisEuler, EcefState,
};
pub use listener::{decode_datagram, DecodeError, EntityRecord, Listener, ListenerStats};
pub use publisher::{Due, EntityPublisher, PublisherCounts, UdpSender};

/// The dis-rs crate, for its enumerations (`ForceId`, `Country`, …) and PDU
/// model.
pub use dis_rs;
