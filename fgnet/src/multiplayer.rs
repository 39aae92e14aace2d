//! FlightGear multiplayer position messages: the datagram FlightGear 2020.3
//! reads on `--multiplay=in,...` and shows as one `/ai/models/multiplayer[i]`
//! node per callsign.
//!
//! * [`MultiplayerPosition`]: the message, with units in the field names;
//!   [`MultiplayerPosition::encode`] / [`MultiplayerPosition::encode_into`]
//!   and [`MultiplayerPosition::decode`], with typed errors
//!   ([`MpEncodeError`], [`MpDecodeError`], [`NameError`]).
//! * [`ecef_angle_axis_from_attitude`] and [`attitude_from_ecef_angle_axis`]:
//!   the orientation field from and to geodetic latitude/longitude plus local
//!   heading, pitch and roll, the way FlightGear composes it.
//!
//! # Wire format
//!
//! Everything is XDR: big-endian, every item a multiple of 4 bytes (`u32`,
//! IEEE-754 `f32`, IEEE-754 `f64`, and fixed-size character arrays), no gaps.
//! A datagram is a 32-byte header followed by a 200-byte position body, and
//! optionally by property words:
//!
//! | offset | size | content |
//! | ---: | ---: | --- |
//! | 0 | 4 | magic `0x46474653`, the ASCII letters `FGFS` ([`MP_MAGIC`]) |
//! | 4 | 4 | protocol version `0x00010001` ([`MP_PROTOCOL_VERSION`]) |
//! | 8 | 4 | message id, 7 for a position message ([`MP_POSITION_MESSAGE_ID`]) |
//! | 12 | 4 | length of the whole datagram in bytes, header included |
//! | 16 | 4 | requested range in nautical miles (once a reply address); 0 is fine |
//! | 20 | 4 | reply port (no longer used); 0 |
//! | 24 | 8 | callsign: 1 to 7 ASCII characters, NUL-padded |
//! | 32 | 96 | model path relative to FlightGear's data directory, NUL-padded |
//! | 128 | 8 | time of this state, seconds on the sender's monotonic clock |
//! | 136 | 8 | lag, seconds |
//! | 144 | 24 | position: ECEF x, y, z (WGS-84), metres, `f64` |
//! | 168 | 12 | orientation: rotation vector (axis × angle, radians), `f32` |
//! | 180 | 12 | linear velocity, body axes, m/s, `f32` |
//! | 192 | 12 | angular velocity, body axes, rad/s, `f32` |
//! | 204 | 12 | linear acceleration, body axes, m/s², `f32` |
//! | 216 | 12 | angular acceleration, body axes, rad/s², `f32` |
//! | 228 | 4 | padding, 0 |
//! | 232 | 4·n | optional property values (id, value pairs) |
//!
//! A 232-byte datagram whose length word says 232 is a complete position
//! message. The body axes are x forward, y right, z down.
//!
//! The property list's value encodings depend on a table of property ids
//! inside FlightGear, which this crate does not carry. The message therefore
//! keeps whatever follows offset 232 as opaque big-endian 32-bit words
//! ([`MultiplayerPosition::property_words`]): they round-trip unchanged, and
//! an empty list (the usual case here) is a complete message.
//!
//! ## Orientation
//!
//! The orientation field is the rotation from the Earth-centred, Earth-fixed
//! (ECEF) frame to the body frame, written as a rotation vector: unit axis
//! times angle in radians, in ECEF coordinates. FlightGear's sender builds it
//! from two quaternions (SimGear conventions: Hamilton product; `q` rotates
//! frame A into frame B when B's axes, written in A, are `q`'s active
//! rotation of A's axes):
//!
//! 1. ECEF → local horizontal (x north, y east, z down): rotate about ECEF z
//!    by the longitude, then about the new y by `-(90° + latitude)`.
//! 2. Local horizontal → body: yaw (heading) about z, then pitch about the
//!    new y, then roll about the new x.
//!
//! The product of the two is turned into angle and axis with
//! `angle = 2·acos(w)` (so the angle lies in `[0, 2π]`; the quaternion is not
//! flipped to `w ≥ 0`) and `axis = (x, y, z) / sin(angle / 2)`.
//! [`ecef_angle_axis_from_attitude`] does exactly this in `f64`;
//! [`attitude_from_ecef_angle_axis`] undoes it (rotation vector → quaternion,
//! remove the local-horizontal rotation, read heading in `[0°, 360°)`, pitch
//! in `[-90°, 90°]` and roll in `(-180°, 180°]`), which is what FlightGear
//! does on receive to fill `orientation/true-heading-deg`, `pitch-deg` and
//! `roll-deg` (it works in `f32` there).
//!
//! The position is an input: this module has no geodesy. Convert geodetic
//! latitude, longitude and height to ECEF with the project's WGS-84 code and
//! pass the same latitude and longitude to the orientation helpers.
//!
//! # Example
//!
//! ```
//! use fgnet::{HorizontalAttitudeDeg, MultiplayerPosition};
//!
//! let mut msg = MultiplayerPosition::new("MP1", "Aircraft/c172p/Models/c172p.xml")?;
//! msg.time_s = 12.5;
//! msg.lag_s = 0.1;
//! // lat 0, lon 0, height 0 on WGS-84 is (a, 0, 0).
//! msg.position_ecef_m = [6_378_137.0, 0.0, 0.0];
//! let attitude = HorizontalAttitudeDeg { heading_deg: 90.0, pitch_deg: 0.0, roll_deg: 0.0 };
//! msg.set_orientation_from_attitude(0.0, 0.0, attitude);
//!
//! let bytes = msg.encode()?;
//! assert_eq!(bytes.len(), 232);
//! let back = MultiplayerPosition::decode(&bytes)?;
//! assert_eq!(back, msg);
//! let read = back.attitude(0.0, 0.0);
//! assert!((read.heading_deg - 90.0).abs() < 1e-4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod attitude;

pub use attitude::{
    attitude_from_ecef_angle_axis, ecef_angle_axis_from_attitude, HorizontalAttitudeDeg,
};

use thiserror::Error;

/// Header magic: the ASCII letters `FGFS` read as a big-endian `u32`.
pub const MP_MAGIC: u32 = 0x4647_4653;

/// Multiplayer protocol version FlightGear 2020.3 speaks (major 1, minor 1).
pub const MP_PROTOCOL_VERSION: u32 = 0x0001_0001;

/// Message id of a position message.
pub const MP_POSITION_MESSAGE_ID: u32 = 7;

/// Size of the header, bytes.
pub const MP_HEADER_LEN: usize = 32;

/// Size of a complete position message without properties, bytes.
pub const MP_POSITION_LEN: usize = 232;

/// Largest datagram this codec writes or reads: the largest UDP payload over
/// IPv4 (65 535 − 8-byte UDP header − 20-byte IP header).
pub const MP_MAX_DATAGRAM_LEN: usize = 65_507;

/// Size of the callsign field, bytes (at most 7 characters plus a NUL).
pub const CALLSIGN_FIELD_LEN: usize = 8;

/// Size of the model path field, bytes (at most 95 characters plus a NUL).
pub const MODEL_PATH_FIELD_LEN: usize = 96;

/// One FlightGear multiplayer position message (message id 7).
///
/// Magic, protocol version, message id and length are not fields: the
/// encoder writes them and the decoder checks them. Every other wire field
/// is here, in wire order, with its offset in the doc.
///
/// `PartialEq` compares floats by value (so a message holding a NaN is not
/// equal to itself); compare [`encode`](Self::encode) outputs to compare bit
/// patterns. Encoding and decoding keep every bit, NaN payloads included.
#[derive(Debug, Clone, PartialEq)]
pub struct MultiplayerPosition {
    /// Offset 16, `u32`: range of interest in nautical miles (the word once
    /// held a reply address). 0 is accepted.
    pub requested_range_nm: u32,
    /// Offset 20, `u32`: reply port, no longer used; send 0.
    pub reply_port: u32,
    /// Offset 24, 8 bytes: callsign, 1 to 7 printable ASCII characters
    /// (space to `~`), NUL-padded on the wire. FlightGear makes one
    /// `/ai/models/multiplayer[i]` per distinct callsign and drops datagrams
    /// carrying its own.
    pub callsign: String,
    /// Offset 32, 96 bytes: the aircraft model FlightGear loads, relative to
    /// its data directory (e.g. `Aircraft/ufo/Models/ufo.xml`), 1 to 95
    /// printable ASCII characters, NUL-padded on the wire.
    pub model_path: String,
    /// Offset 128, `f64`: time of this state on the sender's monotonic clock,
    /// seconds. FlightGear interpolates between messages by this time, so it
    /// must increase from one message to the next.
    pub time_s: f64,
    /// Offset 136, `f64`: the sender's lag estimate, seconds.
    pub lag_s: f64,
    /// Offset 144, `3 × f64`: position in the WGS-84 ECEF frame, metres.
    pub position_ecef_m: [f64; 3],
    /// Offset 168, `3 × f32`: rotation from the ECEF frame to the body frame
    /// as a rotation vector (unit axis in ECEF × angle), radians. See
    /// [`set_orientation_from_attitude`](Self::set_orientation_from_attitude).
    pub orientation_angle_axis_rad: [f32; 3],
    /// Offset 180, `3 × f32`: linear velocity in body axes (x forward,
    /// y right, z down), m/s.
    pub linear_velocity_body_mps: [f32; 3],
    /// Offset 192, `3 × f32`: angular velocity in body axes, rad/s.
    pub angular_velocity_body_radps: [f32; 3],
    /// Offset 204, `3 × f32`: linear acceleration in body axes, m/s².
    pub linear_acceleration_body_mps2: [f32; 3],
    /// Offset 216, `3 × f32`: angular acceleration in body axes, rad/s².
    pub angular_acceleration_body_radps2: [f32; 3],
    /// Offset 228, `u32`: padding; send 0. Kept so that decoding and
    /// re-encoding give back the same bytes.
    pub padding: u32,
    /// Offset 232 onwards: the optional property list as opaque big-endian
    /// 32-bit words (empty: no properties). See the module docs.
    pub property_words: Vec<u32>,
}

/// Which text field a [`NameError`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NameField {
    /// The callsign (offset 24, at most 7 characters).
    Callsign,
    /// The model path (offset 32, at most 95 characters).
    ModelPath,
}

impl NameField {
    /// Size of the field on the wire, bytes.
    pub const fn field_len(self) -> usize {
        match self {
            Self::Callsign => CALLSIGN_FIELD_LEN,
            Self::ModelPath => MODEL_PATH_FIELD_LEN,
        }
    }

    /// Longest text the field holds (one byte is kept for the NUL).
    pub const fn max_chars(self) -> usize {
        self.field_len() - 1
    }

    /// Byte offset of the field in the datagram.
    pub const fn offset(self) -> usize {
        match self {
            Self::Callsign => 24,
            Self::ModelPath => 32,
        }
    }

    /// Lower-case name used in messages, e.g. `"callsign"`.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Callsign => "callsign",
            Self::ModelPath => "model path",
        }
    }
}

impl core::fmt::Display for NameField {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// What is wrong with a callsign or model path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NameProblem {
    /// No characters at all.
    Empty,
    /// More characters than the field holds with its terminating NUL. When
    /// decoding, `len` is the field size (no NUL was found).
    TooLong {
        /// Number of characters (bytes) found.
        len: usize,
        /// The most the field allows.
        max: usize,
    },
    /// A byte that is not printable ASCII (space to `~`): a control
    /// character, a NUL inside the text, or part of a non-ASCII character.
    NotPrintableAscii {
        /// Byte index within the text.
        index: usize,
        /// The byte.
        byte: u8,
    },
    /// Decoding only: a non-NUL byte after the terminating NUL.
    NotNulPadded {
        /// Byte index within the field.
        index: usize,
        /// The byte.
        byte: u8,
    },
}

/// A callsign or model path that cannot be put on (or was read from) the
/// wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Error)]
#[error("{field}: {}", describe(self.problem))]
pub struct NameError {
    /// The field.
    pub field: NameField,
    /// What is wrong with it.
    pub problem: NameProblem,
}

fn describe(p: NameProblem) -> String {
    match p {
        NameProblem::Empty => "empty".to_owned(),
        NameProblem::TooLong { len, max } => {
            format!("{len} characters, at most {max} fit")
        }
        NameProblem::NotPrintableAscii { index, byte } => {
            format!("byte {index} is 0x{byte:02x}, not printable ASCII")
        }
        NameProblem::NotNulPadded { index, byte } => {
            format!("byte {index} is 0x{byte:02x} after the terminating NUL")
        }
    }
}

/// Why a message cannot be encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum MpEncodeError {
    /// The callsign or model path does not fit the wire format.
    #[error("invalid {0}")]
    Name(#[from] NameError),
    /// The output buffer is shorter than the datagram.
    #[error("buffer of {got} bytes is too small for a {need}-byte multiplayer datagram")]
    BufferTooSmall {
        /// Bytes the datagram needs.
        need: usize,
        /// Bytes the buffer has.
        got: usize,
    },
    /// So many property words that the datagram would exceed
    /// [`MP_MAX_DATAGRAM_LEN`].
    #[error("multiplayer datagram of {len} bytes exceeds the {max}-byte UDP limit")]
    TooLong {
        /// Length the datagram would have.
        len: usize,
        /// [`MP_MAX_DATAGRAM_LEN`].
        max: usize,
    },
}

/// Why a buffer is not a valid multiplayer position message. The checks run
/// in the order of the variants.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum MpDecodeError {
    /// Shorter than the header (32 bytes) or, once the header checks out,
    /// than a position message (232 bytes).
    #[error("multiplayer datagram of {len} bytes is truncated, need at least {need}")]
    Truncated {
        /// Length of the buffer.
        len: usize,
        /// Bytes needed.
        need: usize,
    },
    /// Longer than [`MP_MAX_DATAGRAM_LEN`].
    #[error("multiplayer datagram of {len} bytes exceeds the {max}-byte UDP limit")]
    TooLong {
        /// Length of the buffer.
        len: usize,
        /// [`MP_MAX_DATAGRAM_LEN`].
        max: usize,
    },
    /// The first word is not `FGFS`.
    #[error("magic 0x{found:08x}, expected 0x46474653 (\"FGFS\")")]
    WrongMagic {
        /// The big-endian word read at offset 0.
        found: u32,
    },
    /// The protocol version is not `0x00010001`.
    #[error("multiplayer protocol version 0x{found:08x}, expected 0x00010001")]
    WrongVersion {
        /// The big-endian word read at offset 4.
        found: u32,
    },
    /// Not a position message (id 7).
    #[error("multiplayer message id {found}, expected 7 (position)")]
    WrongMessageId {
        /// The big-endian word read at offset 8.
        found: u32,
    },
    /// The length word does not match the number of bytes received.
    #[error("length word says {header_len} bytes, datagram has {datagram_len}")]
    LengthMismatch {
        /// The big-endian word read at offset 12.
        header_len: u32,
        /// Length of the buffer.
        datagram_len: usize,
    },
    /// What follows offset 232 is not a whole number of 4-byte words.
    #[error("{trailing} bytes of properties after offset 232, not a multiple of 4")]
    UnalignedProperties {
        /// Bytes after offset 232.
        trailing: usize,
    },
    /// The callsign or model path is not valid.
    #[error("invalid {0}")]
    Name(#[from] NameError),
}

/// Checks a callsign or model path: 1 to `field.max_chars()` bytes, each
/// printable ASCII.
///
/// # Errors
/// The first [`NameProblem`] found, tagged with `field`.
pub fn validate_name(field: NameField, text: &str) -> Result<(), NameError> {
    let err = |problem| NameError { field, problem };
    if text.is_empty() {
        return Err(err(NameProblem::Empty));
    }
    if let Some((index, &byte)) = text
        .as_bytes()
        .iter()
        .enumerate()
        .find(|(_, b)| !(b' '..=b'~').contains(*b))
    {
        return Err(err(NameProblem::NotPrintableAscii { index, byte }));
    }
    if text.len() > field.max_chars() {
        return Err(err(NameProblem::TooLong {
            len: text.len(),
            max: field.max_chars(),
        }));
    }
    Ok(())
}

/// One wire field of [`MultiplayerPosition`], as listed in
/// [`MultiplayerPosition::FIELDS`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WireField {
    /// The Rust field name.
    pub name: &'static str,
    /// Byte offset in the datagram.
    pub offset: usize,
    /// Size on the wire, bytes.
    pub len: usize,
}

/// Declares the wire fields once, in wire order, and derives from that one
/// list the encoder body, the decoder body and [`MultiplayerPosition::FIELDS`].
/// Each entry is `field: kind @ offset`; `kind` names a `Writer`/`Reader`
/// method and its size comes from `kind_len!`.
macro_rules! wire_fields {
    ($($field:ident : $kind:ident @ $offset:literal),* $(,)?) => {
        impl MultiplayerPosition {
            /// Every wire field of the message after the fixed words (magic,
            /// version, message id, length), in wire order, with its offset
            /// and size. The property words follow at offset 232.
            pub const FIELDS: &'static [WireField] = &[
                $(WireField { name: stringify!($field), offset: $offset, len: kind_len!($kind) },)*
            ];

            fn write_fields(&self, w: &mut Writer<'_>) {
                $(
                    debug_assert_eq!(w.pos, $offset);
                    w.$kind(&self.$field);
                )*
            }

            fn read_fields(r: &mut Reader<'_>, property_words: Vec<u32>) -> Result<Self, MpDecodeError> {
                Ok(Self {
                    $($field: {
                        debug_assert_eq!(r.pos, $offset);
                        r.$kind()?
                    },)*
                    property_words,
                })
            }
        }
    };
}

macro_rules! kind_len {
    (u32) => {
        4
    };
    (f64) => {
        8
    };
    (f64x3) => {
        24
    };
    (f32x3) => {
        12
    };
    (callsign) => {
        CALLSIGN_FIELD_LEN
    };
    (model_path) => {
        MODEL_PATH_FIELD_LEN
    };
}

wire_fields! {
    requested_range_nm: u32 @ 16,
    reply_port: u32 @ 20,
    callsign: callsign @ 24,
    model_path: model_path @ 32,
    time_s: f64 @ 128,
    lag_s: f64 @ 136,
    position_ecef_m: f64x3 @ 144,
    orientation_angle_axis_rad: f32x3 @ 168,
    linear_velocity_body_mps: f32x3 @ 180,
    angular_velocity_body_radps: f32x3 @ 192,
    linear_acceleration_body_mps2: f32x3 @ 204,
    angular_acceleration_body_radps2: f32x3 @ 216,
    padding: u32 @ 228,
}

impl MultiplayerPosition {
    /// A message for `callsign` flying `model_path`, with every number 0 and
    /// no properties. Set at least [`time_s`](Self::time_s),
    /// [`position_ecef_m`](Self::position_ecef_m) and the orientation before
    /// sending.
    ///
    /// # Errors
    /// [`NameError`] if either text does not fit (see [`validate_name`]).
    pub fn new(callsign: &str, model_path: &str) -> Result<Self, NameError> {
        validate_name(NameField::Callsign, callsign)?;
        validate_name(NameField::ModelPath, model_path)?;
        Ok(Self {
            requested_range_nm: 0,
            reply_port: 0,
            callsign: callsign.to_owned(),
            model_path: model_path.to_owned(),
            time_s: 0.0,
            lag_s: 0.0,
            position_ecef_m: [0.0; 3],
            orientation_angle_axis_rad: [0.0; 3],
            linear_velocity_body_mps: [0.0; 3],
            angular_velocity_body_radps: [0.0; 3],
            linear_acceleration_body_mps2: [0.0; 3],
            angular_acceleration_body_radps2: [0.0; 3],
            padding: 0,
            property_words: Vec::new(),
        })
    }

    /// Sets [`orientation_angle_axis_rad`](Self::orientation_angle_axis_rad)
    /// from the geodetic latitude and longitude of the aircraft (degrees) and
    /// its attitude relative to the local horizontal, via
    /// [`ecef_angle_axis_from_attitude`] (computed in `f64`, then each
    /// component rounded to `f32`).
    pub fn set_orientation_from_attitude(
        &mut self,
        latitude_deg: f64,
        longitude_deg: f64,
        attitude: HorizontalAttitudeDeg,
    ) {
        let v = ecef_angle_axis_from_attitude(latitude_deg, longitude_deg, attitude);
        self.orientation_angle_axis_rad = v.map(|c| c as f32);
    }

    /// Heading, pitch and roll relative to the local horizontal at the given
    /// geodetic latitude and longitude (degrees), read back from
    /// [`orientation_angle_axis_rad`](Self::orientation_angle_axis_rad) with
    /// [`attitude_from_ecef_angle_axis`].
    #[must_use]
    pub fn attitude(&self, latitude_deg: f64, longitude_deg: f64) -> HorizontalAttitudeDeg {
        attitude_from_ecef_angle_axis(
            self.orientation_angle_axis_rad.map(f64::from),
            latitude_deg,
            longitude_deg,
        )
    }

    /// Length of the encoded datagram: 232 bytes plus 4 per property word.
    #[must_use]
    pub fn encoded_len(&self) -> usize {
        MP_POSITION_LEN.saturating_add(self.property_words.len().saturating_mul(4))
    }

    /// Encodes the datagram into a new vector of
    /// [`encoded_len`](Self::encoded_len) bytes.
    ///
    /// ```
    /// let msg = fgnet::MultiplayerPosition::new("MP1", "Aircraft/ufo/Models/ufo.xml")?;
    /// let bytes = msg.encode()?;
    /// assert_eq!(bytes[..16], [b'F', b'G', b'F', b'S', 0, 1, 0, 1, 0, 0, 0, 7, 0, 0, 0, 232]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`MpEncodeError::Name`] for a callsign or model path that does not
    /// fit; [`MpEncodeError::TooLong`] past [`MP_MAX_DATAGRAM_LEN`].
    pub fn encode(&self) -> Result<Vec<u8>, MpEncodeError> {
        self.check_encodable()?;
        let mut out = vec![0u8; self.encoded_len()];
        self.encode_into(&mut out)?;
        Ok(out)
    }

    /// Encodes the datagram into the start of `out` and returns its length;
    /// bytes of `out` past that length are left alone. Nothing is written on
    /// error.
    ///
    /// # Errors
    /// As [`encode`](Self::encode), plus [`MpEncodeError::BufferTooSmall`].
    pub fn encode_into(&self, out: &mut [u8]) -> Result<usize, MpEncodeError> {
        let len = self.check_encodable()?;
        let got = out.len();
        let Some(buf) = out.get_mut(..len) else {
            return Err(MpEncodeError::BufferTooSmall { need: len, got });
        };
        let mut w = Writer { buf, pos: 0 };
        w.u32(&MP_MAGIC);
        w.u32(&MP_PROTOCOL_VERSION);
        w.u32(&MP_POSITION_MESSAGE_ID);
        // `check_encodable` bounds `len` by MP_MAX_DATAGRAM_LEN, far below u32::MAX.
        w.u32(&(len as u32));
        self.write_fields(&mut w);
        debug_assert_eq!(w.pos, MP_POSITION_LEN);
        for word in &self.property_words {
            w.u32(word);
        }
        debug_assert_eq!(w.pos, len);
        Ok(len)
    }

    fn check_encodable(&self) -> Result<usize, MpEncodeError> {
        validate_name(NameField::Callsign, &self.callsign)?;
        validate_name(NameField::ModelPath, &self.model_path)?;
        let len = self.encoded_len();
        if len > MP_MAX_DATAGRAM_LEN {
            return Err(MpEncodeError::TooLong {
                len,
                max: MP_MAX_DATAGRAM_LEN,
            });
        }
        Ok(len)
    }

    /// Decodes one datagram, bit-exactly (NaN payloads included). Never
    /// panics, whatever the bytes.
    ///
    /// Checks, in this order: at least 32 bytes, at most
    /// [`MP_MAX_DATAGRAM_LEN`]; magic; version; message id; length word equal
    /// to the buffer length; at least 232 bytes; properties a whole number of
    /// words; callsign and model path (1 to 7 resp. 95 printable ASCII
    /// characters, then only NULs).
    ///
    /// ```
    /// use fgnet::{MpDecodeError, MultiplayerPosition};
    /// let bytes = MultiplayerPosition::new("MP1", "Aircraft/ufo/Models/ufo.xml")?.encode()?;
    /// assert_eq!(MultiplayerPosition::decode(&bytes)?.callsign, "MP1");
    /// assert_eq!(
    ///     MultiplayerPosition::decode(&bytes[..231]),
    ///     Err(MpDecodeError::LengthMismatch { header_len: 232, datagram_len: 231 })
    /// );
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// The first [`MpDecodeError`] found.
    pub fn decode(buf: &[u8]) -> Result<Self, MpDecodeError> {
        let len = buf.len();
        if len < MP_HEADER_LEN {
            return Err(MpDecodeError::Truncated {
                len,
                need: MP_HEADER_LEN,
            });
        }
        if len > MP_MAX_DATAGRAM_LEN {
            return Err(MpDecodeError::TooLong {
                len,
                max: MP_MAX_DATAGRAM_LEN,
            });
        }
        let mut r = Reader { buf, pos: 0 };
        let magic = r.u32()?;
        if magic != MP_MAGIC {
            return Err(MpDecodeError::WrongMagic { found: magic });
        }
        let version = r.u32()?;
        if version != MP_PROTOCOL_VERSION {
            return Err(MpDecodeError::WrongVersion { found: version });
        }
        let id = r.u32()?;
        if id != MP_POSITION_MESSAGE_ID {
            return Err(MpDecodeError::WrongMessageId { found: id });
        }
        let header_len = r.u32()?;
        if usize::try_from(header_len) != Ok(len) {
            return Err(MpDecodeError::LengthMismatch {
                header_len,
                datagram_len: len,
            });
        }
        if len < MP_POSITION_LEN {
            return Err(MpDecodeError::Truncated {
                len,
                need: MP_POSITION_LEN,
            });
        }
        let tail = &buf[MP_POSITION_LEN..];
        let words = tail.chunks_exact(4);
        if !words.remainder().is_empty() {
            return Err(MpDecodeError::UnalignedProperties {
                trailing: tail.len(),
            });
        }
        let property_words = words
            .map(|c| u32::from_be_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let msg = Self::read_fields(&mut r, property_words)?;
        debug_assert_eq!(r.pos, MP_POSITION_LEN);
        Ok(msg)
    }
}

/// Sequential big-endian writer over a buffer whose length the caller has
/// checked.
struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
}

impl Writer<'_> {
    #[inline(always)]
    fn bytes(&mut self, b: &[u8]) {
        self.buf[self.pos..self.pos + b.len()].copy_from_slice(b);
        self.pos += b.len();
    }
    #[inline(always)]
    fn u32(&mut self, v: &u32) {
        self.bytes(&v.to_be_bytes());
    }
    #[inline(always)]
    fn f64(&mut self, v: &f64) {
        self.bytes(&v.to_be_bytes());
    }
    #[inline(always)]
    fn f64x3(&mut self, v: &[f64; 3]) {
        for x in v {
            self.f64(x);
        }
    }
    #[inline(always)]
    fn f32x3(&mut self, v: &[f32; 3]) {
        for x in v {
            self.bytes(&x.to_be_bytes());
        }
    }
    /// Text already validated: fits with at least one NUL after it.
    fn text<const N: usize>(&mut self, s: &str) {
        let mut field = [0u8; N];
        field[..s.len()].copy_from_slice(s.as_bytes());
        self.bytes(&field);
    }
    fn callsign(&mut self, s: &str) {
        self.text::<CALLSIGN_FIELD_LEN>(s);
    }
    fn model_path(&mut self, s: &str) {
        self.text::<MODEL_PATH_FIELD_LEN>(s);
    }
}

/// Sequential big-endian reader; every read is bounds-checked and returns
/// [`MpDecodeError::Truncated`] rather than panicking.
struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    #[inline(always)]
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], MpDecodeError> {
        let b = self
            .pos
            .checked_add(N)
            .and_then(|end| self.buf.get(self.pos..end))
            .and_then(|s| <[u8; N]>::try_from(s).ok())
            .ok_or(MpDecodeError::Truncated {
                len: self.buf.len(),
                need: self.pos.saturating_add(N),
            })?;
        self.pos += N;
        Ok(b)
    }
    #[inline(always)]
    fn u32(&mut self) -> Result<u32, MpDecodeError> {
        self.bytes().map(u32::from_be_bytes)
    }
    #[inline(always)]
    fn f64(&mut self) -> Result<f64, MpDecodeError> {
        self.bytes().map(f64::from_be_bytes)
    }
    #[inline(always)]
    fn f64x3(&mut self) -> Result<[f64; 3], MpDecodeError> {
        Ok([self.f64()?, self.f64()?, self.f64()?])
    }
    #[inline(always)]
    fn f32x3(&mut self) -> Result<[f32; 3], MpDecodeError> {
        let mut one = || self.bytes().map(f32::from_be_bytes);
        Ok([one()?, one()?, one()?])
    }
    fn text<const N: usize>(&mut self, field: NameField) -> Result<String, MpDecodeError> {
        let raw: [u8; N] = self.bytes()?;
        let err = |problem| MpDecodeError::Name(NameError { field, problem });
        let Some(end) = raw.iter().position(|&b| b == 0) else {
            return Err(err(NameProblem::TooLong { len: N, max: N - 1 }));
        };
        if let Some((index, &byte)) = raw.iter().enumerate().skip(end).find(|(_, &b)| b != 0) {
            return Err(err(NameProblem::NotNulPadded { index, byte }));
        }
        let text = &raw[..end];
        if let Some((index, &byte)) = text
            .iter()
            .enumerate()
            .find(|(_, b)| !(b' '..=b'~').contains(*b))
        {
            return Err(err(NameProblem::NotPrintableAscii { index, byte }));
        }
        if text.is_empty() {
            return Err(err(NameProblem::Empty));
        }
        // Printable ASCII is UTF-8, one char per byte.
        let s: String = text.iter().map(|&b| char::from(b)).collect();
        Ok(s)
    }
    fn callsign(&mut self) -> Result<String, MpDecodeError> {
        self.text::<CALLSIGN_FIELD_LEN>(NameField::Callsign)
    }
    fn model_path(&mut self) -> Result<String, MpDecodeError> {
        self.text::<MODEL_PATH_FIELD_LEN>(NameField::ModelPath)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_tile_the_body_without_gaps() {
        let mut next = 16;
        for f in MultiplayerPosition::FIELDS {
            assert_eq!(f.offset, next, "{}", f.name);
            assert_eq!(f.offset % 4, 0, "{}", f.name);
            next = f.offset + f.len;
        }
        assert_eq!(next, MP_POSITION_LEN);
    }

    #[test]
    fn validate_name_reports_the_first_problem() {
        use NameField::*;
        assert_eq!(validate_name(Callsign, "ABCDEFG"), Ok(()));
        assert_eq!(
            validate_name(Callsign, "ABCDEFGH").unwrap_err().problem,
            NameProblem::TooLong { len: 8, max: 7 }
        );
        assert_eq!(
            validate_name(Callsign, "").unwrap_err().problem,
            NameProblem::Empty
        );
        assert_eq!(
            validate_name(Callsign, "A\0B").unwrap_err().problem,
            NameProblem::NotPrintableAscii { index: 1, byte: 0 }
        );
        // 'é' is two UTF-8 bytes, 0xc3 0xa9: the first is reported.
        assert_eq!(
            validate_name(ModelPath, "caf\u{e9}").unwrap_err().problem,
            NameProblem::NotPrintableAscii {
                index: 3,
                byte: 0xc3
            }
        );
        assert_eq!(validate_name(ModelPath, &"a".repeat(95)), Ok(()));
        let e = validate_name(ModelPath, &"a".repeat(96)).unwrap_err();
        assert_eq!(e.problem, NameProblem::TooLong { len: 96, max: 95 });
        assert_eq!(e.to_string(), "model path: 96 characters, at most 95 fit");
    }
}
