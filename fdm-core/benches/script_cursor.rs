//! Script replay cost over a whole run: [`ScriptCursor`] (sweep) against the
//! per-frame scan of [`Script::actions_at`].
//!
//! Scripts are shaped like a long scripted flight: rules of 1 to 8 frames spread
//! uniformly over the run, four rules per frame on average (the one-hour
//! run: 108000 frames at 30 fps, 432k lines). Each iteration replays every frame
//! and counts the actions.
//!
//! * `script_cursor/<rules>x<frames>`: the sweep at 1/8, 1/4, 1/2 and the full
//!   size; time should grow in proportion to rules + frames.
//! * `script_scan/<rules>x<frames>`: the scan, at sizes small enough to finish;
//!   time grows with rules × frames (4× per doubling of both).
//!
//! `cargo bench -p fdm-core --bench script_cursor`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fdm_core::palmer::PalmerAction;
use fdm_core::script::{Rule, Script, ScriptAction, ScriptCursor};

/// `rules` rules of 1..=8 frames starting uniformly in 1..=frames (a fixed LCG, so
/// every run benches the same script).
fn script(rules: u64, frames: u64) -> Script<PalmerAction> {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        state >> 33
    };
    let all = PalmerAction::ALL;
    Script::from_rules(
        (0..rules)
            .map(|_| {
                let first = 1 + next() % frames;
                Rule {
                    first_frame: first,
                    last_frame: first + next() % 8,
                    action: all[(next() % all.len() as u64) as usize],
                }
            })
            .collect(),
    )
}

fn sweep(script: &Script<PalmerAction>, frames: u64) -> usize {
    let mut cursor = ScriptCursor::new();
    (1..=frames)
        .map(|frame| cursor.actions(script, frame).count())
        .sum()
}

fn scan(script: &Script<PalmerAction>, frames: u64) -> usize {
    (1..=frames)
        .map(|frame| script.actions_at(frame).count())
        .sum()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("script_cursor");
    group.sample_size(10);
    for frames in [13_500_u64, 27_000, 54_000, 108_000] {
        let rules = 4 * frames;
        let s = script(rules, frames);
        group.throughput(Throughput::Elements(rules + frames));
        group.bench_with_input(
            BenchmarkId::from_parameter(format!("{rules}x{frames}")),
            &frames,
            |b, &frames| b.iter(|| black_box(sweep(black_box(&s), frames))),
        );
    }
    group.finish();

    let mut group = c.benchmark_group("script_scan");
    group.sample_size(10);
    for frames in [500_u64, 1_000, 2_000] {
        let rules = 4 * frames;
        let s = script(rules, frames);
        // The two replays agree (the unit tests check it frame by frame).
        assert_eq!(sweep(&s, frames), scan(&s, frames));
        group.throughput(Throughput::Elements(rules + frames));
        group.bench_with_input(
            BenchmarkId::from_parameter(format!("{rules}x{frames}")),
            &frames,
            |b, &frames| b.iter(|| black_box(scan(black_box(&s), frames))),
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
