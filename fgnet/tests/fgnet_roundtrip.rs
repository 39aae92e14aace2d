//! Property tests: bit-exact round trips (NaN payloads included), count
//! clamping, and decoding arbitrary, truncated and oversized buffers without
//! panicking.

use fdm_tests::fgnet_fields::{assert_bitwise_eq, element_bits, element_count, fields, Kind};
use fgnet::{CountField, DecodeError, FgNetFdm, DATAGRAM_LEN};
use proptest::prelude::*;

/// f32 bit patterns biased towards the awkward ones: NaNs with arbitrary
/// payload and sign (quiet and signalling), infinities, zeros, subnormals.
fn f32_bits() -> BoxedStrategy<u64> {
    prop_oneof![
        4 => any::<u32>(),
        3 => (any::<bool>(), 1u32..(1 << 23))
            .prop_map(|(neg, payload)| (u32::from(neg) << 31) | 0x7f80_0000 | payload),
        1 => prop::sample::select(vec![
            0x7f80_0000u32, 0xff80_0000, 0, 0x8000_0000, 1, 0x807f_ffff, 0x7f7f_ffff
        ]),
    ]
    .prop_map(u64::from)
    .boxed()
}

fn f64_bits() -> BoxedStrategy<u64> {
    prop_oneof![
        4 => any::<u64>(),
        3 => (any::<bool>(), 1u64..(1 << 52))
            .prop_map(|(neg, payload)| (u64::from(neg) << 63) | 0x7ff0_0000_0000_0000 | payload),
        1 => prop::sample::select(vec![
            0x7ff0_0000_0000_0000u64, 0xfff0_0000_0000_0000, 0, 0x8000_0000_0000_0000, 1,
        ]),
    ]
    .boxed()
}

/// One strategy per field element, in wire order. `counts_any` lets the
/// counts take any `u32` (to exercise clamping); otherwise they stay valid.
fn element_strategies(counts_any: bool) -> Vec<BoxedStrategy<u64>> {
    let mut v = Vec::new();
    for f in fields() {
        for _ in 0..f.len {
            let s = match (f.name, f.count_max(), f.kind) {
                ("version", _, _) => Just(24u64).boxed(),
                (_, Some(max), _) if !counts_any => (0..=max).boxed(),
                (_, _, Kind::U32 | Kind::I32) => any::<u32>().prop_map(u64::from).boxed(),
                (_, _, Kind::F32) => f32_bits(),
                (_, _, Kind::F64) => f64_bits(),
            };
            v.push(s);
        }
    }
    assert_eq!(v.len(), element_count());
    v
}

fn any_fdm(counts_any: bool) -> impl Strategy<Value = FgNetFdm> {
    element_strategies(counts_any)
        .prop_map(|bits| fdm_tests::fgnet_fields::from_element_bits(&bits))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn round_trip_is_bit_exact(fdm in any_fdm(false)) {
        let bytes = fdm.encode();
        prop_assert_eq!(bytes, fdm.encode_bincode());
        let back = FgNetFdm::decode(&bytes).expect("valid datagram decodes");
        assert_bitwise_eq(&back, &fdm, "decode(encode(x))");
        let back_b = FgNetFdm::decode_bincode(&bytes).expect("valid datagram decodes (bincode)");
        assert_bitwise_eq(&back_b, &fdm, "decode_bincode(encode(x))");
        prop_assert_eq!(back.encode(), bytes);
    }

    #[test]
    fn encoders_clamp_counts_and_keep_everything_else(fdm in any_fdm(true)) {
        let bytes = fdm.encode();
        prop_assert_eq!(bytes, fdm.encode_bincode());
        let back = FgNetFdm::decode(&bytes).expect("clamped datagram decodes");
        prop_assert_eq!(back.num_engines, fdm.num_engines.min(4));
        prop_assert_eq!(back.num_tanks, fdm.num_tanks.min(4));
        prop_assert_eq!(back.num_wheels, fdm.num_wheels.min(3));
        assert_bitwise_eq(&back, &fdm.clamped(), "decode(encode(x)) == x.clamped()");
    }

    #[test]
    fn decoding_arbitrary_bytes_never_panics(buf in prop::collection::vec(any::<u8>(), 0..1200)) {
        let a = FgNetFdm::decode(&buf);
        let b = FgNetFdm::decode_bincode(&buf);
        match (&a, &b) {
            (Ok(x), Ok(y)) => prop_assert_eq!(x.encode(), y.encode()),
            _ => prop_assert_eq!(a.err(), b.err()),
        }
        if buf.len() != DATAGRAM_LEN {
            prop_assert_eq!(FgNetFdm::decode(&buf).err(), Some(DecodeError::WrongLength { len: buf.len() }));
        }
    }

    #[test]
    fn decoding_408_random_bytes_checks_version_then_counts(
        mut buf in prop::collection::vec(any::<u8>(), DATAGRAM_LEN),
        version_is_24 in any::<bool>(),
        counts in (0u32..8, 0u32..8, 0u32..6),
    ) {
        if version_is_24 {
            buf[..4].copy_from_slice(&24u32.to_be_bytes());
        }
        buf[120..124].copy_from_slice(&counts.0.to_be_bytes());
        buf[284..288].copy_from_slice(&counts.1.to_be_bytes());
        buf[304..308].copy_from_slice(&counts.2.to_be_bytes());
        let version = u32::from_be_bytes([buf[0], buf[1], buf[2], buf[3]]);
        let expected_err = if version != 24 {
            Some(DecodeError::WrongVersion { found: version })
        } else if counts.0 > 4 {
            Some(DecodeError::CountTooLarge { field: CountField::NumEngines, value: counts.0 })
        } else if counts.1 > 4 {
            Some(DecodeError::CountTooLarge { field: CountField::NumTanks, value: counts.1 })
        } else if counts.2 > 3 {
            Some(DecodeError::CountTooLarge { field: CountField::NumWheels, value: counts.2 })
        } else {
            None
        };
        match FgNetFdm::decode(&buf) {
            Ok(fdm) => {
                prop_assert_eq!(expected_err, None);
                // Any valid 408-byte buffer re-encodes to itself, bit for bit.
                prop_assert_eq!(&fdm.encode()[..], &buf[..]);
            }
            Err(e) => prop_assert_eq!(Some(e), expected_err),
        }
    }

    #[test]
    fn truncated_and_oversized_datagrams_are_rejected_with_their_length(
        fdm in any_fdm(false),
        cut in 0usize..DATAGRAM_LEN,
        extra in prop::collection::vec(any::<u8>(), 1..600),
    ) {
        let bytes = fdm.encode();
        prop_assert_eq!(
            FgNetFdm::decode(&bytes[..cut]),
            Err(DecodeError::WrongLength { len: cut })
        );
        let mut long = bytes.to_vec();
        long.extend_from_slice(&extra);
        prop_assert_eq!(
            FgNetFdm::decode(&long),
            Err(DecodeError::WrongLength { len: DATAGRAM_LEN + extra.len() })
        );
        prop_assert_eq!(
            FgNetFdm::decode_bincode(&long),
            Err(DecodeError::WrongLength { len: DATAGRAM_LEN + extra.len() })
        );
    }
}

#[test]
fn nan_payloads_survive_a_round_trip() {
    let mut fdm = FgNetFdm::new();
    fdm.latitude = f64::from_bits(0x7ff0_0000_0000_0001); // signalling
    fdm.longitude = f64::from_bits(0xfff8_dead_beef_0001); // quiet, negative
    fdm.phi = f32::from_bits(0x7f80_0001); // signalling
    fdm.rpm[3] = f32::from_bits(0xffc0_1234); // quiet, negative
    let back = FgNetFdm::decode(&fdm.encode()).unwrap();
    let bits = element_bits(&back);
    let get = |n: &str| bits.iter().find(|(name, _)| name == n).unwrap().1;
    assert_eq!(get("latitude"), 0x7ff0_0000_0000_0001);
    assert_eq!(get("longitude"), 0xfff8_dead_beef_0001);
    assert_eq!(get("phi"), 0x7f80_0001);
    assert_eq!(get("rpm[3]"), 0xffc0_1234);
}

#[test]
fn wrong_endian_count_is_clamped_not_sent() {
    // 4 engines written little-endian reads as 67108864 in FlightGear and
    // would overrun its arrays; our encoder never puts more than 4 on the wire.
    let mut fdm = FgNetFdm::new();
    fdm.num_engines = 67_108_864;
    fdm.num_tanks = 5;
    fdm.num_wheels = u32::MAX;
    let b = fdm.encode();
    assert_eq!(b[120..124], [0, 0, 0, 4]);
    assert_eq!(b[284..288], [0, 0, 0, 4]);
    assert_eq!(b[304..308], [0, 0, 0, 3]);
}
