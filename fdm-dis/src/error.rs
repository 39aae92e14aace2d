//! The crate's error type.

use thiserror::Error;

/// Why a state could not be converted, a PDU not built, or a configuration
/// not accepted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DisOutputError {
    /// An input number is NaN or infinite (the field is named).
    #[error("{0} is not finite")]
    NonFinite(&'static str),
    /// Latitude outside `[-90, 90]` degrees.
    #[error("latitude {0}° is outside [-90, 90]")]
    LatitudeOutOfRange(f64),
    /// The marking is longer than the 11 characters an Entity State PDU holds.
    #[error("marking {0:?} is longer than 11 characters")]
    MarkingTooLong(String),
    /// The marking has a character outside printable ASCII (0x20..=0x7E).
    #[error("marking {0:?} has a character outside printable ASCII")]
    MarkingNotAscii(String),
    /// A site, application or entity number that DIS reserves (0 means
    /// "none", 0xFFFF "all", entity 0xFFFE "request an id").
    #[error("{field} {value} is reserved by DIS")]
    ReservedId {
        /// Which number: `site`, `application` or `entity`.
        field: &'static str,
        /// The number given.
        value: u16,
    },
    /// A dead-reckoning threshold or heartbeat that is not a positive finite
    /// number.
    #[error("dead-reckoning {0} must be positive and finite")]
    BadThreshold(&'static str),
    /// dis-rs refused to serialise the PDU.
    #[error("dis-rs could not serialise the PDU: {0}")]
    Encode(String),
    /// A socket operation failed.
    #[error("UDP: {0}")]
    Io(String),
}
