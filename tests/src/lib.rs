//! Test support shared by every crate's tests (the workspace's `tests/`
//! package): where the reference data is, how to read it, bitwise views of
//! model states, direct `fdm-core` runs of the reference scenarios, and the
//! FGNetFDM field table. Each crate's own tests live with that crate and
//! dev-depend on this one; it is never published.
//!
//! It re-exports the member crates so support code has one import root.

pub use fdm_core;
pub use fdm_ecs;
pub use fgnet;

pub mod ecs;
pub mod fgnet_fields;
pub mod python;

/// Directory holding the original programs' reference outputs
/// (`palmer.json`, `bourg.json`, `bourg_math.md`, `fgnetfdm_golden.json`);
/// `docs/reference-provenance.md` says where each came from.
pub const REFERENCE_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../reference");

/// Reads a file from [`REFERENCE_DIR`].
///
/// # Errors
/// Returns the I/O error if the file is missing or unreadable.
pub fn read_reference(name: &str) -> std::io::Result<String> {
    std::fs::read_to_string(std::path::Path::new(REFERENCE_DIR).join(name))
}
