//! `sim-cli study`'s plots: one SVG (`study.svg`) with a histogram per
//! measure and, when the study measures `touchdown_x_m` and
//! `touchdown_y_m`, the touchdown points as a scatter (east/north, as the
//! flight plots' ground track). Drawn with `plotters`' SVG backend, in the
//! style of [`crate::plot`].

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::CliError;

/// Bins of each histogram.
pub const HISTOGRAM_BINS: usize = 30;

/// Most touchdown points drawn (the first runs'): keeps the SVG small.
pub const MAX_SCATTER_POINTS: usize = 20_000;

/// Width of the SVG and height of one row of panels, pixels.
const WIDTH: u32 = 1200;
const ROW_HEIGHT: u32 = 360;

fn draw_error(e: impl std::fmt::Display) -> CliError {
    CliError::runtime(format!("drawing the study plot: {e}"))
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
) -> Result<(), CliError> {
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
) -> Result<(), CliError> {
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
        crate::plot::east_north_chart(area, (&caption, 16), east, north).map_err(draw_error)?;
    chart
        .draw_series(
            points_east_north_m
                .iter()
                .map(|&p| Circle::new(p, 2, RED.mix(0.5).filled())),
        )
        .map_err(draw_error)?;
    Ok(())
}

/// The study's plots as one SVG document: a histogram per measure (two per
/// row), then the touchdown scatter if `touchdown_points` has any.
///
/// # Errors
/// [`CliError::Runtime`] if drawing fails.
pub fn render(
    measures: &[(String, Vec<f64>)],
    touchdown_points_east_north_m: &[(f64, f64)],
) -> Result<String, CliError> {
    let histogram_rows = measures.len().div_ceil(2);
    let scatter_rows = if touchdown_points_east_north_m.is_empty() {
        0
    } else {
        2
    };
    let rows = u32::try_from(histogram_rows + scatter_rows)
        .unwrap_or(1)
        .max(1);
    let mut svg = String::new();
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
        if scatter_rows > 0 {
            scatter(&bottom, touchdown_points_east_north_m)?;
        }
        root.present().map_err(draw_error)?;
    }
    Ok(svg)
}
