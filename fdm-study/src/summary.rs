//! The summary of a study's runs: counts by status and, per measure, the
//! mean with a 95 % confidence interval and percentiles (`summary.json`).

use std::fmt::Write as _;

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

use crate::table::{RunStatus, RunTable};

/// The summary of one measure over the runs where it applies.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasureSummary {
    /// Runs with a value (the measure applies and is finite).
    pub count: u64,
    /// Mean; `None` (JSON `null`) without values.
    pub mean: Option<f64>,
    /// Sample standard deviation; `None` with fewer than 2 values.
    pub sd: Option<f64>,
    /// 95 % confidence interval of the mean, `[low, high]`: mean ± 1.96 ×
    /// sd / sqrt(count) (normal approximation); `None` with fewer than 2
    /// values.
    pub ci95: Option<[f64; 2]>,
    /// Smallest value.
    pub min: Option<f64>,
    /// 1st percentile (linear interpolation between order statistics, as
    /// NumPy's default).
    pub p1: Option<f64>,
    /// 5th percentile.
    pub p5: Option<f64>,
    /// Median.
    pub p50: Option<f64>,
    /// 95th percentile.
    pub p95: Option<f64>,
    /// 99th percentile.
    pub p99: Option<f64>,
    /// Largest value.
    pub max: Option<f64>,
}

/// Why a summary covers only the first runs of its study: the study was
/// stopped before its end ([`Summary::stopped`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoppedEarly {
    /// What stopped it, as the caller names it (`sim-cli` writes the
    /// signal's name, `SIGTERM`).
    pub by: String,
    /// The study's runs (the summary's [`Summary::runs`] are the first of
    /// them, runs 0 to `runs - 1`).
    pub runs_planned: u64,
}

/// A study's summary, `summary.json`'s shape: `runs`, then for a study
/// stopped early `stopped_by`, `runs_completed` (the same number as
/// `runs`) and `runs_planned`, then `seed`, `maths` (the fingerprint of the
/// maths that flew the runs, as text `0x` and 16 hex digits), `statuses`
/// (every status code with its count) and `measures` (per measure, in the
/// study's order, a [`MeasureSummary`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Runs summarised.
    pub runs: u64,
    /// `Some` when the study was stopped before its end and the summary is
    /// of its first [`Summary::runs`] runs only.
    pub stopped: Option<StoppedEarly>,
    /// The study's master seed (0 until [`Summary::with_seed`]).
    pub seed: u64,
    /// [`fdm_core::fingerprint::maths`] of the build that summarised the
    /// runs: the same study with the same seed gives the same table only
    /// with the same maths (docs/determinism.md).
    pub maths: u64,
    /// Every status code ([`RunStatus::CODES`]) with its count.
    pub statuses: Vec<(&'static str, u64)>,
    /// Per measure, in the table's order.
    pub measures: Vec<(String, MeasureSummary)>,
}

impl Serialize for Summary {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        struct Ordered<'a, K, V>(&'a [(K, V)]);
        impl<K: Serialize, V: Serialize> Serialize for Ordered<'_, K, V> {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_map(self.0.iter().map(|(k, v)| (k, v)))
            }
        }
        let mut map = serializer.serialize_map(Some(if self.stopped.is_some() { 8 } else { 5 }))?;
        map.serialize_entry("runs", &self.runs)?;
        if let Some(stopped) = &self.stopped {
            map.serialize_entry("stopped_by", &stopped.by)?;
            map.serialize_entry("runs_completed", &self.runs)?;
            map.serialize_entry("runs_planned", &stopped.runs_planned)?;
        }
        map.serialize_entry("seed", &self.seed)?;
        // Text: a JSON number above 2^53 loses bits in many readers.
        map.serialize_entry("maths", &format!("{:#018x}", self.maths))?;
        map.serialize_entry("statuses", &Ordered(&self.statuses))?;
        map.serialize_entry("measures", &Ordered(&self.measures))?;
        map.end()
    }
}

impl Summary {
    /// The same summary with the study's seed.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The same summary marked as that of a study stopped by `by` (e.g.
    /// `SIGTERM`) after its first [`Summary::runs`] of `runs_planned` runs.
    #[must_use]
    pub fn stopped(mut self, by: impl Into<String>, runs_planned: u64) -> Self {
        self.stopped = Some(StoppedEarly {
            by: by.into(),
            runs_planned,
        });
        self
    }

    /// The summary as text for a terminal: for a study stopped early, a
    /// line saying so; then status counts, then one line per measure.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        if let Some(stopped) = &self.stopped {
            let of = match self.runs {
                0 => "no run was completed".to_owned(),
                runs => format!("the summary is of runs 0 to {} only", runs - 1),
            };
            let _ = writeln!(
                out,
                "stopped by {} after {} of {} runs: {of}",
                stopped.by, self.runs, stopped.runs_planned
            );
        }
        let _ = writeln!(out, "{} runs, seed {}", self.runs, self.seed);
        let statuses: Vec<String> = self
            .statuses
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|(code, n)| format!("{code} {n}"))
            .collect();
        let _ = writeln!(out, "status: {}", statuses.join(", "));
        let width = self
            .measures
            .iter()
            .map(|(n, _)| n.len())
            .max()
            .unwrap_or(0);
        let _ = writeln!(
            out,
            "{:width$}  {:>8} {:>12} {:>25} {:>12} {:>12} {:>12}",
            "measure", "n", "mean", "95% CI", "p5", "p50", "p95"
        );
        let f = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.4}"));
        for (name, m) in &self.measures {
            let ci = m
                .ci95
                .map_or_else(|| "-".to_owned(), |[l, h]| format!("[{l:.4}, {h:.4}]"));
            let _ = writeln!(
                out,
                "{name:width$}  {:>8} {:>12} {ci:>25} {:>12} {:>12} {:>12}",
                m.count,
                f(m.mean),
                f(m.p5),
                f(m.p50),
                f(m.p95)
            );
        }
        out
    }
}

/// Percentile `p` (0..=100) of the sorted `values` by linear interpolation
/// between the closest ranks (NumPy's default, "type 7").
fn percentile(sorted: &[f64], p: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    #[allow(clippy::cast_precision_loss)]
    let h = last as f64 * p / 100.0;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let low = (h.floor() as usize).min(last);
    let high = (low + 1).min(last);
    #[allow(clippy::cast_precision_loss)]
    let frac = h - low as f64;
    Some(sorted[low] + frac * (sorted[high] - sorted[low]))
}

/// The summary of one measure's values (the `None`s are left out).
#[must_use]
pub fn summarize_values(values: &[Option<f64>]) -> MeasureSummary {
    summarize_present(
        values
            .iter()
            .flatten()
            .copied()
            .filter(|v| v.is_finite())
            .collect(),
    )
}

/// The summary of the finite `values`, in run order.
fn summarize_present(values: Vec<f64>) -> MeasureSummary {
    let count = values.len();
    #[allow(clippy::cast_precision_loss)]
    let n = count as f64;
    // Summed in run order, before the sort.
    let mean = (count > 0).then(|| values.iter().sum::<f64>() / n);
    let sd = mean.filter(|_| count > 1).map(|m| {
        let ss: f64 = values.iter().map(|v| (v - m) * (v - m)).sum();
        fdm_core::math::sqrt(ss / (n - 1.0))
    });
    let ci95 = mean.zip(sd).map(|(m, s)| {
        let half = 1.96 * s / fdm_core::math::sqrt(n);
        [m - half, m + half]
    });
    let mut sorted = values;
    sorted.sort_by(f64::total_cmp);
    let finite = |v: Option<f64>| v.filter(|v| v.is_finite());
    MeasureSummary {
        count: count as u64,
        mean: finite(mean),
        sd: finite(sd),
        ci95: ci95.filter(|[l, h]| l.is_finite() && h.is_finite()),
        min: sorted.first().copied(),
        p1: percentile(&sorted, 1.0),
        p5: percentile(&sorted, 5.0),
        p50: percentile(&sorted, 50.0),
        p95: percentile(&sorted, 95.0),
        p99: percentile(&sorted, 99.0),
        max: sorted.last().copied(),
    }
}

/// A summary built block by block, keeping only what the summary needs:
/// the count of each status and, per measure, the values present, in run
/// order (8 bytes per value: [`SummaryBuilder::BYTES_PER_VALUE`]). Adding the
/// blocks of a study in run order gives exactly [`summarize`] of the whole
/// table.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SummaryBuilder {
    runs: u64,
    statuses: Vec<u64>,
    measures: Vec<(String, Vec<f64>)>,
}

impl SummaryBuilder {
    /// Bytes the builder keeps per measure value.
    pub const BYTES_PER_VALUE: usize = core::mem::size_of::<f64>();

    /// An empty builder.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes `table`'s rows (after those added before).
    pub fn add(&mut self, table: &RunTable) {
        if self.statuses.is_empty() {
            self.statuses = vec![0; RunStatus::CODES.len()];
        }
        if self.measures.is_empty() {
            self.measures = table
                .measures
                .iter()
                .map(|(n, _)| (n.clone(), Vec::new()))
                .collect();
        }
        self.runs += table.len() as u64;
        for status in &table.status {
            if let Some(i) = RunStatus::CODES.iter().position(|c| *c == status.code()) {
                self.statuses[i] += 1;
            }
        }
        for ((_, kept), (_, column)) in self.measures.iter_mut().zip(&table.measures) {
            kept.extend(column.iter().flatten().copied().filter(|v| v.is_finite()));
        }
    }

    /// Each measure's values kept so far (present ones, in run order): what
    /// histograms are drawn from.
    #[must_use]
    pub fn measure_values(&self) -> &[(String, Vec<f64>)] {
        &self.measures
    }

    /// The summary (seed 0 until [`Summary::with_seed`]).
    #[must_use]
    pub fn finish(self) -> Summary {
        let mut statuses = self.statuses;
        statuses.resize(RunStatus::CODES.len(), 0);
        Summary {
            runs: self.runs,
            stopped: None,
            seed: 0,
            maths: fdm_core::fingerprint::maths(),
            statuses: RunStatus::CODES.iter().copied().zip(statuses).collect(),
            measures: self
                .measures
                .into_iter()
                .map(|(name, values)| (name, summarize_present(values)))
                .collect(),
        }
    }
}

/// The summary of `table`: counts by status and each measure's statistics
/// over the runs where it applies (its `None`s are left out, never turned
/// into NaN). The seed is 0 until [`Summary::with_seed`].
///
/// ```
/// use fdm_study::{summarize, RunStatus, RunTable};
/// use fdm_core::model::FlightStatus;
///
/// let table = RunTable {
///     run: vec![0, 1, 2],
///     status: vec![RunStatus::Flown(FlightStatus::Airborne); 3],
///     frames: vec![10; 3],
///     measures: vec![("max_height_m".into(), vec![Some(1.0), None, Some(3.0)])],
///     ..RunTable::default()
/// };
/// let summary = summarize(&table);
/// assert_eq!(summary.measures[0].1.count, 2);
/// assert_eq!(summary.measures[0].1.mean, Some(2.0));
/// assert_eq!(summary.measures[0].1.p50, Some(2.0));
/// ```
#[must_use]
pub fn summarize(table: &RunTable) -> Summary {
    let mut builder = SummaryBuilder::new();
    builder.add(table);
    if table.is_empty() && builder.measures.is_empty() {
        builder.measures = table
            .measures
            .iter()
            .map(|(n, _)| (n.clone(), Vec::new()))
            .collect();
    }
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::model::{FlightStatus, LandingState};

    /// Percentiles as NumPy's `percentile(..., method="linear")` gives them
    /// for 1..=10 (hand-computed: h = 9p/100): exact to 1e-12.
    #[test]
    fn percentiles_interpolate_linearly() {
        let values: Vec<Option<f64>> = (1..=10).map(|v| Some(f64::from(v))).collect();
        let s = summarize_values(&values);
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-12;
        assert!(close(s.p1, 1.09));
        assert!(close(s.p5, 1.45));
        assert!(close(s.p50, 5.5));
        assert!(close(s.p95, 9.55));
        assert!(close(s.p99, 9.91));
        assert!(close(s.mean, 5.5));
        // sd of 1..=10 is sqrt(55/6).
        assert!(close(s.sd, (55.0f64 / 6.0).sqrt()));
    }

    /// The same for values unevenly spaced and out of order (the squares
    /// 1..=100 shuffled, with a missing and a non-finite value left out),
    /// so that the interpolation's `frac · (high − low)` and the sort show:
    /// h = 9p/100 between the sorted squares, worked by hand. The mean is
    /// 385/10; the sample sd is √((Σi⁴ − 10·38.5²)/9) = √(10510.5/9),
    /// worked by the other formula than the summary's Σ(v − mean)²; the
    /// interval mean ± 1.96·sd/√10. Within 1e-12 (a few roundings of
    /// numbers below 100).
    #[test]
    fn statistics_of_unevenly_spaced_values_in_run_order() {
        let mut values: Vec<Option<f64>> = [49, 1, 100, 16, 81, 4, 64, 9, 36, 25]
            .iter()
            .map(|&v| Some(f64::from(v)))
            .collect();
        values.insert(3, None);
        values.insert(7, Some(f64::NAN));
        let s = summarize_values(&values);
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-12;
        assert_eq!(s.count, 10);
        assert_eq!((s.min, s.max), (Some(1.0), Some(100.0)));
        assert!(close(s.p1, 1.0 + 0.09 * 3.0), "{:?}", s.p1);
        assert!(close(s.p5, 1.0 + 0.45 * 3.0), "{:?}", s.p5);
        assert!(close(s.p50, 25.0 + 0.5 * 11.0), "{:?}", s.p50);
        assert!(close(s.p95, 81.0 + 0.55 * 19.0), "{:?}", s.p95);
        assert!(close(s.p99, 81.0 + 0.91 * 19.0), "{:?}", s.p99);
        assert!(close(s.mean, 38.5));
        let sd = (10_510.5f64 / 9.0).sqrt();
        assert!(close(s.sd, sd), "{:?} against {sd}", s.sd);
        let half = 1.96 * sd / 10f64.sqrt();
        let [low, high] = s.ci95.unwrap();
        assert!(close(Some(low), 38.5 - half) && close(Some(high), 38.5 + half));
        // Values far from 0 and close together, whose mean 1e9 + 2/3 is
        // rounded (by up to 6e-8): the squared deviations from the rounded
        // mean give the sd √(1/3) to about 1e-14, where Σ(v² − mean²)
        // (mathematically the same sum) adds 2·mean·Σ(v − mean), about 2e9
        // times the mean's rounding, and loses every digit.
        let offset = summarize_values(&[Some(1e9), Some(1e9 + 1.0), Some(1e9 + 1.0)]);
        let sd = offset.sd.unwrap();
        assert!((sd - (1.0f64 / 3.0).sqrt()).abs() < 1e-12, "{sd}");
        // One value: a mean, its percentiles, no sd nor interval.
        let one = summarize_values(&[Some(2.5)]);
        assert_eq!(
            (one.count, one.mean, one.p1, one.p99),
            (1, Some(2.5), Some(2.5), Some(2.5))
        );
        assert_eq!((one.sd, one.ci95), (None, None));
    }

    /// A table of the statuses and measures below, in two blocks or whole.
    fn table(runs: std::ops::Range<u64>) -> RunTable {
        let status = |run: u64| match run % 3 {
            0 => RunStatus::Flown(FlightStatus::Airborne),
            1 => RunStatus::Flown(FlightStatus::Landed(LandingState::Safe)),
            _ => RunStatus::StartRefused,
        };
        RunTable {
            run: runs.clone().collect(),
            status: runs.clone().map(status).collect(),
            frames: runs.clone().map(|_| 10).collect(),
            measures: vec![(
                "max_height_m".into(),
                runs.map(|r| (r % 3 != 2).then_some(r as f64)).collect(),
            )],
            ..RunTable::default()
        }
    }

    /// The builder counts each status and keeps the present values in run
    /// order, and two blocks added in order are the whole table's summary.
    #[test]
    fn the_builder_counts_statuses_and_blocks_make_the_whole() {
        let mut builder = SummaryBuilder::new();
        builder.add(&table(0..4));
        builder.add(&table(4..7));
        assert_eq!(
            builder.measure_values(),
            &[("max_height_m".to_owned(), vec![0.0, 1.0, 3.0, 4.0, 6.0])]
        );
        let summary = builder.finish();
        assert_eq!(summary, summarize(&table(0..7)));
        assert_eq!(summary.runs, 7);
        let count = |code: &str| summary.statuses.iter().find(|(c, _)| *c == code).unwrap().1;
        assert_eq!(count("airborne"), 3);
        assert_eq!(count("landed_safe"), 2);
        assert_eq!(count("start_refused"), 2);
        assert_eq!(count("crashed"), 0);
        assert_eq!(summary.statuses.len(), RunStatus::CODES.len());
        assert_eq!(summary.measures[0].1.count, 5);
        // An empty table keeps its measures' names, with nothing in them.
        let empty = summarize(&RunTable::empty(&[crate::Measure::MaxBankDeg]));
        assert_eq!(empty.measures.len(), 1);
        assert_eq!(empty.measures[0].0, "max_bank_deg");
        assert_eq!(empty.measures[0].1.count, 0);
    }

    /// The terminal text: the statuses that occur (not those at 0), then a
    /// line per measure with its count, mean, interval and percentiles.
    #[test]
    fn the_text_lists_the_statuses_that_occur_and_each_measure() {
        let text = summarize(&table(0..7)).with_seed(42).to_text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "7 runs, seed 42");
        assert_eq!(
            lines[1],
            "status: airborne 3, landed_safe 2, start_refused 2"
        );
        assert!(lines[2].starts_with("measure"), "{text}");
        let cells: Vec<&str> = lines[3].split_whitespace().collect();
        // 0, 1, 3, 4, 6: mean 2.8, p50 3.
        assert_eq!(&cells[..3], ["max_height_m", "5", "2.8000"], "{text}");
        assert_eq!(cells[6], "3.0000", "{text}");
        assert_eq!(lines.len(), 4, "{text}");
    }

    /// A stopped study's summary says so, in JSON right after `runs` and
    /// first in the text; an unstopped one has none of those fields.
    #[test]
    fn a_stopped_summary_says_so() {
        let table = RunTable {
            run: vec![0, 1],
            status: vec![RunStatus::StartRefused; 2],
            frames: vec![0; 2],
            measures: vec![("max_height_m".into(), vec![None, None])],
            ..RunTable::default()
        };
        let whole = summarize(&table);
        let json = serde_json::to_string(&whole).unwrap();
        assert!(!json.contains("stopped"), "{json}");
        let stopped = summarize(&table).stopped("SIGINT", 7);
        let json = serde_json::to_string(&stopped).unwrap();
        assert!(
            json.starts_with(
                r#"{"runs":2,"stopped_by":"SIGINT","runs_completed":2,"runs_planned":7,"seed":0,"#
            ),
            "{json}"
        );
        assert!(stopped.to_text().starts_with(
            "stopped by SIGINT after 2 of 7 runs: the summary is of runs 0 to 1 only\n2 runs, seed 0\n"
        ));
        let none = summarize(&RunTable::empty(&[])).stopped("SIGTERM", 7);
        assert!(none
            .to_text()
            .starts_with("stopped by SIGTERM after 0 of 7 runs: no run was completed\n"));
    }

    #[test]
    fn no_values_give_nulls_not_nan() {
        let s = summarize_values(&[None, None]);
        assert_eq!(s.count, 0);
        assert_eq!(s.mean, None);
        let json = serde_json::to_string(&s).unwrap();
        assert!(
            !json.contains("NaN") && json.contains("\"mean\":null"),
            "{json}"
        );
    }
}
