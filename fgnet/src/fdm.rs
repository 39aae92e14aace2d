//! The FGNetFDM v24 struct, its encoders and its decoders.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Protocol version FlightGear 2020.3 accepts (`FG_NET_FDM_VERSION`).
pub const FG_NET_FDM_VERSION: u32 = 24;

/// Size in bytes of one v24 datagram (no trailing padding).
pub const DATAGRAM_LEN: usize = 408;

/// `FG_MAX_ENGINES`: length of the engine arrays and the largest valid `num_engines`.
pub const MAX_ENGINES: usize = 4;

/// `FG_MAX_TANKS`: length of `fuel_quantity` and the largest valid `num_tanks`.
pub const MAX_TANKS: usize = 4;

/// `FG_MAX_WHEELS`: length of the gear arrays and the largest valid `num_wheels`.
pub const MAX_WHEELS: usize = 3;

/// AGL value that makes FlightGear compute the height above ground itself.
///
/// FlightGear only uses the received `agl` when it is greater than -9000 m;
/// otherwise it computes `(altitude - ground elevation) * M2FT` from its own
/// terrain. Neither flight model in this workspace knows FlightGear's terrain,
/// so [`FgNetFdm::new`] sends this value.
pub const AGL_UNKNOWN: f32 = -9999.0;

/// Declares the FGNetFDM v24 fields once, in wire order, and generates from
/// that one list the struct (with every field's rustdoc and serde attributes),
/// the neutral values behind [`FgNetFdm::new`], the encoder and decoder
/// bodies, and the count clamping and checks.
///
/// Each entry is `pub name: Type = neutral value`, optionally followed by
/// `=> clamped to Count` for the three array counts (`Count` names a
/// [`CountField`] variant): the encoders write `min(value, Count.max())` and
/// the decoders reject larger values. Each type is written and read
/// big-endian through [`Wire`], so the list needs no sizes or offsets; the
/// layout tests in `tests/fgnet_layout.rs` pin every offset.
macro_rules! fgnetfdm_fields {
    (
        $(#[$struct_meta:meta])*
        pub struct $name:ident {
            $(
                $(#[$field_meta:meta])*
                pub $field:ident : $ty:ty = $neutral:expr $(=> clamped to $count:ident)?,
            )*
        }
    ) => {
        $(#[$struct_meta])*
        pub struct $name {
            $(
                $(#[$field_meta])*
                pub $field: $ty,
            )*
        }

        impl $name {
            /// Every field at its neutral value (see [`FgNetFdm::new`]).
            const fn neutral() -> Self {
                Self { $($field: $neutral,)* }
            }

            /// `self` with each count clamped to its array length.
            const fn clamp_counts(mut self) -> Self {
                $($(self.$field = clamp_count(self.$field, CountField::$count);)?)*
                self
            }

            /// The first count above its array length, if any.
            fn check_counts(&self) -> Result<(), DecodeError> {
                $($(
                    if self.$field > CountField::$count.max() {
                        return Err(DecodeError::CountTooLarge {
                            field: CountField::$count,
                            value: self.$field,
                        });
                    }
                )?)*
                Ok(())
            }

            /// Writes every field in wire order, counts clamped.
            #[inline(always)]
            fn write_fields(&self, w: &mut Writer<'_>) {
                $(w.put(&fgnetfdm_fields!(@on_wire self.$field $(, $count)?));)*
            }

            /// Reads every field in wire order, unchecked.
            #[inline(always)]
            fn read_fields(r: &mut Reader<'_>) -> Self {
                Self { $($field: r.get(),)* }
            }
        }
    };
    (@on_wire $value:expr) => {
        $value
    };
    (@on_wire $value:expr, $count:ident) => {
        clamp_count($value, CountField::$count)
    };
}

fgnetfdm_fields! {
    /// One FlightGear native-FDM datagram, protocol version 24 (`struct FGNetFDM`
    /// from FlightGear's `net_fdm.hxx`), 408 bytes on the wire.
    ///
    /// Field order, types and units follow the field table of docs/fgnetfdm.md §3; every field is
    /// sent big-endian. The "FlightGear does" notes describe what FlightGear 2020.3
    /// does with the field on receive (`FGNetFDM2Props`). `R2Df` is SimGear's
    /// *float* radians-to-degrees constant 57.2957763671875, so FlightGear shows
    /// angles 5.49e-8 (relative) smaller than the exact conversion.
    ///
    /// The serde field names are the C header's (so `A_X_pilot`, not
    /// `a_x_pilot`), which lets the struct be read from JSON such as the
    /// project's golden datagram. Deserialization rejects unknown fields.
    ///
    /// Array entries at index `>= num_*` are neither byte-swapped nor applied by
    /// FlightGear, but they are still transmitted and round-trip through
    /// [`encode`](Self::encode)/[`decode`](Self::decode).
    #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct FgNetFdm {
        /// Offset 0, `u32`: protocol version, must be 24.
        /// FlightGear byte-swaps the whole struct first and then compares this with
        /// 24; on mismatch it logs `read N need 24` and applies nothing.
        /// [`encode`](Self::encode) writes it verbatim (so a wrong version can be
        /// sent on purpose); [`decode`](Self::decode) rejects anything but 24.
        pub version: u32 = FG_NET_FDM_VERSION,
        /// Offset 4, `u32`: alignment padding so the first double is 8-byte
        /// aligned. FlightGear never reads it; send 0.
        pub padding: u32 = 0,
        /// Offset 8, `f64`: geodetic longitude, radians, east positive.
        /// FlightGear: `/position/longitude-deg = longitude * R2Df`.
        pub longitude: f64 = 0.0,
        /// Offset 16, `f64`: geodetic latitude, radians, north positive.
        /// FlightGear: `/position/latitude-deg = latitude * R2Df`.
        pub latitude: f64 = 0.0,
        /// Offset 24, `f64`: altitude above sea level, metres.
        /// FlightGear: `/position/altitude-ft = altitude * 3.28083989501312335958`.
        pub altitude: f64 = 0.0,
        /// Offset 32, `f32`: altitude above ground level, metres.
        /// FlightGear: if `agl > -9000`, `/position/altitude-agl-ft = agl * M2FT`;
        /// otherwise it computes AGL from its own terrain (see [`AGL_UNKNOWN`]).
        pub agl: f32 = AGL_UNKNOWN,
        /// Offset 36, `f32`: roll angle (phi), radians.
        /// FlightGear: `/orientation/roll-deg = phi * R2Df`.
        pub phi: f32 = 0.0,
        /// Offset 40, `f32`: pitch angle (theta), radians.
        /// FlightGear: `/orientation/pitch-deg = theta * R2Df`.
        pub theta: f32 = 0.0,
        /// Offset 44, `f32`: yaw angle (psi) = true heading, radians.
        /// FlightGear: `/orientation/heading-deg = psi * R2Df` (same setter as
        /// `/orientation/true-heading-deg`).
        pub psi: f32 = 0.0,
        /// Offset 48, `f32`: angle of attack, radians.
        /// FlightGear: `/orientation/alpha-deg = alpha * R2Df`.
        pub alpha: f32 = 0.0,
        /// Offset 52, `f32`: sideslip angle, radians.
        /// FlightGear: `/orientation/side-slip-rad = beta` (no conversion).
        pub beta: f32 = 0.0,
        /// Offset 56, `f32`: roll (Euler) rate, rad/s.
        /// FlightGear: `/orientation/roll-rate-degps = phidot * R2Df`.
        pub phidot: f32 = 0.0,
        /// Offset 60, `f32`: pitch rate, rad/s.
        /// FlightGear: `/orientation/pitch-rate-degps = thetadot * R2Df`.
        pub thetadot: f32 = 0.0,
        /// Offset 64, `f32`: yaw rate, rad/s.
        /// FlightGear: `/orientation/yaw-rate-degps = psidot * R2Df`.
        pub psidot: f32 = 0.0,
        /// Offset 68, `f32`: calibrated airspeed, knots.
        /// FlightGear: `/velocities/airspeed-kt`.
        pub vcas: f32 = 0.0,
        /// Offset 72, `f32`: vertical speed, ft/s (up positive).
        /// FlightGear: `/velocities/vertical-speed-fps`.
        pub climb_rate: f32 = 0.0,
        /// Offset 76, `f32`: north velocity (NED frame), ft/s.
        /// FlightGear: `/velocities/speed-north-fps`.
        pub v_north: f32 = 0.0,
        /// Offset 80, `f32`: east velocity (NED frame), ft/s.
        /// FlightGear: `/velocities/speed-east-fps`.
        pub v_east: f32 = 0.0,
        /// Offset 84, `f32`: down velocity (NED frame), ft/s.
        /// FlightGear: `/velocities/speed-down-fps`.
        pub v_down: f32 = 0.0,
        /// Offset 88, `f32`: ECEF velocity in the body frame, x (forward), ft/s.
        /// FlightGear: `/velocities/uBody-fps`.
        pub v_body_u: f32 = 0.0,
        /// Offset 92, `f32`: ECEF velocity in the body frame, y (right), ft/s.
        /// FlightGear: `/velocities/vBody-fps`.
        pub v_body_v: f32 = 0.0,
        /// Offset 96, `f32`: ECEF velocity in the body frame, z (down), ft/s.
        /// FlightGear: `/velocities/wBody-fps`.
        pub v_body_w: f32 = 0.0,
        /// Offset 100, `f32`: pilot x acceleration, body frame, ft/s².
        /// FlightGear: `/accelerations/pilot/x-accel-fps_sec`.
        #[serde(rename = "A_X_pilot")]
        pub a_x_pilot: f32 = 0.0,
        /// Offset 104, `f32`: pilot y acceleration, body frame, ft/s².
        /// FlightGear: `/accelerations/pilot/y-accel-fps_sec`.
        #[serde(rename = "A_Y_pilot")]
        pub a_y_pilot: f32 = 0.0,
        /// Offset 108, `f32`: pilot z acceleration, body frame, ft/s².
        /// FlightGear: `/accelerations/pilot/z-accel-fps_sec`.
        #[serde(rename = "A_Z_pilot")]
        pub a_z_pilot: f32 = 0.0,
        /// Offset 112, `f32`: amount of stall, 0.0 to 1.0.
        /// FlightGear: `/sim/alarms/stall-warning`.
        pub stall_warning: f32 = 0.0,
        /// Offset 116, `f32`: slip-ball deflection.
        /// FlightGear: `/instrumentation/slip-skid-ball/indicated-slip-skid`, and
        /// it also sets `/instrumentation/slip-skid-ball/override = true`.
        pub slip_deg: f32 = 0.0,
        /// Offset 120, `u32`: number of valid engines, at most [`MAX_ENGINES`].
        /// FlightGear uses it unchecked as the loop bound for byte-swapping and
        /// applying the engine arrays, so the encoder clamps it to 4 and
        /// [`decode`](Self::decode) rejects larger values.
        pub num_engines: u32 = 0 => clamped to NumEngines,
        /// Offset 124, `u32[4]`: engine state, 0 off, 1 cranking, 2 running.
        /// FlightGear sets `/engines/engine[i]/cranking` and `/running`
        /// (0 → false, false; 1 → true, false; 2 → false, true; other values leave
        /// both unchanged).
        pub eng_state: [u32; MAX_ENGINES] = [0; MAX_ENGINES],
        /// Offset 140, `f32[4]`: engine speed, rev/min.
        /// FlightGear: `/engines/engine[i]/rpm`.
        pub rpm: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 156, `f32[4]`: fuel flow, US gallons/hour.
        /// FlightGear: `/engines/engine[i]/fuel-flow-gph`.
        pub fuel_flow: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 172, `f32[4]`: fuel pressure, psi.
        /// FlightGear: `/engines/engine[i]/fuel-px-psi`.
        pub fuel_px: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 188, `f32[4]`: exhaust gas temperature, °F.
        /// FlightGear: `/engines/engine[i]/egt-degf`.
        pub egt: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 204, `f32[4]`: cylinder head temperature, °F.
        /// FlightGear: `/engines/engine[i]/cht-degf`.
        pub cht: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 220, `f32[4]`: manifold pressure (unit not stated by the
        /// header; JSBSim sends inHg).
        /// FlightGear: `/engines/engine[i]/mp-osi`.
        pub mp_osi: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 236, `f32[4]`: turbine inlet temperature (unit not stated by
        /// the header).
        /// FlightGear: `/engines/engine[i]/tit`.
        pub tit: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 252, `f32[4]`: oil temperature, °F.
        /// FlightGear: `/engines/engine[i]/oil-temperature-degf`.
        pub oil_temp: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 268, `f32[4]`: oil pressure, psi.
        /// FlightGear: `/engines/engine[i]/oil-pressure-psi`.
        pub oil_px: [f32; MAX_ENGINES] = [0.0; MAX_ENGINES],
        /// Offset 284, `u32`: number of valid tanks, at most [`MAX_TANKS`].
        /// Unchecked loop bound in FlightGear: clamped by the encoder, rejected
        /// above 4 by the decoder.
        pub num_tanks: u32 = 0 => clamped to NumTanks,
        /// Offset 288, `f32[4]`: fuel per tank, US gallons (FlightGear's own
        /// sender and receiver; JSBSim sends pounds).
        /// FlightGear: `/consumables/fuel/tank[i]/level-gal_us`.
        pub fuel_quantity: [f32; MAX_TANKS] = [0.0; MAX_TANKS],
        /// Offset 304, `u32`: number of valid gear units, at most [`MAX_WHEELS`].
        /// Unchecked loop bound in FlightGear: clamped by the encoder, rejected
        /// above 3 by the decoder.
        pub num_wheels: u32 = 0 => clamped to NumWheels,
        /// Offset 308, `u32[3]`: weight on wheels, 0 or 1.
        /// FlightGear: `/gear/gear[i]/wow` (written with `setDoubleValue`).
        pub wow: [u32; MAX_WHEELS] = [0; MAX_WHEELS],
        /// Offset 320, `f32[3]`: gear position, normalised (1 = down).
        /// FlightGear: `/gear/gear[i]/position-norm`.
        pub gear_pos: [f32; MAX_WHEELS] = [0.0; MAX_WHEELS],
        /// Offset 332, `f32[3]`: gear steering, normalised.
        /// FlightGear: `/gear/gear[i]/steering-norm`.
        pub gear_steer: [f32; MAX_WHEELS] = [0.0; MAX_WHEELS],
        /// Offset 344, `f32[3]`: gear compression, normalised.
        /// FlightGear: `/gear/gear[i]/compression-norm`.
        pub gear_compression: [f32; MAX_WHEELS] = [0.0; MAX_WHEELS],
        /// Offset 356, `u32`: current Unix time, seconds.
        /// FlightGear byte-swaps it and then ignores it.
        pub cur_time: u32 = 0,
        /// Offset 360, `i32`: offset in seconds to Unix time.
        /// FlightGear byte-swaps it and then ignores it.
        pub warp: i32 = 0,
        /// Offset 364, `f32`: visibility, metres.
        /// FlightGear byte-swaps it and then ignores it.
        pub visibility: f32 = 0.0,
        /// Offset 368, `f32`: elevator position, normalised.
        /// FlightGear: `/surface-positions/elevator-pos-norm`.
        pub elevator: f32 = 0.0,
        /// Offset 372, `f32`: elevator trim tab position, normalised.
        /// FlightGear: `/surface-positions/elevator-trim-tab-pos-norm`.
        pub elevator_trim_tab: f32 = 0.0,
        /// Offset 376, `f32`: left flap position, normalised.
        /// FlightGear writes it to `/surface-positions/flap-pos-norm` and then
        /// overwrites that same property with [`right_flap`](Self::right_flap):
        /// in effect this field is ignored.
        pub left_flap: f32 = 0.0,
        /// Offset 380, `f32`: right flap position, normalised.
        /// FlightGear: `/surface-positions/flap-pos-norm` (it wins over
        /// [`left_flap`](Self::left_flap)).
        pub right_flap: f32 = 0.0,
        /// Offset 384, `f32`: left aileron position, normalised.
        /// FlightGear: `/surface-positions/left-aileron-pos-norm`.
        pub left_aileron: f32 = 0.0,
        /// Offset 388, `f32`: right aileron position, normalised.
        /// FlightGear: `/surface-positions/right-aileron-pos-norm`.
        pub right_aileron: f32 = 0.0,
        /// Offset 392, `f32`: rudder position, normalised.
        /// FlightGear: `/surface-positions/rudder-pos-norm`.
        pub rudder: f32 = 0.0,
        /// Offset 396, `f32`: nose wheel position, normalised.
        /// FlightGear: `/surface-positions/nose-wheel-pos-norm`.
        pub nose_wheel: f32 = 0.0,
        /// Offset 400, `f32`: speedbrake position, normalised.
        /// FlightGear: `/surface-positions/speedbrake-pos-norm`.
        pub speedbrake: f32 = 0.0,
        /// Offset 404, `f32`: spoiler position, normalised.
        /// FlightGear: `/surface-positions/spoilers-pos-norm`.
        pub spoilers: f32 = 0.0,
    }
}

/// Which of the three array counts a [`DecodeError::CountTooLarge`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CountField {
    /// `num_engines` (at most [`MAX_ENGINES`]).
    NumEngines,
    /// `num_tanks` (at most [`MAX_TANKS`]).
    NumTanks,
    /// `num_wheels` (at most [`MAX_WHEELS`]).
    NumWheels,
}

impl CountField {
    /// The C header's field name, e.g. `"num_engines"`.
    pub const fn name(self) -> &'static str {
        match self {
            Self::NumEngines => "num_engines",
            Self::NumTanks => "num_tanks",
            Self::NumWheels => "num_wheels",
        }
    }

    /// The largest value FlightGear's fixed arrays allow for this count.
    pub const fn max(self) -> u32 {
        match self {
            Self::NumEngines => MAX_ENGINES as u32,
            Self::NumTanks => MAX_TANKS as u32,
            Self::NumWheels => MAX_WHEELS as u32,
        }
    }
}

impl core::fmt::Display for CountField {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a buffer is not a valid FGNetFDM v24 datagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum DecodeError {
    /// The buffer is not exactly [`DATAGRAM_LEN`] (408) bytes long.
    #[error("FGNetFDM v24 datagram must be exactly 408 bytes, got {len}")]
    WrongLength {
        /// Length of the rejected buffer, in bytes.
        len: usize,
    },
    /// The big-endian version field is not 24. A little-endian 24 reads as
    /// 402653184 (0x18000000), which is what FlightGear logs as
    /// `read 402653184 need 24`.
    #[error(
        "FGNetFDM version {found} (0x{found:08x}), need 24{}",
        if *found == FG_NET_FDM_VERSION.swap_bytes() {
            ": this is 24 written little-endian"
        } else {
            ""
        }
    )]
    WrongVersion {
        /// The version value read big-endian from offset 0.
        found: u32,
    },
    /// `num_engines`, `num_tanks` or `num_wheels` exceeds FlightGear's array
    /// size (4, 4, 3); FlightGear would write past its buffers.
    #[error("FGNetFDM {field} = {value} exceeds FlightGear's maximum of {}", field.max())]
    CountTooLarge {
        /// Which count.
        field: CountField,
        /// The value read.
        value: u32,
    },
}

impl Default for FgNetFdm {
    /// Same as [`FgNetFdm::new`].
    fn default() -> Self {
        Self::new()
    }
}

/// bincode 2 configuration matching the wire format: big-endian, fixed-size
/// integers (no varints). Fixed-size arrays are serde tuples, which bincode
/// writes without a length prefix; a test asserts the 408-byte result.
const BINCODE_CONFIG: bincode::config::Configuration<
    bincode::config::BigEndian,
    bincode::config::Fixint,
> = bincode::config::standard()
    .with_big_endian()
    .with_fixed_int_encoding();

impl FgNetFdm {
    /// A neutral datagram that FlightGear accepts and that overwrites as
    /// little as possible of its state:
    ///
    /// * `version` = 24, `padding` = 0;
    /// * `agl` = [`AGL_UNKNOWN`] (-9999 m), so FlightGear computes the height
    ///   above ground from its own terrain rather than trusting a value the
    ///   flight models cannot know;
    /// * `num_engines` = `num_tanks` = `num_wheels` = 0: FlightGear then
    ///   neither byte-swaps nor applies any engine, tank or gear array entry,
    ///   so its own engine, fuel and gear properties are left alone (docs/fgnetfdm.md §5
    ///   calls 0 the safest count). Set them explicitly when sending those
    ///   arrays; [`FgNetFdm::from_display`] sets `num_engines` = 1;
    /// * every other field 0 (position 0°N 0°E at sea level, level attitude,
    ///   at rest, surfaces centred, engines off, `cur_time`, `warp` and
    ///   `visibility` 0, which FlightGear ignores anyway).
    pub const fn new() -> Self {
        Self::neutral()
    }

    /// A copy with `num_engines`, `num_tanks` and `num_wheels` clamped to
    /// 4, 4 and 3: what the encoders put on the wire.
    ///
    /// ```
    /// let mut fdm = fgnet::FgNetFdm::new();
    /// fdm.num_engines = 9;
    /// fdm.num_wheels = u32::MAX;
    /// let c = fdm.clamped();
    /// assert_eq!((c.num_engines, c.num_tanks, c.num_wheels), (4, 0, 3));
    /// ```
    #[must_use]
    pub const fn clamped(&self) -> Self {
        self.clamp_counts()
    }

    /// Encodes the datagram: exactly 408 bytes, every field big-endian, with
    /// the counts clamped to 4/4/3 (see [`clamped`](Self::clamped)).
    ///
    /// Uses the `to_be_bytes` encoder generated from the field list; see the crate docs for
    /// why, and [`encode_bincode`](Self::encode_bincode) for the serde +
    /// bincode 2 encoder that a test keeps byte-identical.
    ///
    /// ```
    /// let bytes = fgnet::FgNetFdm::new().encode();
    /// assert_eq!(bytes.len(), 408);
    /// assert_eq!(bytes[..8], [0, 0, 0, 24, 0, 0, 0, 0]);
    /// ```
    #[must_use]
    pub fn encode(&self) -> [u8; DATAGRAM_LEN] {
        let mut out = [0u8; DATAGRAM_LEN];
        self.encode_into(&mut out);
        out
    }

    /// Like [`encode`](Self::encode), writing into an existing buffer (every
    /// byte is overwritten).
    pub fn encode_into(&self, out: &mut [u8; DATAGRAM_LEN]) {
        let mut w = Writer { buf: out, pos: 0 };
        self.write_fields(&mut w);
        debug_assert_eq!(w.pos, DATAGRAM_LEN);
    }

    /// The serde + bincode 2 encoder (big-endian, fixed-int configuration):
    /// the same 408 bytes as [`encode`](Self::encode), counts clamped the
    /// same way. Kept for cross-checking and benchmarking; a test asserts
    /// both encoders give identical bytes.
    ///
    /// # Panics
    /// Never in practice: under the fixed-int configuration the struct always
    /// serializes to exactly 408 bytes, which a test asserts.
    #[must_use]
    pub fn encode_bincode(&self) -> [u8; DATAGRAM_LEN] {
        let mut out = [0u8; DATAGRAM_LEN];
        let written = bincode::serde::encode_into_slice(self.clamped(), &mut out, BINCODE_CONFIG)
            .expect("FGNetFDM serializes to exactly 408 bytes under fixed-int encoding");
        debug_assert_eq!(written, DATAGRAM_LEN);
        out
    }

    /// Decodes one datagram, bit-exactly (NaN payloads included).
    ///
    /// Stricter than FlightGear, which applies the first 408 bytes of a longer
    /// datagram: this rejects any length other than 408, a version other than
    /// 24 and counts above 4/4/3, in that order. It never panics.
    ///
    /// ```
    /// use fgnet::{DecodeError, FgNetFdm};
    /// let bytes = FgNetFdm::new().encode();
    /// assert_eq!(FgNetFdm::decode(&bytes), Ok(FgNetFdm::new()));
    /// assert_eq!(FgNetFdm::decode(&bytes[..407]), Err(DecodeError::WrongLength { len: 407 }));
    ///
    /// let mut little_endian = bytes;
    /// little_endian[..4].copy_from_slice(&24u32.to_le_bytes());
    /// assert_eq!(
    ///     FgNetFdm::decode(&little_endian),
    ///     Err(DecodeError::WrongVersion { found: 402_653_184 })
    /// );
    /// ```
    ///
    /// # Errors
    /// [`DecodeError`] naming the wrong length, the version read, or the
    /// count and its value.
    pub fn decode(buf: &[u8]) -> Result<Self, DecodeError> {
        let buf: &[u8; DATAGRAM_LEN] = buf
            .try_into()
            .map_err(|_| DecodeError::WrongLength { len: buf.len() })?;
        let mut r = Reader { buf, pos: 0 };
        let fdm = Self::read_fields(&mut r);
        debug_assert_eq!(r.pos, DATAGRAM_LEN);
        fdm.validate()
    }

    /// The serde + bincode 2 decoder: same checks and results as
    /// [`decode`](Self::decode) (a test keeps them identical). Kept for
    /// cross-checking and benchmarking.
    ///
    /// # Errors
    /// The same [`DecodeError`]s as [`decode`](Self::decode).
    pub fn decode_bincode(buf: &[u8]) -> Result<Self, DecodeError> {
        if buf.len() != DATAGRAM_LEN {
            return Err(DecodeError::WrongLength { len: buf.len() });
        }
        // Every 408-byte buffer is a valid bit pattern for the struct's
        // integer and float fields, so bincode cannot fail here; map the
        // impossible case to the length error rather than panicking.
        let (fdm, _): (Self, usize) = bincode::serde::decode_from_slice(buf, BINCODE_CONFIG)
            .map_err(|_| DecodeError::WrongLength { len: buf.len() })?;
        fdm.validate()
    }

    fn validate(self) -> Result<Self, DecodeError> {
        if self.version != FG_NET_FDM_VERSION {
            return Err(DecodeError::WrongVersion {
                found: self.version,
            });
        }
        self.check_counts()?;
        Ok(self)
    }
}

/// `value`, or the largest value `field` allows if `value` is larger.
const fn clamp_count(value: u32, field: CountField) -> u32 {
    if value > field.max() {
        field.max()
    } else {
        value
    }
}

/// Sequential big-endian writer; after inlining every offset is a constant.
struct Writer<'a> {
    buf: &'a mut [u8; DATAGRAM_LEN],
    pos: usize,
}

impl Writer<'_> {
    #[inline(always)]
    fn bytes<const N: usize>(&mut self, b: [u8; N]) {
        self.buf[self.pos..self.pos + N].copy_from_slice(&b);
        self.pos += N;
    }
    #[inline(always)]
    fn put<T: Wire>(&mut self, v: &T) {
        v.write(self);
    }
}

/// Sequential big-endian reader over a buffer already known to be 408 bytes.
struct Reader<'a> {
    buf: &'a [u8; DATAGRAM_LEN],
    pos: usize,
}

impl Reader<'_> {
    #[inline(always)]
    fn bytes<const N: usize>(&mut self) -> [u8; N] {
        let mut b = [0u8; N];
        b.copy_from_slice(&self.buf[self.pos..self.pos + N]);
        self.pos += N;
        b
    }
    #[inline(always)]
    fn get<T: Wire>(&mut self) -> T {
        T::read(self)
    }
}

/// A field type of the datagram: written and read big-endian, arrays entry
/// by entry with no length prefix.
trait Wire: Sized {
    fn write(&self, w: &mut Writer<'_>);
    fn read(r: &mut Reader<'_>) -> Self;
}

macro_rules! wire_scalar {
    ($($t:ty),*) => {$(
        impl Wire for $t {
            #[inline(always)]
            fn write(&self, w: &mut Writer<'_>) {
                w.bytes(self.to_be_bytes());
            }
            #[inline(always)]
            fn read(r: &mut Reader<'_>) -> Self {
                Self::from_be_bytes(r.bytes())
            }
        }
    )*};
}

wire_scalar!(u32, i32, f32, f64);

impl<T: Wire, const N: usize> Wire for [T; N] {
    #[inline(always)]
    fn write(&self, w: &mut Writer<'_>) {
        for x in self {
            x.write(w);
        }
    }
    #[inline(always)]
    fn read(r: &mut Reader<'_>) -> Self {
        core::array::from_fn(|_| T::read(r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> FgNetFdm {
        let mut f = FgNetFdm::new();
        f.longitude = -2.1358466721280607;
        f.latitude = f64::from_bits(0x7ff0_0000_dead_beef); // signalling NaN
        f.phi = f32::from_bits(0x7f80_0001); // signalling NaN
        f.theta = f32::from_bits(0xffc1_2345); // negative quiet NaN with payload
        f.num_engines = 2;
        f.eng_state = [2, 1, 7, u32::MAX];
        f.rpm = [2400.0, -0.0, f32::INFINITY, f32::MIN_POSITIVE / 2.0];
        f.num_tanks = 4;
        f.num_wheels = 3;
        f.wow = [1, 0, 1];
        f.warp = i32::MIN;
        f.cur_time = u32::MAX;
        f.spoilers = 0.75;
        f
    }

    #[test]
    fn encoders_agree_and_round_trip() {
        let f = sample();
        let a = f.encode();
        assert_eq!(a, f.encode_bincode());
        let back = FgNetFdm::decode(&a).unwrap();
        assert_eq!(back.encode(), a);
        assert_eq!(back.latitude.to_bits(), 0x7ff0_0000_dead_beef);
        assert_eq!(back.phi.to_bits(), 0x7f80_0001);
        assert_eq!(back.theta.to_bits(), 0xffc1_2345);
        assert_eq!(back.warp, i32::MIN);
        let back_b = FgNetFdm::decode_bincode(&a).unwrap();
        assert_eq!(back_b.encode(), a);
    }

    #[test]
    fn bincode_writes_exactly_408_bytes_without_length_prefixes() {
        let mut big = [0u8; 512];
        let n = bincode::serde::encode_into_slice(sample(), &mut big, BINCODE_CONFIG).unwrap();
        assert_eq!(n, DATAGRAM_LEN);
        // First array (eng_state) starts right after num_engines at 124: no prefix.
        assert_eq!(big[120..128], [0, 0, 0, 2, 0, 0, 0, 2]);
    }

    #[test]
    fn encoders_clamp_counts() {
        let mut f = FgNetFdm::new();
        f.num_engines = 5;
        f.num_tanks = 67_108_864; // 4 read with the wrong byte order
        f.num_wheels = 4;
        for bytes in [f.encode(), f.encode_bincode()] {
            assert_eq!(bytes[120..124], 4u32.to_be_bytes());
            assert_eq!(bytes[284..288], 4u32.to_be_bytes());
            assert_eq!(bytes[304..308], 3u32.to_be_bytes());
        }
        // Counts at the limit are kept as they are.
        f.num_engines = 3;
        f.num_tanks = 1;
        f.num_wheels = 2;
        let bytes = f.encode();
        assert_eq!(bytes[123], 3);
        assert_eq!(bytes[287], 1);
        assert_eq!(bytes[307], 2);
    }

    #[test]
    fn decode_errors_name_what_is_wrong() {
        let good = FgNetFdm::new().encode();
        let e = FgNetFdm::decode(&[0u8; 409]).unwrap_err();
        assert_eq!(e, DecodeError::WrongLength { len: 409 });
        assert!(e.to_string().contains("409"), "{e}");

        let mut le = good;
        le[..4].copy_from_slice(&24u32.to_le_bytes());
        let e = FgNetFdm::decode(&le).unwrap_err();
        assert_eq!(e, DecodeError::WrongVersion { found: 402_653_184 });
        let msg = e.to_string();
        assert!(
            msg.contains("402653184") && msg.contains("little-endian"),
            "{msg}"
        );

        let mut v25 = good;
        v25[..4].copy_from_slice(&25u32.to_be_bytes());
        let msg = FgNetFdm::decode(&v25).unwrap_err().to_string();
        assert!(
            msg.contains("25") && !msg.contains("little-endian"),
            "{msg}"
        );

        for (off, field, value) in [
            (120, CountField::NumEngines, 5u32),
            (284, CountField::NumTanks, 67_108_864),
            (304, CountField::NumWheels, 4),
        ] {
            let mut b = good;
            b[off..off + 4].copy_from_slice(&value.to_be_bytes());
            let e = FgNetFdm::decode(&b).unwrap_err();
            assert_eq!(e, DecodeError::CountTooLarge { field, value });
            assert_eq!(FgNetFdm::decode_bincode(&b).unwrap_err(), e);
            let msg = e.to_string();
            assert!(
                msg.contains(field.name()) && msg.contains(&value.to_string()),
                "{msg}"
            );
        }
    }

    #[test]
    fn new_is_neutral_and_default() {
        let f = FgNetFdm::default();
        assert_eq!(f, FgNetFdm::new());
        assert_eq!(f.version, 24);
        assert_eq!(f.agl, AGL_UNKNOWN);
        assert_eq!((f.num_engines, f.num_tanks, f.num_wheels), (0, 0, 0));
    }
}
