//! The plot of one flight: six panels against simulated time or position
//! in one SVG ([`render_svg`]): height above the ground plane (ft), airspeed
//! (kt), roll and pitch (deg), heading (deg), the display status
//! ([`DisplayStatus`]), and the ground track (north against east, m). Drawn
//! with `plotters`' SVG backend only, so no font or bitmap system library is
//! needed (text is left to the SVG viewer's fonts).
//!
//! A run's samples are collected by [`PlotOutput`], an [`Output`] of the run
//! library: one [`PlotSample`] for the initial state, after every flown frame
//! and after every reset; [`Output::finish`] draws and writes the SVG (also
//! when the run stopped early: the plot shows the flight up to there). Any
//! other source of samples (`sim-cli plot` reads them from a CSV) pushes
//! them into a [`TraceBuilder`] itself.
//!
//! After a reset the model's clock starts again at 0; the plot's time axis
//! does not: it is the simulated time elapsed since the start of the run, so
//! each segment is drawn after the previous one (its own line, a grey
//! vertical line at the reset) instead of over it.
//!
//! Any run plots in a small SVG. The samples are kept in bounded memory
//! ([`TraceBuilder`]: past [`KEEP_SAMPLES`], they are thinned to the first,
//! last, lowest and highest sample of every quantity in each of
//! [`KEEP_COLUMNS`] time columns), and each curve is drawn from the first,
//! last, lowest and highest of its points in each of [`DRAW_COLUMNS`] columns
//! (about two per pixel), which draws the same picture as every point would.
//! A two-hour run at 100 fps gives an SVG of a few hundred kilobytes.

use std::io::Write;

use fdm_core::model::{DisplayStatus, FlightStatus, Model};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use fdm_run::{Event, Frame, Output, OutputError};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

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
    /// The sample of a run's frame: the model's common view (position in
    /// metres, x north and y west; airspeed), the placement's attitude (what
    /// FlightGear and the reports show) and the frame's status.
    #[must_use]
    pub fn from_frame<M: Model>(frame: &Frame<'_, M>) -> Self {
        let view = frame.view;
        let attitude = &frame.placement.attitude;
        Self {
            time_s: view.time_s,
            height_m: view.position_m.z,
            airspeed_mps: view.airspeed_mps,
            roll_deg: attitude.roll_deg,
            pitch_deg: attitude.pitch_deg,
            heading_deg: attitude.heading_deg,
            north_m: view.position_m.x,
            east_m: -view.position_m.y,
            status: frame.status,
            stalling: view.stalling,
            reset: false,
        }
    }

    /// The display status of the sample.
    #[must_use]
    pub fn display_status(&self) -> DisplayStatus {
        DisplayStatus::new(self.status, self.stalling)
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

/// The status levels of the status panel, bottom to top: the display
/// vocabulary's ([`DisplayStatus::PANEL_LABELS`]).
const STATUS_LEVELS: [&str; 6] = DisplayStatus::PANEL_LABELS;

fn status_level(sample: &PlotSample) -> i32 {
    i32::try_from(sample.display_status().panel_level()).unwrap_or(0)
}

/// Splits `samples` at each reset.
#[must_use]
pub fn segments(samples: &[PlotSample]) -> Vec<&[PlotSample]> {
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

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
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
) -> Result<(), PlotError> {
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
) -> Result<(), PlotError> {
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

fn heading_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    trace: &Trace,
) -> Result<(), PlotError> {
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

fn status_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, trace: &Trace) -> Result<(), PlotError> {
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

fn track_panel(area: &DrawingArea<SVGBackend<'_>, Shift>, trace: &Trace) -> Result<(), PlotError> {
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
/// [`PlotError::Empty`] if there is nothing to plot, [`PlotError::Draw`] if
/// drawing fails.
pub fn render_svg(trace: &Trace) -> Result<String, PlotError> {
    if trace.samples.is_empty() {
        return Err(PlotError::Empty);
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

/// A plot's SVG file, created (and locked against a second writer,
/// [`fdm_run::outfile::create_locked`]) before the run, so that an
/// unwritable path is refused before anything flies.
#[derive(Debug)]
pub struct PlotFile {
    path: std::path::PathBuf,
    file: std::fs::File,
}

impl PlotFile {
    /// Creates (truncates) `path`, locked.
    ///
    /// # Errors
    /// The OS error, or the file being written by another process.
    pub fn create(path: &std::path::Path) -> std::io::Result<Self> {
        Ok(Self {
            path: path.to_owned(),
            file: fdm_run::outfile::create_locked(path)?,
        })
    }

    /// The file as a run's plot output ([`PlotOutput`], titled `title`,
    /// errors naming the path).
    #[must_use]
    pub fn into_output(self, title: &str) -> PlotOutput<std::fs::File> {
        PlotOutput::new(self.file, self.path.display().to_string(), title)
    }

    /// Draws `trace` into the file ([`write_svg`]).
    ///
    /// # Errors
    /// [`PlotError`] naming the path.
    pub fn write(mut self, trace: &Trace) -> Result<(), PlotError> {
        let name = self.path.display().to_string();
        write_svg(&mut self.file, &name, trace)
    }
}

/// A run's plot as an [`Output`] of the run library: one [`PlotSample`] for
/// frame 0 (when attached), after every flown frame and after every reset
/// (a diverged frame, which the run stops on, is not sampled); at
/// [`Output::finish`] the SVG ([`render_svg`]) is written to the writer, also
/// when the run stopped early.
///
/// ```
/// use fdm_core::palmer::Palmer;
/// use fdm_plot::PlotOutput;
/// use fdm_run::{Run, Scenario, SharedOutput, Start};
///
/// let mut run = Run::new(Scenario::<Palmer>::new(Start::thesis(), 30, 90)?)?;
/// let plot = SharedOutput::new(PlotOutput::new(Vec::new(), "memory", "Palmer"));
/// run.attach(plot.clone())?;
/// run.run_to_end()?;
/// run.finish()?;
/// let svg = plot.take().and_then(PlotOutput::into_inner).unwrap_or_default();
/// assert!(String::from_utf8(svg)?.contains("Palmer: 91 samples"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct PlotOutput<W: Write> {
    /// Where the SVG goes; taken when it is written.
    out: Option<W>,
    /// The writer's name (its path), in error messages.
    name: String,
    /// Written once: the SVG is in `out`.
    written: bool,
    builder: TraceBuilder,
}

impl<W: Write> PlotOutput<W> {
    /// A plot titled `title` written to `out` at the end; `name` names
    /// `out` in error messages (its path).
    pub fn new(out: W, name: impl Into<String>, title: impl Into<String>) -> Self {
        Self {
            out: Some(out),
            name: name.into(),
            written: false,
            builder: TraceBuilder::new(title.into()),
        }
    }

    /// The samples so far.
    #[must_use]
    pub fn trace(&self) -> &Trace {
        self.builder.trace()
    }

    /// The writer, once [`Output::finish`] has written the SVG into it
    /// (`None` before, or when writing failed).
    #[must_use]
    pub fn into_inner(self) -> Option<W> {
        if self.written {
            self.out
        } else {
            None
        }
    }

    /// Draws the samples so far and writes the SVG (once).
    ///
    /// # Errors
    /// [`PlotError::Draw`] if drawing fails, [`PlotError::Write`] if
    /// writing fails.
    pub fn write_svg(&mut self) -> Result<(), PlotError> {
        if self.written {
            return Ok(());
        }
        let Some(out) = self.out.as_mut() else {
            return Ok(());
        };
        write_svg(out, &self.name, self.builder.trace())?;
        self.written = true;
        Ok(())
    }
}

/// Draws `trace` ([`render_svg`]) and writes the SVG to `out` (flushed);
/// `name` names `out` in error messages.
///
/// # Errors
/// As [`render_svg`], and [`PlotError::Write`] if writing fails.
pub fn write_svg<W: Write>(out: &mut W, name: &str, trace: &Trace) -> Result<(), PlotError> {
    let svg = render_svg(trace)?;
    out.write_all(svg.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|source| PlotError::Write {
            name: name.to_owned(),
            source,
        })
}

impl<M: Model, W: Write> Output<M> for PlotOutput<W> {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        if frame.event == Event::Step && frame.status == FlightStatus::Diverged {
            return Ok(());
        }
        self.builder.push(PlotSample::from_frame(frame));
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(self.write_svg()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
    fn empty_trace_is_an_error_not_a_panic() {
        assert!(render_svg(&Trace::default()).is_err());
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

    /// The plot output samples frame 0, every flown frame and the reset
    /// (its sample starts a new segment), in metres for a model flying in
    /// feet, with the placement's attitude; at the end it writes exactly
    /// `render_svg` of its trace.
    #[test]
    fn the_output_samples_every_frame_and_writes_the_svg_at_the_end() {
        use fdm_core::bourg::{Bourg, BourgAction};
        use fdm_run::{Run, Scenario, SharedOutput, Start};
        let mut run = Run::new(Scenario::<Bourg>::new(Start::thesis(), 30, 0).unwrap()).unwrap();
        let plot = SharedOutput::new(PlotOutput::new(Vec::new(), "mem", "Bourg"));
        run.attach(plot.clone()).unwrap();
        let mut expected = Vec::new();
        let now = |run: &Run<Bourg>| {
            let view = run.view();
            let placement = run.placement();
            (
                view.position_m.z,
                -view.position_m.y,
                view.airspeed_mps,
                placement.attitude.heading_deg,
                run.status(),
            )
        };
        expected.push(now(&run));
        for _ in 0..20 {
            run.step_actions(&[BourgAction::RollRight]).unwrap();
            expected.push(now(&run));
        }
        run.reset().unwrap();
        expected.push(now(&run));
        run.finish().unwrap();
        let output = plot.take().unwrap();
        let trace = output.trace().clone();
        let got: Vec<_> = trace
            .samples
            .iter()
            .map(|s| {
                (
                    s.height_m,
                    s.east_m,
                    s.airspeed_mps,
                    s.heading_deg,
                    s.status,
                )
            })
            .collect();
        assert_eq!(got, expected);
        assert_eq!(trace.samples.iter().filter(|s| s.reset).count(), 1);
        assert!(trace.samples[21].reset);
        let bytes = output.into_inner().unwrap();
        assert_eq!(
            String::from_utf8(bytes).unwrap(),
            render_svg(&trace).unwrap()
        );
    }

    /// A writer that fails: the plot's error names the file and keeps the
    /// cause.
    #[test]
    fn a_failing_write_names_the_file_and_keeps_the_cause() {
        struct Full;
        impl Write for Full {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(std::io::Error::other("disk full"))
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let mut output = PlotOutput::new(Full, "out.svg", "t");
        output
            .builder
            .push(sample(0.0, 0.0, FlightStatus::OnGround));
        let err = output.write_svg().unwrap_err();
        assert_eq!(err.to_string(), "writing plot file out.svg");
        let source = std::error::Error::source(&err).map(ToString::to_string);
        assert_eq!(source.as_deref(), Some("disk full"));
    }
}
