//! FGNetFDM v24 layout: the golden datagram byte for byte, and the offset of
//! every field against that table (`docs/fgnetfdm.md` §3).

use fdm_tests::fgnet_fields::{assert_bitwise_eq, fields, Kind};
use fgnet::{FgNetFdm, DATAGRAM_LEN};

fn golden() -> (FgNetFdm, Vec<u8>) {
    let text = fdm_tests::read_reference("fgnetfdm_golden.json").expect("golden file");
    let json: serde_json::Value = serde_json::from_str(&text).expect("golden JSON");
    let fdm: FgNetFdm =
        serde_json::from_value(json["fields"].clone()).expect("golden fields deserialize");
    let hex = json["bytes_hex"].as_str().expect("bytes_hex");
    let bytes: Vec<u8> = (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).expect("hex"))
        .collect();
    assert_eq!(json["size"], 408);
    assert_eq!(bytes.len(), 408);
    (fdm, bytes)
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn golden_datagram_byte_for_byte() {
    let (fdm, bytes) = golden();
    for (name, encoded) in [
        ("encode", fdm.encode()),
        ("encode_bincode", fdm.encode_bincode()),
    ] {
        if let Some(at) = encoded.iter().zip(&bytes).position(|(a, b)| a != b) {
            panic!(
                "{name} differs from the golden datagram at byte {at}:\n ours   {}\n golden {}",
                hex(&encoded[at..(at + 16).min(408)]),
                hex(&bytes[at..(at + 16).min(408)])
            );
        }
    }
    let mut into = [0xAAu8; DATAGRAM_LEN];
    fdm.encode_into(&mut into);
    assert_eq!(into[..], bytes[..], "encode_into overwrites every byte");

    // The spot checks of docs/fgnetfdm.md §8 step 2.
    assert_eq!(hex(&bytes[0..8]), "0000001800000000");
    assert_eq!(hex(&bytes[8..16]), "c0011636c7b07bd0");
    assert_eq!(hex(&bytes[16..24]), "3fe503860cdb22dc");
    assert_eq!(hex(&bytes[24..32]), "4059000000000000");
    assert_eq!(hex(&bytes[356..360]), "499602d2");
    assert_eq!(hex(&bytes[360..364]), "fffff1f0");

    // And back.
    let decoded = FgNetFdm::decode(&bytes).expect("golden decodes");
    assert_bitwise_eq(&decoded, &fdm, "decode(golden)");
    let decoded = FgNetFdm::decode_bincode(&bytes).expect("golden decodes (bincode)");
    assert_bitwise_eq(&decoded, &fdm, "decode_bincode(golden)");
    assert_eq!(decoded.latitude, 37.625f64.to_radians());
    assert_eq!(decoded.longitude, (-122.375f64).to_radians());
    assert_eq!(decoded.a_z_pilot, -32.0);
}

#[test]
fn spec_table_tiles_408_bytes() {
    let mut next = 0;
    for f in fields() {
        assert_eq!(
            f.offset, next,
            "{} does not follow the previous field",
            f.name
        );
        assert_eq!(f.offset % f.kind.size(), 0, "{} misaligned", f.name);
        next += f.len * f.kind.size();
    }
    assert_eq!(next, DATAGRAM_LEN);
}

/// A value whose big-endian bytes are distinct and (except for the small
/// counts) all non-zero, so the changed bytes show exactly where it went.
fn distinctive(kind: Kind, count_max: Option<u64>) -> u64 {
    match (kind, count_max) {
        (_, Some(max)) => max, // the largest count that is not clamped
        (Kind::F64, _) => 0x4142_4344_4546_4748,
        (_, _) => 0x5152_5354,
    }
}

#[test]
fn every_field_lands_at_its_spec_offset() {
    // Set one element at a time on a neutral struct: the element's bytes must
    // equal the value's big-endian bytes at the documented offset, and no byte
    // outside that range may change.
    let baseline = FgNetFdm::new();
    let base = baseline.encode();
    let mut checked = 0;
    for f in fields() {
        for i in 0..f.len {
            let value = distinctive(f.kind, f.count_max());
            let mut fdm = baseline;
            (f.set)(&mut fdm, i, value);
            let bytes = fdm.encode();
            let at = f.offset + i * f.kind.size();
            let size = f.kind.size();
            let expected = &value.to_be_bytes()[8 - size..];
            assert_eq!(
                &bytes[at..at + size],
                expected,
                "{} should be at offset {at}",
                f.element_name(i)
            );
            for (pos, (a, b)) in bytes.iter().zip(&base).enumerate() {
                if a != b {
                    assert!(
                        (at..at + size).contains(&pos),
                        "setting {} changed byte {pos}, outside {at}..{}",
                        f.element_name(i),
                        at + size
                    );
                }
            }
            assert_eq!(
                fdm.encode_bincode(),
                bytes,
                "bincode, {}",
                f.element_name(i)
            );
            if f.name == "version" {
                let err = FgNetFdm::decode(&bytes).expect_err("version 0x51525354 is rejected");
                assert_eq!(
                    err.to_string(),
                    "FGNetFDM version 1364349780 (0x51525354), need 24"
                );
            } else {
                let back = FgNetFdm::decode(&bytes).expect("decodes");
                assert_eq!((f.get)(&back, i), value, "decode of {}", f.element_name(i));
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 99, "every field element checked");
}

#[test]
fn neutral_datagram_header_and_counts() {
    let b = FgNetFdm::new().encode();
    assert_eq!(b[..8], [0, 0, 0, 24, 0, 0, 0, 0]);
    assert_eq!(b[32..36], (-9999.0f32).to_be_bytes(), "agl = -9999");
    assert_eq!(b[120..124], [0; 4], "num_engines = 0");
    assert_eq!(b[284..288], [0; 4], "num_tanks = 0");
    assert_eq!(b[304..308], [0; 4], "num_wheels = 0");
}
