//! Run by hand, not in CI: it finds panics inside dis-rs 0.14 itself (Signal and
//! Transmitter PDUs, see docs/dis.md), which the listener catches.
//! Arbitrary datagrams into the DIS listener: it must never panic (libFuzzer
//! aborts on any panic, also one inside dis-rs that the listener's
//! `catch_unwind` would otherwise turn into a counted error).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut listener = fdm_dis::Listener::new();
    let outcome = listener.ingest(data);
    let stats = listener.stats();
    assert_eq!(stats.datagrams, 1);
    assert_eq!(stats.malformed_datagrams, u64::from(outcome.is_err()));
    assert_eq!(stats.decoder_panics, 0);
});
