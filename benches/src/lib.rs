//! The workspace's criterion benchmarks (the files next to this crate's
//! manifest, see BENCHMARKS.md), the object-oriented fleet baseline
//! ([`oop`]) they compare the ECS with, and their shared timing loop.

use std::time::{Duration, Instant};

pub mod oop;

/// Frames between resets of a fleet to its initial states in
/// [`timed_frames`]: every variant flies the same 10 s of flight at 30 FPS,
/// whatever its iteration count.
pub const RESET_EVERY: u64 = 300;

/// Times `iters` frames of `frame`, calling `reset` (untimed) every
/// [`RESET_EVERY`] frames, starting with a reset; for criterion's
/// `iter_custom`.
pub fn timed_frames<T>(
    iters: u64,
    target: &mut T,
    mut frame: impl FnMut(&mut T),
    mut reset: impl FnMut(&mut T),
) -> Duration {
    let mut total = Duration::ZERO;
    for i in 0..iters {
        if i % RESET_EVERY == 0 {
            reset(target);
        }
        let start = Instant::now();
        frame(target);
        total += start.elapsed();
    }
    total
}
