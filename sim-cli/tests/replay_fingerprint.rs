//! The flight's fingerprint (docs/recording.md, "The fingerprint"): a
//! recording of format version 3 carries, in its end marker, the hash of the
//! final state and of the maths that flew it, and `sim-cli replay` compares
//! its own end with them. Each test alters only the fingerprint (and then
//! recomputes the end block's checksum, so that the file is otherwise intact)
//! and checks what the replay says and its exit status (docs/cli.md, "Exit
//! status"). Tolerance 0: fingerprints are compared as 64-bit values, the
//! JSON reports as bytes.

mod support;

use support::{scratch, sim, text};

/// FNV-1a 64, the block checksum of docs/recording.md.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Where the end block's two fingerprints are. The file ends with the end
/// block `len (u32) | Sealed { frames, checksum, state, maths } | checksum
/// (u64)`; bincode stores a `u64` of 2^32 or more as the byte 253 and eight
/// little-endian bytes, so `maths` is the 9 bytes before the checksum and
/// `state` the 9 before those (a fingerprint below 2^32, a 1 in 4e9 chance,
/// would be shorter: the test then says so rather than guess).
struct Tail {
    state_at: usize,
    maths_at: usize,
    checksum_at: usize,
}

fn tail(bytes: &[u8]) -> Tail {
    let checksum_at = bytes.len() - 8;
    let maths_at = checksum_at - 8;
    let state_at = maths_at - 9;
    assert_eq!(
        bytes[maths_at - 1],
        253,
        "the maths fingerprint's varint marker"
    );
    assert_eq!(
        bytes[state_at - 1],
        253,
        "the state fingerprint's varint marker"
    );
    Tail {
        state_at,
        maths_at,
        checksum_at,
    }
}

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
}

/// `good` with the u64 at `at` XORed with `flip` and the end block's
/// checksum recomputed: only the fingerprint is wrong.
fn altered(good: &[u8], at: usize, flip: u64) -> Vec<u8> {
    let mut bytes = good.to_vec();
    let value = u64_at(&bytes, at) ^ flip;
    bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
    let t = tail(&bytes);
    let checksum = fnv1a(&bytes[..t.checksum_at]);
    bytes[t.checksum_at..].copy_from_slice(&checksum.to_le_bytes());
    bytes
}

/// Records a flight; returns its JSON report and recording.
fn record(dir: &std::path::Path, model: &str) -> (String, Vec<u8>) {
    let rec = dir.join(format!("{model}.rec"));
    let out = sim(&[
        model,
        "--headless",
        "--json",
        "--frames",
        "100",
        "--record",
        rec.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    (text(&out.stdout), std::fs::read(rec).unwrap())
}

fn replay(dir: &std::path::Path, name: &str, bytes: &[u8]) -> std::process::Output {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    sim(&["replay", path.to_str().unwrap(), "--json"])
}

#[test]
fn a_faithful_replay_is_silent_and_the_fingerprint_is_this_builds() {
    let dir = scratch("fingerprint-same");
    for model in ["palmer", "bourg"] {
        let (json, good) = record(&dir, model);
        assert_eq!(good[8..10], 3_u16.to_le_bytes(), "format version 3");
        let t = tail(&good);
        assert_eq!(
            u64_at(&good, t.maths_at),
            fdm_core::fingerprint::maths(),
            "{model}: the recorded maths fingerprint is this build's"
        );
        let out = replay(&dir, &format!("{model}-same.rec"), &good);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        assert!(out.stderr.is_empty(), "{model}: {}", text(&out.stderr));
        assert_eq!(text(&out.stdout), json, "{model}");
    }
}

#[test]
fn another_final_state_is_reported_as_a_different_flight_with_status_4() {
    let dir = scratch("fingerprint-state");
    for model in ["palmer", "bourg"] {
        let (json, good) = record(&dir, model);
        let t = tail(&good);
        let recorded = u64_at(&good, t.state_at);
        let bad = altered(&good, t.state_at, 1);
        let out = replay(&dir, &format!("{model}-state.rec"), &bad);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(4), "{model}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("sim-cli: error: ")
                && stderr.contains("the replay flew a different flight")
                && stderr.contains(&format!("the recording's {:#018x}", recorded ^ 1))
                && stderr.contains(&format!(
                    "its final state's fingerprint is {recorded:#018x}"
                ))
                && stderr.contains("the maths are the same"),
            "{model}: {stderr}"
        );
        // Every output is still complete: the report is the flight's.
        assert_eq!(text(&out.stdout), json, "{model}");

        // Without the recomputed checksum the end block does not check: the
        // reader takes it for a last block torn by a cut (status 3), and the
        // altered fingerprint is not trusted.
        let mut damaged = good.clone();
        damaged[t.state_at] ^= 1;
        let out = replay(&dir, &format!("{model}-damaged.rec"), &damaged);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{stderr}");
        assert!(stderr.contains("before its end marker"), "{stderr}");
    }
}

#[test]
fn other_maths_are_said_plainly() {
    let dir = scratch("fingerprint-maths");
    let (json, good) = record(&dir, "palmer");
    let t = tail(&good);
    let ours = fdm_core::fingerprint::maths();

    // Other maths, the same final state: a warning, status 0.
    let out = replay(&dir, "maths.rec", &altered(&good, t.maths_at, 1 << 63));
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("sim-cli: warning: ")
            && stderr.contains("the recording was made with different maths")
            && stderr.contains(&format!("maths fingerprint {:#018x}", ours ^ (1 << 63)))
            && stderr.contains(&format!("this sim-cli's {ours:#018x}")),
        "{stderr}"
    );
    assert_eq!(text(&out.stdout), json);

    // Other maths and another final state: a different flight, and why.
    let both = altered(&altered(&good, t.maths_at, 1 << 63), t.state_at, 1);
    let out = replay(&dir, "both.rec", &both);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("the replay flew a different flight")
            && stderr.contains("the recording was made with different maths"),
        "{stderr}"
    );
}

#[test]
fn recordings_without_a_fingerprint_replay_with_a_note() {
    let dir = scratch("fingerprint-none");
    for version in [1, 2] {
        let rec = format!(
            "{}/tests/golden/palmer_v{version}.rec",
            env!("CARGO_MANIFEST_DIR")
        );
        let out = sim(&["replay", &rec, "--json"]);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "v{version}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("sim-cli: note: ")
                && stderr.contains("has no fingerprint; the replay was not checked"),
            "v{version}: {stderr}"
        );
    }
    // A cut recording: its one error line says it could not be checked.
    let (_, good) = record(&dir, "palmer");
    let out = replay(&dir, "cut.rec", &good[..good.len() - 3]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("has no fingerprint to check them against"),
        "{stderr}"
    );
}
