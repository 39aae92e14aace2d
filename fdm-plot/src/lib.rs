//! Plots of flights and studies as SVG, and the plot as an output of a run.
//!
//! | module | what |
//! |---|---|
//! | [`flight`] | one flight's six panels ([`render_svg`]), its samples in bounded memory ([`TraceBuilder`]), and [`PlotOutput`], the plot as an [`fdm_run::Output`] (`sim-cli --plot`, `sim-cli replay --plot`) |
//! | [`csv`] | a flight CSV (`sim-cli --csv`) read back into samples ([`csv::read_trace`], [`csv::read_trace_among`]), the model the CSV's first line names, `# model: NAME` (`sim-cli plot`) |
//! | [`study`] | a Monte Carlo study's `study.svg`: histograms, touchdown scatter, ground tracks ([`study::render`]) |
//!
//! Drawn with `plotters`' SVG backend only (no font or bitmap system
//! library). This crate sits above `fdm-run` and `fdm-study` (it draws both
//! a run's frames and a study's tracks), so neither of those carries a
//! drawing library: the Python package and the study runner build without
//! it.

pub mod csv;
pub mod flight;
pub mod study;

pub use flight::{
    render_svg, write_svg, PlotFile, PlotOutput, PlotSample, Trace, TraceBuilder, DRAW_COLUMNS,
    KEEP_COLUMNS, KEEP_SAMPLES, SVG_SIZE,
};

/// Why a plot was not drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The trace has no sample.
    #[error("nothing to plot: no samples")]
    Empty,
    /// plotters failed to draw a flight's plot.
    #[error("drawing the plot: {0}")]
    Draw(String),
    /// plotters failed to draw a study's plot.
    #[error("drawing the study plot: {0}")]
    DrawStudy(String),
    /// Writing the SVG failed; the cause is the source.
    #[error("writing plot file {name}")]
    Write {
        /// The file's name (its path), as given.
        name: String,
        /// What the OS said.
        #[source]
        source: std::io::Error,
    },
}
