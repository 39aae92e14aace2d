//! FlightGear multiplayer position messages: a golden datagram written by
//! hand from the layout table (not by the encoder), every field's offset,
//! bit-exact round trips, decoding arbitrary bytes without panicking, the
//! typed errors, and a UDP send/receive over 127.0.0.1.

use std::net::UdpSocket;
use std::time::Duration;

use fgnet::{
    MpDecodeError, MpEncodeError, MultiplayerPosition, NameError, NameField, NameProblem,
    MP_MAX_DATAGRAM_LEN, MP_POSITION_LEN,
};
use proptest::prelude::*;

/// Big-endian hex text to bytes (spaces ignored).
fn hex(text: &str) -> Vec<u8> {
    let digits: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    digits
        .chunks(2)
        .map(|p| u8::from_str_radix(std::str::from_utf8(p).unwrap(), 16).unwrap())
        .collect()
}

/// `text` NUL-padded to `n` bytes.
fn padded(text: &str, n: usize) -> Vec<u8> {
    let mut v = text.as_bytes().to_vec();
    v.resize(n, 0);
    v
}

const MODEL: &str = "Aircraft/ufo/Models/ufo.xml";

/// The message the golden bytes describe.
fn golden_message() -> MultiplayerPosition {
    let mut m = MultiplayerPosition::new("MP1", MODEL).unwrap();
    m.requested_range_nm = 100;
    m.time_s = 1.5;
    m.lag_s = 0.25;
    m.position_ecef_m = [6_378_137.0, -1.0, 1024.0];
    m.orientation_angle_axis_rad = [0.5, -2.0, 0.0];
    m.linear_velocity_body_mps = [100.0, 1.0, -1.0];
    m.angular_velocity_body_radps = [0.25, 0.0, -0.0];
    m.linear_acceleration_body_mps2 = [2.0, 4.0, 8.0];
    m.angular_acceleration_body_radps2 = [f32::INFINITY, f32::from_bits(0x7fc0_0001), -1.5];
    m
}

/// The golden datagram, one line per row of the layout table. The IEEE-754
/// patterns were worked out by hand (sign, biased exponent, mantissa): e.g.
/// 1.5 = 1.1b × 2^0 → 0x3FF8…; 6378137 = 0x615299 = 1.0000101010010100110011b
/// × 2^22 → exponent 1023 + 22 = 0x415, mantissa 0x215299 << 30 =
/// 0x854A640000000 → 0x415854A640000000; 100.0f = 1.5625 × 2^6 → 0x42C80000.
fn golden_bytes() -> Vec<u8> {
    let mut b = Vec::new();
    b.extend(hex("46474653")); //   0 magic "FGFS"
    b.extend(hex("00010001")); //   4 version 1.1
    b.extend(hex("00000007")); //   8 message id 7
    b.extend(hex("000000e8")); //  12 length 232
    b.extend(hex("00000064")); //  16 requested range 100 nm
    b.extend(hex("00000000")); //  20 reply port
    b.extend(hex("4d50310000000000")); // 24 "MP1" NUL-padded to 8
    b.extend(padded(MODEL, 96)); // 32 model path NUL-padded to 96
    b.extend(hex("3ff8000000000000")); // 128 time 1.5 s
    b.extend(hex("3fd0000000000000")); // 136 lag 0.25 s
    b.extend(hex("415854a640000000")); // 144 x 6378137 m
    b.extend(hex("bff0000000000000")); // 152 y -1 m
    b.extend(hex("4090000000000000")); // 160 z 1024 m
    b.extend(hex("3f000000 c0000000 00000000")); // 168 orientation 0.5, -2, 0
    b.extend(hex("42c80000 3f800000 bf800000")); // 180 velocity 100, 1, -1
    b.extend(hex("3e800000 00000000 80000000")); // 192 angular velocity 0.25, 0, -0
    b.extend(hex("40000000 40800000 41000000")); // 204 acceleration 2, 4, 8
    b.extend(hex("7f800000 7fc00001 bfc00000")); // 216 angular accel. inf, NaN(1), -1.5
    b.extend(hex("00000000")); // 228 padding
    assert_eq!(b.len(), 232);
    b
}

/// Every number of the message as raw bits, in wire order, plus the texts
/// and property words: equality of this is bitwise equality.
fn bits(m: &MultiplayerPosition) -> (Vec<u64>, String, String, Vec<u32>) {
    let mut v = vec![
        u64::from(m.requested_range_nm),
        u64::from(m.reply_port),
        m.time_s.to_bits(),
        m.lag_s.to_bits(),
    ];
    v.extend(m.position_ecef_m.map(f64::to_bits));
    for a in [
        m.orientation_angle_axis_rad,
        m.linear_velocity_body_mps,
        m.angular_velocity_body_radps,
        m.linear_acceleration_body_mps2,
        m.angular_acceleration_body_radps2,
    ] {
        v.extend(a.map(|x| u64::from(x.to_bits())));
    }
    v.push(u64::from(m.padding));
    (
        v,
        m.callsign.clone(),
        m.model_path.clone(),
        m.property_words.clone(),
    )
}

#[test]
fn golden_datagram_byte_for_byte() {
    let golden = golden_bytes();
    let m = golden_message();
    let encoded = m.encode().unwrap();
    if let Some(at) = encoded.iter().zip(&golden).position(|(a, b)| a != b) {
        panic!(
            "encode differs from the golden datagram at byte {at}: ours {:02x?}, golden {:02x?}",
            &encoded[at..(at + 8).min(232)],
            &golden[at..(at + 8).min(232)]
        );
    }
    assert_eq!(encoded.len(), golden.len());

    let mut buf = [0xAAu8; 300];
    assert_eq!(m.encode_into(&mut buf), Ok(232));
    assert_eq!(buf[..232], golden[..], "encode_into writes the datagram");
    assert!(
        buf[232..].iter().all(|&b| b == 0xAA),
        "and nothing after it"
    );

    let decoded = MultiplayerPosition::decode(&golden).unwrap();
    assert_eq!(bits(&decoded), bits(&m));
    assert_eq!(
        decoded.angular_acceleration_body_radps2[1].to_bits(),
        0x7fc0_0001
    );
    assert_eq!(decoded.callsign, "MP1");
    assert_eq!(decoded.model_path, MODEL);
}

#[test]
fn property_words_follow_at_232_and_count_in_the_length() {
    let mut m = golden_message();
    m.property_words = vec![0x0000_0064, 0xdead_beef];
    let mut golden = golden_bytes();
    golden[12..16].copy_from_slice(&hex("000000f0")); // 240
    golden.extend(hex("00000064 deadbeef"));
    assert_eq!(m.encoded_len(), 240);
    assert_eq!(m.encode().unwrap(), golden);
    assert_eq!(
        bits(&MultiplayerPosition::decode(&golden).unwrap()),
        bits(&m)
    );
}

/// (name, offset, size in bytes) from the layout table, typed in from it.
const SPEC_FIELDS: &[(&str, usize, usize)] = &[
    ("requested_range_nm", 16, 4),
    ("reply_port", 20, 4),
    ("callsign", 24, 8),
    ("model_path", 32, 96),
    ("time_s", 128, 8),
    ("lag_s", 136, 8),
    ("position_ecef_m", 144, 24),
    ("orientation_angle_axis_rad", 168, 12),
    ("linear_velocity_body_mps", 180, 12),
    ("angular_velocity_body_radps", 192, 12),
    ("linear_acceleration_body_mps2", 204, 12),
    ("angular_acceleration_body_radps2", 216, 12),
    ("padding", 228, 4),
];

#[test]
fn the_crate_field_list_matches_the_layout_table() {
    let ours: Vec<(&str, usize, usize)> = MultiplayerPosition::FIELDS
        .iter()
        .map(|f| (f.name, f.offset, f.len))
        .collect();
    assert_eq!(ours, SPEC_FIELDS);
}

/// Changing one field changes exactly the bytes of its slot in the table,
/// and they hold the new value big-endian.
#[test]
fn every_field_lands_at_its_offset() {
    let base = MultiplayerPosition::new("A", "B").unwrap();
    let base_bytes = base.encode().unwrap();
    type Set = fn(&mut MultiplayerPosition);
    let cases: &[(&str, Set, Vec<u8>)] = &[
        (
            "requested_range_nm",
            |m| m.requested_range_nm = 0x0102_0304,
            hex("01020304"),
        ),
        (
            "reply_port",
            |m| m.reply_port = 0xa1b2_c3d4,
            hex("a1b2c3d4"),
        ),
        (
            "callsign",
            |m| m.callsign = "ABCDEFG".into(),
            hex("4142434445464700"),
        ),
        ("model_path", |m| m.model_path = "x".repeat(95), {
            let mut v = vec![b'x'; 95];
            v.push(0);
            v
        }),
        ("time_s", |m| m.time_s = -2.0, hex("c000000000000000")),
        ("lag_s", |m| m.lag_s = 0.5, hex("3fe0000000000000")),
        (
            "position_ecef_m",
            |m| m.position_ecef_m = [1.0, -2.0, 0.25],
            hex("3ff0000000000000 c000000000000000 3fd0000000000000"),
        ),
        (
            "orientation_angle_axis_rad",
            |m| m.orientation_angle_axis_rad = [1.0, 2.0, -0.5],
            hex("3f800000 40000000 bf000000"),
        ),
        (
            "linear_velocity_body_mps",
            |m| m.linear_velocity_body_mps = [4.0, 8.0, 0.5],
            hex("40800000 41000000 3f000000"),
        ),
        (
            "angular_velocity_body_radps",
            |m| m.angular_velocity_body_radps = [-1.0, -2.0, -4.0],
            hex("bf800000 c0000000 c0800000"),
        ),
        (
            "linear_acceleration_body_mps2",
            |m| m.linear_acceleration_body_mps2 = [0.25, 100.0, 1.5],
            hex("3e800000 42c80000 3fc00000"),
        ),
        (
            "angular_acceleration_body_radps2",
            |m| m.angular_acceleration_body_radps2 = [f32::NEG_INFINITY, 2.0, 1.0],
            hex("ff800000 40000000 3f800000"),
        ),
        ("padding", |m| m.padding = 0xffff_ffff, hex("ffffffff")),
    ];
    assert_eq!(cases.len(), SPEC_FIELDS.len());
    for ((name, set, expected), &(spec_name, offset, size)) in cases.iter().zip(SPEC_FIELDS) {
        assert_eq!(*name, spec_name);
        assert_eq!(expected.len(), size, "{name}");
        let mut m = base.clone();
        set(&mut m);
        let bytes = m.encode().unwrap();
        assert_eq!(
            bytes[offset..offset + size],
            expected[..],
            "{name} at {offset}"
        );
        for (i, (a, b)) in bytes.iter().zip(&base_bytes).enumerate() {
            if !(offset..offset + size).contains(&i) {
                assert_eq!(a, b, "{name}: byte {i} outside its slot changed");
            }
        }
    }
}

#[test]
fn header_words_are_fixed() {
    let bytes = MultiplayerPosition::new("A", "B")
        .unwrap()
        .encode()
        .unwrap();
    assert_eq!(&bytes[0..4], b"FGFS");
    assert_eq!(bytes[4..16], hex("00010001 00000007 000000e8")[..]);
}

// ---------------------------------------------------------------- errors

fn good() -> Vec<u8> {
    golden_bytes()
}

fn with_word(mut b: Vec<u8>, at: usize, word: u32) -> Vec<u8> {
    b[at..at + 4].copy_from_slice(&word.to_be_bytes());
    b
}

#[test]
fn decode_errors_name_what_is_wrong() {
    use MpDecodeError::*;
    let d = MultiplayerPosition::decode;
    assert_eq!(d(&[]), Err(Truncated { len: 0, need: 32 }));
    assert_eq!(d(&good()[..31]), Err(Truncated { len: 31, need: 32 }));
    assert_eq!(
        d(&with_word(good(), 0, 0x5346_4746)),
        Err(WrongMagic { found: 0x5346_4746 })
    );
    assert_eq!(
        d(&with_word(good(), 4, 0x0001_0000)),
        Err(WrongVersion { found: 0x0001_0000 })
    );
    // Little-endian version 1.1 happens to be 0x01000100.
    assert_eq!(
        d(&with_word(good(), 4, 0x0100_0100)),
        Err(WrongVersion { found: 0x0100_0100 })
    );
    assert_eq!(
        d(&with_word(good(), 8, 1)),
        Err(WrongMessageId { found: 1 })
    );
    assert_eq!(
        d(&good()[..200]),
        Err(LengthMismatch {
            header_len: 232,
            datagram_len: 200
        })
    );
    // A header-consistent datagram that stops inside the body.
    let short = with_word(good()[..100].to_vec(), 12, 100);
    assert_eq!(
        d(&short),
        Err(Truncated {
            len: 100,
            need: 232
        })
    );
    let mut long = good();
    long.extend([0, 0]);
    assert_eq!(
        d(&long),
        Err(LengthMismatch {
            header_len: 232,
            datagram_len: 234
        })
    );
    let long = with_word(long, 12, 234);
    assert_eq!(d(&long), Err(UnalignedProperties { trailing: 2 }));
    let huge = with_word(vec![0u8; MP_MAX_DATAGRAM_LEN + 1], 12, 0);
    assert_eq!(
        d(&huge),
        Err(TooLong {
            len: 65_508,
            max: 65_507
        })
    );

    let name = |field, problem| Err(Name(NameError { field, problem }));
    let mut b = good();
    b[24..32].copy_from_slice(b"ABCDEFGH");
    assert_eq!(
        d(&b),
        name(NameField::Callsign, NameProblem::TooLong { len: 8, max: 7 })
    );
    b[24..32].copy_from_slice(b"AB\0\0X\0\0\0");
    assert_eq!(
        d(&b),
        name(
            NameField::Callsign,
            NameProblem::NotNulPadded {
                index: 4,
                byte: b'X'
            }
        )
    );
    b[24..32].copy_from_slice(&[0; 8]);
    assert_eq!(d(&b), name(NameField::Callsign, NameProblem::Empty));
    b[24..32].copy_from_slice(b"A\xc3\xa9\0\0\0\0\0");
    assert_eq!(
        d(&b),
        name(
            NameField::Callsign,
            NameProblem::NotPrintableAscii {
                index: 1,
                byte: 0xc3
            }
        )
    );
    let mut b = good();
    b[32..128].fill(b'x');
    let e = d(&b).unwrap_err();
    assert_eq!(
        e,
        Name(NameError {
            field: NameField::ModelPath,
            problem: NameProblem::TooLong { len: 96, max: 95 }
        })
    );
    assert_eq!(
        e.to_string(),
        "invalid model path: 96 characters, at most 95 fit"
    );
    b[32..128].fill(0);
    b[32] = b'\n';
    assert_eq!(
        d(&b),
        name(
            NameField::ModelPath,
            NameProblem::NotPrintableAscii {
                index: 0,
                byte: b'\n'
            }
        )
    );
}

#[test]
fn encode_rejects_bad_names_small_buffers_and_oversized_datagrams() {
    let mut m = golden_message();
    m.callsign = "TOOLONG8".into();
    let expected = MpEncodeError::Name(NameError {
        field: NameField::Callsign,
        problem: NameProblem::TooLong { len: 8, max: 7 },
    });
    assert_eq!(m.encode(), Err(expected));
    let mut buf = [0x55u8; 300];
    assert_eq!(m.encode_into(&mut buf), Err(expected));
    assert!(buf.iter().all(|&b| b == 0x55), "nothing written on error");

    m.callsign = "CAF\u{c9}".into();
    assert!(matches!(
        m.encode(),
        Err(MpEncodeError::Name(NameError {
            field: NameField::Callsign,
            problem: NameProblem::NotPrintableAscii {
                index: 3,
                byte: 0xc3
            }
        }))
    ));
    m.callsign = "OK".into();
    m.model_path = String::new();
    assert!(matches!(
        m.encode(),
        Err(MpEncodeError::Name(NameError {
            field: NameField::ModelPath,
            problem: NameProblem::Empty
        }))
    ));
    assert!(MultiplayerPosition::new("OK", "").is_err());
    assert!(MultiplayerPosition::new("", "B").is_err());

    let m = golden_message();
    let mut small = [0x55u8; 231];
    assert_eq!(
        m.encode_into(&mut small),
        Err(MpEncodeError::BufferTooSmall {
            need: 232,
            got: 231
        })
    );
    assert!(small.iter().all(|&b| b == 0x55));

    let mut m = golden_message();
    m.property_words = vec![0; (MP_MAX_DATAGRAM_LEN - MP_POSITION_LEN) / 4];
    assert_eq!(m.encoded_len(), 65_504);
    let bytes = m.encode().unwrap();
    assert_eq!(
        bits(&MultiplayerPosition::decode(&bytes).unwrap()),
        bits(&m)
    );
    m.property_words.push(0);
    assert_eq!(
        m.encode(),
        Err(MpEncodeError::TooLong {
            len: 65_508,
            max: 65_507
        })
    );
}

// ------------------------------------------------------------ properties

/// f32 bit patterns biased towards NaNs with payloads, infinities, zeros
/// and subnormals.
fn f32_any() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => any::<u32>(),
        2 => (any::<bool>(), 1u32..(1 << 23))
            .prop_map(|(neg, payload)| (u32::from(neg) << 31) | 0x7f80_0000 | payload),
        1 => prop::sample::select(vec![0x7f80_0000u32, 0xff80_0000, 0, 0x8000_0000, 1, 0x807f_ffff]),
    ]
    .prop_map(f32::from_bits)
}

fn f64_any() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => any::<u64>(),
        2 => (any::<bool>(), 1u64..(1 << 52))
            .prop_map(|(neg, payload)| (u64::from(neg) << 63) | 0x7ff0_0000_0000_0000 | payload),
        1 => prop::sample::select(vec![0x7ff0_0000_0000_0000u64, 0x8000_0000_0000_0000, 0, 1]),
    ]
    .prop_map(f64::from_bits)
}

fn f32x3() -> impl Strategy<Value = [f32; 3]> {
    [f32_any(), f32_any(), f32_any()]
}

prop_compose! {
    fn any_message()(
        callsign in "[ -~]{1,7}",
        model_path in "[ -~]{1,95}",
        words in (any::<u32>(), any::<u32>()),
        time_s in f64_any(),
        lag_s in f64_any(),
        position_ecef_m in [f64_any(), f64_any(), f64_any()],
        o in f32x3(), v in f32x3(), w in f32x3(), a in f32x3(), aa in f32x3(),
        padding in any::<u32>(),
        property_words in prop::collection::vec(any::<u32>(), 0..40),
    ) -> MultiplayerPosition {
        MultiplayerPosition {
            requested_range_nm: words.0,
            reply_port: words.1,
            callsign,
            model_path,
            time_s,
            lag_s,
            position_ecef_m,
            orientation_angle_axis_rad: o,
            linear_velocity_body_mps: v,
            angular_velocity_body_radps: w,
            linear_acceleration_body_mps2: a,
            angular_acceleration_body_radps2: aa,
            padding,
            property_words,
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn round_trip_is_bit_exact(m in any_message()) {
        let bytes = m.encode().unwrap();
        prop_assert_eq!(bytes.len(), 232 + 4 * m.property_words.len());
        let back = MultiplayerPosition::decode(&bytes).unwrap();
        prop_assert_eq!(bits(&back), bits(&m));
        prop_assert_eq!(back.encode().unwrap(), bytes);
    }

    /// Any byte string: no panic, and whatever decodes re-encodes to the
    /// same bytes (the decoder accepts only canonical datagrams).
    #[test]
    fn decoding_arbitrary_bytes_never_panics(buf in prop::collection::vec(any::<u8>(), 0..1200)) {
        if let Ok(m) = MultiplayerPosition::decode(&buf) {
            prop_assert_eq!(m.encode().unwrap(), buf);
        }
    }

    /// Valid datagrams with random bytes overwritten (header included):
    /// exercises the checks past the magic. Same property as above.
    #[test]
    fn decoding_corrupted_datagrams_never_panics(
        m in any_message(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
    ) {
        let mut buf = m.encode().unwrap();
        for (at, byte) in edits {
            let i = at.index(buf.len());
            buf[i] = byte;
        }
        if let Ok(m) = MultiplayerPosition::decode(&buf) {
            prop_assert_eq!(m.encode().unwrap(), buf);
        }
    }

    /// Every proper prefix is rejected; so is anything appended, unless the
    /// length word is fixed up and the extra bytes are whole words, in which
    /// case they come back as property words.
    #[test]
    fn truncated_and_oversized_datagrams(
        m in any_message(),
        cut in any::<prop::sample::Index>(),
        extra in prop::collection::vec(any::<u8>(), 1..64),
    ) {
        let bytes = m.encode().unwrap();
        let n = cut.index(bytes.len());
        let err = MultiplayerPosition::decode(&bytes[..n]).unwrap_err();
        let is_length_error = matches!(
            err,
            MpDecodeError::Truncated { .. } | MpDecodeError::LengthMismatch { .. }
        );
        prop_assert!(is_length_error, "{err:?}");

        let mut long = bytes.clone();
        long.extend(&extra);
        prop_assert_eq!(
            MultiplayerPosition::decode(&long),
            Err(MpDecodeError::LengthMismatch { header_len: bytes.len() as u32, datagram_len: long.len() })
        );
        let len = long.len() as u32;
        long[12..16].copy_from_slice(&len.to_be_bytes());
        match MultiplayerPosition::decode(&long) {
            Ok(back) => {
                prop_assert_eq!(extra.len() % 4, 0);
                let added: Vec<u32> = extra
                    .chunks(4)
                    .map(|c| u32::from_be_bytes([c[0], c[1], c[2], c[3]]))
                    .collect();
                prop_assert_eq!(&back.property_words[m.property_words.len()..], &added[..]);
            }
            Err(e) => prop_assert_eq!(
                e,
                MpDecodeError::UnalignedProperties { trailing: long.len() - 232 }
            ),
        }
    }
}

// ------------------------------------------------------------------- UDP

#[test]
fn udp_loopback_send_and_receive() {
    let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
    rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
    tx.connect(rx.local_addr().unwrap()).unwrap();

    let mut sent = Vec::new();
    let mut out = [0u8; 512];
    for i in 0..20u32 {
        let mut m = golden_message();
        m.time_s = 100.0 + f64::from(i) * 0.1;
        m.position_ecef_m[2] += f64::from(i);
        m.property_words = (0..i % 3).collect();
        let n = m.encode_into(&mut out).unwrap();
        assert_eq!(tx.send(&out[..n]).unwrap(), n);
        sent.push(m);
    }
    let mut buf = [0u8; 2048];
    for m in &sent {
        let (n, from) = rx.recv_from(&mut buf).unwrap();
        assert_eq!(from, tx.local_addr().unwrap());
        let got = MultiplayerPosition::decode(&buf[..n]).unwrap();
        assert_eq!(bits(&got), bits(m));
    }
}
