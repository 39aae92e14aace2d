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
/// stopped from another thread once it is under way (the closure has been
/// asked 8 times). What is proven is counted, not timed: after the stop
/// request every worker gives up at its next question (the closure is
/// asked before each block and every 16 frames of a fleet), so the closure
/// is asked at most once more per worker thread after the request, i.e. at
/// most 16 frames of one block's fleet are flown per thread after it; the
/// flight keeps fewer runs than asked for, without a gap. The wall clock
/// only guards against a hang (60 s: the whole flight would take minutes;
/// the counted bound is what makes it quick, a few tens of ms of frames
/// even in a debug build, and it does not depend on the machine's load, on
/// which a 2 s wall-clock bound once failed).
#[test]
fn a_stop_from_another_thread_ends_a_long_flight_quickly() {
    const THREADS: usize = 2;
    let study =
        Study::from_toml_str(&SHARED_FLEET.replace("duration_s = 1.0", "duration_s = 60.0"))
            .unwrap()
            .with_runs(50_000)
            .unwrap();
    let stop = AtomicBool::new(false);
    let asked = AtomicU64::new(0);
    let answered_stop = AtomicU64::new(0);
    let asked_at_request = std::sync::Mutex::new(None);
    let table = std::thread::scope(|scope| {
        scope.spawn(|| {
            while asked.load(Ordering::SeqCst) < 8 {
                std::thread::sleep(Duration::from_millis(1));
            }
            stop.store(true, Ordering::SeqCst);
            // Every question counted from here on was asked after the
            // request (and answered `true`).
            *asked_at_request.lock().unwrap() =
                Some((asked.load(Ordering::SeqCst), Instant::now()));
        });
        study
            .fly_runs_until(0..50_000, &options(THREADS), || {
                asked.fetch_add(1, Ordering::SeqCst);
                let now = stop.load(Ordering::SeqCst);
                if now {
                    answered_stop.fetch_add(1, Ordering::SeqCst);
                }
                now
            })
            .unwrap()
    });
    let returned = Instant::now();
    let (at_request, requested) = asked_at_request
        .into_inner()
        .unwrap()
        .expect("the stop was sent");
    let after = asked.load(Ordering::SeqCst) - at_request;
    let answered_stop = answered_stop.load(Ordering::SeqCst);
    assert!(
        after <= THREADS as u64,
        "{after} questions after the request: a worker flew past its next check"
    );
    assert!(
        (1..=THREADS as u64).contains(&answered_stop),
        "{answered_stop} workers were told to stop (once told, a worker asks no more)"
    );
    let latency = returned.duration_since(requested);
    assert!(
        latency < Duration::from_secs(60),
        "hang guard: stopped in {latency:?}"
    );
    assert!(table.len() < 50_000, "{} runs", table.len());
    let expected: Vec<u64> = (0..table.len() as u64).collect();
    assert_eq!(table.run, expected);
}
