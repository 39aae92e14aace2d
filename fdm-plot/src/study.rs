//! A study's plots (`sim-cli study`'s `study.svg`): one SVG with a histogram per
//! measure, when the study measures `touchdown_x_m` and `touchdown_y_m` the
//! touchdown points as a scatter (east/north, as the flight plots' ground
//! track), and a thinned sample of ground tracks ([`fdm_study::TrackPlan`]:
//! at most 50 runs spread evenly over the run indices, each at most about
//! 300 points). Drawn with `plotters`' SVG backend, in the style of the
//! flight plot ([`crate::flight`], whose ground chart it shares); each track is one `<polyline class="ground-track"
//! data-run="I" data-frame-step="S">` whose points are the track's
//! positions (east = −y, north = x) in the panel's axes, in pixels to
//! 0.01 px.

use std::fmt::Write as _;

use fdm_study::GroundTrack;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

/// Bins of each histogram.
pub const HISTOGRAM_BINS: usize = 30;

/// Most touchdown points drawn (the first runs'): keeps the SVG small.
pub const MAX_SCATTER_POINTS: usize = 20_000;

/// Width of the SVG and height of one row of panels, pixels.
const WIDTH: u32 = 1200;
const ROW_HEIGHT: u32 = 360;

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::DrawStudy(e.to_string())
}

/// A range around `values` (with a margin; a span of at least `1e-9` so a
/// constant measure still has a bin).
fn range_of(values: impl Iterator<Item = f64>) -> Option<std::ops::Range<f64>> {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        low = low.min(v);
        high = high.max(v);
    }
    if !(low.is_finite() && high.is_finite()) {
        return None;
    }
    let span = (high - low).max(1e-9 * (1.0 + low.abs()));
    Some((low - span * 0.05)..(high + span * 0.05))
}

fn histogram(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    name: &str,
    values: &[f64],
) -> Result<(), PlotError> {
    let Some(x) = range_of(values.iter().copied()) else {
        area.titled(&format!("{name}: no values"), ("sans-serif", 16))
            .map_err(draw_error)?;
        return Ok(());
    };
    let width = (x.end - x.start) / HISTOGRAM_BINS as f64;
    let mut counts = [0u64; HISTOGRAM_BINS];
    for v in values {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let bin = (((v - x.start) / width) as usize).min(HISTOGRAM_BINS - 1);
        counts[bin] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(1).max(1);
    #[allow(clippy::cast_precision_loss)]
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{name} ({} runs)", values.len()),
            ("sans-serif", 16),
        )
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(x.clone(), 0.0..(top as f64 * 1.1))
        .map_err(draw_error)?;
    chart
        .configure_mesh()
        .y_desc("runs")
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(draw_error)?;
    #[allow(clippy::cast_precision_loss)]
    chart
        .draw_series(counts.iter().enumerate().map(|(i, &n)| {
            let left = x.start + width * i as f64;
            Rectangle::new(
                [(left, 0.0), (left + width, n as f64)],
                BLUE.mix(0.6).filled(),
            )
        }))
        .map_err(draw_error)?;
    Ok(())
}

fn scatter(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    points_east_north_m: &[(f64, f64)],
) -> Result<(), PlotError> {
    let (Some(mut east), Some(mut north)) = (
        range_of(points_east_north_m.iter().map(|p| p.0)),
        range_of(points_east_north_m.iter().map(|p| p.1)),
    ) else {
        return Ok(());
    };
    // Same scale on both axes would flatten a long, narrow scatter; keep
    // each axis its own but say so in the caption.
    if east.end - east.start < 1.0 {
        let mid = (east.start + east.end) / 2.0;
        east = (mid - 0.5)..(mid + 0.5);
    }
    if north.end - north.start < 1.0 {
        let mid = (north.start + north.end) / 2.0;
        north = (mid - 0.5)..(mid + 0.5);
    }
    let caption = format!(
        "Touchdown points ({} runs; axes not to the same scale)",
        points_east_north_m.len()
    );
    let mut chart =
        crate::flight::east_north_chart(area, (&caption, 16), east, north).map_err(draw_error)?;
    chart
        .draw_series(
            points_east_north_m
                .iter()
                .map(|&p| Circle::new(p, 2, RED.mix(0.5).filled())),
        )
        .map_err(draw_error)?;
    Ok(())
}

/// The panel of ground tracks: axes drawn by plotters, and the tracks as
/// SVG polylines (returned, to be added to the document) in the axes'
/// pixels.
fn ground_tracks(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    tracks: &[GroundTrack],
    frame_step: u64,
) -> Result<String, PlotError> {
    // East = −y, north = x, as the scatter and the flight plots.
    let points = || {
        tracks
            .iter()
            .flat_map(|t| t.position_m.iter().map(|p| (-p[1], p[0])))
    };
    let (Some(mut east), Some(mut north)) = (
        range_of(points().map(|p| p.0)),
        range_of(points().map(|p| p.1)),
    ) else {
        return Ok(String::new());
    };
    if east.end - east.start < 1.0 {
        let mid = (east.start + east.end) / 2.0;
        east = (mid - 0.5)..(mid + 0.5);
    }
    if north.end - north.start < 1.0 {
        let mid = (north.start + north.end) / 2.0;
        north = (mid - 0.5)..(mid + 0.5);
    }
    let caption = format!(
        "Ground tracks ({} runs spread over the study, every {frame_step} frames; axes not to the same scale)",
        tracks.len()
    );
    let chart = crate::flight::east_north_chart(area, (&caption, 16), east.clone(), north.clone())
        .map_err(draw_error)?;
    // The plotting area's pixels: east grows rightwards, north upwards.
    let (x_px, y_px) = chart.plotting_area().get_pixel_range();
    let (x0, x1) = (f64::from(x_px.start), f64::from(x_px.end));
    let (y0, y1) = (f64::from(y_px.start), f64::from(y_px.end));
    let to_px = |(e, n): (f64, f64)| {
        (
            x0 + (e - east.start) / (east.end - east.start) * (x1 - x0),
            y1 - (n - north.start) / (north.end - north.start) * (y1 - y0),
        )
    };
    let mut out = String::from("<g class=\"ground-tracks\">\n");
    for (k, track) in tracks.iter().enumerate() {
        let (r, g, b) = Palette99::pick(k).to_rgba().rgb();
        let _ = write!(
            out,
            "<polyline class=\"ground-track\" data-run=\"{}\" data-frame-step=\"{frame_step}\" \
             fill=\"none\" stroke=\"#{r:02x}{g:02x}{b:02x}\" stroke-opacity=\"0.8\" \
             stroke-width=\"1\" points=\"",
            track.run
        );
        for (i, p) in track.position_m.iter().enumerate() {
            let (x, y) = to_px((-p[1], p[0]));
            let sep = if i == 0 { "" } else { " " };
            let _ = write!(out, "{sep}{x:.2},{y:.2}");
        }
        let _ = writeln!(out, "\"><title>run {}</title></polyline>", track.run);
    }
    out.push_str("</g>\n");
    Ok(out)
}

/// The study's plots as one SVG document: a histogram per measure (two per
/// row), then the touchdown scatter if `touchdown_points` has any, then the
/// ground tracks if `tracks` has any (kept every `frame_step` frames).
///
/// # Errors
/// [`PlotError::DrawStudy`] if drawing fails.
pub fn render(
    measures: &[(String, Vec<f64>)],
    touchdown_points_east_north_m: &[(f64, f64)],
    tracks: &[GroundTrack],
    frame_step: u64,
) -> Result<String, PlotError> {
    let histogram_rows = measures.len().div_ceil(2);
    let scatter_rows = if touchdown_points_east_north_m.is_empty() {
        0
    } else {
        2
    };
    let track_rows = if tracks.is_empty() { 0 } else { 2 };
    let rows = u32::try_from(histogram_rows + scatter_rows + track_rows)
        .unwrap_or(1)
        .max(1);
    let mut svg = String::new();
    let polylines;
    {
        let root =
            SVGBackend::with_string(&mut svg, (WIDTH, ROW_HEIGHT * rows)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_error)?;
        let (top, bottom) =
            root.split_vertically(ROW_HEIGHT * u32::try_from(histogram_rows).unwrap_or(0));
        let cells = top.split_evenly((histogram_rows.max(1), 2));
        for ((name, values), cell) in measures.iter().zip(&cells) {
            histogram(cell, name, values)?;
        }
        let (middle, tracks_area) =
            bottom.split_vertically(ROW_HEIGHT * u32::try_from(scatter_rows).unwrap_or(0));
        if scatter_rows > 0 {
            scatter(&middle, touchdown_points_east_north_m)?;
        }
        polylines = if track_rows > 0 {
            ground_tracks(&tracks_area, tracks, frame_step)?
        } else {
            String::new()
        };
        root.present().map_err(draw_error)?;
    }
    // The tracks go last, over their panel's axes.
    match svg.rfind("</svg>") {
        Some(end) => svg.insert_str(end, &polylines),
        None => return Err(draw_error("the SVG backend wrote no </svg>")),
    }
    Ok(svg)
}
