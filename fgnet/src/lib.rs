//! FlightGear "native FDM" datagrams (FGNetFDM, protocol version 24): the
//! 408-byte big-endian struct FlightGear 2020.3 accepts on
//! `--native-fdm=socket,in,...,udp`, its encoder and decoder, and a UDP sender.
//!
//! * [`FgNetFdm`]: every v24 field, with its unit and what FlightGear does
//!   with it; [`FgNetFdm::encode`] / [`FgNetFdm::encode_into`] and
//!   [`FgNetFdm::decode`].
//! * [`DisplayState`]: what a flight model hands over (degrees, metres, ft/s,
//!   knots), converted with [`FgNetFdm::from_display`].
//! * [`Sender`]: a connected UDP socket that keeps going when nobody listens.
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
//! are hand-written: one `to_be_bytes`/`from_be_bytes` per field at offsets
//! that inlining turns into constants. The serde + bincode 2 path
//! (`bincode::config::standard().with_big_endian().with_fixed_int_encoding()`,
//! arrays as serde tuples, so no length prefixes) is kept as
//! [`FgNetFdm::encode_bincode`] and [`FgNetFdm::decode_bincode`]; tests assert
//! that both give identical bytes and identical decoded values (NaN payloads
//! included). The hand-written path is clearly better on speed, so it is the
//! one used. Criterion medians (`benches/fgnet_encode.rs`, `cargo bench --bench
//! fgnet_encode -- --warm-up-time 1 --measurement-time 5`, on the project's
//! shared 2-core x86-64 machine):
//!
//! | operation | hand-written | serde + bincode 2 |
//! | --- | ---: | ---: |
//! | encode into an existing buffer | 18 ns (`encode_into`) | |
//! | encode returning `[u8; 408]` | 40 ns (`encode`) | 162 ns (`encode_bincode`) |
//! | decode with validation | 26 ns (`decode`) | 248 ns (`decode_bincode`) |
//!
//! bincode goes through serde's visitor for each of the 60 fields and checks
//! the remaining slice length and propagates a `Result` per write, which
//! costs about 2.5 ns per field; the hand-written code has no error paths
//! because the buffer is a `[u8; 408]`. Returning the array by value costs
//! about 20 ns over [`FgNetFdm::encode_into`] (zeroing and copying 408 bytes),
//! which is why [`Sender`] encodes into a buffer it keeps.
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

mod display;
mod fdm;
mod sender;

pub use display::{DisplayState, EngineState};
pub use fdm::{
    CountField, DecodeError, FgNetFdm, AGL_UNKNOWN, DATAGRAM_LEN, FG_NET_FDM_VERSION, MAX_ENGINES,
    MAX_TANKS, MAX_WHEELS,
};
pub use sender::{SendOutcome, Sender, SenderError, SenderStats};
