//! Parts of the public API the datagram tests do not reach (found by mutation
//! testing, docs/testing.md). The expectations come from FlightGear's
//! `net_fdm.hxx` (field names, `FG_MAX_*` array sizes) and from the
//! documented conversions, not from values the code printed.

use fgnet::{
    CountField, DecodeError, DisplayState, EngineState, FgNetFdm, MpDecodeError,
    MultiplayerPosition, NameField, SendOutcome, DATAGRAM_LEN, MP_MAX_DATAGRAM_LEN,
};

/// The count fields are named as in the C header, in the enum's `name`, its
/// `Display` and the decode error; the maxima are `FG_MAX_ENGINES` (4),
/// `FG_MAX_TANKS` (4) and `FG_MAX_WHEELS` (3).
#[test]
fn count_fields_carry_the_c_header_names_and_sizes() {
    for (field, name, max) in [
        (CountField::NumEngines, "num_engines", 4),
        (CountField::NumTanks, "num_tanks", 4),
        (CountField::NumWheels, "num_wheels", 3),
    ] {
        assert_eq!(field.name(), name);
        assert_eq!(field.to_string(), name);
        assert_eq!(field.max(), max);
        let err = DecodeError::CountTooLarge {
            field,
            value: max + 1,
        };
        let msg = err.to_string();
        assert!(msg.contains(&format!("{name} = {}", max + 1)), "{msg}");
    }
}

/// A count one above its array size, written into an otherwise valid
/// datagram, is rejected naming that field. The offsets are the v24 layout's
/// (docs/fgnetfdm.md §3): `num_engines` at 120, `num_tanks` at 284,
/// `num_wheels` at 304, each a big-endian `u32`.
#[test]
fn decode_names_the_count_that_is_too_large() {
    for (offset, field, value) in [
        (120, CountField::NumEngines, 5u32),
        (284, CountField::NumTanks, 5),
        (304, CountField::NumWheels, 4),
    ] {
        let mut bytes = FgNetFdm::new().encode();
        assert_eq!(bytes.len(), DATAGRAM_LEN);
        bytes[offset..offset + 4].copy_from_slice(&value.to_be_bytes());
        let err = FgNetFdm::decode(&bytes).unwrap_err();
        assert_eq!(err, DecodeError::CountTooLarge { field, value });
        assert!(err.to_string().contains(field.name()), "{err}");
    }
}

/// `From<&DisplayState>` and `From<DisplayState>` are `from_display`: the
/// same datagram, bit for bit, with the documented degree-to-radian and
/// engine conversions.
#[test]
fn from_display_state_by_reference_and_by_value() {
    let state = DisplayState {
        latitude_deg: 21.3,
        longitude_deg: -157.9,
        altitude_m: 1234.5,
        roll_deg: -12.0,
        pitch_deg: 4.5,
        heading_deg: 271.0,
        airspeed_kt: 101.0,
        engine_state: EngineState::Cranking,
        engine_rpm: 900.0,
        flaps_norm: 0.25,
        ..DisplayState::default()
    };
    let direct = FgNetFdm::from_display(&state);
    assert_eq!(direct.latitude, 21.3f64.to_radians());
    assert_eq!(direct.longitude, (-157.9f64).to_radians());
    assert_eq!(direct.altitude, 1234.5);
    assert_eq!(direct.psi, 271.0f64.to_radians() as f32);
    assert_eq!((direct.num_engines, direct.eng_state[0]), (1, 1));
    for converted in [FgNetFdm::from(&state), FgNetFdm::from(state)] {
        assert_eq!(converted.encode(), direct.encode());
    }
}

/// `NameField` describes the two text fields of the multiplayer header as the
/// layout table of docs/fg-multiplayer.md gives them: the callsign at byte 24
/// (8 bytes), the model path at byte 32 (96 bytes), and an encoded message
/// has the NUL-padded texts exactly there.
#[test]
fn name_fields_sit_where_the_layout_puts_them() {
    let model = "Aircraft/c172p/Models/c172p.xml";
    let bytes = MultiplayerPosition::new("N172", model)
        .unwrap()
        .encode()
        .unwrap();
    for (field, offset, len, text) in [
        (NameField::Callsign, 24, 8, "N172"),
        (NameField::ModelPath, 32, 96, model),
    ] {
        assert_eq!(field.offset(), offset);
        assert_eq!(field.field_len(), len);
        assert_eq!(field.max_chars(), len - 1);
        let mut expected = text.as_bytes().to_vec();
        expected.resize(len, 0);
        assert_eq!(&bytes[offset..offset + len], &expected[..], "{field}");
    }
}

/// The decoder's size limits at their edges. A datagram of exactly the
/// 32-byte header is long enough to read the header (so its own length field
/// is checked), then too short for the 232-byte position message. A datagram
/// of exactly 65507 bytes, the largest UDP payload over IPv4
/// (65535 - 20 - 8), is not too long: the decoder reports what is really
/// wrong with it.
#[test]
fn decode_limits_at_their_edges() {
    let header = MultiplayerPosition::new("N172", "Aircraft/c172p/Models/c172p.xml")
        .unwrap()
        .encode()
        .unwrap();
    let mut short = header[..32].to_vec();
    short[12..16].copy_from_slice(&32u32.to_be_bytes());
    assert_eq!(
        MultiplayerPosition::decode(&short),
        Err(MpDecodeError::Truncated { len: 32, need: 232 })
    );
    assert_eq!(MP_MAX_DATAGRAM_LEN, 65_535 - 20 - 8);
    let zeros = vec![0u8; 65_507];
    assert_eq!(
        MultiplayerPosition::decode(&zeros),
        Err(MpDecodeError::WrongMagic { found: 0 })
    );
    let too_long = vec![0u8; 65_508];
    assert_eq!(
        MultiplayerPosition::decode(&too_long),
        Err(MpDecodeError::TooLong {
            len: 65_508,
            max: 65_507
        })
    );
}

/// `is_sent` is true for a datagram handed to the operating system and false
/// for both kinds of failure.
#[test]
fn only_a_sent_datagram_is_sent() {
    assert!(SendOutcome::Sent.is_sent());
    assert!(!SendOutcome::Failed.is_sent());
    assert!(!SendOutcome::FirstFailure(std::io::Error::other("refused")).is_sent());
}
