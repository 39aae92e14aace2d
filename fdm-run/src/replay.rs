//! Replaying a recording ([`crate::recording`]) as a library call: its
//! events fed to a run ([`replay`]: each run of recorded frames stepped with
//! its actions, each reset a reset; optionally paced in real time;
//! stoppable), and the replay's end compared with the recording's
//! fingerprint ([`check_fingerprint`], [`Verdict`]). What `sim-cli replay`
//! does.
//!
//! A replay flies the recorded flight bit for bit when it starts where the
//! recording starts (its [`Recording::start`](crate::recording::Recording),
//! fps and origin): the outputs attached see every frame as the recorded
//! run's did (a reset writes a new frame 0).
//!
//! ```
//! use fdm_core::palmer::Palmer;
//! use fdm_core::script::Script;
//! use fdm_run::recording::{RecordWriter, Recording};
//! use fdm_run::replay::{check_fingerprint, replay, ReplayOptions, Verdict};
//! use fdm_run::{Run, RunModel, Scenario, SharedOutput, Start};
//!
//! let script = Script::parse("1-20 throttle-up\n")?;
//! let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 60)?.with_script(script);
//! let mut run = Run::new(scenario.clone())?;
//! let writer = RecordWriter::new(Vec::new(), 30, &scenario.origin, &scenario.start)?;
//! let shared = SharedOutput::new(writer);
//! run.attach(shared.clone())?;
//! run.run_to_end()?;
//! run.finish()?;
//! let bytes = shared.take().map(|w| w.into_inner()).unwrap_or_default();
//!
//! let recording = Recording::<Palmer>::parse(&bytes)?;
//! let mut again = Run::new(Scenario::new(recording.start.clone(), recording.fps, 0)?)?;
//! let end = replay(&mut again, recording.events(), &ReplayOptions::new(recording.fps), || false, |_| {})?;
//! assert_eq!(end.frames, 60);
//! let verdict = check_fingerprint(
//!     recording.fingerprint,
//!     Palmer::state_fingerprint(&again.state()?),
//!     fdm_core::fingerprint::maths(),
//! );
//! assert_eq!(verdict, Verdict::Same);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::time::Instant;

use fdm_core::fingerprint::Fingerprint;
use fdm_core::model::Model;

use crate::pacer::FramePacer;
use crate::recording::{RecordingError, Replayed};
use crate::run::{Run, RunError};

/// What a recording can be replayed on: a [`Run`], or a program's own
/// flight that wraps one (it steps with the given actions and resets to the
/// recording's start).
pub trait ReplayTarget<A> {
    /// Why a step or a reset failed.
    type Error;

    /// Flies one frame applying `actions` in order.
    ///
    /// # Errors
    /// Why the frame was not flown.
    fn step(&mut self, actions: &[A]) -> Result<(), Self::Error>;

    /// Resets to the start.
    ///
    /// # Errors
    /// Why the reset failed.
    fn reset(&mut self) -> Result<(), Self::Error>;
}

impl<M: Model> ReplayTarget<M::Action> for Run<M> {
    type Error = RunError;

    fn step(&mut self, actions: &[M::Action]) -> Result<(), RunError> {
        self.step_actions(actions)
    }

    fn reset(&mut self) -> Result<(), RunError> {
        Run::reset(self)
    }
}

/// How a replay runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplayOptions {
    /// The recording's frames per second (the pacing's period).
    pub fps: u32,
    /// Pace the frames at 1/fps of wall-clock time each (so that a viewer
    /// such as FlightGear shows every frame); off: as fast as possible.
    pub realtime: bool,
}

impl ReplayOptions {
    /// As fast as possible, at `fps`.
    #[must_use]
    pub fn new(fps: u32) -> Self {
        Self {
            fps,
            realtime: false,
        }
    }
}

/// How a replay ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplayEnd {
    /// Frames replayed, across resets (the recording's frames unless
    /// stopped).
    pub frames: u64,
    /// With real-time pacing: frames that missed their deadline.
    pub overruns: Option<u64>,
    /// Whether the stop request ended the replay before the recording's end.
    pub stopped: bool,
}

/// Why a replay stopped on an error.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError<E> {
    /// Frame `frame` (counted from the last reset, as the CSV's frames)
    /// was not flown.
    #[error("frame {frame}")]
    Step {
        /// The frame's number since the last reset, from 1.
        frame: u64,
        /// The target's error.
        #[source]
        source: E,
    },
    /// A recorded reset failed.
    #[error("reset")]
    Reset(#[source] E),
    /// An event did not decode (not after a successful
    /// [`Recording::parse`](crate::recording::Recording::parse)).
    #[error(transparent)]
    Event(RecordingError),
}

/// Replays `events` (a recording's [`Recording::events`](crate::recording::Recording::events))
/// on `target`, which starts where the recording starts: each run of frames
/// steps it with the run's actions, a reset resets it. `stop()` is asked
/// before every frame (a stop ends the replay there; the caller finishes
/// the outputs for the frames replayed); `after_frame(done)` is called after
/// every frame with the frames replayed so far (progress, link warnings).
///
/// # Errors
/// A failing step or reset ([`ReplayError::Step`], [`ReplayError::Reset`]),
/// or an event that does not decode ([`ReplayError::Event`]).
pub fn replay<A, T: ReplayTarget<A>>(
    target: &mut T,
    events: impl IntoIterator<Item = Result<Replayed<A>, RecordingError>>,
    options: &ReplayOptions,
    mut stop: impl FnMut() -> bool,
    mut after_frame: impl FnMut(u64),
) -> Result<ReplayEnd, ReplayError<T::Error>> {
    let mut pacer = options
        .realtime
        .then(|| FramePacer::new(FramePacer::period_for(options.fps), Instant::now()));
    let mut frame = 0_u64;
    let mut done = 0_u64;
    let mut stopped = false;
    'replay: for event in events {
        match event.map_err(ReplayError::Event)? {
            Replayed::Frames { count, actions } => {
                for _ in 0..count {
                    if stop() {
                        stopped = true;
                        break 'replay;
                    }
                    frame += 1;
                    done += 1;
                    target
                        .step(&actions)
                        .map_err(|source| ReplayError::Step { frame, source })?;
                    after_frame(done);
                    if let Some(pacer) = pacer.as_mut() {
                        let sleep = pacer.finish_frame(Instant::now());
                        if !sleep.is_zero() {
                            std::thread::sleep(sleep);
                        }
                    }
                }
            }
            Replayed::Reset => {
                target.reset().map_err(ReplayError::Reset)?;
                frame = 0;
            }
        }
    }
    Ok(ReplayEnd {
        frames: done,
        overruns: pacer.map(|p| p.overruns()),
        stopped,
    })
}

/// What comparing a replay's end with the recording's fingerprint found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The final state and the maths are the recording's.
    Same,
    /// The recording carries no fingerprint (format versions 1 and 2, or a
    /// cut recording).
    Unchecked,
    /// The final state is the recording's, the maths are not.
    OtherMaths {
        /// The recording's maths fingerprint.
        recorded: u64,
        /// This build's.
        ours: u64,
    },
    /// The final state is not the recording's.
    DifferentFlight {
        /// The recording's state fingerprint.
        recorded: u64,
        /// The replay's.
        replayed: u64,
        /// The recording's and this build's maths fingerprints, when they differ.
        maths: Option<(u64, u64)>,
    },
}

impl Verdict {
    /// What the verdict means, in words for the person replaying, or `None`
    /// for [`Verdict::Same`]; `program` names the replaying program ("this
    /// sim-cli's" maths). [`Verdict::Unchecked`] is a note,
    /// [`Verdict::OtherMaths`] a warning (the flight may still be the
    /// same), [`Verdict::DifferentFlight`] a failure.
    #[must_use]
    pub fn describe(&self, program: &str) -> Option<String> {
        let maths = |recorded: u64, ours: u64| {
            format!(
                "the recording was made with different maths (maths fingerprint \
                 {recorded:#018x}, this {program}'s {ours:#018x})"
            )
        };
        Some(match *self {
            Self::Same => return None,
            Self::Unchecked => "this recording (format version 1 or 2) has no fingerprint; the \
                                replay was not checked against the recorded flight"
                .to_owned(),
            Self::OtherMaths { recorded, ours } => format!(
                "{}; the replay still ended in the recorded final state",
                maths(recorded, ours)
            ),
            Self::DifferentFlight {
                recorded,
                replayed,
                maths: other,
            } => format!(
                "the replay flew a different flight: its final state's fingerprint is \
                 {replayed:#018x}, the recording's {recorded:#018x}; {}",
                other.map_or_else(
                    || "the maths are the same, so the build or the machine differs".to_owned(),
                    |(recorded, ours)| maths(recorded, ours)
                )
            ),
        })
    }
}

/// Compares a replay's final state (`replayed`, [`crate::RunModel::state_fingerprint`])
/// and this build's maths (`maths`, [`fdm_core::fingerprint::maths`]) with the
/// recording's fingerprint.
#[must_use]
pub fn check_fingerprint(recorded: Option<Fingerprint>, replayed: u64, maths: u64) -> Verdict {
    let Some(recorded) = recorded else {
        return Verdict::Unchecked;
    };
    let other_maths = (recorded.maths != maths).then_some((recorded.maths, maths));
    if recorded.state != replayed {
        return Verdict::DifferentFlight {
            recorded: recorded.state,
            replayed,
            maths: other_maths,
        };
    }
    match other_maths {
        None => Verdict::Same,
        Some((recorded, ours)) => Verdict::OtherMaths { recorded, ours },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_are_described_in_the_program_s_name() {
        assert_eq!(Verdict::Same.describe("sim-cli"), None);
        assert!(Verdict::Unchecked
            .describe("sim-cli")
            .unwrap()
            .starts_with("this recording (format version 1 or 2) has no fingerprint; the replay"));
        let other = Verdict::OtherMaths {
            recorded: 2,
            ours: 3,
        };
        assert_eq!(
            other.describe("x").unwrap(),
            "the recording was made with different maths (maths fingerprint 0x0000000000000002, \
             this x's 0x0000000000000003); the replay still ended in the recorded final state"
        );
        let different = |maths| Verdict::DifferentFlight {
            recorded: 1,
            replayed: 4,
            maths,
        };
        assert!(different(None)
            .describe("sim-cli")
            .unwrap()
            .ends_with("the recording's 0x0000000000000001; the maths are the same, so the build or the machine differs"));
        assert!(different(Some((2, 3)))
            .describe("sim-cli")
            .unwrap()
            .ends_with("; the recording was made with different maths (maths fingerprint 0x0000000000000002, this sim-cli's 0x0000000000000003)"));
    }

    #[test]
    fn verdicts() {
        let recorded = Fingerprint { state: 1, maths: 2 };
        assert_eq!(check_fingerprint(None, 1, 2), Verdict::Unchecked);
        assert_eq!(check_fingerprint(Some(recorded), 1, 2), Verdict::Same);
        assert_eq!(
            check_fingerprint(Some(recorded), 1, 3),
            Verdict::OtherMaths {
                recorded: 2,
                ours: 3
            }
        );
        assert_eq!(
            check_fingerprint(Some(recorded), 9, 3),
            Verdict::DifferentFlight {
                recorded: 1,
                replayed: 9,
                maths: Some((2, 3))
            }
        );
        assert_eq!(
            check_fingerprint(Some(recorded), 9, 2),
            Verdict::DifferentFlight {
                recorded: 1,
                replayed: 9,
                maths: None
            }
        );
    }

    /// A target that counts, failing on a chosen step.
    struct Counter {
        steps: Vec<Vec<u8>>,
        resets: u32,
        fail_at: Option<usize>,
    }

    impl ReplayTarget<u8> for Counter {
        type Error = &'static str;
        fn step(&mut self, actions: &[u8]) -> Result<(), &'static str> {
            if self.fail_at == Some(self.steps.len()) {
                return Err("boom");
            }
            self.steps.push(actions.to_vec());
            Ok(())
        }
        fn reset(&mut self) -> Result<(), &'static str> {
            self.resets += 1;
            Ok(())
        }
    }

    fn events() -> Vec<Result<Replayed<u8>, RecordingError>> {
        vec![
            Ok(Replayed::Frames {
                count: 2,
                actions: vec![7],
            }),
            Ok(Replayed::Reset),
            Ok(Replayed::Frames {
                count: 3,
                actions: vec![],
            }),
        ]
    }

    #[test]
    fn frames_and_resets_are_fed_in_order_and_frames_count_from_the_reset() {
        let mut target = Counter {
            steps: Vec::new(),
            resets: 0,
            fail_at: None,
        };
        let mut seen = Vec::new();
        let end = replay(
            &mut target,
            events(),
            &ReplayOptions::new(30),
            || false,
            |done| seen.push(done),
        )
        .unwrap();
        assert_eq!(
            end,
            ReplayEnd {
                frames: 5,
                overruns: None,
                stopped: false
            }
        );
        assert_eq!(seen, [1, 2, 3, 4, 5]);
        assert_eq!(target.steps, [vec![7], vec![7], vec![], vec![], vec![]]);
        assert_eq!(target.resets, 1);
        // The fourth step fails: frame 2 since the reset.
        let mut failing = Counter {
            steps: Vec::new(),
            resets: 0,
            fail_at: Some(3),
        };
        let err = replay(
            &mut failing,
            events(),
            &ReplayOptions::new(30),
            || false,
            |_| {},
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                ReplayError::Step {
                    frame: 2,
                    source: "boom"
                }
            ),
            "{err:?}"
        );
        assert_eq!(err.to_string(), "frame 2");
    }

    /// With real-time pacing each frame takes its period of wall-clock
    /// time: ten frames at 50 per second take at least 200 ms (the pacer's
    /// sleeps never end early; 150 ms is asserted, below that by a margin
    /// for the clock's granularity), and the overruns are counted.
    #[test]
    fn a_paced_replay_takes_a_period_a_frame() {
        let mut target = Counter {
            steps: Vec::new(),
            resets: 0,
            fail_at: None,
        };
        let events = vec![Ok(Replayed::Frames {
            count: 10,
            actions: vec![1],
        })];
        let options = ReplayOptions {
            fps: 50,
            realtime: true,
        };
        let started = Instant::now();
        let end = replay(&mut target, events, &options, || false, |_| {}).unwrap();
        let took = started.elapsed();
        assert_eq!(end.frames, 10);
        assert!(end.overruns.is_some());
        assert!(took >= std::time::Duration::from_millis(150), "{took:?}");
    }

    /// A [`Run`] is a replay target: the recorded frames and resets fed
    /// through [`replay`] fly it exactly as stepping and resetting it by
    /// hand does (the same state, to the bit, and the same frames flown).
    #[test]
    fn a_run_replays_frames_and_resets() {
        use crate::model::RunModel as _;
        use crate::{Scenario, Start};
        use fdm_core::palmer::{Palmer, PalmerAction};
        let run = || Run::new(Scenario::<Palmer>::new(Start::thesis(), 30, 0).unwrap()).unwrap();
        let up = vec![PalmerAction::ThrottleUp];
        let events = vec![
            Ok(Replayed::Frames {
                count: 3,
                actions: up.clone(),
            }),
            Ok(Replayed::Reset),
            Ok(Replayed::Frames {
                count: 4,
                actions: up.clone(),
            }),
            Ok(Replayed::Frames {
                count: 2,
                actions: vec![],
            }),
        ];
        let mut replayed = run();
        let end = replay(
            &mut replayed,
            events,
            &ReplayOptions::new(30),
            || false,
            |_| {},
        )
        .unwrap();
        assert_eq!(end.frames, 9);

        let mut by_hand = run();
        for _ in 0..3 {
            by_hand.step_actions(&up).unwrap();
        }
        let before_reset = by_hand.state().unwrap();
        by_hand.reset().unwrap();
        for _ in 0..4 {
            by_hand.step_actions(&up).unwrap();
        }
        for _ in 0..2 {
            by_hand.step_actions(&[]).unwrap();
        }
        assert_eq!(replayed.flown(), 9);
        assert_eq!(replayed.flown(), by_hand.flown());
        assert_eq!(
            Palmer::state_fingerprint(&replayed.state().unwrap()),
            Palmer::state_fingerprint(&by_hand.state().unwrap())
        );
        assert_ne!(
            Palmer::state_fingerprint(&replayed.state().unwrap()),
            Palmer::state_fingerprint(&before_reset)
        );
        assert!(replayed.controls().unwrap().throttle > run().controls().unwrap().throttle);
    }

    #[test]
    fn a_stop_ends_the_replay_before_the_next_frame() {
        let mut target = Counter {
            steps: Vec::new(),
            resets: 0,
            fail_at: None,
        };
        let mut asked = 0;
        let end = replay(
            &mut target,
            events(),
            &ReplayOptions::new(30),
            || {
                asked += 1;
                asked > 3
            },
            |_| {},
        )
        .unwrap();
        assert_eq!(end.frames, 3);
        assert!(end.stopped);
        assert_eq!(target.steps.len(), 3);
    }
}
