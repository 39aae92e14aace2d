//! `--plot`'s side of a run: [`Plotted`], a [`Flight`] wrapper that records
//! one [`PlotSample`] for the initial state, after every step and after every
//! reset (the run loops do not know about it), and [`fly_plotted`], which
//! flies with it and writes the plot at the end. The drawing is
//! [`crate::plot`]'s.

use fdm_core::script::Script;

use crate::config::RunConfig;
use crate::error::CliError;
use crate::plot::{PlotFile, PlotSample, Trace, TraceBuilder};
use crate::run::{fly, Flight, Links};
use crate::snapshot::Snapshot;

/// A [`Flight`] that records a [`PlotSample`] of the wrapped flight at
/// creation, after every step and after every reset.
#[derive(Debug)]
pub struct Plotted<F> {
    inner: F,
    trace: TraceBuilder,
}

impl<F: Flight> Plotted<F> {
    /// Wraps `inner` and records its initial state.
    pub fn new(inner: F) -> Self {
        let mut trace = TraceBuilder::new(F::TITLE.to_owned());
        trace.push(PlotSample::from_snapshot(&inner.snapshot()));
        Self { inner, trace }
    }

    /// The samples so far.
    #[must_use]
    pub fn trace(&self) -> &Trace {
        self.trace.trace()
    }

    fn record(&mut self) {
        let sample = PlotSample::from_snapshot(&self.inner.snapshot());
        self.trace.push(sample);
    }
}

impl<F: Flight> Flight for Plotted<F> {
    type Action = F::Action;
    type Details = F::Details;

    const TITLE: &'static str = F::TITLE;

    fn step(&mut self, actions: &[Self::Action]) -> anyhow::Result<()> {
        self.inner.step(actions)?;
        self.record();
        Ok(())
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        self.inner.reset()?;
        self.record();
        Ok(())
    }

    fn snapshot(&self) -> Snapshot<Self::Details> {
        self.inner.snapshot()
    }

    fn links(&self) -> Links {
        self.inner.links()
    }

    fn finish(&mut self) -> anyhow::Result<()> {
        self.inner.finish()
    }
}

/// Flies `flight` as [`fly`] does while recording it, then writes the plot,
/// also when the run stopped on an error (the plot shows the flight up to the
/// failing frame; the run's error is returned).
///
/// # Errors
/// The run's error, else a failure to write the plot.
pub fn fly_plotted<F: Flight>(
    flight: F,
    script: &Script<F::Action>,
    run: RunConfig,
    plot: PlotFile,
) -> Result<(), CliError> {
    let mut plotted = Plotted::new(flight);
    let result = fly(&mut plotted, script, run);
    let written = plot.write(plotted.trace());
    result.and(written)
}
