//! Arbitrary datagrams into the DIS listener, with the listener's own guard
//! in place: a panic inside dis-rs that the listener catches (and counts as
//! `decoder_panics`) is allowed, as in a normal build; a panic escaping
//! `Listener::ingest`, or counts that do not add up, is a crash. (The
//! `dis_listener_strict` target instead treats every panic, even a caught one, as a
//! crash, to find dis-rs bugs.)
#![no_main]

use std::sync::Once;

use libfuzzer_sys::fuzz_target;

static QUIET: Once = Once::new();

fuzz_target!(|data: &[u8]| {
    // libFuzzer's hook aborts on any panic, caught or not; put back a silent
    // one so that only panics escaping the listener (which libfuzzer-sys
    // still turns into an abort) count.
    QUIET.call_once(|| std::panic::set_hook(Box::new(|_| {})));
    let mut listener = fdm_dis::Listener::new();
    let outcome = listener.ingest(data);
    let stats = listener.stats();
    assert_eq!(stats.datagrams, 1);
    assert_eq!(stats.bytes, data.len() as u64);
    assert_eq!(stats.malformed_datagrams, u64::from(outcome.is_err()));
    assert!(stats.decoder_panics <= stats.malformed_datagrams);
    if let Ok(n) = outcome {
        assert_eq!(stats.pdus, n as u64);
        assert!(listener.entity_count() as u64 <= stats.entity_state_pdus);
    }
});
