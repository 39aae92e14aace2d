//! `Study::fly_runs_until` (docs/studies.md, "Stopping a study"): a stop gives
//! the rows of runs `first..first + K` without a gap, each the same bits as the
//! unstopped flight's; flying the rest later and appending gives the whole
//! table; a stop asked once is kept; a stop from another thread ends a long
//! flight within a fraction of a second. Every comparison of rows is exact
//! (f64 bits).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use fdm_study::{summarize, RunTable, Study, BLOCK_RUNS};

mod support;
use support::{bits, options};

/// 2,100 runs (three blocks, the last of 52) of 1 s; a dispersed mass, so
/// every run flies in a fleet of its own (the stop is asked inside each).
const DISPERSED: &str = r#"
model = "palmer"
runs = 2100
seed = 11
duration_s = 1.0
measures = ["max_height_m", "final_x_m"]
[controls]
throttle = 1.0
alpha_deg = 4.0
[[dispersion]]
key = "aircraft.mass_kg"
distribution = "uniform"
low = 1000.0
high = 1114.0
"#;

/// The same without the aircraft dispersion: one fleet per block.
const SHARED_FLEET: &str = r#"
model = "palmer"
runs = 2100
seed = 11
duration_s = 1.0
measures = ["max_height_m", "final_x_m"]
[controls]
throttle = 1.0
alpha_deg = 4.0
[[dispersion]]
key = "initial.speed_kt"
distribution = "normal"
mean = 70.0
sd = 2.0
"#;

/// Stops after the closure has been asked `calls` times; checks the prefix
/// property and the bits; returns K.
fn stopped_after(study: &Study, whole: &RunTable, threads: usize, calls: u64) -> usize {
    let asked = AtomicU64::new(0);
    let table = study
        .fly_runs_until(0..study.runs(), &options(threads), || {
            asked.fetch_add(1, Ordering::Relaxed) >= calls
        })
        .unwrap();
    let k = table.len();
    let expected: Vec<u64> = (0..k as u64).collect();
    assert_eq!(table.run, expected, "runs 0..K in order, no gap");
    assert!(
        k == whole.len() || (k as u64).is_multiple_of(BLOCK_RUNS),
        "{k}: only whole blocks are kept"
    );
    assert_eq!(
        bits(&table),
        bits(whole)[..k].to_vec(),
        "{threads} threads, stop after {calls} calls"
    );
    k
}

#[test]
fn a_stop_keeps_the_completed_runs_without_a_gap_and_with_the_same_bits() {
    for text in [DISPERSED, SHARED_FLEET] {
        let study = Study::from_toml_str(text).unwrap();
        let whole = study.fly_runs(0..study.runs(), &options(2)).unwrap();
        assert_eq!(whole.len(), 2100);
        // Asked to stop before anything flies: nothing.
        assert_eq!(stopped_after(&study, &whole, 1, 0), 0);
        // Never stopped: everything, as fly_runs.
        assert_eq!(stopped_after(&study, &whole, 2, u64::MAX), 2100);
        // On one thread the blocks fly in order, so a stop after the first
        // block's questions keeps that block and drops the rest. A 1 s run is
        // 30 frames: the closure is asked at frames 0 and 16 of every fleet
        // (one per run with the dispersed mass, one per block without),
        // plus once per block; stopping after those of the first block plus
        // a few keeps exactly one block. (The exact count is not the
        // contract: K being a whole number of blocks, 0 < K < N, is.)
        let per_block = if text == DISPERSED {
            1 + 2 * BLOCK_RUNS
        } else {
            1 + 2
        };
        let k = stopped_after(&study, &whole, 1, per_block + 2);
        assert_eq!(k as u64, BLOCK_RUNS, "one block kept");
        // On three threads, wherever the stop falls: a prefix, same bits.
        let mut kept = Vec::new();
        for calls in [1, 7, per_block, 2 * per_block] {
            kept.push(stopped_after(&study, &whole, 3, calls));
        }
        // Every block asks at least twice (its start, its first frame), so a
        // stop on the second question keeps nothing, on any thread.
        assert_eq!(kept[0], 0, "{kept:?}");
        // The rest flown later joins to the whole table, and the summary of
        // the joined table is the whole one's.
        let mut first = study
            .fly_runs_until(0..2100, &options(1), {
                let asked = AtomicU64::new(0);
                move || asked.fetch_add(1, Ordering::Relaxed) >= per_block + 2
            })
            .unwrap();
        let k = first.len() as u64;
        first
            .append(
                study
                    .fly_runs_until(k..2100, &options(2), || false)
                    .unwrap(),
            )
            .unwrap();
        assert_eq!(bits(&first), bits(&whole));
        assert_eq!(summarize(&first), summarize(&whole));
    }
}

#[test]
fn a_stop_asked_once_is_kept() {
    let study = Study::from_toml_str(SHARED_FLEET).unwrap();
    let whole = study.fly_runs(0..2100, &options(1)).unwrap();
    // `true` only on the 5th question (the second block's first frame: the
    // first block asks 3 times, at its start and frames 0 and 16), `false`
    // after: the flight still stops there.
    let asked = AtomicU64::new(0);
    let table = study
        .fly_runs_until(0..2100, &options(1), || {
            asked.fetch_add(1, Ordering::Relaxed) == 4
        })
        .unwrap();
    assert_eq!(table.len() as u64, BLOCK_RUNS);
    assert_eq!(bits(&table), bits(&whole)[..table.len()].to_vec());
}

/// A flight of about 100 million frames of lanes (minutes unoptimised) is
/// stopped from another thread 200 ms after it starts: it returns within
/// 2 s of the stop (a check every 16 frames of a 1,024-lane fleet is a few
/// tens of ms apart even in a debug build on a loaded machine; 2 s is the
/// margin that still keeps well inside `sim-cli`'s 3 s grace) and keeps fewer
/// runs than asked for.
#[test]
fn a_stop_from_another_thread_ends_a_long_flight_quickly() {
    let study =
        Study::from_toml_str(&SHARED_FLEET.replace("duration_s = 1.0", "duration_s = 60.0"))
            .unwrap()
            .with_runs(50_000)
            .unwrap();
    let stop = AtomicBool::new(false);
    let stopped_at = std::sync::Mutex::new(None);
    let table = std::thread::scope(|scope| {
        scope.spawn(|| {
            std::thread::sleep(Duration::from_millis(200));
            *stopped_at.lock().unwrap() = Some(Instant::now());
            stop.store(true, Ordering::Relaxed);
        });
        study
            .fly_runs_until(0..50_000, &options(2), || stop.load(Ordering::Relaxed))
            .unwrap()
    });
    let returned = Instant::now();
    let stopped_at = stopped_at.into_inner().unwrap().expect("the stop was sent");
    let latency = returned.duration_since(stopped_at);
    assert!(latency < Duration::from_secs(2), "stopped in {latency:?}");
    assert!(table.len() < 50_000, "{} runs", table.len());
    let expected: Vec<u64> = (0..table.len() as u64).collect();
    assert_eq!(table.run, expected);
}
