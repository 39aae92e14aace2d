//! FGNetFDM datagrams as they arrive from the network: [`FgNetFdm::decode`] must
//! never panic, must agree with the serde + bincode decoder, and every datagram it
//! accepts must re-encode to exactly the same 408 bytes (NaN payloads included).

#![no_main]

use fgnet::FgNetFdm;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let decoded = FgNetFdm::decode(data);
    let by_bincode = FgNetFdm::decode_bincode(data);
    match (&decoded, &by_bincode) {
        (Ok(a), Ok(b)) => assert_eq!(a.encode(), b.encode(), "the two decoders differ"),
        (Err(a), Err(b)) => assert_eq!(a, b, "the two decoders refuse differently"),
        _ => panic!("one decoder accepts what the other refuses: {decoded:?} / {by_bincode:?}"),
    }
    if let Ok(fdm) = decoded {
        assert_eq!(
            &fdm.encode()[..],
            data,
            "accepted datagram does not re-encode identically"
        );
        let mut again = [0_u8; fgnet::DATAGRAM_LEN];
        fdm.encode_into(&mut again);
        assert_eq!(&again[..], data, "encode_into differs from the input");
        assert_eq!(fdm.encode_bincode(), again, "bincode encoder differs");
    }
});
