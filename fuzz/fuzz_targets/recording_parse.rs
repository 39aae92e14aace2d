//! Recordings (`fdm_run::recording`, read by `sim-cli replay`): [`parse_recording`] must never panic on any bytes
//! (docs/recording.md); its error messages are one line without control
//! characters (whatever names the file stores); and an accepted recording
//! parses the same again.

#![no_main]

use libfuzzer_sys::fuzz_target;
use fdm_run::recording::parse_recording;

fuzz_target!(|data: &[u8]| {
    match parse_recording(data) {
        Ok(info) => {
            assert_eq!(parse_recording(data), Ok(info.clone()));
            assert!((1..=10_000).contains(&info.fps), "{info:?}");
            assert!(info.events >= info.resets, "{info:?}");
        }
        Err(e) => {
            let message = e.to_string();
            assert!(!message.chars().any(char::is_control), "{message:?}");
        }
    }
});
