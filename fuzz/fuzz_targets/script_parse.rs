//! `--script` files: [`Script::parse`] must never panic on any text, for either
//! model; an accepted script printed back (`Display`) must parse to an equal
//! script; error messages must contain no control characters; and the
//! [`ScriptCursor`] sweep must give the per-frame scan's actions on every frame.

#![no_main]

use fdm_core::bourg::BourgAction;
use fdm_core::palmer::PalmerAction;
use fdm_core::script::{Script, ScriptAction, ScriptCursor};
use libfuzzer_sys::fuzz_target;

/// Frames checked frame by frame against the scan (keeps each input fast).
const MAX_FRAMES_CHECKED: u64 = 512;

fn check<A: ScriptAction + PartialEq + core::fmt::Debug>(text: &str) {
    match Script::<A>::parse(text) {
        Ok(script) => {
            let printed = script.to_string();
            assert_eq!(
                Script::<A>::parse(&printed).as_ref(),
                Ok(&script),
                "{printed}"
            );
            let mut cursor = ScriptCursor::new();
            let last = script
                .last_frame()
                .saturating_add(1)
                .min(MAX_FRAMES_CHECKED);
            for frame in 0..=last {
                assert!(
                    cursor.actions(&script, frame).eq(script.actions_at(frame)),
                    "frame {frame}"
                );
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(!message.chars().any(char::is_control), "{message:?}");
        }
    }
}

fuzz_target!(|data: &[u8]| {
    // sim-cli hands the parser UTF-8 text only (it refuses other bytes itself).
    if let Ok(text) = core::str::from_utf8(data) {
        check::<PalmerAction>(text);
        check::<BourgAction>(text);
    }
});
