//! A thinned sample of ground tracks: which runs of a study are tracked
//! ([`TrackPlan`]: a bounded, deterministic sample spread evenly over the
//! run indices) and at which frames, and the tracks themselves
//! ([`GroundTrack`]), kept while the batch flies
//! ([`crate::Study::fly_runs_tracked`]).
//!
//! Memory is bounded whatever the number of runs: at most
//! [`TrackPlan::DEFAULT_TRACKS`] tracks of at most
//! [`TrackPlan::DEFAULT_POINTS`]` + 2` points of 32 bytes (a frame number and
//! a position), about 490 KB for the defaults, for 1,000 or 1,000,000 runs.

/// Which runs a study tracks and how thinly.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TrackPlan {
    /// The tracked runs, ascending, distinct.
    runs: Vec<u64>,
    /// A tracked run keeps its position every `frame_step` frames.
    frame_step: u64,
}

impl TrackPlan {
    /// The tracks `sim-cli study` draws in `study.svg`.
    pub const DEFAULT_TRACKS: u64 = 50;
    /// The thinning `sim-cli study` uses: at most this many frame steps per
    /// track.
    pub const DEFAULT_POINTS: u64 = 300;

    /// No run tracked.
    #[must_use]
    pub fn none() -> Self {
        Self {
            runs: Vec::new(),
            frame_step: 1,
        }
    }

    /// The sample of a study of `runs` runs of at most `frames` frames:
    /// `n = min(max_tracks, runs)` runs, run `⌊k · runs / n⌋` for `k` in
    /// `0..n` (the first run, then evenly spread; distinct because
    /// `runs ≥ n`), each keeping its position at frame 0, every
    /// `frame_step = max(1, ⌈frames / max_points⌉)` frames and at its last
    /// frame (its stop): at most `max_points + 2` points.
    #[must_use]
    pub fn spread(runs: u64, frames: u64, max_tracks: u64, max_points: u64) -> Self {
        let n = max_tracks.min(runs);
        let runs_tracked = (0..n)
            .map(|k| {
                let run = u128::from(k) * u128::from(runs) / u128::from(n);
                u64::try_from(run).unwrap_or(u64::MAX)
            })
            .collect();
        Self {
            runs: runs_tracked,
            frame_step: frames.div_ceil(max_points.max(1)).max(1),
        }
    }

    /// The tracked runs, ascending.
    #[must_use]
    pub fn runs(&self) -> &[u64] {
        &self.runs
    }

    /// Frames between two kept positions.
    #[must_use]
    pub fn frame_step(&self) -> u64 {
        self.frame_step
    }

    /// Whether run `run` is tracked.
    #[must_use]
    pub fn tracks(&self, run: u64) -> bool {
        self.runs.binary_search(&run).is_ok()
    }

    /// Whether a tracked run keeps frame `frame` (`last`: the run's last
    /// frame, its stop or the study's end).
    #[must_use]
    pub fn keeps(&self, frame: u64, last: bool) -> bool {
        last || frame.is_multiple_of(self.frame_step)
    }
}

/// The thinned ground track of one run: its position at the frames a
/// [`TrackPlan`] keeps.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GroundTrack {
    /// The run.
    pub run: u64,
    /// The frames kept, ascending (0 first, the run's last frame last).
    pub frames: Vec<u64>,
    /// The position at each kept frame in the model's earth frame (x north,
    /// y west, z up; metres from the origin), the same bits as the run
    /// flown alone gives at that frame.
    pub position_m: Vec<[f64; 3]>,
}

impl GroundTrack {
    /// Bytes one kept point takes (a frame and a position).
    pub const BYTES_PER_POINT: usize =
        core::mem::size_of::<u64>() + 3 * core::mem::size_of::<f64>();

    pub(crate) fn new(run: u64) -> Self {
        Self {
            run,
            ..Self::default()
        }
    }

    pub(crate) fn keep(&mut self, frame: u64, position_m: [f64; 3]) {
        if self.frames.last() != Some(&frame) {
            self.frames.push(frame);
            self.position_m.push(position_m);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_is_bounded_spread_and_distinct() {
        let plan = TrackPlan::spread(1_000_000, 1800, 50, 300);
        assert_eq!(plan.runs().len(), 50);
        assert_eq!(plan.runs()[0], 0);
        assert_eq!(plan.runs()[1], 20_000);
        assert_eq!(plan.runs()[49], 980_000);
        assert_eq!(plan.frame_step(), 6);
        // 0, 6, ..., 1800: 301 points, the last frame among them.
        let kept = (0..=1800).filter(|&f| plan.keeps(f, f == 1800)).count();
        assert_eq!(kept, 301);
        let few = TrackPlan::spread(7, 10, 50, 300);
        assert_eq!(few.runs(), [0, 1, 2, 3, 4, 5, 6]);
        assert_eq!(few.frame_step(), 1);
        let odd = TrackPlan::spread(103, 1000, 50, 300);
        assert_eq!(odd.runs().len(), 50);
        assert!(odd.runs().windows(2).all(|w| w[0] < w[1]));
        assert!(odd.tracks(0) && !odd.tracks(1) && odd.tracks(2));
        // At most max_points + 2: frame 0 .. the multiples .. a last frame
        // between two multiples.
        let kept = (0..=1000).filter(|&f| odd.keeps(f, f == 1000)).count();
        assert!(kept <= 302, "{kept}");
        // No run tracked: every frame would be kept (a step of 1).
        let none = TrackPlan::none();
        assert!(none.runs().is_empty() && !none.tracks(0));
        assert_eq!(none.frame_step(), 1);
        assert!(none.keeps(7, false));
        // 2^40 runs do not overflow.
        let huge = TrackPlan::spread(crate::MAX_RUNS, 1, 50, 300);
        assert_eq!(
            u128::from(huge.runs()[49]),
            49 * u128::from(crate::MAX_RUNS) / 50
        );
    }

    /// A track keeps each frame once: a stop on a frame the step already
    /// kept is not a second point. A point is a frame and three `f64`s:
    /// 32 bytes (the module's bound).
    #[test]
    fn a_track_keeps_each_frame_once() {
        let mut track = GroundTrack::new(9);
        track.keep(0, [0.0, 0.0, 1.0]);
        track.keep(6, [1.0, 2.0, 3.0]);
        track.keep(6, [1.0, 2.0, 3.0]);
        track.keep(8, [4.0, 5.0, 0.0]);
        assert_eq!(track.run, 9);
        assert_eq!(track.frames, [0, 6, 8]);
        assert_eq!(
            track.position_m,
            [[0.0, 0.0, 1.0], [1.0, 2.0, 3.0], [4.0, 5.0, 0.0]]
        );
        assert_eq!(GroundTrack::BYTES_PER_POINT, 32);
    }
}
