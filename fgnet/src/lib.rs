//! FlightGear "native FDM" datagrams (FGNetFDM, protocol version 24): the
//! 408-byte big-endian struct FlightGear 2020.3 accepts on
//! `--native-fdm=socket,in,...,udp`, its encoder and decoder, and a UDP sender.
//!
//! * [`FgNetFdm`]: every v24 field, with its unit and what FlightGear does
//!   with it; [`FgNetFdm::encode`] / [`FgNetFdm::encode_into`] and
//!   [`FgNetFdm::decode`].
//! * [`DisplayState`]: what a flight model hands over (degrees, metres, ft/s,
//!   knots), converted with [`FgNetFdm::from_display`].
//! * [`Sender`]: a connected UDP socket that keeps going when nobody listens;
//!   [`address`]: FlightGear's `HOST:PORT` endpoints, parsed strictly (IPv4
//!   only, no broadcast or unspecified target) with typed errors.
//! * [`MultiplayerPosition`]: FlightGear's multiplayer position message
//!   (protocol 1.1, message id 7), to show many aircraft at once; the
//!   [`multiplayer`] module documents the format and the orientation helpers.
//!
//! # Wire format
//!
//! Every field is big-endian (`u32`, `i32`, IEEE-754 `f32` and `f64` alike),
//! at its natural alignment, 408 bytes in total with no trailing padding.
//! `num_engines`, `num_tanks` and `num_wheels` are unchecked loop bounds in
//! FlightGear (larger values overrun its buffers), so the encoders clamp them
//! to 4, 4 and 3 and [`FgNetFdm::decode`] rejects larger ones.
//!
//! # Encoder choice
//!
//! [`FgNetFdm::encode`], [`FgNetFdm::encode_into`] and [`FgNetFdm::decode`]
//! use one `to_be_bytes`/`from_be_bytes` per field, in wire order, on a
//! fixed-size `[u8; 408]`; they, the struct and its neutral values are all
//! generated from the one field list in `fdm.rs`. The serde + bincode 2 path
//! (`bincode::config::standard().with_big_endian().with_fixed_int_encoding()`,
//! arrays as serde tuples, so no length prefixes) is kept as
//! [`FgNetFdm::encode_bincode`] and [`FgNetFdm::decode_bincode`]; tests assert
//! that both give identical bytes and identical decoded values (NaN payloads
//! included). The `to_be_bytes` path is clearly better on speed, so it is the
//! one used. Criterion medians of two runs (`benches/fgnet_encode.rs`,
//! `cargo bench --bench fgnet_encode -- --warm-up-time 1 --measurement-time 5`,
//! on the project's 2-core x86-64 machine shared with other builds):
//!
//! | operation | `to_be_bytes` | serde + bincode 2 |
//! | --- | ---: | ---: |
//! | encode into an existing buffer | 18 ns (`encode_into`) | |
//! | encode returning `[u8; 408]` | 40-46 ns (`encode`) | 157-162 ns (`encode_bincode`) |
//! | decode with validation | 26-28 ns (`decode`) | 248-260 ns (`decode_bincode`) |
//!
//! The bincode path goes through serde's per-field calls with a `Result` and
//! a remaining-length check on every write or read, which is the likely
//! source of its roughly 2.5 ns per field; the `to_be_bytes` code works on a
//! `[u8; 408]` with constant offsets and has no error paths. Returning the
//! array by value measured about 25 ns more than [`FgNetFdm::encode_into`]
//! (a zeroed 408-byte array, then copied out), which is why [`Sender`]
//! encodes into a buffer it keeps.
//!
//! # Interoperability
//!
//! `tests/fgnet_interop.rs` checks both directions over UDP against the PyPI
//! package flightgear-python 2.1.0 (`flightgear_python.fdm_v24`), bit for
//! bit. Its `fdm_v24.fdm_struct.parse`/`build` do not touch angles. Its
//! `FDMConnection` receive path, however, adds `math.degrees(x) *
//! 1.09349403e-9` radians (a relative +6.265e-8) to longitude, latitude,
//! phi, theta, psi, alpha, beta and the three angular rates of every
//! datagram it receives, to undo the shrink caused by FlightGear's float
//! radians-to-degrees constant, and does not remove it when it sends the
//! datagram back. Values read through `FDMConnection` therefore differ from
//! what this crate sent by exactly that amount; the test predicts it exactly.
//!
//! # Example
//!
//! ```
//! use fgnet::{DisplayState, EngineState, FgNetFdm, Sender};
//!
//! # let fg = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
//! # let fg_addr = fg.local_addr().unwrap().to_string();
//! // FlightGear: --fdm=null --native-fdm=socket,in,30,127.0.0.1,5500,udp
//! let mut sender = Sender::connect(&fg_addr)?; // e.g. "127.0.0.1:5500"
//! let state = DisplayState {
//!     latitude_deg: 37.625,
//!     longitude_deg: -122.375,
//!     altitude_m: 300.0,
//!     heading_deg: 280.0,
//!     airspeed_kt: 95.0,
//!     engine_state: EngineState::Running,
//!     engine_rpm: 2350.0,
//!     ..DisplayState::default()
//! };
//! if let fgnet::SendOutcome::FirstFailure(e) = sender.send(&FgNetFdm::from_display(&state)) {
//!     eprintln!("FlightGear at {} unreachable: {e} (further failures only counted)", sender.peer());
//! }
//! # let mut buf = [0u8; 512];
//! # assert_eq!(fg.recv(&mut buf).unwrap(), 408);
//! # Ok::<(), fgnet::SenderError>(())
//! ```

pub mod address;
pub mod bridge;
mod display;
mod fdm;
pub mod multiplayer;
mod sender;

pub use display::{DisplayState, EngineState};
pub use fdm::{
    CountField, DecodeError, FgNetFdm, AGL_UNKNOWN, DATAGRAM_LEN, FG_NET_FDM_VERSION, MAX_ENGINES,
    MAX_TANKS, MAX_WHEELS,
};
pub use multiplayer::{
    attitude_from_ecef_angle_axis, ecef_angle_axis_from_attitude, validate_name,
    HorizontalAttitudeDeg, MpDecodeError, MpEncodeError, MultiplayerPosition, NameError, NameField,
    NameProblem, WireField, CALLSIGN_FIELD_LEN, MODEL_PATH_FIELD_LEN, MP_HEADER_LEN, MP_MAGIC,
    MP_MAX_DATAGRAM_LEN, MP_POSITION_LEN, MP_POSITION_MESSAGE_ID, MP_PROTOCOL_VERSION,
};
pub use sender::{SendOutcome, Sender, SenderError, SenderStats};

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
