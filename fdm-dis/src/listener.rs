//! The receiving side: decode DIS datagrams with dis-rs, count what arrives,
//! and keep each entity's last state converted back to geodetic terms.
//!
//! A datagram may hold several PDUs back to back. Each PDU's header says its
//! length; the datagram is split on those lengths here (first checking that
//! every length is at least a header and fits in what is left) and each
//! piece is handed to dis-rs alone, so the parser never sees bytes of the
//! next PDU or reads past the declared length. A datagram is taken whole or
//! not at all: if any piece fails, the datagram is counted as malformed and
//! nothing from it is applied.
//!
//! dis-rs 0.14 can panic on malformed input: the cargo-fuzz target found a
//! Signal PDU whose "application specific" encoding has less data than the
//! parser slices (see `tests/listener.rs`), and a Transmitter PDU whose
//! variable parameter record is shorter than its header (an overflowing
//! subtraction, a panic where overflow checks are on). dis-rs is therefore
//! called under
//! `catch_unwind`; such a datagram is counted as malformed and in
//! [`ListenerStats::decoder_panics`]. That guard needs the default
//! `panic = "unwind"` (the workspace's setting); with `panic = "abort"` the
//! process would end.

use std::collections::BTreeMap;

use dis_rs::enumerations::{EntityMarkingCharacterSet, ForceId};
use dis_rs::model::{EntityType, Pdu, PduBody};
use nalgebra::Vector3;
use thiserror::Error;

use crate::entity::{DrAlgorithm, EntityIdentity};
use crate::frames::{ecef_vector_to_ned, local_from_ecef, DisEuler};
use crate::geodesy::{Attitude, Geodetic};

/// DIS PDU header length, bytes (both versions).
pub const PDU_HEADER_LEN: usize = 12;

/// Why a datagram was rejected.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum DecodeError {
    /// Fewer bytes left than a PDU header.
    #[error("{left} bytes at offset {offset}: shorter than a PDU header")]
    ShortHeader {
        /// Offset of the piece in the datagram.
        offset: usize,
        /// Bytes left.
        left: usize,
    },
    /// The header's length field is below the header size or beyond the
    /// datagram.
    #[error("PDU at offset {offset} declares {declared} bytes, {left} left")]
    BadLength {
        /// Offset of the PDU in the datagram.
        offset: usize,
        /// The header's PDU length.
        declared: usize,
        /// Bytes left from the offset.
        left: usize,
    },
    /// dis-rs could not parse the PDU.
    #[error("PDU at offset {offset}: {message}")]
    Parse {
        /// Offset of the PDU in the datagram.
        offset: usize,
        /// dis-rs's message.
        message: String,
    },
    /// dis-rs panicked on the PDU (caught; a bug to report upstream).
    #[error("PDU at offset {offset}: the decoder panicked")]
    DecoderPanic {
        /// Offset of the PDU in the datagram.
        offset: usize,
    },
}

/// Splits a datagram into PDUs and decodes each with dis-rs. Never panics,
/// whatever the bytes (dis-rs is called under `catch_unwind` as a last line
/// of defence; a panic there comes back as [`DecodeError::DecoderPanic`]).
///
/// # Errors
/// The first piece that does not decode.
pub fn decode_datagram(datagram: &[u8]) -> Result<Vec<Pdu>, DecodeError> {
    let mut pdus = Vec::new();
    // The bytes not split off yet. Each turn splits off at least a header,
    // so the loop ends whatever the lengths say (with a running offset
    // added to instead, one wrong step, `offset *= declared` for one, would
    // loop for ever, appending PDUs until memory runs out).
    let mut rest = datagram;
    while !rest.is_empty() {
        let offset = datagram.len() - rest.len();
        if rest.len() < PDU_HEADER_LEN {
            return Err(DecodeError::ShortHeader {
                offset,
                left: rest.len(),
            });
        }
        let declared = usize::from(u16::from_be_bytes([rest[8], rest[9]]));
        if declared < PDU_HEADER_LEN || declared > rest.len() {
            return Err(DecodeError::BadLength {
                offset,
                declared,
                left: rest.len(),
            });
        }
        let (piece, after) = rest.split_at(declared);
        let parsed = std::panic::catch_unwind(|| dis_rs::parse(piece))
            .map_err(|_| DecodeError::DecoderPanic { offset })?;
        let mut got = parsed.map_err(|e| DecodeError::Parse {
            offset,
            message: e.to_string(),
        })?;
        // The piece holds exactly one PDU by its declared length; dis-rs
        // returns what it parsed from it.
        if got.len() != 1 {
            return Err(DecodeError::Parse {
                offset,
                message: format!("{} PDUs in one declared length", got.len()),
            });
        }
        pdus.append(&mut got);
        rest = after;
    }
    if pdus.is_empty() {
        return Err(DecodeError::ShortHeader { offset: 0, left: 0 });
    }
    Ok(pdus)
}

/// What a receiver knows of one entity: its last Entity State PDU, in
/// geodetic terms.
#[derive(Debug, Clone, PartialEq)]
pub struct EntityRecord {
    /// Site, application, entity.
    pub id: EntityIdentity,
    /// DIS protocol version of the last PDU (6 or 7).
    pub protocol_version: u8,
    /// Exercise id of the last PDU.
    pub exercise_id: u8,
    /// Entity type.
    pub entity_type: EntityType,
    /// Force.
    pub force: ForceId,
    /// Marking characters (as dis-rs returns them: trailing padding removed).
    pub marking: String,
    /// Whether the marking's character set was ASCII.
    pub marking_is_ascii: bool,
    /// Dead-reckoning model announced, if it is one of the four world models.
    pub dr_algorithm: Option<DrAlgorithm>,
    /// Raw DIS timestamp of the last PDU.
    pub timestamp: u32,
    /// Location, ECEF metres.
    pub location_m: Vector3<f64>,
    /// Orientation, DIS Euler angles.
    pub orientation: DisEuler,
    /// Position converted back to latitude, longitude, height.
    pub position: Geodetic,
    /// Attitude converted back to heading, pitch, roll relative to local NED.
    pub attitude: Attitude,
    /// Velocity converted back to local NED, m/s.
    pub velocity_ned_m_s: Vector3<f64>,
    /// Entity State PDUs received for this entity.
    pub updates: u64,
}

/// Counts kept by a [`Listener`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ListenerStats {
    /// Datagrams given to [`Listener::ingest`], good or bad.
    pub datagrams: u64,
    /// Bytes in those datagrams.
    pub bytes: u64,
    /// PDUs decoded from good datagrams, all types.
    pub pdus: u64,
    /// … of which Entity State PDUs.
    pub entity_state_pdus: u64,
    /// Datagrams rejected whole (see [`decode_datagram`]).
    pub malformed_datagrams: u64,
    /// … of which because dis-rs panicked (should stay 0).
    pub decoder_panics: u64,
    /// Entity State PDUs of entities not kept because the entity table was
    /// full ([`Listener::with_max_entities`]); counted, not stored.
    pub untracked_entity_pdus: u64,
}

/// A DIS receiver's bookkeeping: feed it datagrams, read counts and entities.
#[derive(Debug, Clone, Default)]
pub struct Listener {
    stats: ListenerStats,
    entities: BTreeMap<EntityIdentity, EntityRecord>,
    /// Most entities kept; `None`: no limit.
    max_entities: Option<usize>,
}

impl Listener {
    /// An empty listener that keeps every entity it hears of (memory grows
    /// with the number of distinct entities; see
    /// [`Listener::with_max_entities`] for a bound).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty listener that keeps at most `max` entities: once the table
    /// holds `max`, Entity State PDUs of further entities are counted in
    /// [`ListenerStats::untracked_entity_pdus`] and not stored, so memory
    /// stays bounded whatever arrives. Entities already kept go on being
    /// updated.
    #[must_use]
    pub fn with_max_entities(max: usize) -> Self {
        Self {
            max_entities: Some(max),
            ..Self::default()
        }
    }

    /// The bound set by [`Listener::with_max_entities`], if any.
    #[must_use]
    pub fn max_entities(&self) -> Option<usize> {
        self.max_entities
    }

    /// Takes one datagram: counts it and, if it decodes, its PDUs, and
    /// updates the entities of its Entity State PDUs. Never panics.
    ///
    /// # Errors
    /// Why the datagram was rejected (it is counted as malformed and
    /// skipped; the listener stays usable).
    pub fn ingest(&mut self, datagram: &[u8]) -> Result<usize, DecodeError> {
        self.stats.datagrams += 1;
        self.stats.bytes += datagram.len() as u64;
        let pdus = match decode_datagram(datagram) {
            Ok(p) => p,
            Err(e) => {
                self.stats.malformed_datagrams += 1;
                if matches!(e, DecodeError::DecoderPanic { .. }) {
                    self.stats.decoder_panics += 1;
                }
                return Err(e);
            }
        };
        for pdu in &pdus {
            self.stats.pdus += 1;
            if let PduBody::EntityState(es) = &pdu.body {
                self.stats.entity_state_pdus += 1;
                let id = EntityIdentity::from_dis(&es.entity_id);
                if let Some(max) = self.max_entities {
                    if self.entities.len() >= max && !self.entities.contains_key(&id) {
                        self.stats.untracked_entity_pdus += 1;
                        continue;
                    }
                }
                let location_m = Vector3::new(
                    es.entity_location.x_coordinate,
                    es.entity_location.y_coordinate,
                    es.entity_location.z_coordinate,
                );
                let orientation = DisEuler {
                    psi_rad: f64::from(es.entity_orientation.psi),
                    theta_rad: f64::from(es.entity_orientation.theta),
                    phi_rad: f64::from(es.entity_orientation.phi),
                };
                let (position, attitude) = local_from_ecef(location_m, orientation);
                let v = &es.entity_linear_velocity;
                let velocity_ned_m_s = ecef_vector_to_ned(
                    position,
                    Vector3::new(
                        f64::from(v.first_vector_component),
                        f64::from(v.second_vector_component),
                        f64::from(v.third_vector_component),
                    ),
                );
                let updates = self.entities.get(&id).map_or(0, |r| r.updates) + 1;
                self.entities.insert(
                    id,
                    EntityRecord {
                        id,
                        protocol_version: u8::from(pdu.header.protocol_version),
                        exercise_id: pdu.header.exercise_id,
                        entity_type: es.entity_type,
                        force: es.force_id,
                        marking: es.entity_marking.marking_string.clone(),
                        marking_is_ascii: es.entity_marking.marking_character_set
                            == EntityMarkingCharacterSet::ASCII,
                        dr_algorithm: DrAlgorithm::from_dis(es.dead_reckoning_parameters.algorithm),
                        timestamp: pdu.header.timestamp.into(),
                        location_m,
                        orientation,
                        position,
                        attitude,
                        velocity_ned_m_s,
                        updates,
                    },
                );
            }
        }
        Ok(pdus.len())
    }

    /// The counts so far.
    #[must_use]
    pub fn stats(&self) -> ListenerStats {
        self.stats
    }

    /// Number of distinct entities seen in Entity State PDUs.
    #[must_use]
    pub fn entity_count(&self) -> usize {
        self.entities.len()
    }

    /// The last state of one entity.
    #[must_use]
    pub fn entity(&self, id: &EntityIdentity) -> Option<&EntityRecord> {
        self.entities.get(id)
    }

    /// All entities, ordered by id.
    pub fn entities(&self) -> impl Iterator<Item = &EntityRecord> {
        self.entities.values()
    }
}
