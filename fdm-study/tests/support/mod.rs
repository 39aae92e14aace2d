//! Helpers shared by fdm-study's integration tests.

use fdm_study::{FlyOptions, RunTable};

/// One row as bits: run, status code, frames, every measure, every drawn
/// input, the fingerprint.
pub type RowBits = (
    u64,
    &'static str,
    u64,
    Vec<Option<u64>>,
    Vec<u64>,
    Option<u64>,
);

/// The table's values as bits (run, status code, frames, every measure,
/// every drawn input, the fingerprint), to compare two tables exactly.
pub fn bits(table: &RunTable) -> Vec<RowBits> {
    (0..table.len())
        .map(|row| {
            (
                table.run[row],
                table.status[row].code(),
                table.frames[row],
                table
                    .measures
                    .iter()
                    .map(|(_, c)| c[row].map(f64::to_bits))
                    .collect(),
                table.inputs.iter().map(|(_, c)| c[row].to_bits()).collect(),
                table.fingerprint[row],
            )
        })
        .collect()
}

/// The default fly options on `threads` threads.
pub fn options(threads: usize) -> FlyOptions {
    FlyOptions {
        threads,
        ..FlyOptions::default()
    }
}
