//! A scenario: what a run starts from and how long it lasts.

use std::path::Path;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::message::ShortNumber;
use fdm_core::model::Model;
use fdm_core::script::{Script, ScriptAction, ScriptError};
use fdm_core::start::{InitialConditions, StartError, TrimReport};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};

use crate::input::{read_text, show_path, InputError, MAX_INPUT_BYTES};

/// Highest frame rate a run accepts, frames per second. Far above any useful
/// real-time rate; it only keeps dt = 1/N away from values where `f32`
/// (Bourg) loses all meaning. `sim-cli --fps` reads its limit from here.
pub const MAX_FPS: u32 = 10_000;

/// Longest run in frames. About 1e9 frames is hours of CPU even for Palmer;
/// more is surely a typo. `sim-cli --frames` reads its limit from here.
pub const MAX_FRAMES: u64 = 1_000_000_000;

/// How an aircraft of model `M` starts (and restarts on a reset): its
/// parameters, controls and state at frame 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Start<M: Model> {
    /// The aircraft's parameters.
    pub aircraft: M::Aircraft,
    /// Controls at frame 0.
    pub controls: M::Controls,
    /// State at frame 0.
    pub state: M::State,
}

impl<M: Model> Start<M> {
    /// The thesis's start: the default aircraft, initial controls and state.
    #[must_use]
    pub fn thesis() -> Self {
        Self {
            aircraft: M::default_aircraft(),
            controls: M::initial_controls(),
            state: M::initial_state(),
        }
    }
}

/// Highest accepted start altitude, ft: far above both models' ceilings (the
/// atmosphere of Palmer's model ends near 145 000 ft). `sim-cli
/// --altitude-ft`, the Python bindings and study files read it from here.
pub const MAX_ALTITUDE_FT: f64 = 100_000.0;
/// Highest accepted start airspeed, kt.
pub const MAX_SPEED_KT: f64 = 1000.0;
/// Largest accepted start heading either way, degrees (−360 to 360).
pub const MAX_HEADING_DEG: f64 = 360.0;

/// Where and how an aircraft starts when not at the thesis's start, in the
/// units of the command line, the Python bindings and study files: each of
/// the three may be missing (then it comes from the model's own start:
/// Palmer 0 ft, 0 kt; Bourg 2000 ft, 60 ft/s; heading north), and trim for
/// steady level flight may be asked.
///
/// ```
/// use fdm_core::model::Model;
/// use fdm_core::palmer::Palmer;
/// use fdm_run::scenario::StartOptions;
///
/// let cruise = StartOptions { altitude_ft: Some(3000.0), speed_kt: Some(100.0), trim: true, ..StartOptions::default() };
/// let (start, report) = cruise.start::<Palmer>(Palmer::default_aircraft(), Palmer::initial_controls())?;
/// assert!((start.state.position_m.z - 914.4).abs() < 1e-9);
/// assert!(report.is_some());
/// # Ok::<(), fdm_run::scenario::StartRefused>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StartOptions {
    /// Height above the origin, ft (0 to [`MAX_ALTITUDE_FT`]).
    pub altitude_ft: Option<f64>,
    /// True airspeed, kt (0 to [`MAX_SPEED_KT`]).
    pub speed_kt: Option<f64>,
    /// True heading, degrees clockwise from north (±[`MAX_HEADING_DEG`]).
    pub heading_deg: Option<f64>,
    /// Trim for steady, wings-level, unaccelerated flight.
    pub trim: bool,
}

/// Why a start was refused. Each front end words it in its own terms (a
/// flag, a key); the variants say what went wrong.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum StartRefused {
    /// A value outside its range (or not finite).
    #[error("{name}: {} is not in {low}..{high}", ShortNumber(*.value))]
    OutOfRange {
        /// The option's name (`altitude_ft`, `speed_kt`, `heading_deg`).
        name: &'static str,
        /// The value given.
        value: f64,
        /// Lowest accepted.
        low: f64,
        /// Highest accepted.
        high: f64,
    },
    /// Trim asked at or below the ground: there is no steady flight there.
    #[error("cannot trim on the ground; give an altitude above 0")]
    TrimOnGround,
    /// The model's trim found no steady flight ([`Model::trim`]).
    #[error("trim: {0}")]
    Trim(StartError),
    /// The model cannot start at these conditions ([`Model::state_at`]).
    #[error("initial conditions: {0}")]
    Conditions(StartError),
}

impl StartOptions {
    /// Whether nothing is given: the thesis's start.
    #[must_use]
    pub fn is_thesis(&self) -> bool {
        *self == Self::default()
    }

    /// Checks each given value against its range.
    ///
    /// # Errors
    /// [`StartRefused::OutOfRange`] for the first value out of range.
    pub fn validate(&self) -> Result<(), StartRefused> {
        let checks = [
            ("altitude_ft", self.altitude_ft, 0.0, MAX_ALTITUDE_FT),
            ("speed_kt", self.speed_kt, 0.0, MAX_SPEED_KT),
            (
                "heading_deg",
                self.heading_deg,
                -MAX_HEADING_DEG,
                MAX_HEADING_DEG,
            ),
        ];
        for (name, value, low, high) in checks {
            match value {
                Some(value) if !(value.is_finite() && (low..=high).contains(&value)) => {
                    return Err(StartRefused::OutOfRange {
                        name,
                        value,
                        low,
                        high,
                    })
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The initial conditions: the values given, the rest from model `M`'s
    /// own start (its height, its airspeed, north).
    #[must_use]
    pub fn conditions<M: Model>(&self, aircraft: &M::Aircraft) -> InitialConditions {
        let own = M::view(aircraft, &M::initial_controls(), &M::initial_state());
        InitialConditions {
            altitude_m: self
                .altitude_ft
                .map_or(own.height_m(), |ft| ft * METRES_PER_FOOT),
            speed_mps: self
                .speed_kt
                .map_or(own.airspeed_mps, |kt| kt / KNOTS_PER_MPS),
            heading_deg: self.heading_deg.unwrap_or(0.0),
        }
    }

    /// Model `M`'s start with `aircraft`: the thesis's state when nothing is
    /// given; else [`Model::state_at`] the [`conditions`](Self::conditions)
    /// with `controls`, or with `trim` [`Model::trim`]'s controls and state
    /// and its report (for the caller to show).
    ///
    /// # Errors
    /// A value out of range, or why the model cannot start or trim there.
    pub fn start<M: Model>(
        &self,
        aircraft: M::Aircraft,
        controls: M::Controls,
    ) -> Result<(Start<M>, Option<TrimReport>), StartRefused> {
        self.validate()?;
        if self.is_thesis() {
            let state = M::initial_state();
            return Ok((
                Start {
                    aircraft,
                    controls,
                    state,
                },
                None,
            ));
        }
        let conditions = self.conditions::<M>(&aircraft);
        if self.trim {
            let trimmed = M::trim(&aircraft, &controls, &conditions).map_err(|e| match e {
                StartError::InvalidConditions if conditions.altitude_m <= 0.0 => {
                    StartRefused::TrimOnGround
                }
                e => StartRefused::Trim(e),
            })?;
            return Ok((
                Start {
                    aircraft,
                    controls: trimmed.controls,
                    state: trimmed.state,
                },
                Some(trimmed.report),
            ));
        }
        let state = M::state_at(&aircraft, &conditions).map_err(StartRefused::Conditions)?;
        Ok((
            Start {
                aircraft,
                controls,
                state,
            },
            None,
        ))
    }
}

/// Why a scenario was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScenarioError {
    /// A frame rate outside `1..=MAX_FPS`.
    #[error("frame rate {0} is not a whole number from 1 to {MAX_FPS}")]
    Fps(u32),
    /// More frames than [`MAX_FRAMES`].
    #[error("{0} frames, more than the {MAX_FRAMES} a run can have")]
    Frames(u64),
}

/// Why a run's length in seconds gives no frame count
/// ([`frames_for_duration`]). Display starts with the duration (short
/// number form), so a front end can put its option's name first
/// (`--duration 1e300 at 30 fps is 3e301 frames, more than 1000000000`).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum DurationError {
    /// A negative, NaN or infinite duration.
    #[error("{} is not a non-negative number of seconds", ShortNumber(*.0))]
    NotADuration(f64),
    /// More than [`MAX_FRAMES`] frames at that frame rate.
    #[error("{} at {fps} fps is {}", ShortNumber(*.duration_s), FrameCount(*.frames))]
    TooLong {
        /// The duration given, s.
        duration_s: f64,
        /// The frame rate, frames per second.
        fps: u32,
        /// `duration_s × fps` rounded: a whole number above [`MAX_FRAMES`],
        /// or +inf when the product overflows (the duration is fine, the
        /// product is too long).
        frames: f64,
    },
}

/// A frame count above [`MAX_FRAMES`] as [`DurationError::TooLong`] shows it.
struct FrameCount(f64);

impl std::fmt::Display for FrameCount {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() {
            write!(f, "{} frames, more than {MAX_FRAMES}", ShortNumber(self.0))
        } else {
            write!(f, "more than {MAX_FRAMES} frames")
        }
    }
}

/// The frames a run of `duration_s` seconds has at `fps`:
/// round(`duration_s` × `fps`), half away from zero, checked against [`MAX_FRAMES`].
///
/// ```
/// use fdm_run::scenario::{frames_for_duration, DurationError};
///
/// assert_eq!(frames_for_duration(2.5, 10), Ok(25));
/// assert_eq!(frames_for_duration(0.05, 30), Ok(2)); // 1.5 rounds up
/// assert!(matches!(frames_for_duration(-1.0, 30), Err(DurationError::NotADuration(_))));
/// ```
///
/// # Errors
/// [`DurationError::NotADuration`] for a negative or non-finite duration,
/// [`DurationError::TooLong`] for more than [`MAX_FRAMES`] frames.
pub fn frames_for_duration(duration_s: f64, fps: u32) -> Result<u64, DurationError> {
    if !(duration_s >= 0.0 && duration_s.is_finite()) {
        return Err(DurationError::NotADuration(duration_s));
    }
    let frames = (duration_s * f64::from(fps)).round();
    // duration_s is finite and non-negative, so frames is a number or +inf (never NaN).
    // MAX_FRAMES (1e9) is exact in f64.
    if frames > MAX_FRAMES as f64 {
        return Err(DurationError::TooLong {
            duration_s,
            fps,
            frames,
        });
    }
    // In range, non-negative and integral, so the cast is exact.
    Ok(frames as u64)
}

/// One flight of model `M`: its start, where on Earth, how fast frames go,
/// how many there are, and the scripted controls.
///
/// ```
/// use fdm_core::palmer::Palmer;
/// use fdm_run::{Run, Scenario, Start};
///
/// let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 90)?;
/// let mut run = Run::new(scenario)?;
/// let end = run.run_to_end()?;
/// assert_eq!(end.frames, 90);
/// assert!(run.view().time_s > 2.9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Scenario<M: Model> {
    /// The aircraft's start.
    pub start: Start<M>,
    /// The earth-frame origin (the model's `x, y, z = 0` on WGS-84).
    pub origin: GeodeticOrigin,
    /// Frames per second: every frame advances the model by dt = 1/fps
    /// ([`Model::time_step`]).
    pub fps: u32,
    /// Frames [`crate::Run::run_to_end`] flies.
    pub frames: u64,
    /// Scripted controls: the rules of frame N apply, in file order, before
    /// any other action of that frame.
    pub script: Script<M::Action>,
}

impl<M: Model> Scenario<M> {
    /// A scenario from `start` at `fps` for `frames` frames, at the default
    /// origin ([`GeodeticOrigin::default`]) without a script.
    ///
    /// # Errors
    /// A frame rate outside `1..=`[`MAX_FPS`] or more than [`MAX_FRAMES`] frames.
    pub fn new(start: Start<M>, fps: u32, frames: u64) -> Result<Self, ScenarioError> {
        if !(1..=MAX_FPS).contains(&fps) {
            return Err(ScenarioError::Fps(fps));
        }
        if frames > MAX_FRAMES {
            return Err(ScenarioError::Frames(frames));
        }
        Ok(Self {
            start,
            origin: GeodeticOrigin::default(),
            fps,
            frames,
            script: Script::default(),
        })
    }

    /// The same scenario at `origin`.
    #[must_use]
    pub fn with_origin(mut self, origin: GeodeticOrigin) -> Self {
        self.origin = origin;
        self
    }

    /// The same scenario with `script`.
    #[must_use]
    pub fn with_script(mut self, script: Script<M::Action>) -> Self {
        self.script = script;
        self
    }
}

/// A script file refused ([`load_script`]).
#[derive(Debug, thiserror::Error)]
pub enum ScriptFileError {
    /// The file cannot be read ([`crate::input::read_text`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A bad line, shown as `FILE:LINE: message` (the convention of
    /// compilers and editors).
    #[error("{path}:{}: {}", .error.line, line_message(.error))]
    Line {
        /// The file, as shown ([`crate::input::show_path`]).
        path: String,
        /// The first bad line.
        error: ScriptError,
    },
}

/// A script error's message without its `line N: ` prefix.
fn line_message(error: &ScriptError) -> String {
    let full = error.to_string();
    let prefix = format!("line {}: ", error.line);
    full.strip_prefix(&prefix).unwrap_or(&full).to_owned()
}

/// Reads and parses a script file: a regular file or a pipe of at most
/// [`MAX_INPUT_BYTES`] ([`crate::input::read_text`]; `waiting` as there).
///
/// # Errors
/// [`ScriptFileError::Input`] for an unreadable, oversized or non-UTF-8
/// file or a path that is not a regular file or pipe,
/// [`ScriptFileError::Line`] for the first bad line.
pub fn load_script<A: ScriptAction>(
    path: &Path,
    waiting: impl FnOnce(String) + Send + 'static,
) -> Result<Script<A>, ScriptFileError> {
    let text = read_text(path, "script", MAX_INPUT_BYTES, waiting)?;
    Script::parse(&text).map_err(|error| ScriptFileError::Line {
        path: show_path(path),
        error,
    })
}

#[cfg(test)]
mod tests {
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;

    use super::*;

    #[test]
    fn duration_rounds_to_nearest_frame() {
        assert_eq!(frames_for_duration(1.0 / 30.0 * 2.4, 30), Ok(2));
        assert_eq!(frames_for_duration(0.05, 30), Ok(2)); // 1.5 rounds away from zero
        assert_eq!(frames_for_duration(0.0, 30), Ok(0));
        assert_eq!(frames_for_duration(2.5, 10), Ok(25));
        assert_eq!(
            frames_for_duration(1e8, 10),
            Ok(MAX_FRAMES),
            "the longest run is accepted"
        );
        assert!(frames_for_duration(f64::NAN, 30).is_err());
    }

    #[test]
    fn overlong_durations_say_too_many_frames_in_short_numbers() {
        assert_eq!(
            frames_for_duration(1e308, 10_000).unwrap_err().to_string(),
            "1e308 at 10000 fps is more than 1000000000 frames"
        );
        assert_eq!(
            frames_for_duration(1e300, 30).unwrap_err().to_string(),
            "1e300 at 30 fps is 3e301 frames, more than 1000000000"
        );
        assert_eq!(
            frames_for_duration(-0.5, 30).unwrap_err(),
            DurationError::NotADuration(-0.5)
        );
        assert_eq!(
            frames_for_duration(f64::INFINITY, 30)
                .unwrap_err()
                .to_string(),
            "inf is not a non-negative number of seconds"
        );
    }

    #[test]
    fn no_option_is_the_thesis_start_bit_for_bit() {
        let (start, report) = StartOptions::default()
            .start::<Bourg>(Bourg::default_aircraft(), Bourg::initial_controls())
            .unwrap();
        assert_eq!(start, Start::<Bourg>::thesis());
        assert!(report.is_none());
    }

    #[test]
    fn out_of_range_values_are_refused_by_name() {
        for (options, name) in [
            (
                StartOptions {
                    altitude_ft: Some(-1.0),
                    ..StartOptions::default()
                },
                "altitude_ft",
            ),
            (
                StartOptions {
                    speed_kt: Some(f64::NAN),
                    ..StartOptions::default()
                },
                "speed_kt",
            ),
            (
                StartOptions {
                    heading_deg: Some(360.5),
                    ..StartOptions::default()
                },
                "heading_deg",
            ),
        ] {
            match options.start::<Palmer>(Palmer::default_aircraft(), Palmer::initial_controls()) {
                Err(StartRefused::OutOfRange { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: expected OutOfRange, got {other:?}"),
            }
        }
    }

    /// The documented ranges' ends are accepted (docs/cli.md: heading
    /// −360..360, west of north as well as east), just past them refused.
    #[test]
    fn the_ranges_ends_are_accepted() {
        let given = |altitude_ft, speed_kt, heading_deg| StartOptions {
            altitude_ft: Some(altitude_ft),
            speed_kt: Some(speed_kt),
            heading_deg: Some(heading_deg),
            ..StartOptions::default()
        };
        for (alt, kt, hdg) in [
            (0.0, 0.0, -MAX_HEADING_DEG),
            (MAX_ALTITUDE_FT, MAX_SPEED_KT, MAX_HEADING_DEG),
            (5000.0, 100.0, -90.0),
            (5000.0, 100.0, 0.0),
        ] {
            assert_eq!(given(alt, kt, hdg).validate(), Ok(()), "{alt} {kt} {hdg}");
        }
        for (alt, kt, hdg, name) in [
            (-0.1, 100.0, 0.0, "altitude_ft"),
            (MAX_ALTITUDE_FT + 1.0, 100.0, 0.0, "altitude_ft"),
            (5000.0, -0.1, 0.0, "speed_kt"),
            (5000.0, MAX_SPEED_KT + 1.0, 0.0, "speed_kt"),
            (5000.0, 100.0, -360.5, "heading_deg"),
            (5000.0, 100.0, f64::INFINITY, "heading_deg"),
        ] {
            match given(alt, kt, hdg).validate() {
                Err(StartRefused::OutOfRange { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: expected OutOfRange, got {other:?}"),
            }
        }
    }

    #[test]
    fn a_huge_value_is_shown_short() {
        let refused = StartOptions {
            altitude_ft: Some(1e308),
            ..StartOptions::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!(
            refused.to_string(),
            "altitude_ft: 1e308 is not in 0..100000"
        );
    }

    #[test]
    fn trim_on_the_ground_is_refused_as_such() {
        let on_ground = StartOptions {
            trim: true,
            speed_kt: Some(100.0),
            ..StartOptions::default()
        };
        // Palmer's own start is on the ground (0 ft).
        assert_eq!(
            on_ground
                .start::<Palmer>(Palmer::default_aircraft(), Palmer::initial_controls())
                .unwrap_err(),
            StartRefused::TrimOnGround
        );
    }

    #[test]
    fn missing_values_come_from_the_model_start() {
        let east = StartOptions {
            heading_deg: Some(90.0),
            ..StartOptions::default()
        };
        let own = Bourg::view(
            &Bourg::default_aircraft(),
            &Bourg::initial_controls(),
            &Bourg::initial_state(),
        );
        let conditions = east.conditions::<Bourg>(&Bourg::default_aircraft());
        assert_eq!(conditions.altitude_m.to_bits(), own.height_m().to_bits());
        assert_eq!(conditions.speed_mps.to_bits(), own.airspeed_mps.to_bits());
        assert_eq!(conditions.heading_deg, 90.0);
    }

    #[test]
    fn script_errors_name_file_and_line() {
        let dir = std::env::temp_dir().join(format!("fdm-run-script-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.txt");
        std::fs::write(&path, "# ok\n1-5 thrust-up\n\n3-2 thrust-up\n").unwrap();
        let err = super::load_script::<fdm_core::bourg::BourgAction>(&path, drop).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}:4: range 3-2 ends before it starts", path.display())
        );
        let missing = dir.join("missing.txt");
        let err = super::load_script::<fdm_core::bourg::BourgAction>(&missing, drop).unwrap_err();
        assert!(err.to_string().starts_with("cannot read script "), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
