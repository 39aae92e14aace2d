//! A run's network outputs as a program reads them while it flies: shared
//! handles ([`SharedOutput`]) to the FlightGear native-FDM link and (feature
//! `dis`) the DIS output attached to one [`Run`], with their counters and
//! first failures. What `sim-cli --fg`/`--dis` report and warn from.
//!
//! ```
//! use fdm_core::palmer::Palmer;
//! use fdm_run::flightgear::FlightGearOutput;
//! use fdm_run::links::Links;
//! use fdm_run::{LinkStats, Run, Scenario, SharedOutput, Start};
//!
//! let receiver = std::net::UdpSocket::bind("127.0.0.1:0")?;
//! let scenario = Scenario::<Palmer>::new(Start::thesis(), 30, 3)?;
//! let fg = FlightGearOutput::connect(&receiver.local_addr()?.to_string(), scenario.origin)?;
//! let links = Links { fg: Some(SharedOutput::new(fg)), ..Links::default() };
//! let mut run = Run::new(scenario)?;
//! links.attach_to(&mut run)?;
//! run.run_to_end()?;
//! assert_eq!(links.fg_stats(), Some(LinkStats { sent: 3, failed: 0 }));
//! assert!(links.take_failure().is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use fdm_core::model::Model;

#[cfg(feature = "dis")]
use crate::dis::{DisOutput, DisReport};
use crate::flightgear::FlightGearOutput;
use crate::output::LinkStats;
use crate::run::{Run, RunError};
use crate::shared::SharedOutput;

/// Handles to a run's network outputs (cloning shares them): each `None`
/// when the run has no such output.
#[derive(Debug, Clone, Default)]
pub struct Links {
    /// The FlightGear native-FDM link.
    pub fg: Option<SharedOutput<FlightGearOutput>>,
    /// The DIS output.
    #[cfg(feature = "dis")]
    pub dis: Option<SharedOutput<DisOutput>>,
}

impl Links {
    /// Attaches the outputs to `run` (the FlightGear link first, then DIS):
    /// they take its frame 0 now and every later frame.
    ///
    /// # Errors
    /// An output fails on frame 0.
    pub fn attach_to<M: Model>(&self, run: &mut Run<M>) -> Result<(), RunError> {
        if let Some(fg) = &self.fg {
            run.attach(fg.clone())?;
        }
        #[cfg(feature = "dis")]
        if let Some(dis) = &self.dis {
            run.attach(dis.clone())?;
        }
        Ok(())
    }

    /// The FlightGear link's datagram counters, or `None` without one.
    #[must_use]
    pub fn fg_stats(&self) -> Option<LinkStats> {
        self.fg.as_ref()?.with(|o| o.map(|o| o.stats()))
    }

    /// The DIS output's counts, or `None` without one.
    #[cfg(feature = "dis")]
    #[must_use]
    pub fn dis_report(&self) -> Option<DisReport> {
        self.dis.as_ref()?.with(|o| o.map(|o| o.report()))
    }

    /// A one-line description of the first failed send of an output (the
    /// FlightGear link's first, then DIS's), each returned once: later
    /// failures are only counted. A failing link never stops the run; a
    /// program shows this at most once per output and run, never per frame.
    #[must_use]
    pub fn take_failure(&self) -> Option<String> {
        let fg = self.fg.as_ref();
        if let Some(message) =
            fg.and_then(|fg| fg.with(|o| o.and_then(FlightGearOutput::take_failure)))
        {
            return Some(message);
        }
        #[cfg(feature = "dis")]
        if let Some(message) = self
            .dis
            .as_ref()
            .and_then(|d| d.with(|o| o.and_then(DisOutput::take_failure)))
        {
            return Some(message);
        }
        None
    }
}
