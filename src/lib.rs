//! Workspace-level home of the integration tests (`tests/`) and criterion
//! benchmarks (`benches/`) that exercise `fdm-core`, `fdm-ecs`, `fgnet` and
//! `sim-cli` together.
//!
//! It re-exports the member crates so tests and benches have one import root,
//! gives them the path of the committed reference data, and holds the
//! object-oriented fleet baseline ([`oop`]) the benchmarks compare the ECS with.

pub use fdm_core;
pub use fdm_ecs;
pub use fgnet;

pub mod oop;

/// Directory holding the original programs' reference outputs
/// (`palmer.json`, `bourg.json`, `bourg_math.md`, `fgnetfdm_golden.json`),
/// copied verbatim from the project's shared reference set.
pub const REFERENCE_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/reference");

/// Reads a file from [`REFERENCE_DIR`].
///
/// # Errors
/// Returns the I/O error if the file is missing or unreadable.
pub fn read_reference(name: &str) -> std::io::Result<String> {
    std::fs::read_to_string(std::path::Path::new(REFERENCE_DIR).join(name))
}
