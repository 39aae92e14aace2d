//! The study file (TOML) and the validated [`Study`].

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::message::ShortNumber;
use fdm_core::model::Model;
use fdm_core::script::{Rule, Script};
use fdm_fleet::Precision;
use fdm_run::{Scenario, Start, StartOptions, StartRefused, MAX_FPS, MAX_FRAMES};
use serde::Deserialize;
use toml::Spanned;

use crate::measure::Measure;
use crate::memory::MemoryEstimate;
use crate::model::{registry_models, EachModel, StudyJob, StudyModel};
use crate::rng::{normal_cdf, normal_quantile, uniform};
use crate::table::RunTable;
use crate::track::{GroundTrack, TrackPlan};
use crate::StudyError;

/// Largest study file read: 16 MiB ([`fdm_run::input::MAX_INPUT_BYTES`], a
/// script's limit). A study file is a few kilobytes; its `script` is the
/// largest part, and a script is held to the same limit.
pub const MAX_STUDY_FILE_BYTES: u64 = fdm_run::input::MAX_INPUT_BYTES;

/// Most runs one study may have (2^40, about 1.1e12): far beyond one
/// machine, it only keeps counts exact in `f64` summaries.
pub const MAX_RUNS: u64 = 1 << 40;

/// When a run ends before its duration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// Fly the whole duration.
    Duration,
    /// End at the first touchdown (or a crash, or a divergence).
    Touchdown,
}

/// A distribution of one dispersion.
#[derive(Debug, Clone, PartialEq)]
pub enum Distribution {
    /// Normal with mean `mean` and standard deviation `sd`.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (> 0).
        sd: f64,
    },
    /// Uniform on [`low`, `high`].
    Uniform {
        /// Lowest value.
        low: f64,
        /// Highest value.
        high: f64,
    },
    /// Normal(`mean`, `sd`) restricted to [`low`, `high`], by inversion of
    /// the CDF (one uniform, no rejection loop).
    TruncatedNormal {
        /// Mean of the untruncated normal.
        mean: f64,
        /// Its standard deviation (> 0).
        sd: f64,
        /// Lowest value.
        low: f64,
        /// Highest value.
        high: f64,
    },
    /// One of `values`, with the probabilities `weights` (normalised).
    Choice {
        /// The values.
        values: Vec<f64>,
        /// Their cumulative weights, normalised, the last exactly 1.
        cumulative: Vec<f64>,
    },
}

impl Distribution {
    /// The value for the uniform `u` in (0, 1).
    #[must_use]
    pub fn sample(&self, u: f64) -> f64 {
        match self {
            Self::Normal { mean, sd } => mean + sd * normal_quantile(u),
            Self::Uniform { low, high } => low + (high - low) * u,
            Self::TruncatedNormal {
                mean,
                sd,
                low,
                high,
            } => {
                let (a, b) = truncated_cdfs(*mean, *sd, *low, *high);
                let x = if mirrored(*mean, *low) {
                    // Drawn through the lower tail ([`truncated_cdfs`]):
                    // u's order kept (a larger u, a larger x).
                    mean - sd * normal_quantile(a + (1.0 - u) * (b - a))
                } else {
                    mean + sd * normal_quantile(a + u * (b - a))
                };
                // The CDF's rounding can put x a hair outside: clamp. (The
                // study refuses an interval without probability mass in
                // `f64`, whose quantile could be infinite.)
                if x.is_finite() {
                    x.clamp(*low, *high)
                } else {
                    (low + high) / 2.0
                }
            }
            Self::Choice { values, cumulative } => {
                let index = cumulative
                    .iter()
                    .position(|&c| u < c)
                    .unwrap_or(values.len() - 1);
                values[index]
            }
        }
    }
}

/// Whether a truncated normal is drawn mirrored: an interval wholly above
/// the mean, where Φ is near 1 and `f64` has few values left (Φ(8) is
/// within 6e-16 of 1, so an interval 8 to 9 standard deviations up would
/// get only a handful of distinct draws).
fn mirrored(mean: f64, low: f64) -> bool {
    low > mean
}

/// Φ at the ends of a truncated normal's standardised interval, from the
/// lower tail, where Φ keeps its full relative precision: Φ(α), Φ(β), or
/// for a [`mirrored`] interval Φ(−β), Φ(−α).
fn truncated_cdfs(mean: f64, sd: f64, low: f64, high: f64) -> (f64, f64) {
    let (alpha, beta) = ((low - mean) / sd, (high - mean) / sd);
    if mirrored(mean, low) {
        (normal_cdf(-beta), normal_cdf(-alpha))
    } else {
        (normal_cdf(alpha), normal_cdf(beta))
    }
}

/// What a dispersion sets.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Target {
    Initial(&'static str),
    Control(String),
    Aircraft(String),
    ScriptDelay,
}

/// One dispersion of a study.
#[derive(Debug, Clone, PartialEq)]
struct Dispersion {
    key: String,
    target: Target,
    distribution: Distribution,
}

/// The initial conditions of a study file's `[initial]`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct InitialSpec {
    altitude_ft: Option<f64>,
    speed_kt: Option<f64>,
    heading_deg: Option<f64>,
    #[serde(default)]
    trim: bool,
}

impl InitialSpec {
    fn options(self) -> StartOptions {
        StartOptions {
            altitude_ft: self.altitude_ft,
            speed_kt: self.speed_kt,
            heading_deg: self.heading_deg,
            trim: self.trim,
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct OriginSpec {
    lat_deg: f64,
    lon_deg: f64,
    alt_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DispersionSpec {
    key: Spanned<String>,
    distribution: Spanned<String>,
    mean: Option<f64>,
    sd: Option<f64>,
    low: Option<f64>,
    high: Option<f64>,
    values: Option<Vec<f64>>,
    weights: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    model: Spanned<String>,
    runs: Spanned<i64>,
    #[serde(default)]
    seed: u64,
    fps: Option<Spanned<i64>>,
    duration_s: Spanned<f64>,
    stop: Option<Spanned<String>>,
    measures: Spanned<Vec<Spanned<String>>>,
    target_height_m: Option<Spanned<f64>>,
    origin: Option<Spanned<OriginSpec>>,
    initial: Option<Spanned<InitialSpec>>,
    #[serde(default)]
    controls: BTreeMap<String, Spanned<f64>>,
    #[serde(default)]
    aircraft: BTreeMap<String, Spanned<f64>>,
    script: Option<Spanned<String>>,
    script_delay_s: Option<Spanned<f64>>,
    #[serde(default)]
    dispersion: Vec<Spanned<DispersionSpec>>,
}

/// A parsed, validated study: the scenario, its dispersions, the number of
/// runs, the seed and the measures (docs/studies.md).
///
/// ```
/// use fdm_study::Study;
///
/// let study = Study::from_toml_str(
///     r#"
/// model = "palmer"
/// runs = 4
/// seed = 1
/// duration_s = 2.0
/// measures = ["max_height_m"]
/// [[dispersion]]
/// key = "controls.throttle"
/// distribution = "uniform"
/// low = 0.5
/// high = 1.0
/// "#,
/// )?;
/// assert_eq!(study.runs(), 4);
/// assert_eq!(study.measure_names(), ["max_height_m"]);
/// # Ok::<(), fdm_study::StudyError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    model: StudyEntry,
    runs: u64,
    seed: u64,
    fps: u32,
    frames: u64,
    stop: Stop,
    measures: Vec<Measure>,
    target_height_m: Option<f64>,
    origin: Option<[f64; 3]>,
    initial: Option<InitialSpec>,
    controls: Vec<(String, f64)>,
    aircraft: Vec<(String, f64)>,
    script: String,
    script_delay_s: f64,
    dispersions: Vec<Dispersion>,
}

/// The line (from 1) of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text.get(..offset).map_or(1, |before| {
        before.bytes().filter(|&b| b == b'\n').count() + 1
    })
}

/// One run's values: the study's base values with the run's draws.
#[derive(Debug, Clone, Default)]
pub(crate) struct RunValues {
    initial: InitialSpec,
    controls: Vec<(String, f64)>,
    aircraft: Vec<(String, f64)>,
    script_delay_s: f64,
    /// The values drawn, one per dispersion in the file's order: the same
    /// `f64`s as set above (the `input.*` columns).
    pub(crate) drawn: Vec<f64>,
}

/// Run `run` of a study ready to fly, or why its start was refused.
pub(crate) struct RunSetup<M: Model> {
    pub(crate) start: Start<M>,
    pub(crate) script: Script<M::Action>,
}

impl Study {
    /// Where a study's files go unless told otherwise: the directory of
    /// its file `path` (`.` for a bare file name).
    #[must_use]
    pub fn default_out_dir(path: &std::path::Path) -> std::path::PathBuf {
        path.parent().map_or_else(
            || std::path::PathBuf::from("."),
            std::path::Path::to_path_buf,
        )
    }

    /// Parses and validates a study file's text; its model is one of the
    /// run library's registry ([`StudyEntry::registry`]).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the line, the key and what was
    /// expected.
    pub fn from_toml_str(text: &str) -> Result<Self, StudyError> {
        Self::from_toml_str_among(text, &StudyEntry::registry())
    }

    /// Parses and validates a study file's text whose model is one of
    /// `models` (a program's own registry, e.g. `sim-cli`'s).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] naming the line, the key and what was
    /// expected (for `model`: one of `models`' names).
    pub fn from_toml_str_among(text: &str, models: &[StudyEntry]) -> Result<Self, StudyError> {
        let file: StudyFile = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(1, |s| line_of(text, s.start));
            StudyError::Syntax {
                line,
                message: e.message().trim().replace('\n', "; "),
            }
        })?;
        let invalid = |span: Range<usize>, key: &str, expected: String| StudyError::Invalid {
            line: line_of(text, span.start),
            key: key.to_owned(),
            expected,
        };
        let model = models
            .iter()
            .copied()
            .find(|m| m.name() == file.model.get_ref())
            .ok_or_else(|| {
                let names: Vec<&str> = models.iter().map(StudyEntry::name).collect();
                invalid(
                    file.model.span(),
                    "model",
                    format!(
                        "one of {}, found \"{}\"",
                        names.join(", "),
                        file.model.get_ref()
                    ),
                )
            })?;
        let runs = u64::try_from(*file.runs.get_ref())
            .ok()
            .filter(|r| (1..=MAX_RUNS).contains(r))
            .ok_or_else(|| {
                invalid(
                    file.runs.span(),
                    "runs",
                    format!(
                        "a whole number from 1 to {MAX_RUNS}, found {}",
                        file.runs.get_ref()
                    ),
                )
            })?;
        let fps = match &file.fps {
            None => 30,
            Some(fps) => u32::try_from(*fps.get_ref())
                .ok()
                .filter(|f| (1..=MAX_FPS).contains(f))
                .ok_or_else(|| {
                    invalid(
                        fps.span(),
                        "fps",
                        format!(
                            "a whole number from 1 to {MAX_FPS}, found {}",
                            fps.get_ref()
                        ),
                    )
                })?,
        };
        let duration = *file.duration_s.get_ref();
        let frames_f = (duration * f64::from(fps)).round();
        #[allow(clippy::cast_precision_loss)]
        if !(duration.is_finite() && frames_f >= 1.0 && frames_f <= MAX_FRAMES as f64) {
            return Err(invalid(
                file.duration_s.span(),
                "duration_s",
                format!(
                    "seconds giving 1 to {MAX_FRAMES} frames at {fps} frames per second, found {}",
                    ShortNumber(duration)
                ),
            ));
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let frames = frames_f as u64;
        let stop = match &file.stop {
            None => Stop::Duration,
            Some(s) => match s.get_ref().as_str() {
                "duration" => Stop::Duration,
                "touchdown" => Stop::Touchdown,
                other => {
                    return Err(invalid(
                        s.span(),
                        "stop",
                        format!("\"duration\" or \"touchdown\", found \"{other}\""),
                    ))
                }
            },
        };
        let mut measures = Vec::new();
        for name in file.measures.get_ref() {
            let measure = Measure::from_name(name.get_ref()).ok_or_else(|| {
                invalid(
                    name.span(),
                    "measures",
                    format!(
                        "measure names among {}, found \"{}\"",
                        Measure::ALL
                            .iter()
                            .map(|m| m.name())
                            .collect::<Vec<_>>()
                            .join(", "),
                        name.get_ref()
                    ),
                )
            })?;
            if measures.contains(&measure) {
                return Err(invalid(
                    name.span(),
                    "measures",
                    format!("each measure once, found \"{}\" twice", measure.name()),
                ));
            }
            measures.push(measure);
        }
        if measures.is_empty() {
            return Err(invalid(
                file.measures.span(),
                "measures",
                "at least one measure".to_owned(),
            ));
        }
        let target_height_m = match &file.target_height_m {
            Some(t) if !t.get_ref().is_finite() => {
                return Err(invalid(
                    t.span(),
                    "target_height_m",
                    "a finite height in metres".to_owned(),
                ))
            }
            Some(t) => Some(*t.get_ref()),
            None => None,
        };
        if let Some(m) = measures.iter().find(|m| m.needs_target_height()) {
            if target_height_m.is_none() {
                return Err(invalid(
                    file.measures.span(),
                    "target_height_m",
                    format!("a height in metres for the measure {}", m.name()),
                ));
            }
        }
        let origin = match &file.origin {
            None => None,
            Some(o) => {
                let spec = o.get_ref();
                GeodeticOrigin::new(spec.lat_deg, spec.lon_deg, spec.alt_m)
                    .map_err(|e| invalid(o.span(), "origin", format!("a geodetic origin ({e})")))?;
                Some([spec.lat_deg, spec.lon_deg, spec.alt_m])
            }
        };
        let initial = file.initial.as_ref().map(|i| *i.get_ref());
        if let (Some(span), Some(spec)) = (file.initial.as_ref().map(Spanned::span), initial) {
            check_initial(&spec).map_err(|e| invalid(span, "initial", e))?;
        }
        let script_delay_s = file.script_delay_s.as_ref().map_or(Ok(0.0), |d| {
            let v = *d.get_ref();
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(invalid(
                    d.span(),
                    "script_delay_s",
                    format!("seconds >= 0, found {}", ShortNumber(v)),
                ))
            }
        })?;
        let mut dispersions = Vec::new();
        for d in &file.dispersion {
            let spec = d.get_ref();
            let key = spec.key.get_ref().clone();
            let target = parse_target(&key).ok_or_else(|| {
                invalid(
                    spec.key.span(),
                    "dispersion.key",
                    format!(
                        "initial.altitude_ft, initial.speed_kt, initial.heading_deg, \
                         controls.NAME, aircraft.NAME or script_delay_s, found \"{key}\""
                    ),
                )
            })?;
            if dispersions.iter().any(|o: &Dispersion| o.key == key) {
                return Err(invalid(
                    spec.key.span(),
                    "dispersion.key",
                    format!("each key dispersed once, found \"{key}\" twice"),
                ));
            }
            let distribution = parse_distribution(spec)
                .map_err(|(field, e)| invalid(d.span(), &format!("dispersion.{field}"), e))?;
            dispersions.push(Dispersion {
                key,
                target,
                distribution,
            });
        }
        let study = Self {
            model,
            runs,
            seed: file.seed,
            fps,
            frames,
            stop,
            measures,
            target_height_m,
            origin,
            initial,
            controls: file
                .controls
                .iter()
                .map(|(k, v)| (k.clone(), *v.get_ref()))
                .collect(),
            aircraft: file
                .aircraft
                .iter()
                .map(|(k, v)| (k.clone(), *v.get_ref()))
                .collect(),
            script: file
                .script
                .as_ref()
                .map(|s| s.get_ref().clone())
                .unwrap_or_default(),
            script_delay_s,
            dispersions,
        };
        // The model's own checks: the names of controls, parameters, the
        // script's actions, and the nominal run's start.
        model.check(CheckModel {
            study: &study,
            file: &file,
            text,
        })?;
        Ok(study)
    }

    /// Reads and parses a study file ([`Self::read_file`], silently).
    ///
    /// # Errors
    /// [`StudyError::Input`] when it cannot be read; as [`Self::from_toml_str`].
    pub fn from_path(path: &Path) -> Result<Self, StudyError> {
        Self::from_toml_str(&Self::read_file(path, |_| {})?)
    }

    /// Reads and parses a study file whose model is one of `models`
    /// ([`Study::from_toml_str_among`]).
    ///
    /// # Errors
    /// As [`Study::from_path`].
    pub fn from_path_among(path: &Path, models: &[StudyEntry]) -> Result<Self, StudyError> {
        Self::from_toml_str_among(&Self::read_file(path, |_| {})?, models)
    }

    /// The text of the study file `path`, read as the run library reads a
    /// script ([`fdm_run::input::read_text`]): a regular file or a pipe of
    /// at most [`MAX_STUDY_FILE_BYTES`], so that `/dev/zero` or an endless
    /// pipe is refused instead of filling the memory. A named pipe that no
    /// program writes to yet is waited for; past a second, `waiting` is
    /// called (on another thread) with a note saying so, for a caller to
    /// show.
    ///
    /// # Errors
    /// [`StudyError::Input`]: missing or unreadable, neither a regular file
    /// nor a pipe, too large, or not UTF-8.
    pub fn read_file(
        path: &Path,
        waiting: impl FnOnce(String) + Send + 'static,
    ) -> Result<String, StudyError> {
        Ok(fdm_run::input::read_text(
            path,
            "study file",
            MAX_STUDY_FILE_BYTES,
            waiting,
        )?)
    }

    /// The same study with `runs` runs.
    ///
    /// # Errors
    /// [`StudyError::Runs`] outside 1 to [`MAX_RUNS`].
    pub fn with_runs(mut self, runs: u64) -> Result<Self, StudyError> {
        if !(1..=MAX_RUNS).contains(&runs) {
            return Err(StudyError::Runs(runs));
        }
        self.runs = runs;
        Ok(self)
    }

    /// The same study with the master seed `seed`.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Number of runs.
    #[must_use]
    pub fn runs(&self) -> u64 {
        self.runs
    }

    /// The master seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The model's name ([`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn model(&self) -> &'static str {
        self.model.name()
    }

    /// The study's model's entry (its name and its type's study work).
    #[must_use]
    pub fn entry(&self) -> StudyEntry {
        self.model
    }

    /// Frames per second.
    #[must_use]
    pub fn fps(&self) -> u32 {
        self.fps
    }

    /// Frames of a run that flies its whole duration.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The stop condition.
    #[must_use]
    pub fn stop(&self) -> Stop {
        self.stop
    }

    /// The measures, in the file's order.
    #[must_use]
    pub fn measures(&self) -> &[Measure] {
        &self.measures
    }

    /// The measures' names, in the file's order: the measure columns.
    #[must_use]
    pub fn measure_names(&self) -> Vec<String> {
        self.measures.iter().map(|m| m.name().to_owned()).collect()
    }

    /// The height of `time_to_height_s` and `distance_to_height_m`, m.
    #[must_use]
    pub fn target_height_m(&self) -> Option<f64> {
        self.target_height_m
    }

    /// The earth-frame origin (the default, Wright-Patterson, unless given).
    #[must_use]
    pub fn origin(&self) -> GeodeticOrigin {
        self.origin
            .and_then(|[lat, lon, alt]| GeodeticOrigin::new(lat, lon, alt).ok())
            .unwrap_or_default()
    }

    /// Whether any dispersion changes the aircraft's physical parameters
    /// (then every run flies with an aircraft of its own).
    #[must_use]
    pub fn disperses_aircraft(&self) -> bool {
        self.dispersions
            .iter()
            .any(|d| matches!(d.target, Target::Aircraft(_)))
    }

    /// The dispersed values of run `run`: each dispersion's key and the value
    /// drawn for the run, in the file's order (to relate measures to inputs,
    /// e.g. climb against mass). They are the values the run flies with
    /// (the same draws, by the same code, as the run's set-up) and its
    /// `input.*` columns ([`Study::input_names`]).
    #[must_use]
    pub fn dispersed_values(&self, run: u64) -> Vec<(String, f64)> {
        self.dispersions
            .iter()
            .zip(self.run_values(run).drawn)
            .map(|(d, value)| (d.key.clone(), value))
            .collect()
    }

    /// The input columns' names, one per dispersion in the file's order:
    /// `input.` and the dispersion's key
    /// ([`crate::table::input_column_name`]).
    #[must_use]
    pub fn input_names(&self) -> Vec<String> {
        self.dispersions
            .iter()
            .map(|d| crate::table::input_column_name(&d.key))
            .collect()
    }

    /// An empty table with this study's columns (measures and inputs).
    #[must_use]
    pub fn empty_table(&self) -> crate::RunTable {
        crate::RunTable::empty_with_inputs(&self.measures, &self.input_names())
    }

    /// Run `run`'s values: the base values, then each dispersion's draw
    /// from the run's stream at the dispersion's position.
    pub(crate) fn run_values(&self, run: u64) -> RunValues {
        let mut values = RunValues {
            initial: self.initial.unwrap_or_default(),
            controls: self.controls.clone(),
            aircraft: self.aircraft.clone(),
            script_delay_s: self.script_delay_s,
            drawn: Vec::with_capacity(self.dispersions.len()),
        };
        let set = |list: &mut Vec<(String, f64)>, name: &str, value: f64| match list
            .iter_mut()
            .find(|(k, _)| k == name)
        {
            Some(entry) => entry.1 = value,
            None => list.push((name.to_owned(), value)),
        };
        for (index, d) in self.dispersions.iter().enumerate() {
            #[allow(clippy::cast_possible_truncation)]
            let value = d.distribution.sample(uniform(self.seed, run, index as u32));
            values.drawn.push(value);
            match &d.target {
                Target::Initial("altitude_ft") => values.initial.altitude_ft = Some(value),
                Target::Initial("speed_kt") => values.initial.speed_kt = Some(value),
                Target::Initial(_) => values.initial.heading_deg = Some(value),
                Target::Control(name) => set(&mut values.controls, name, value),
                Target::Aircraft(name) => set(&mut values.aircraft, name, value),
                Target::ScriptDelay => values.script_delay_s = value,
            }
        }
        values
    }

    /// Whether the study's `initial` gives anything (else runs start at the
    /// model's own initial state).
    fn has_initial(&self) -> bool {
        self.initial.is_some()
            || self
                .dispersions
                .iter()
                .any(|d| matches!(d.target, Target::Initial(_)))
    }

    /// Run `run` ready to fly: its aircraft, controls, state and script, or
    /// why the start is refused (the run's status `start_refused`).
    pub(crate) fn setup<M: StudyModel>(&self, run: u64) -> Result<RunSetup<M>, String> {
        self.setup_from::<M>(&self.run_values(run))
    }

    /// [`Study::setup`] from the run's values ([`Study::run_values`]).
    pub(crate) fn setup_from<M: StudyModel>(
        &self,
        values: &RunValues,
    ) -> Result<RunSetup<M>, String> {
        let aircraft = if values.aircraft.is_empty() {
            M::default_aircraft()
        } else {
            let pairs: Vec<(&str, f64)> = values
                .aircraft
                .iter()
                .map(|(k, v)| (k.as_str(), *v))
                .collect();
            M::aircraft_with(&pairs).map_err(|e| format!("aircraft: {e}"))?
        };
        let mut controls = M::initial_controls();
        for (key, value) in &values.controls {
            M::set_control(&mut controls, key, *value).map_err(|e| format!("controls: {e}"))?;
        }
        let (start, _trim_report) = if self.has_initial() {
            let spec = values.initial;
            check_initial(&spec).map_err(|e| format!("initial: {e}"))?;
            spec.options()
                .start::<M>(aircraft, controls)
                .map_err(|refused| match refused {
                    StartRefused::TrimOnGround => {
                        "trim: cannot trim on the ground; give altitude_ft above 0".to_owned()
                    }
                    refused => refused.to_string(),
                })?
        } else {
            let state = M::initial_state();
            (
                Start {
                    aircraft,
                    controls,
                    state,
                },
                None,
            )
        };
        let base = Script::<M::Action>::parse(&self.script).map_err(|e| e.to_string())?;
        let delay = values.script_delay_s * f64::from(self.fps);
        if !(delay.is_finite() && delay >= 0.0) {
            return Err(format!(
                "script_delay_s = {}: expected seconds >= 0",
                ShortNumber(values.script_delay_s)
            ));
        }
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let delay_frames = delay.round().min(MAX_FRAMES as f64) as u64;
        let script = if delay_frames == 0 {
            base
        } else {
            Script::from_rules(
                base.rules()
                    .iter()
                    .map(|r| Rule {
                        first_frame: r.first_frame.saturating_add(delay_frames),
                        last_frame: r.last_frame.saturating_add(delay_frames),
                        action: r.action,
                    })
                    .collect(),
            )
        };
        Ok(RunSetup { start, script })
    }

    /// Rules of the study's script for model `M` (0 when it has none).
    pub(crate) fn script_rules<M: StudyModel>(&self) -> usize {
        Script::<M::Action>::parse(&self.script).map_or(0, |s| s.rules().len())
    }

    /// Run `run` as an `fdm_run` scenario of model `M`, to fly alone (with
    /// every output of a single flight) for `frames` frames.
    ///
    /// # Errors
    /// [`StudyError::Model`] when `M` is not the study's model;
    /// [`StudyError::StartRefused`] when the run's start is refused.
    pub fn scenario<M: StudyModel>(
        &self,
        run: u64,
        frames: u64,
    ) -> Result<Scenario<M>, StudyError> {
        if M::NAME != self.model() {
            return Err(StudyError::Model {
                study: self.model(),
                asked: M::NAME,
            });
        }
        let setup = self
            .setup::<M>(run)
            .map_err(|reason| StudyError::StartRefused { run, reason })?;
        let scenario = Scenario::new(setup.start, self.fps, frames)
            .map_err(|e| StudyError::StartRefused {
                run,
                reason: e.to_string(),
            })?
            .with_origin(self.origin())
            .with_script(setup.script);
        Ok(scenario)
    }
}

fn check_initial(spec: &InitialSpec) -> Result<(), String> {
    spec.options().validate().map_err(|refused| match refused {
        StartRefused::OutOfRange {
            name,
            value,
            low,
            high,
        } => format!(
            "{name}: expected a number from {low} to {high}, found {}",
            ShortNumber(value)
        ),
        refused => refused.to_string(),
    })
}

fn parse_target(key: &str) -> Option<Target> {
    match key.split_once('.') {
        Some(("initial", f @ ("altitude_ft" | "speed_kt" | "heading_deg"))) => {
            Some(Target::Initial(match f {
                "altitude_ft" => "altitude_ft",
                "speed_kt" => "speed_kt",
                _ => "heading_deg",
            }))
        }
        Some(("controls", name)) if !name.is_empty() => Some(Target::Control(name.to_owned())),
        Some(("aircraft", name)) if !name.is_empty() => Some(Target::Aircraft(name.to_owned())),
        None if key == "script_delay_s" => Some(Target::ScriptDelay),
        _ => None,
    }
}

/// A dispersion's distribution, or the field at fault and what was expected.
fn parse_distribution(spec: &DispersionSpec) -> Result<Distribution, (&'static str, String)> {
    let need = |field: &'static str, v: Option<f64>| {
        v.filter(|x| x.is_finite())
            .ok_or((field, format!("a finite number `{field}`")))
    };
    let positive = |v: f64| {
        if v > 0.0 {
            Ok(v)
        } else {
            Err((
                "sd",
                format!("a standard deviation > 0, found {}", ShortNumber(v)),
            ))
        }
    };
    let ordered = |low: f64, high: f64| {
        if low < high {
            Ok(())
        } else {
            Err((
                "high",
                format!(
                    "low < high, found low {} and high {}",
                    ShortNumber(low),
                    ShortNumber(high)
                ),
            ))
        }
    };
    let allowed: &[&str] = match spec.distribution.get_ref().as_str() {
        "normal" => &["mean", "sd"],
        "uniform" => &["low", "high"],
        "truncated_normal" => &["mean", "sd", "low", "high"],
        "choice" => &["values", "weights"],
        other => {
            return Err((
                "distribution",
                format!("normal, uniform, truncated_normal or choice, found \"{other}\""),
            ))
        }
    };
    let given = [
        ("mean", spec.mean.is_some()),
        ("sd", spec.sd.is_some()),
        ("low", spec.low.is_some()),
        ("high", spec.high.is_some()),
        ("values", spec.values.is_some()),
        ("weights", spec.weights.is_some()),
    ];
    for (field, present) in given {
        if present && !allowed.contains(&field) {
            return Err((
                field,
                format!(
                    "only {} for a {} distribution",
                    allowed.join(", "),
                    spec.distribution.get_ref()
                ),
            ));
        }
    }
    Ok(match spec.distribution.get_ref().as_str() {
        "normal" => Distribution::Normal {
            mean: need("mean", spec.mean)?,
            sd: positive(need("sd", spec.sd)?)?,
        },
        "uniform" => {
            let (low, high) = (need("low", spec.low)?, need("high", spec.high)?);
            ordered(low, high)?;
            // high − low overflowing would make every draw infinite.
            if !(high - low).is_finite() {
                return Err((
                    "high",
                    format!(
                        "high − low within f64's range, found low {} and high {}",
                        ShortNumber(low),
                        ShortNumber(high)
                    ),
                ));
            }
            Distribution::Uniform { low, high }
        }
        "truncated_normal" => {
            let (low, high) = (need("low", spec.low)?, need("high", spec.high)?);
            ordered(low, high)?;
            let (mean, sd) = (need("mean", spec.mean)?, positive(need("sd", spec.sd)?)?);
            // No probability mass in `f64` (the interval some 38 standard
            // deviations or more from the mean): every draw would be one
            // arbitrary value.
            let (a, b) = truncated_cdfs(mean, sd, low, high);
            if b <= a {
                return Err((
                    "low",
                    format!(
                        "an interval with a probability under the normal (within about 38 \
                         standard deviations of the mean), found low {} and high {} for mean {} \
                         and sd {}",
                        ShortNumber(low),
                        ShortNumber(high),
                        ShortNumber(mean),
                        ShortNumber(sd)
                    ),
                ));
            }
            Distribution::TruncatedNormal {
                mean,
                sd,
                low,
                high,
            }
        }
        _ => {
            let values = spec
                .values
                .clone()
                .filter(|v| !v.is_empty() && v.iter().all(|x| x.is_finite()))
                .ok_or(("values", "a non-empty array of finite numbers".to_owned()))?;
            let weights = spec
                .weights
                .clone()
                .unwrap_or_else(|| vec![1.0; values.len()]);
            let total: f64 = weights.iter().sum();
            // A sum that overflows (weights near f64::MAX) would make every
            // quotient 0 and the last value certain: refused, not drawn.
            if weights.len() != values.len()
                || !weights.iter().all(|w| w.is_finite() && *w >= 0.0)
                || !(total > 0.0 && total.is_finite())
            {
                return Err((
                    "weights",
                    format!(
                        "{} finite weights >= 0 with a positive, finite sum",
                        values.len()
                    ),
                ));
            }
            let mut sum = 0.0;
            let mut cumulative: Vec<f64> = weights
                .iter()
                .map(|w| {
                    sum += w;
                    sum / total
                })
                .collect();
            if let Some(last) = cumulative.last_mut() {
                *last = 1.0;
            }
            Distribution::Choice { values, cumulative }
        }
    })
}

/// One model a study file may name (`model = "NAME"`): its name and the
/// study's work done with its type, made by [`StudyEntry::of`]. The models
/// a study may name are a list of these: the run library's registry
/// ([`StudyEntry::registry`], what [`Study::from_toml_str`] reads with) or a
/// program's own ([`Study::from_toml_str_among`]: `sim-cli`'s registry, whose
/// `glider` feature adds a model outside the library crates). The study
/// keeps its model's entry, so it flies it without looking it up again.
///
#[derive(Clone, Copy)]
pub struct StudyEntry {
    name: &'static str,
    check: for<'a> fn(CheckModel<'a>) -> Result<(), StudyError>,
    fly: for<'a> fn(FlyJob<'a>) -> FlyResult,
    memory: for<'a> fn(MemoryJob<'a>) -> MemoryEstimate,
}

impl StudyEntry {
    /// Model `M`'s entry.
    #[must_use]
    pub fn of<M: StudyModel>() -> Self {
        Self {
            name: <M as fdm_core::model::Model>::NAME,
            check: |job| job.call::<M>(),
            fly: |job| job.call::<M>(),
            memory: |job| job.call::<M>(),
        }
    }

    /// The run library's registry's models ([`fdm_run::model::MODELS`]:
    /// Palmer, Bourg), in its order.
    #[must_use]
    pub fn registry() -> Vec<Self> {
        struct Entries(Vec<StudyEntry>);
        impl EachModel for Entries {
            fn model<M: StudyModel>(&mut self) {
                self.0.push(StudyEntry::of::<M>());
            }
        }
        let mut all = Entries(Vec::new());
        registry_models(&mut all);
        debug_assert!(all
            .0
            .iter()
            .map(|e| e.name)
            .eq(fdm_run::model::MODELS.iter().copied()));
        all.0
    }

    /// The model's name ([`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.name
    }

    pub(crate) fn check(self, job: CheckModel<'_>) -> Result<(), StudyError> {
        (self.check)(job)
    }

    pub(crate) fn fly(self, job: FlyJob<'_>) -> FlyResult {
        (self.fly)(job)
    }

    pub(crate) fn memory(self, job: MemoryJob<'_>) -> MemoryEstimate {
        (self.memory)(job)
    }
}

/// Entries are the same model's when their names are.
impl PartialEq for StudyEntry {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl std::fmt::Debug for StudyEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("StudyEntry").field(&self.name).finish()
    }
}

/// What flying a study's runs returns: the runs' rows and the ground tracks
/// kept.
pub(crate) type FlyResult = Result<(RunTable, Vec<GroundTrack>), StudyError>;

/// Flying a study's runs with its model's type (done in [`crate::fly`]).
pub(crate) struct FlyJob<'a> {
    pub(crate) study: &'a Study,
    pub(crate) runs: Range<u64>,
    pub(crate) threads: usize,
    pub(crate) precision: Precision,
    pub(crate) stop: &'a (dyn Fn() -> bool + Sync),
    pub(crate) plan: &'a TrackPlan,
}

/// A study's memory estimate with its model's type (done in
/// [`crate::fly`]).
pub(crate) struct MemoryJob<'a> {
    pub(crate) study: &'a Study,
    pub(crate) chunk_runs: u64,
}

/// The model-specific checks of a study file.
pub(crate) struct CheckModel<'a> {
    study: &'a Study,
    file: &'a StudyFile,
    text: &'a str,
}

impl StudyJob for CheckModel<'_> {
    type Output = Result<(), StudyError>;

    fn call<M: StudyModel>(self) -> Result<(), StudyError> {
        let text = self.text;
        let invalid = |span: Range<usize>, key: String, expected: String| StudyError::Invalid {
            line: line_of(text, span.start),
            key,
            expected,
        };
        let mut control = M::initial_controls();
        for (key, value) in &self.file.controls {
            M::set_control(&mut control, key, *value.get_ref())
                .map_err(|e| invalid(value.span(), format!("controls.{key}"), e))?;
        }
        for (key, value) in &self.file.aircraft {
            M::aircraft_with(&[(key.as_str(), *value.get_ref())])
                .map_err(|e| invalid(value.span(), format!("aircraft.{key}"), e))?;
        }
        for d in &self.file.dispersion {
            let key = d.get_ref().key.get_ref();
            let span = d.get_ref().key.span();
            match parse_target(key) {
                Some(Target::Control(name)) if !M::CONTROL_KEYS.contains(&name.as_str()) => {
                    return Err(invalid(
                        span,
                        "dispersion.key".to_owned(),
                        format!(
                            "controls.NAME with NAME among {} for {}, found \"{key}\"",
                            M::CONTROL_KEYS.join(", "),
                            M::NAME
                        ),
                    ))
                }
                Some(Target::Aircraft(name)) if !M::AIRCRAFT_KEYS.contains(&name.as_str()) => {
                    return Err(invalid(
                        span,
                        "dispersion.key".to_owned(),
                        format!(
                            "aircraft.NAME with NAME among {} for {}, found \"{key}\"",
                            M::AIRCRAFT_KEYS.join(", "),
                            M::NAME
                        ),
                    ))
                }
                _ => {}
            }
        }
        if let Some(script) = &self.file.script {
            Script::<M::Action>::parse(script.get_ref()).map_err(|e| {
                invalid(
                    script.span(),
                    "script".to_owned(),
                    format!("a script of {} actions: {e}", M::NAME),
                )
            })?;
        }
        // The nominal run (no dispersion) must be able to start.
        let nominal = Study {
            dispersions: Vec::new(),
            ..self.study.clone()
        };
        nominal.setup::<M>(0).map_err(|e| StudyError::Invalid {
            line: 1,
            key: "initial".to_owned(),
            expected: format!("a start the model can fly without dispersions: {e}"),
        })?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;

    /// A study file is read as a script is: a device unread, a regular
    /// file past the limit unread, a file that is a study parsed.
    #[cfg(unix)]
    #[test]
    fn a_study_file_is_read_within_bounds() {
        use fdm_run::input::InputError;
        let zero = Study::from_path(Path::new("/dev/zero")).unwrap_err();
        assert!(
            matches!(zero, StudyError::Input(InputError::NotAFileOrPipe { .. })),
            "{zero}"
        );
        let dir = std::env::temp_dir().join(format!("fdm-study-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let big = dir.join("big.toml");
        std::fs::File::create(&big)
            .unwrap()
            .set_len(MAX_STUDY_FILE_BYTES + 1)
            .unwrap();
        let err = Study::from_path(&big).unwrap_err();
        assert!(
            matches!(err, StudyError::Input(InputError::TooLarge { .. })),
            "{err}"
        );
        let small = dir.join("s.toml");
        let text = "model = \"bourg\"\nruns = 2\nduration_s = 1.0\nmeasures = [\"final_x_m\"]\n";
        std::fs::write(&small, text).unwrap();
        assert_eq!(
            Study::from_path(&small).unwrap(),
            Study::from_toml_str(text).unwrap()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A study's model is looked up in the list it is read with: the run
    /// library's registry by default, a program's own list otherwise (the
    /// error names that list's models).
    #[test]
    fn a_study_names_a_model_of_its_list() {
        let names: Vec<&str> = StudyEntry::registry()
            .iter()
            .map(StudyEntry::name)
            .collect();
        assert_eq!(names, fdm_run::model::MODELS);
        let text = "model = \"bourg\"\nruns = 2\nduration_s = 1.0\nmeasures = [\"final_x_m\"]\n";
        let study = crate::Study::from_toml_str(text).unwrap();
        assert_eq!(study.model(), "bourg");
        assert_eq!(study.entry(), StudyEntry::of::<Bourg>());
        let among = crate::Study::from_toml_str_among(text, &StudyEntry::registry()).unwrap();
        assert_eq!(among, study);
        let err = crate::Study::from_toml_str_among(text, &[StudyEntry::of::<Palmer>()])
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`model`") && err.contains("one of palmer, found \"bourg\""),
            "{err}"
        );
        assert_eq!(
            format!("{:?}", StudyEntry::of::<Palmer>()),
            "StudyEntry(\"palmer\")"
        );
    }

    const BASE: &str =
        "model = \"palmer\"\nruns = 10\nduration_s = 1.0\nmeasures = [\"max_height_m\"]\n";

    fn error(text: &str) -> String {
        Study::from_toml_str(text).unwrap_err().to_string()
    }

    /// What a study file says, as the study's accessors give it back.
    #[test]
    fn a_study_gives_back_what_its_file_says() {
        let text = format!(
            "{BASE}seed = 99\nfps = 50\ntarget_height_m = 150.0\nscript_delay_s = 2.5\n\
             [origin]\nlat_deg = 47.5\nlon_deg = 11.25\nalt_m = 700.0\n\
             [[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"uniform\"\n\
             low = 60.0\nhigh = 70.0\n"
        );
        let study = Study::from_toml_str(&text).unwrap();
        assert_eq!((study.runs(), study.seed(), study.fps()), (10, 99, 50));
        // 1 s at 50 frames per second.
        assert_eq!(study.frames(), 50);
        assert_eq!(study.target_height_m(), Some(150.0));
        let origin = study.origin().geodetic();
        assert_eq!(
            (origin.lat_deg, origin.lon_deg, origin.alt_m),
            (47.5, 11.25, 700.0)
        );
        assert!(!study.disperses_aircraft());
        let values = study.dispersed_values(3);
        assert_eq!(values.len(), 1);
        assert_eq!(values[0].0, "initial.speed_kt");
        let want = 60.0 + 10.0 * uniform(99, 3, 0);
        assert_eq!(values[0].1.to_bits(), want.to_bits());
        // Without them: no target height, the default origin.
        let plain = Study::from_toml_str(BASE).unwrap();
        assert_eq!(plain.target_height_m(), None);
        assert_eq!(plain.origin(), GeodeticOrigin::default());
        assert_eq!(plain.frames(), 30);
        assert!(plain.dispersed_values(0).is_empty());
        let mass = format!(
            "{BASE}[[dispersion]]\nkey = \"aircraft.mass_kg\"\ndistribution = \"uniform\"\n\
             low = 1000.0\nhigh = 1100.0\n"
        );
        assert!(Study::from_toml_str(&mass).unwrap().disperses_aircraft());
        // The number of runs, within 1 to MAX_RUNS.
        assert_eq!(plain.clone().with_runs(5).unwrap().runs(), 5);
        assert_eq!(plain.clone().with_runs(MAX_RUNS).unwrap().runs(), MAX_RUNS);
        for bad in [0, MAX_RUNS + 1] {
            assert!(matches!(
                plain.clone().with_runs(bad),
                Err(StudyError::Runs(r)) if r == bad
            ));
        }
    }

    /// The numbers a study file gives are refused when out of their range:
    /// a duration that is not finite or flies no frame or too many, a
    /// target height or script delay that is not a finite height or delay
    /// (a negative delay too), a key dispersed twice.
    #[test]
    fn numbers_out_of_range_are_refused() {
        for (line, key) in [
            ("duration_s = nan", "duration_s"),
            ("duration_s = inf", "duration_s"),
            ("duration_s = 0.01", "duration_s"),
            ("duration_s = 1e12", "duration_s"),
            ("target_height_m = inf", "target_height_m"),
            ("target_height_m = nan", "target_height_m"),
            ("script_delay_s = -1.0", "script_delay_s"),
            ("script_delay_s = nan", "script_delay_s"),
            ("script_delay_s = inf", "script_delay_s"),
        ] {
            let text = if key == "duration_s" {
                BASE.replace("duration_s = 1.0", line)
            } else {
                format!("{BASE}{line}\n")
            };
            let e = error(&text);
            assert!(e.contains(&format!("`{key}`")), "{line}: {e}");
        }
        for ok in [
            "script_delay_s = 0.0",
            "script_delay_s = 2.5",
            "target_height_m = -5.0",
        ] {
            assert!(
                Study::from_toml_str(&format!("{BASE}{ok}\n")).is_ok(),
                "{ok}"
            );
        }
        let uniform = "[[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"uniform\"\n\
                       low = 60.0\nhigh = 70.0\n";
        let e = error(&format!("{BASE}{uniform}{uniform}"));
        assert!(e.contains("initial.speed_kt"), "{e}");
    }

    /// Each distribution's value for a given u: the normal's mean + sd ·
    /// Φ⁻¹(u), the uniform's low + (high − low) · u, and a truncated normal
    /// with no mass in `f64` its interval's middle (the choice's below).
    /// Exact: each is the formula's own rounding.
    #[test]
    fn each_distribution_maps_u_as_documented() {
        let normal = Distribution::Normal {
            mean: 10.0,
            sd: 2.0,
        };
        for u in [0.025, 0.3, 0.975] {
            assert_eq!(normal.sample(u), 10.0 + 2.0 * normal_quantile(u));
        }
        assert!((normal.sample(0.975) - (10.0 + 2.0 * 1.959_963_984_540_054)).abs() < 1e-13);
        let flat = Distribution::Uniform {
            low: 2.0,
            high: 10.0,
        };
        assert_eq!(flat.sample(0.25), 4.0);
        assert_eq!(flat.sample(0.5), 6.0);
        let empty_in_f64 = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 50.0,
            high: 60.0,
        };
        assert_eq!(empty_in_f64.sample(0.5), 55.0);
    }

    /// What a dispersion's key sets: the three initial conditions by name,
    /// any named control or aircraft parameter (checked against the model
    /// later), the script's delay; nothing else.
    #[test]
    fn dispersion_keys_name_their_targets() {
        let cases = [
            ("initial.altitude_ft", Some(Target::Initial("altitude_ft"))),
            ("initial.speed_kt", Some(Target::Initial("speed_kt"))),
            ("initial.heading_deg", Some(Target::Initial("heading_deg"))),
            (
                "controls.throttle",
                Some(Target::Control("throttle".into())),
            ),
            ("aircraft.mass_kg", Some(Target::Aircraft("mass_kg".into()))),
            ("script_delay_s", Some(Target::ScriptDelay)),
            ("initial.trim", None),
            ("controls.", None),
            ("aircraft.", None),
            ("speed_kt", None),
            ("script_delay_s.x", None),
        ];
        for (key, want) in cases {
            assert_eq!(parse_target(key), want, "{key}");
        }
        // A parameter the model does not have is refused with the model's.
        let e = error(&format!(
            "{BASE}[[dispersion]]\nkey = \"aircraft.wing_furlongs\"\n\
             distribution = \"uniform\"\nlow = 1.0\nhigh = 2.0\n"
        ));
        assert!(
            e.contains("aircraft.NAME with NAME among wing_area_m2"),
            "{e}"
        );
        assert_ne!(StudyEntry::of::<Palmer>(), StudyEntry::of::<Bourg>());
    }

    /// A distribution's numbers are refused outside their ranges: an sd of
    /// 0, an empty interval, an empty or non-finite list of values.
    #[test]
    fn distributions_refuse_degenerate_numbers() {
        let dispersion =
            |body: &str| format!("{BASE}[[dispersion]]\nkey = \"initial.speed_kt\"\n{body}\n");
        for (body, field) in [
            (
                "distribution = \"normal\"\nmean = 60.0\nsd = 0.0",
                "dispersion.sd",
            ),
            (
                "distribution = \"uniform\"\nlow = 60.0\nhigh = 60.0",
                "dispersion.high",
            ),
            (
                "distribution = \"choice\"\nvalues = []",
                "dispersion.values",
            ),
            (
                "distribution = \"choice\"\nvalues = [60.0, nan]",
                "dispersion.values",
            ),
        ] {
            let e = error(&dispersion(body));
            assert!(e.contains(field), "{body}: {e}");
        }
        for body in [
            "distribution = \"normal\"\nmean = 60.0\nsd = 1e-300",
            "distribution = \"uniform\"\nlow = 60.0\nhigh = 60.000001",
            "distribution = \"choice\"\nvalues = [60.0]",
        ] {
            assert!(Study::from_toml_str(&dispersion(body)).is_ok(), "{body}");
        }
    }

    /// A run's values: a dispersed control replaces the file's value of
    /// that control and no other; a run set up without `[initial]` starts
    /// at the model's own initial state; the script's delay shifts its
    /// rules by delay × fps frames, and a delay drawn below 0 refuses the
    /// start.
    #[test]
    fn a_runs_setup_takes_its_draws() {
        let text = format!(
            "{BASE}seed = 5\nscript = \"1-5 throttle-down\\n10-10 flaps-down\"\n\
             script_delay_s = 2.0\n[controls]\nalpha_deg = 4.0\nthrottle = 0.5\n\
             [[dispersion]]\nkey = \"controls.throttle\"\ndistribution = \"uniform\"\n\
             low = 0.6\nhigh = 0.9\n"
        );
        let study = Study::from_toml_str(&text).unwrap();
        let values = study.run_values(2);
        let drawn = 0.6 + (0.9 - 0.6) * uniform(5, 2, 0);
        assert_eq!(
            values.controls,
            [
                ("alpha_deg".to_owned(), 4.0),
                ("throttle".to_owned(), drawn)
            ]
        );
        assert_eq!(study.script_rules::<Palmer>(), 2);
        assert_eq!(
            Study::from_toml_str(BASE).unwrap().script_rules::<Palmer>(),
            0
        );
        let setup = study.setup::<Palmer>(2).unwrap();
        assert_eq!(setup.start.state, Palmer::initial_state());
        assert_eq!(setup.start.controls.throttle, drawn);
        assert_eq!(setup.start.controls.alpha_deg, 4.0);
        // 2 s at 30 frames per second: 60 frames later.
        let rules: Vec<(u64, u64)> = setup
            .script
            .rules()
            .iter()
            .map(|r| (r.first_frame, r.last_frame))
            .collect();
        assert_eq!(rules, [(61, 65), (70, 70)]);
        let mut late = values.clone();
        late.script_delay_s = -0.5;
        let e = study.setup_from::<Palmer>(&late).err().unwrap();
        assert!(e.starts_with("script_delay_s = -0.5"), "{e}");
        late.script_delay_s = 0.0;
        let setup = study.setup_from::<Palmer>(&late).unwrap();
        assert_eq!(setup.script.rules()[0].first_frame, 1);
        // Bourg, without `[initial]`: its own initial state and controls.
        let bourg = Study::from_toml_str(&BASE.replace("palmer", "bourg")).unwrap();
        let setup = bourg.setup::<Bourg>(0).unwrap();
        assert_eq!(setup.start.state, Bourg::initial_state());
        assert_eq!(setup.start.controls, Bourg::initial_controls());
    }

    #[test]
    fn the_files_go_beside_the_study_file_by_default() {
        use std::path::{Path, PathBuf};
        assert_eq!(
            Study::default_out_dir(Path::new("studies/a.toml")),
            PathBuf::from("studies")
        );
        assert_eq!(
            Study::default_out_dir(Path::new("a.toml")),
            PathBuf::from("")
        );
        assert_eq!(Study::default_out_dir(Path::new("/")), PathBuf::from("."));
    }

    #[test]
    fn errors_name_the_line_the_key_and_what_was_expected() {
        let e = error(&format!("{BASE}fps = 0\n"));
        assert!(
            e.contains("line 5") && e.contains("fps") && e.contains("1 to"),
            "{e}"
        );
        let e = error(&BASE.replace("palmer", "cessna"));
        assert!(
            e.contains("line 1") && e.contains("model") && e.contains("palmer, bourg"),
            "{e}"
        );
        let e = error(&format!("{BASE}colour = 3\n"));
        assert!(e.contains("line 5") && e.contains("colour"), "{e}");
        let e = error(&format!(
            "{BASE}[[dispersion]]\nkey = \"controls.throttle\"\ndistribution = \"normal\"\nmean = 0.5\nsd = -1.0\n"
        ));
        assert!(
            e.contains("line 5") && e.contains("dispersion.sd") && e.contains("> 0"),
            "{e}"
        );
        let e = error(&format!(
            "{BASE}[[dispersion]]\nkey = \"controls.thrust_lb\"\ndistribution = \"uniform\"\nlow = 0.0\nhigh = 1.0\n"
        ));
        assert!(e.contains("line 6") && e.contains("throttle"), "{e}");
        let e = error(&BASE.replace("max_height_m", "max_height"));
        assert!(e.contains("line 4") && e.contains("measures"), "{e}");
        let e = error(&BASE.replace("runs = 10", "runs = -1"));
        assert!(e.contains("line 2") && e.contains("runs"), "{e}");
        let e = error(&format!("{BASE}script = \"1-2 fly-away\"\n"));
        assert!(e.contains("line 5") && e.contains("script"), "{e}");
    }

    #[test]
    fn huge_numbers_in_errors_are_short() {
        // 1e308 printed plainly is 309 digits (issue 23, item 9).
        let e = error(&format!(
            "{BASE}[[dispersion]]\nkey = \"controls.throttle\"\ndistribution = \"normal\"\nmean = 0.5\nsd = -1e308\n"
        ));
        assert!(e.contains("found -1e308") && e.len() < 200, "{e}");
        let e = error(&format!("{BASE}[initial]\naltitude_ft = 1e300\n"));
        assert!(e.contains("found 1e300") && e.len() < 200, "{e}");
    }

    /// Weights whose sum overflows (each finite) drew the last value for
    /// every run: refused instead; the largest weights with a finite sum
    /// are taken, and draw every value.
    #[test]
    fn choice_weights_need_a_positive_finite_sum() {
        let choice = |weights: &str| {
            format!(
                "{BASE}[[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"choice\"\n\
                 values = [60.0, 70.0, 80.0]\nweights = {weights}\n"
            )
        };
        for weights in [
            "[1e308, 1e308, 1e308]",
            "[0.0, 0.0, 0.0]",
            "[1.0, 1.0]",
            "[1.0, -1.0, 1.0]",
        ] {
            let e = error(&choice(weights));
            assert!(
                e.contains("line 5")
                    && e.contains("dispersion.weights")
                    && e.contains("3 finite weights >= 0 with a positive, finite sum"),
                "{weights}: {e}"
            );
        }
        let study = Study::from_toml_str(&choice("[5e307, 5e307, 5e307]")).unwrap();
        let mut drawn: Vec<f64> = (0..10).map(|run| study.run_values(run).drawn[0]).collect();
        drawn.sort_by(f64::total_cmp);
        drawn.dedup();
        assert_eq!(drawn, [60.0, 70.0, 80.0]);
    }

    /// A truncated normal wholly above its mean is drawn through the lower
    /// tail: 8 to 9 standard deviations up, the draws spread over the
    /// interval in u's order (through the upper tail Φ(8) and Φ(9) are both
    /// within 6e-16 of 1: a handful of values), the mirror image of the same
    /// interval below the mean; one without mass in `f64` is refused.
    #[test]
    fn a_truncated_normal_far_in_the_tail_keeps_its_spread() {
        let up = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 8.0,
            high: 9.0,
        };
        let down = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: -9.0,
            high: -8.0,
        };
        let draws: Vec<f64> = (1..1000)
            .map(|i| up.sample(f64::from(i) / 1000.0))
            .collect();
        assert!(draws.windows(2).all(|w| w[0] < w[1]), "not increasing");
        assert!(draws.iter().all(|x| (8.0..=9.0).contains(x)));
        // Most of the mass is just above 8: the median about 8.09.
        assert!((8.05..8.15).contains(&up.sample(0.5)), "{}", up.sample(0.5));
        for i in 1..1000 {
            let u = f64::from(i) / 1000.0;
            assert_eq!(up.sample(u), -down.sample(1.0 - u), "{u}");
        }
        // An interval starting at the mean is not mirrored.
        let from_mean = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 0.0,
            high: 2.0,
        };
        let (a, b) = (normal_cdf(0.0), normal_cdf(2.0));
        assert_eq!(
            from_mean.sample(0.3).to_bits(),
            normal_quantile(a + 0.3 * (b - a)).to_bits()
        );
        // An interval containing the mean is drawn as before (no mirror).
        let around = Distribution::TruncatedNormal {
            mean: 1050.0,
            sd: 40.0,
            low: 950.0,
            high: 1114.0,
        };
        let (a, b) = (normal_cdf(-2.5), normal_cdf(1.6));
        assert_eq!(
            around.sample(0.3).to_bits(),
            (1050.0 + 40.0 * normal_quantile(a + 0.3 * (b - a))).to_bits()
        );
        let far = |low: f64, high: f64| {
            format!(
                "{BASE}[[dispersion]]\nkey = \"initial.speed_kt\"\n\
                 distribution = \"truncated_normal\"\nmean = 0.0\nsd = 1.0\n\
                 low = {low}\nhigh = {high}\n"
            )
        };
        assert!(Study::from_toml_str(&far(30.0, 31.0)).is_ok());
        assert!(Study::from_toml_str(&far(-31.0, -30.0)).is_ok());
        for (low, high) in [(50.0, 60.0), (-60.0, -50.0)] {
            let e = error(&far(low, high));
            assert!(
                e.contains("dispersion.low") && e.contains("a probability under the normal"),
                "{e}"
            );
        }
    }

    /// A uniform whose width overflows drew infinity for every run.
    #[test]
    fn a_uniform_wider_than_f64_is_refused() {
        let wide = format!(
            "{BASE}[[dispersion]]\nkey = \"initial.speed_kt\"\ndistribution = \"uniform\"\n\
             low = -1e308\nhigh = 1e308\n"
        );
        let e = error(&wide);
        assert!(
            e.contains("dispersion.high") && e.contains("high − low within"),
            "{e}"
        );
        let half = wide.replace("-1e308", "0.0");
        assert!(Study::from_toml_str(&half).is_ok());
    }

    #[test]
    fn choice_and_truncated_normal_stay_in_their_support() {
        let choice = Distribution::Choice {
            values: vec![1.0, 2.0, 3.0],
            cumulative: vec![0.25, 0.5, 1.0],
        };
        assert_eq!(choice.sample(0.1), 1.0);
        assert_eq!(choice.sample(0.3), 2.0);
        assert_eq!(choice.sample(0.999), 3.0);
        // Value i for u in [cumulative[i - 1], cumulative[i]); the last for u
        // at 1 (outside the uniforms' range), never a panic.
        assert_eq!(choice.sample(0.25), 2.0);
        assert_eq!(choice.sample(0.5), 3.0);
        assert_eq!(choice.sample(1.0), 3.0);
        let t = Distribution::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            low: 2.0,
            high: 3.0,
        };
        for i in 1..100 {
            let x = t.sample(f64::from(i) / 100.0);
            assert!((2.0..=3.0).contains(&x), "{x}");
        }
    }
}
