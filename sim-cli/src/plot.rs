//! Plots of a flight: `--plot FILE.svg` on any `sim-cli palmer|bourg` run
//! (headless or interactive, with or without `--script`) and
//! `sim-cli plot FILE.csv -o FILE.svg` for a CSV written earlier with `--csv`.
//!
//! One SVG with six panels against simulated time or position: height above
//! the ground plane (ft), airspeed (kt), roll and pitch (deg), heading (deg),
//! the flight status, and the ground track (north against east, m). Drawn with
//! `plotters`' SVG backend only, so no font or bitmap system library is needed
//! (text is left to the SVG viewer's fonts).
//!
//! A run's samples are collected by `run::plotted::Plotted`, a `Flight` wrapper that
//! records one [`PlotSample`] for the initial state, after every step and
//! after every reset; the run loops do not know about it. A CSV gives the same
//! samples ([`trace_from_csv`]); the status, which the CSV does not hold, is
//! recomputed row by row with [`FlightStatus::update`] from the height and the
//! climb rate exactly as the simulation computes it.
//!
//! After a reset (interactive R key, or a CSV row whose time goes back) the
//! model's clock starts again at 0; the plot's time axis does not: it is the
//! simulated time elapsed since the start of the run, so each segment is drawn
//! after the previous one (its own line, a grey vertical line at the reset)
//! instead of over it.
//!
//! Any run plots in a small SVG. The samples are kept in bounded memory
//! ([`TraceBuilder`]: past [`KEEP_SAMPLES`], they are thinned to the first,
//! last, lowest and highest sample of every quantity in each of
//! [`KEEP_COLUMNS`] time columns), and each curve is drawn from the first,
//! last, lowest and highest of its points in each of [`DRAW_COLUMNS`] columns
//! (about two per pixel), which draws the same picture as every point would.
//! A two-hour run at 100 fps gives an SVG of a few hundred kilobytes; the CSV
//! keeps every sample.

use std::fs::File;
use std::io::{BufRead, Read as _, Write};
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use fdm_core::model::FlightStatus;
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::CliError;
use crate::hud::status_label;
use crate::input::Echo;
use crate::models::{CliModel, Details, ModelKind, WithModel};
use crate::snapshot::Snapshot;

/// The plotted quantities at one instant, in SI units (converted for display
/// when drawn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotSample {
    /// Simulated time, s.
    pub time_s: f64,
    /// Height above the ground plane through the origin, m.
    pub height_m: f64,
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
    /// Roll as sent to FlightGear, degrees, right wing down positive.
    pub roll_deg: f64,
    /// Pitch as sent to FlightGear, degrees, nose up positive.
    pub pitch_deg: f64,
    /// Heading as sent to FlightGear, degrees clockwise from north.
    pub heading_deg: f64,
    /// Distance north of the origin, m.
    pub north_m: f64,
    /// Distance east of the origin, m.
    pub east_m: f64,
    /// Flight status.
    pub status: FlightStatus,
    /// Whether the model reports a stall.
    pub stalling: bool,
    /// The first sample after a reset (it starts a new segment).
    pub reset: bool,
}

impl PlotSample {
    /// The sample of a snapshot.
    #[must_use]
    pub fn from_snapshot<D: Details>(s: &Snapshot<D>) -> Self {
        let scale = Snapshot::<D>::metres_per_unit();
        let c = &s.common;
        Self {
            time_s: c.time_s,
            height_m: s.height_m(),
            airspeed_mps: s.airspeed_mps,
            roll_deg: c.attitude_deg.roll,
            pitch_deg: c.attitude_deg.pitch,
            heading_deg: c.attitude_deg.heading,
            north_m: c.position[0] * scale,
            east_m: -c.position[1] * scale,
            status: s.status,
            stalling: s.stalling,
            reset: false,
        }
    }

    /// The values thinning keeps the extremes of: every drawn quantity.
    fn extremes_of(&self) -> [f64; 8] {
        [
            self.height_m,
            self.airspeed_mps,
            self.roll_deg,
            self.pitch_deg,
            self.heading_deg,
            f64::from(status_level(self)),
            self.north_m,
            self.east_m,
        ]
    }
}

/// A flight to plot: a title and its samples in order, their `time_s` the
/// simulated time elapsed since the start (continuing across resets).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    /// Shown above the panels.
    pub title: String,
    /// The samples kept, in the order they were taken.
    pub samples: Vec<PlotSample>,
    /// How many samples the flight gave (at least `samples.len()`).
    pub total_samples: u64,
}

/// Samples a [`TraceBuilder`] holds before it thins them: 262,144 (about
/// 25 MB), more than two hours at 30 fps unthinned.
pub const KEEP_SAMPLES: usize = 1 << 18;

/// Time columns a [`TraceBuilder`] thins to: several per pixel of a panel.
pub const KEEP_COLUMNS: usize = 4096;

/// Columns each curve is drawn with: about two per pixel of a panel.
pub const DRAW_COLUMNS: usize = 1200;

/// Collects a flight's samples in bounded memory (see the module docs): the
/// model's clock going back is a reset, after which the time axis continues.
#[derive(Debug, Clone)]
pub struct TraceBuilder {
    trace: Trace,
    /// Added to the model's clock: the elapsed time at the last reset minus
    /// the clock there.
    offset_s: f64,
    /// The model's clock at the last sample.
    last_clock_s: Option<f64>,
}

impl TraceBuilder {
    /// An empty trace titled `title`.
    #[must_use]
    pub fn new(title: String) -> Self {
        Self {
            trace: Trace {
                title,
                samples: Vec::new(),
                total_samples: 0,
            },
            offset_s: 0.0,
            last_clock_s: None,
        }
    }

    /// Adds `sample`, whose `time_s` is the model's clock (it restarts at a
    /// reset); a sample whose clock is behind the previous one starts a new
    /// segment.
    pub fn push(&mut self, mut sample: PlotSample) {
        let clock_s = sample.time_s;
        if let (Some(last_clock_s), Some(last)) = (self.last_clock_s, self.trace.samples.last()) {
            if clock_s < last_clock_s {
                self.offset_s = last.time_s - clock_s;
                sample.reset = true;
            }
        }
        self.last_clock_s = Some(clock_s);
        sample.time_s = clock_s + self.offset_s;
        self.trace.samples.push(sample);
        self.trace.total_samples += 1;
        if self.trace.samples.len() > KEEP_SAMPLES {
            self.trace.samples = thin_samples(&self.trace.samples, KEEP_COLUMNS);
        }
    }

    /// The trace so far.
    #[must_use]
    pub fn trace(&self) -> &Trace {
        &self.trace
    }

    /// The finished trace.
    #[must_use]
    pub fn finish(self) -> Trace {
        self.trace
    }
}

/// Which column of `columns` over `start..=end` the time `t` falls in.
fn column_of(t: f64, start: f64, end: f64, columns: usize) -> usize {
    if end <= start || !t.is_finite() {
        return 0;
    }
    // In 0..=columns-1; the float-to-int cast saturates.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let column = ((t - start) / (end - start) * columns as f64) as usize;
    column.min(columns - 1)
}

/// The samples that keep the picture: in each of `columns` time columns the
/// first and last sample and the lowest and highest of every quantity, and
/// both samples around each reset, in their order.
fn thin_samples(samples: &[PlotSample], columns: usize) -> Vec<PlotSample> {
    let (Some(first), Some(last)) = (samples.first(), samples.last()) else {
        return Vec::new();
    };
    let (start, end) = (first.time_s, last.time_s);
    let mut keep = vec![false; samples.len()];
    let mut i = 0;
    while i < samples.len() {
        let column = column_of(samples[i].time_s, start, end, columns);
        let mut j = i;
        let mut low = [i; 8];
        let mut high = [i; 8];
        while j < samples.len() && column_of(samples[j].time_s, start, end, columns) == column {
            let values = samples[j].extremes_of();
            for q in 0..8 {
                if values[q] < samples[low[q]].extremes_of()[q] {
                    low[q] = j;
                }
                if values[q] > samples[high[q]].extremes_of()[q] {
                    high[q] = j;
                }
            }
            if samples[j].reset {
                keep[j] = true;
                keep[j.saturating_sub(1)] = true;
            }
            j += 1;
        }
        keep[i] = true;
        keep[j - 1] = true;
        for q in 0..8 {
            keep[low[q]] = true;
            keep[high[q]] = true;
        }
        i = j;
    }
    samples
        .iter()
        .zip(keep)
        .filter_map(|(s, k)| k.then_some(*s))
        .collect()
}

/// The points of one curve that draw it as all its points would at
/// `columns` columns over `x`: in each column the first, last, lowest and
/// highest point (by `y`), in their order.
fn thin_curve(points: &[(f64, f64)], x: &std::ops::Range<f64>, columns: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(points.len().min(columns * 4));
    let mut i = 0;
    while i < points.len() {
        let column = column_of(points[i].0, x.start, x.end, columns);
        let mut j = i;
        let (mut low, mut high) = (i, i);
        while j < points.len() && column_of(points[j].0, x.start, x.end, columns) == column {
            if points[j].1 < points[low].1 {
                low = j;
            }
            if points[j].1 > points[high].1 {
                high = j;
            }
            j += 1;
        }
        let mut picked = [i, low, high, j - 1];
        picked.sort_unstable();
        let mut previous = None;
        for k in picked {
            if previous != Some(k) {
                out.push(points[k]);
                previous = Some(k);
            }
        }
        i = j;
    }
    out
}

/// The `--plot` output file, created before the run so that an unwritable path
/// is a usage error (exit status 2) and nothing has been simulated.
#[derive(Debug)]
pub struct PlotFile {
    path: PathBuf,
    file: File,
}

impl PlotFile {
    /// Creates (truncates) `path`.
    ///
    /// # Errors
    /// [`CliError::Usage`] naming the path and the OS reason.
    pub fn create(path: &Path) -> Result<Self, CliError> {
        let file = crate::outfile::create_locked(path).map_err(|e| {
            CliError::usage(format!("cannot create plot file {}: {e}", path.display()))
        })?;
        Ok(Self {
            path: path.to_owned(),
            file,
        })
    }

    /// Draws `trace` and writes the SVG.
    ///
    /// # Errors
    /// [`CliError::Runtime`] if drawing or writing fails.
    pub fn write(mut self, trace: &Trace) -> Result<(), CliError> {
        let svg = render_svg(trace)?;
        self.file
            .write_all(svg.as_bytes())
            .and_then(|()| self.file.flush())
            .with_context(|| format!("writing plot file {}", self.path.display()))?;
        Ok(())
    }
}

/// The status levels of the status panel, bottom to top.
const STATUS_LEVELS: [&str; 6] = [
    "on ground",
    "flying",
    "STALL",
    "landed (safe)",
    "landed (rough)",
    "CRASHED",
];

fn status_level(sample: &PlotSample) -> i32 {
    let label = status_label(sample.status, sample.stalling);
    STATUS_LEVELS
        .iter()
        .position(|&l| l == label)
        .and_then(|i| i32::try_from(i).ok())
        .unwrap_or(0)
}

/// Splits `samples` at each reset.
fn segments(samples: &[PlotSample]) -> Vec<&[PlotSample]> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..samples.len() {
        if samples[i].reset {
            out.push(&samples[start..i]);
            start = i;
        }
    }
    if start < samples.len() {
        out.push(&samples[start..]);
    }
    out
}

/// The heading series of a segment made continuous: a step of more than
/// 180° is taken as a pass through north, so a turn through 360° climbs past 360
/// instead of jumping back to 0 (and a heading dithering around north stays near 0).
fn unwrapped_headings(samples: &[PlotSample]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(samples.len());
    let mut offset = 0.0;
    let mut previous: Option<f64> = None;
    for s in samples {
        if let Some(p) = previous {
            let step = s.heading_deg - p;
            if step > 180.0 {
                offset -= 360.0;
            } else if step < -180.0 {
                offset += 360.0;
            }
        }
        if s.heading_deg.is_finite() {
            previous = Some(s.heading_deg);
        }
        out.push((s.time_s, s.heading_deg + offset));
    }
    out
}

/// [`padded_range`] at least `min_span` wide (centred), so that numerical
/// noise around a constant (a heading dithering by 0.001°) is not magnified
/// to fill the panel.
fn range_at_least(values: impl Iterator<Item = f64>, min_span: f64) -> std::ops::Range<f64> {
    let r = padded_range(values);
    if r.end - r.start >= min_span {
        return r;
    }
    let mid = (r.start + r.end) / 2.0;
    (mid - min_span / 2.0)..(mid + min_span / 2.0)
}

/// `lo..hi` of the finite values, padded by 5 % (or ±1 around a constant).
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let pad = if hi - lo > 0.0 { (hi - lo) * 0.05 } else { 1.0 };
    (lo - pad)..(hi + pad)
}

fn draw_error(e: impl std::fmt::Display) -> CliError {
    CliError::runtime(format!("drawing the plot: {e}"))
}

/// A chart of the ground, metres east and north of the origin, with its axes
/// drawn: the flight's ground track and a study's touchdown points share it.
/// `caption` is the title and its font size in pixels.
pub(crate) fn east_north_chart<'area, 'svg>(
    area: &'area DrawingArea<SVGBackend<'svg>, Shift>,
    (caption, caption_px): (&str, u32),
    east_m: std::ops::Range<f64>,
    north_m: std::ops::Range<f64>,
) -> Result<
    ChartContext<'area, SVGBackend<'svg>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    String,
> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", caption_px))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(70)
        .build_cartesian_2d(east_m, north_m)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("east of origin (m)")
        .y_desc("north of origin (m)")
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

/// A thin grey vertical line at each reset, from `y.start` to `y.end`.
fn draw_resets<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    samples: &[PlotSample],
    y: &std::ops::Range<f64>,
) -> Result<(), CliError> {
    let resets = samples.iter().filter(|s| s.reset).map(|s| {
        PathElement::new(
            vec![(s.time_s, y.start), (s.time_s, y.end)],
            RGBColor(150, 150, 150).stroke_width(1),
        )
    });
    chart.draw_series(resets).map_err(draw_error)?;
    Ok(())
}

/// One time-series panel: `series` are (legend, colour, value of a sample).
type Series<'a> = (&'a str, RGBColor, fn(&PlotSample) -> f64);

/// A panel of `series` against time; the y axis spans at least `min_span`.
fn time_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    trace: &Trace,
    (caption, y_desc, min_span): (&str, &str, f64),
    series: &[Series<'_>],
) -> Result<(), CliError> {
    let samples = &trace.samples;
    let x = padded_range(samples.iter().map(|s| s.time_s));
    let values = series.iter().flat_map(|(_, _, f)| samples.iter().map(*f));
    let mut y = range_at_least(values, min_span);
    if series.len() > 1 {
        // Headroom for the legend in the upper right corner.
        y.end += (y.end - y.start) * 0.3;
    }
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(x.clone(), y.clone())
        .map_err(draw_error)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(y_desc)
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(draw_error)?;
    draw_resets(&mut chart, samples, &y)?;
    for &(label, colour, value) in series {
        for (i, segment) in segments(samples).into_iter().enumerate() {
            let points: Vec<(f64, f64)> = segment.iter().map(|s| (s.time_s, value(s))).collect();
            let drawn = chart
                .draw_series(LineSeries::new(
                    thin_curve(&points, &x, DRAW_COLUMNS),
                    colour.stroke_width(2),
                ))
                .map_err(draw_error)?;
            if i == 0 && series.len() > 1 {
                drawn.label(label).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            }
        }
    }
    if series.len() > 1 {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(draw_error)?;
    }
    Ok(())
}

fn heading_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, trace: &Trace) -> Result<(), CliError> {
    let samples = &trace.samples;
    let runs: Vec<Vec<(f64, f64)>> = segments(samples)
        .into_iter()
        .map(unwrapped_headings)
        .collect();
    let x = padded_range(samples.iter().map(|s| s.time_s));
    let y = range_at_least(runs.iter().flatten().map(|&(_, h)| h), 10.0);
    let mut chart = ChartBuilder::on(area)
        .caption("Heading", ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(x.clone(), y.clone())
        .map_err(draw_error)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("heading (deg true, unwrapped)")
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(draw_error)?;
    draw_resets(&mut chart, samples, &y)?;
    for run in runs {
        chart
            .draw_series(LineSeries::new(
                thin_curve(&run, &x, DRAW_COLUMNS),
                MAGENTA.stroke_width(2),
            ))
            .map_err(draw_error)?;
    }
    Ok(())
}

fn status_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, trace: &Trace) -> Result<(), CliError> {
    let samples = &trace.samples;
    let x = padded_range(samples.iter().map(|s| s.time_s));
    let top = i32::try_from(STATUS_LEVELS.len()).unwrap_or(6);
    let mut chart = ChartBuilder::on(area)
        .caption("Status", ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(110)
        .build_cartesian_2d(x.clone(), -1..top)
        .map_err(draw_error)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_labels(STATUS_LEVELS.len() + 1)
        .y_label_formatter(&|&level| {
            usize::try_from(level)
                .ok()
                .and_then(|i| STATUS_LEVELS.get(i))
                .map_or_else(String::new, |&l| l.to_owned())
        })
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(draw_error)?;
    for segment in segments(samples) {
        let levels: Vec<(f64, f64)> = segment
            .iter()
            .map(|s| (s.time_s, f64::from(status_level(s))))
            .collect();
        let levels = thin_curve(&levels, &x, DRAW_COLUMNS);
        // A step line: each status holds until the next sample.
        let mut points = Vec::with_capacity(levels.len() * 2);
        for (i, &(t, level)) in levels.iter().enumerate() {
            // Levels are small whole numbers (status_level), so the casts are exact.
            #[allow(clippy::cast_possible_truncation)]
            let level = level as i32;
            if i > 0 {
                #[allow(clippy::cast_possible_truncation)]
                let previous = levels[i - 1].1 as i32;
                points.push((t, previous));
            }
            points.push((t, level));
        }
        chart
            .draw_series(LineSeries::new(points, BLACK.stroke_width(2)))
            .map_err(draw_error)?;
    }
    Ok(())
}

fn track_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, trace: &Trace) -> Result<(), CliError> {
    let samples = &trace.samples;
    let mut east = padded_range(samples.iter().map(|s| s.east_m));
    let mut north = padded_range(samples.iter().map(|s| s.north_m));
    // Same scale on both axes (the panel is about as wide as high), so turns look round.
    let span = (east.end - east.start).max(north.end - north.start);
    let widen = |r: &mut std::ops::Range<f64>| {
        let mid = (r.start + r.end) / 2.0;
        *r = (mid - span / 2.0)..(mid + span / 2.0);
    };
    widen(&mut east);
    widen(&mut north);
    // Room above the track for the legend (upper left), the scales kept equal:
    // 30 % more height, and as much more width shared by both sides.
    let room = span * 0.3;
    north.end += room;
    east.start -= room / 2.0;
    east.end += room / 2.0;
    let mut chart =
        east_north_chart(area, ("Ground track", 18), east, north).map_err(draw_error)?;
    let time = padded_range(samples.iter().map(|s| s.time_s));
    for (i, segment) in segments(samples).into_iter().enumerate() {
        // Thinned in time, keeping each column's extremes north and east.
        let by_east: Vec<(f64, f64)> = segment.iter().map(|s| (s.time_s, s.east_m)).collect();
        let by_north: Vec<(f64, f64)> = segment.iter().map(|s| (s.time_s, s.north_m)).collect();
        let mut kept: Vec<f64> = thin_curve(&by_east, &time, DRAW_COLUMNS)
            .into_iter()
            .chain(thin_curve(&by_north, &time, DRAW_COLUMNS))
            .map(|(t, _)| t)
            .collect();
        kept.sort_by(f64::total_cmp);
        kept.dedup();
        let mut next = kept.iter().peekable();
        let points: Vec<(f64, f64)> = segment
            .iter()
            .filter(|s| {
                if next.peek().is_some_and(|&&t| t == s.time_s) {
                    next.next();
                    true
                } else {
                    false
                }
            })
            .map(|s| (s.east_m, s.north_m))
            .collect();
        let drawn = chart
            .draw_series(LineSeries::new(points, BLUE.stroke_width(2)))
            .map_err(draw_error)?;
        if i == 0 {
            drawn
                .label("track")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
        }
    }
    if let Some(first) = samples.first() {
        chart
            .draw_series(std::iter::once(Circle::new(
                (first.east_m, first.north_m),
                5,
                GREEN.filled(),
            )))
            .map_err(draw_error)?
            .label("start")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, GREEN.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(draw_error)?;
    Ok(())
}

/// Width and height of the SVG, pixels.
pub const SVG_SIZE: (u32, u32) = (1200, 1260);

/// Draws `trace` as one SVG document.
///
/// # Errors
/// [`CliError::Runtime`] if there is nothing to plot or drawing fails.
pub fn render_svg(trace: &Trace) -> Result<String, CliError> {
    if trace.samples.is_empty() {
        return Err(CliError::runtime("nothing to plot: no samples"));
    }
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SVG_SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        let times = trace.samples.iter().map(|s| s.time_s);
        let first = times.clone().fold(f64::INFINITY, f64::min);
        let last = times.fold(f64::NEG_INFINITY, f64::max);
        let resets = match segments(&trace.samples).len().saturating_sub(1) {
            0 => String::new(),
            1 => ", 1 reset".to_owned(),
            n => format!(", {n} resets"),
        };
        let title = format!(
            "{}: {} samples, t = {first:.2} to {last:.2} s{resets}",
            trace.title,
            trace.total_samples.max(trace.samples.len() as u64)
        );
        let root = root
            .titled(&title, ("sans-serif", 24))
            .map_err(draw_error)?;
        let panels = root.split_evenly((3, 2));
        time_panel(
            &panels[0],
            trace,
            ("Height above the ground plane", "height (ft)", 10.0),
            &[("height (ft)", RED, |s| s.height_m / METRES_PER_FOOT)],
        )?;
        time_panel(
            &panels[1],
            trace,
            ("Airspeed", "airspeed (kt)", 2.0),
            &[("airspeed (kt)", BLUE, |s| s.airspeed_mps * KNOTS_PER_MPS)],
        )?;
        time_panel(
            &panels[2],
            trace,
            ("Attitude", "angle (deg)", 10.0),
            &[
                ("roll (deg, right wing down +)", RED, |s| s.roll_deg),
                ("pitch (deg, nose up +)", BLUE, |s| s.pitch_deg),
            ],
        )?;
        heading_panel(&panels[3], trace)?;
        status_panel(&panels[4], trace)?;
        track_panel(&panels[5], trace)?;
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}

/// Columns `trace_from_csv` reads, besides the model's speed column.
const CSV_NEEDED: [&str; 8] = [
    "frame",
    "time_s",
    "x",
    "y",
    "z",
    "vz",
    "roll_deg",
    "pitch_deg",
];

/// Largest CSV `sim-cli plot` reads: 8 GiB, some 25 million rows (a day at
/// 300 fps). Memory stays bounded whatever the size ([`TraceBuilder`]).
pub const MAX_CSV_BYTES: u64 = 8 << 30;

/// Longest CSV line accepted: 64 KiB (a row of `--csv` is a few hundred bytes).
pub const MAX_CSV_LINE_BYTES: u64 = 64 * 1024;

/// A CSV read back by [`trace_from_csv`].
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTrace {
    /// The flight, ready to draw.
    pub trace: Trace,
    /// Set when the last row was torn (the file does not end with a newline,
    /// as when the writing run was killed mid-row): what was left out.
    pub torn_last_row: Option<String>,
}

/// Reads one line of at most [`MAX_CSV_LINE_BYTES`] into `line` (cleared
/// first); `Ok(false)` at the end of the input. The newline is kept.
fn read_csv_line(
    reader: &mut impl BufRead,
    line: &mut Vec<u8>,
    name: &str,
    line_no: usize,
    read_total: &mut u64,
) -> Result<bool, CliError> {
    line.clear();
    let n = reader
        .by_ref()
        .take(MAX_CSV_LINE_BYTES + 1)
        .read_until(b'\n', line)
        .map_err(|e| CliError::usage(format!("cannot read {name}: {e}")))?;
    if u64::try_from(line.len()).unwrap_or(u64::MAX) > MAX_CSV_LINE_BYTES {
        return Err(CliError::usage(format!(
            "{name}:{line_no}: a line longer than {} KiB: not a CSV written by sim-cli --csv",
            MAX_CSV_LINE_BYTES / 1024
        )));
    }
    *read_total += u64::try_from(n).unwrap_or(u64::MAX);
    if *read_total > MAX_CSV_BYTES {
        return Err(CliError::usage(format!(
            "{name} is larger than the {} GiB limit",
            MAX_CSV_BYTES >> 30
        )));
    }
    Ok(n > 0)
}

/// What [`trace_from_csv`] knows of a model's CSV, from the model registry.
struct CsvModel {
    /// The model's title ([`fdm_core::model::Model::TITLE`]).
    title: &'static str,
    /// Its name as the error message shows it: `Palmer`, `Bourg`.
    shown: String,
    /// The columns its `--csv` files have after `frame,time_s`.
    columns: Vec<&'static str>,
    /// [`Details::CSV_SPEED_COLUMN`].
    speed_column: &'static str,
    /// [`Details::METRES_PER_UNIT`].
    metres_per_unit: f64,
}

struct DescribeCsv;

impl WithModel for DescribeCsv {
    type Output = CsvModel;
    fn call<M: CliModel>(self) -> CsvModel {
        let name = <M::Details as Details>::MODEL;
        let mut shown = name[..1].to_ascii_uppercase();
        shown.push_str(&name[1..]);
        CsvModel {
            title: M::TITLE,
            shown,
            columns: crate::snapshot::csv_columns::<M::Details>(),
            speed_column: <M::Details as Details>::CSV_SPEED_COLUMN,
            metres_per_unit: <M::Details as Details>::METRES_PER_UNIT,
        }
    }
}

/// The model that wrote a CSV with this `header`, and its speed column's
/// index: the registered model whose `--csv` header it is, or for older and
/// hand-made files the first (in registry order) whose speed column it has.
fn csv_model(header: &[String]) -> Result<(CsvModel, usize), String> {
    let models: Vec<CsvModel> = <ModelKind as clap::ValueEnum>::value_variants()
        .iter()
        .map(|kind| kind.with(DescribeCsv))
        .collect();
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let written_by = |m: &CsvModel| header.len() == m.columns.len() + 2 && header[2..] == m.columns;
    let message = models
        .iter()
        .map(|m| format!("`{}` ({})", m.speed_column, m.shown))
        .collect::<Vec<_>>()
        .join(" or ");
    let found = match models.iter().position(written_by) {
        Some(i) => Some(i),
        None => models.iter().position(|m| column(m.speed_column).is_some()),
    };
    let model = found
        .and_then(|i| models.into_iter().nth(i))
        .ok_or_else(|| format!("no {message} column: not a CSV written by sim-cli --csv"))?;
    let speed = column(model.speed_column).ok_or_else(|| {
        format!(
            "no `{}` column: not a CSV written by sim-cli --csv",
            model.speed_column
        )
    })?;
    Ok((model, speed))
}

/// Reads a CSV written by `--csv` back into a [`Trace`] titled `<model> from <name>`,
/// line by line in bounded memory ([`TraceBuilder`], [`MAX_CSV_LINE_BYTES`],
/// [`MAX_CSV_BYTES`]).
///
/// The model is the registry's whose `--csv` header the file has; in older
/// or hand-made files, the first whose speed column it has
/// ([`Details::CSV_SPEED_COLUMN`]: Palmer's `airspeed` in m/s with positions
/// in metres, Bourg's `speed` in ft/s with positions in feet). The status
/// is the `status` column when there is one
/// ([`crate::snapshot::status_from_number`]); in older files without it, it is
/// recomputed from the rows: [`FlightStatus::initial`] at every frame 0 and
/// [`FlightStatus::update`] after every other row, from the height and the climb
/// rate in metres, as the simulation did before the ground contact; Bourg's
/// `stalling` column gives the stall.
///
/// A last row without its newline is a torn row (the writing run was killed
/// mid-row): it is left out and reported in [`CsvTrace::torn_last_row`].
///
/// # Errors
/// [`CliError::Usage`] naming `name` and the line for anything that is not such
/// a CSV, including a value that is not a finite number.
pub fn trace_from_csv(mut reader: impl BufRead, name: &str) -> Result<CsvTrace, CliError> {
    let bad = |line: usize, what: String| CliError::usage(format!("{name}:{line}: {what}"));
    let mut buffer = Vec::new();
    let mut read_total = 0u64;
    if !read_csv_line(&mut reader, &mut buffer, name, 1, &mut read_total)? {
        return Err(CliError::usage(format!("{name}: empty CSV file")));
    }
    let header_text = std::str::from_utf8(&buffer).map_err(|_| {
        bad(
            1,
            "not UTF-8 text: not a CSV written by sim-cli --csv".to_owned(),
        )
    })?;
    let header: Vec<String> = header_text
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(str::to_owned)
        .collect();
    let column = |wanted: &str| header.iter().position(|c| c == wanted);
    let mut index = [0usize; CSV_NEEDED.len()];
    for (slot, wanted) in index.iter_mut().zip(CSV_NEEDED) {
        *slot = column(wanted).ok_or_else(|| {
            bad(
                1,
                format!("no `{wanted}` column: not a CSV written by sim-cli --csv"),
            )
        })?;
    }
    let [frame_i, time_i, x_i, y_i, z_i, vz_i, roll_i, pitch_i] = index;
    let heading_i = column("fg_heading_deg");
    let (model, speed_i) = csv_model(&header).map_err(|what| bad(1, what))?;
    let (scale, model) = (model.metres_per_unit, model.title);
    let stall_i = column("stalling");
    let status_i = column("status");
    let mut builder = TraceBuilder::new(format!("{model} from {name}"));
    let mut status = FlightStatus::OnGround;
    let mut values = Vec::with_capacity(header.len());
    let mut torn_last_row = None;
    let mut line_no = 1;
    while read_csv_line(&mut reader, &mut buffer, name, line_no + 1, &mut read_total)? {
        line_no += 1;
        if buffer.last() != Some(&b'\n') {
            // The end of the input without a newline: a torn row.
            torn_last_row = Some(format!(
                "{name}:{line_no}: the last row is incomplete (no newline at the end of the \
                 file, as when the run writing it was killed): plotted up to line {}",
                line_no - 1
            ));
            break;
        }
        let line = std::str::from_utf8(&buffer)
            .map_err(|_| bad(line_no, "not UTF-8 text".to_owned()))?
            .trim_end_matches(['\n', '\r']);
        if line.is_empty() {
            continue;
        }
        values.clear();
        for field in line.split(',') {
            let value = field.trim().parse::<f64>().map_err(|_| {
                bad(
                    line_no,
                    format!("`{}` is not a number", Echo::new(field, 40)),
                )
            })?;
            if !value.is_finite() {
                return Err(bad(
                    line_no,
                    format!(
                        "`{}` is not a finite number (sim-cli --csv never writes one)",
                        Echo::new(field, 40)
                    ),
                ));
            }
            values.push(value);
        }
        if values.len() != header.len() {
            return Err(bad(
                line_no,
                format!("{} fields, the header has {}", values.len(), header.len()),
            ));
        }
        let height_m = values[z_i] * scale;
        let recorded = status_i.map(|i| {
            crate::snapshot::status_from_number(values[i])
                .ok_or_else(|| bad(line_no, format!("`{}` is not a status number", values[i])))
        });
        status = match recorded {
            Some(r) => r?.0,
            None if values[frame_i] == 0.0 => FlightStatus::initial(height_m),
            None => status.update(height_m, values[vz_i] * scale),
        };
        builder.push(PlotSample {
            time_s: values[time_i],
            height_m,
            airspeed_mps: values[speed_i] * scale,
            roll_deg: values[roll_i],
            pitch_deg: values[pitch_i],
            heading_deg: heading_i.map_or(f64::NAN, |i| values[i]),
            north_m: values[x_i] * scale,
            east_m: -values[y_i] * scale,
            status,
            stalling: stall_i.is_some_and(|i| values[i] != 0.0),
            reset: false,
        });
    }
    let trace = builder.finish();
    if trace.samples.is_empty() {
        return Err(CliError::usage(format!("{name}: no data rows to plot")));
    }
    Ok(CsvTrace {
        trace,
        torn_last_row,
    })
}

/// `sim-cli plot FILE.csv -o FILE.svg`: the CSV is read as scripts and
/// recordings are (a regular file or a pipe, nothing else), line by line.
///
/// # Errors
/// [`CliError::Usage`] for an unreadable or malformed CSV or an uncreatable
/// output; [`CliError::Runtime`] if drawing or writing fails.
pub fn run_plot(csv: &Path, output: &Path) -> Result<(), CliError> {
    let file = crate::input::open_input(csv, "CSV")?;
    let name = csv.display().to_string();
    let read = trace_from_csv(std::io::BufReader::new(file), &name)?;
    if let Some(warning) = &read.torn_last_row {
        eprintln!("sim-cli: warning: {warning}");
    }
    PlotFile::create(output)?.write(&read.trace)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::snapshot::samples;
    use fdm_core::model::LandingState;

    fn sample(time_s: f64, height_m: f64, status: FlightStatus) -> PlotSample {
        PlotSample {
            time_s,
            height_m,
            airspeed_mps: 50.0,
            roll_deg: 1.0,
            pitch_deg: 2.0,
            heading_deg: 350.0 + time_s * 5.0,
            north_m: time_s * 50.0,
            east_m: 0.0,
            status,
            stalling: false,
            reset: false,
        }
    }

    /// The ground track's legend (upper left) never covers the track, even
    /// a track that runs through the upper left corner of its extent: the
    /// panel keeps room above the track for it (issue 23.9). Checked by
    /// planting the bug: without that room (`room = 0`) the legend box covers 13 of this
    /// track's points.
    #[test]
    fn the_track_legend_does_not_cover_the_track() {
        use quick_xml::events::Event;
        // North 1000 m, then west 1000 m: the track's top left corner is the
        // corner of its bounding box, where the legend goes.
        let mut trace = TraceBuilder::new("t".to_owned());
        for i in 0..=200_u32 {
            let t = f64::from(i);
            let (north_m, east_m) = if i <= 100 {
                (t * 10.0, 0.0)
            } else {
                (1000.0, -(t - 100.0) * 10.0)
            };
            trace.push(PlotSample {
                north_m,
                east_m,
                ..sample(t, 100.0, FlightStatus::Airborne)
            });
        }
        let trace = trace.finish();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (600, 420)).into_drawing_area();
            root.fill(&WHITE).unwrap();
            track_panel(&root, &trace).unwrap();
            root.present().unwrap();
        }
        let attr = |e: &quick_xml::events::BytesStart<'_>, name: &str| {
            e.try_get_attribute(name)
                .unwrap()
                .map(|a| a.unescape_value().unwrap().into_owned())
        };
        let (mut legend, mut track) = (None, Vec::new());
        let mut reader = quick_xml::Reader::from_str(&svg);
        loop {
            match reader.read_event().unwrap() {
                // The legend's box: the one rectangle drawn at 80 % opacity.
                Event::Empty(e)
                    if e.name().as_ref() == b"rect"
                        && attr(&e, "opacity").as_deref() == Some("0.8") =>
                {
                    let n = |name| attr(&e, name).unwrap().parse::<f64>().unwrap();
                    legend = Some((n("x"), n("y"), n("width"), n("height")));
                }
                Event::Empty(e) if e.name().as_ref() == b"polyline" => {
                    let points: Vec<(f64, f64)> = attr(&e, "points")
                        .unwrap()
                        .split_whitespace()
                        .map(|p| {
                            let (x, y) = p.split_once(',').unwrap();
                            (x.parse().unwrap(), y.parse().unwrap())
                        })
                        .collect();
                    // The track, not the legend's 2-point sample line.
                    if attr(&e, "stroke").as_deref() == Some("#0000FF") && points.len() > 2 {
                        track.extend(points);
                    }
                }
                Event::Eof => break,
                _ => {}
            }
        }
        let (x, y, w, h) = legend.expect("a legend box");
        assert!(track.len() > 10, "{track:?}");
        let covered: Vec<_> = track
            .iter()
            .filter(|&&(px, py)| px > x && px < x + w && py > y && py < y + h)
            .collect();
        assert!(
            covered.is_empty(),
            "legend {:?} covers {} track points: {covered:?}",
            (x, y, w, h),
            covered.len()
        );
    }

    #[test]
    fn snapshot_samples_are_in_metres() {
        let p = PlotSample::from_snapshot(&samples::palmer());
        assert_eq!(
            (p.north_m, p.east_m, p.height_m),
            (1234.5678901234567, 0.1, 98.76)
        );
        let b = PlotSample::from_snapshot(&samples::bourg());
        assert_eq!(b.height_m, 98.76 * METRES_PER_FOOT);
        assert_eq!(b.airspeed_mps, samples::bourg().airspeed_mps);
    }

    /// A reset (the model's clock going back) starts a new segment, and the
    /// time axis goes on from where the previous segment ended instead of
    /// drawing the new segment over the first one.
    #[test]
    fn resets_split_segments_and_headings_split_at_north() {
        let mut builder = TraceBuilder::new("t".to_owned());
        for s in [
            sample(0.0, 0.0, FlightStatus::OnGround),
            sample(1.0, 1.0, FlightStatus::Airborne),
            sample(2.0, 2.0, FlightStatus::Airborne),
            sample(0.0, 0.0, FlightStatus::OnGround),
            sample(0.5, 0.0, FlightStatus::OnGround),
        ] {
            builder.push(s);
        }
        let trace = builder.finish();
        let s = trace.samples;
        let times: Vec<f64> = s.iter().map(|s| s.time_s).collect();
        assert_eq!(times, [0.0, 1.0, 2.0, 2.0, 2.5]);
        let parts = segments(&s);
        assert_eq!(parts.iter().map(|p| p.len()).collect::<Vec<_>>(), [3, 2]);
        let s = [s[0], s[1], s[2], s[3]];
        // 350 → 359 → 1 → 359: through north and back.
        let mut wrap = s;
        wrap[1].heading_deg = 359.0;
        wrap[2].heading_deg = 1.0;
        wrap[3] = PlotSample {
            time_s: 3.0,
            heading_deg: 359.0,
            ..wrap[2]
        };
        let h: Vec<f64> = unwrapped_headings(&wrap).iter().map(|p| p.1).collect();
        assert_eq!(h, [350.0, 359.0, 361.0, 359.0]);
    }

    #[test]
    fn ranges_pad_and_keep_a_minimum_span() {
        assert_eq!(padded_range([0.0, 10.0].into_iter()), -0.5..10.5);
        assert_eq!(padded_range([3.0].into_iter()), 2.0..4.0);
        assert_eq!(padded_range([f64::NAN].into_iter()), 0.0..1.0);
        // A heading dithering by a thousandth of a degree is shown on 10°.
        assert_eq!(range_at_least([-0.001, 0.001].into_iter(), 10.0), -5.0..5.0);
        assert_eq!(range_at_least([0.0, 100.0].into_iter(), 10.0), -5.0..105.0);
    }

    #[test]
    fn status_levels_cover_every_label() {
        let mut s = sample(0.0, 0.0, FlightStatus::Landed(LandingState::Crash));
        assert_eq!(status_level(&s), 5);
        s.status = FlightStatus::Airborne;
        s.stalling = true;
        assert_eq!(status_level(&s), 2);
    }

    #[test]
    fn csv_status_is_recomputed_like_the_simulation() {
        // Palmer-like columns; climbs, then comes down at -6 m/s: a crash.
        let csv = "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n\
                   1,0.1,1,0,1,10,0,2,0,5,0,10\n\
                   2,0.2,2,-1,-0.5,10,0,-6,0,-5,0,12\n\
                   0,0,0,0,0,0,0,0,0,0,0,0\n";
        let t = trace_from_csv(csv.as_bytes(), "t.csv").unwrap().trace;
        let statuses: Vec<_> = t.samples.iter().map(|s| s.status).collect();
        assert_eq!(
            statuses,
            [
                FlightStatus::OnGround,
                FlightStatus::Airborne,
                FlightStatus::Landed(LandingState::Crash),
                FlightStatus::OnGround
            ]
        );
        assert_eq!(t.samples[2].east_m, 1.0);
        assert_eq!(segments(&t.samples).len(), 2);
        assert_eq!(t.title, "Palmer Cessna 172 from t.csv");
    }

    /// Every registered model's `--csv` header is recognised as that model,
    /// with its speed column; a header naming no model's speed column is
    /// refused with every model's column in the message.
    #[test]
    fn the_registry_names_the_model_of_a_csv() {
        for kind in <ModelKind as clap::ValueEnum>::value_variants() {
            let described = kind.with(DescribeCsv);
            let mut header = vec!["frame".to_owned(), "time_s".to_owned()];
            header.extend(described.columns.iter().map(|c| (*c).to_owned()));
            let (model, speed) = csv_model(&header).unwrap();
            assert_eq!(model.title, described.title);
            assert_eq!(header[speed], described.speed_column);
        }
        let header: Vec<String> = ["frame", "time_s", "x"].map(str::to_owned).to_vec();
        let Err(message) = csv_model(&header) else {
            panic!("a header without a speed column was accepted")
        };
        assert_eq!(
            message,
            "no `airspeed` (Palmer) or `speed` (Bourg) column: not a CSV written by sim-cli --csv"
        );
    }

    #[test]
    fn bad_csv_is_a_usage_error_naming_the_line() {
        let err = trace_from_csv("a,b\n1,2\n".as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(
            err.to_string().starts_with("x.csv:1: no `frame` column"),
            "{err}"
        );
        let csv = "frame,time_s,x,y,z,vz,roll_deg,pitch_deg,speed\n0,0,0,0,0,0,0,0,oops\n";
        let err = trace_from_csv(csv.as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv:2: `oops` is not a number");
        let err = trace_from_csv("".as_bytes(), "x.csv").unwrap_err();
        assert_eq!(err.to_string(), "x.csv: empty CSV file");
    }

    #[test]
    fn empty_trace_is_an_error_not_a_panic() {
        assert!(render_svg(&Trace::default()).is_err());
    }

    const PALMER_HEADER: &str =
        "frame,time_s,x,y,z,vx,vy,vz,roll_deg,pitch_deg,fg_heading_deg,airspeed\n";

    #[test]
    fn non_finite_values_are_refused_with_their_line() {
        for bad in ["NaN", "inf", "-inf", "1e999"] {
            let csv =
                format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,{bad},0,0,0,0,0,0,0,0,0\n");
            let err = trace_from_csv(csv.as_bytes(), "x.csv").unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(
                err.to_string()
                    .starts_with(&format!("x.csv:3: `{bad}` is not a finite number")),
                "{err}"
            );
        }
    }

    #[test]
    fn a_torn_last_row_is_left_out_with_a_warning() {
        let csv =
            format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n1,0.1,1,0,1,1,0,0,0,0,0,1\n2,0.2,2,0");
        let read = trace_from_csv(csv.as_bytes(), "x.csv").unwrap();
        assert_eq!(read.trace.samples.len(), 2);
        let warning = read.torn_last_row.unwrap();
        assert!(
            warning.starts_with("x.csv:4: the last row is incomplete"),
            "{warning}"
        );
        assert!(warning.ends_with("plotted up to line 3"), "{warning}");
        // A complete file has no warning.
        let whole = format!("{PALMER_HEADER}0,0,0,0,0,0,0,0,0,0,0,0\n");
        assert_eq!(
            trace_from_csv(whole.as_bytes(), "x.csv")
                .unwrap()
                .torn_last_row,
            None
        );
    }

    #[test]
    fn an_endless_line_is_refused_at_the_line_limit() {
        let endless = std::io::repeat(b'1');
        let err = trace_from_csv(std::io::BufReader::new(endless), "x.csv").unwrap_err();
        assert!(
            err.to_string()
                .starts_with("x.csv:1: a line longer than 64 KiB"),
            "{err}"
        );
    }

    /// Two hours at 100 fps: memory stays bounded while collecting, every
    /// curve is drawn with at most 4 points per column, the SVG stays small,
    /// and the extremes survive the thinning.
    #[test]
    fn long_runs_are_thinned_for_drawing_only_as_far_as_pixels_need() {
        let frames: u32 = 2 * 3600 * 100;
        let mut builder = TraceBuilder::new("long".to_owned());
        for i in 0..=frames {
            let t = f64::from(i) / 100.0;
            let mut s = sample(t, 100.0 + 50.0 * (t / 7.0).sin(), FlightStatus::Airborne);
            s.heading_deg = (t * 3.0) % 360.0;
            s.north_m = 1000.0 * (t / 60.0).cos();
            s.east_m = 1000.0 * (t / 60.0).sin();
            if i == 123_457 {
                s.height_m = 10_000.0; // one spike: must still be drawn
            }
            builder.push(s);
            assert!(builder.trace().samples.len() <= KEEP_SAMPLES + 1);
        }
        let trace = builder.finish();
        assert_eq!(trace.total_samples, u64::from(frames) + 1);
        assert!(trace.samples.iter().any(|s| s.height_m == 10_000.0));
        let svg = render_svg(&trace).unwrap();
        assert!(svg.len() < 2_000_000, "{} bytes", svg.len());
        assert!(
            svg.contains("720001 samples"),
            "the title counts every sample"
        );
        let longest_attribute = svg.split('"').map(str::len).max().unwrap();
        assert!(longest_attribute < 200_000, "{longest_attribute}");
    }

    #[test]
    fn thin_curve_keeps_first_last_and_extremes_per_column() {
        let points: Vec<(f64, f64)> = (0..100).map(|i| (f64::from(i), f64::from(i % 7))).collect();
        let thin = thin_curve(&points, &(0.0..100.0), 10);
        assert_eq!(thin.first(), points.first());
        assert_eq!(thin.last(), points.last());
        assert!(thin.len() <= 40);
        // Every column still reaches its lowest and highest value.
        for column in 0..10 {
            let x = f64::from(column) * 10.0;
            let inside = |p: &&(f64, f64)| p.0 >= x && p.0 < x + 10.0;
            let all_max = points
                .iter()
                .filter(inside)
                .map(|p| p.1)
                .fold(f64::MIN, f64::max);
            let kept_max = thin
                .iter()
                .filter(inside)
                .map(|p| p.1)
                .fold(f64::MIN, f64::max);
            assert_eq!(all_max, kept_max);
        }
        // Few points are drawn as they are.
        let few = &points[..5];
        assert_eq!(thin_curve(few, &(0.0..100.0), 1200), few);
    }
}
