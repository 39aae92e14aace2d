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
//!
//! [`Links::open`] builds them from their settings ([`LinkSettings`]).

use std::net::SocketAddrV4;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::Model;
use fgnet::SenderError;

#[cfg(feature = "dis")]
use crate::dis::{DisError, DisOutput, DisReport, FlightDis};
use crate::flightgear::FlightGearOutput;
use crate::model::RunModel;
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

/// Where a run's network outputs send: each `None` for no such output.
#[derive(Debug, Clone, Default)]
pub struct LinkSettings {
    /// The FlightGear native-FDM link's target, resolved.
    pub fg: Option<SocketAddrV4>,
    /// The DIS output's settings and identity.
    #[cfg(feature = "dis")]
    pub dis: Option<FlightDis>,
}

/// Why a run's network outputs could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum LinksError {
    /// The FlightGear link's socket could not be set up.
    #[error("opening the FlightGear link to {target}")]
    FlightGear {
        /// The target.
        target: SocketAddrV4,
        /// Why.
        #[source]
        source: SenderError,
    },
    /// The DIS output was refused or its socket could not be made
    /// ([`DisOutput::open`]).
    #[cfg(feature = "dis")]
    #[error(transparent)]
    Dis(#[from] DisError),
}

impl Links {
    /// Opens the outputs `settings` ask for (the FlightGear link first, then
    /// DIS) for one aircraft of model `M` flown at `fps` frames per second
    /// from `origin`; attach them with [`Self::attach_to`].
    ///
    /// # Errors
    /// [`LinksError::FlightGear`] when the FlightGear socket cannot be set
    /// up, `LinksError::Dis` when the DIS output is refused or its socket
    /// cannot be made.
    #[cfg_attr(not(feature = "dis"), allow(unused_variables))]
    pub fn open<M: RunModel>(
        settings: &LinkSettings,
        origin: GeodeticOrigin,
        fps: u32,
    ) -> Result<Self, LinksError> {
        let fg = match settings.fg {
            Some(target) => Some(SharedOutput::new(
                FlightGearOutput::connect(&target.to_string(), origin)
                    .map_err(|source| LinksError::FlightGear { target, source })?,
            )),
            None => None,
        };
        Ok(Self {
            fg,
            #[cfg(feature = "dis")]
            dis: match &settings.dis {
                Some(dis) => Some(SharedOutput::new(DisOutput::open::<M>(dis, origin, fps)?)),
                None => None,
            },
        })
    }

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

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::Palmer;

    #[test]
    fn open_builds_what_the_settings_ask_for() {
        let origin = crate::Scenario::<Palmer>::new(crate::Start::thesis(), 30, 1)
            .unwrap()
            .origin;
        let none = Links::open::<Palmer>(&LinkSettings::default(), origin, 30).unwrap();
        assert!(none.fg.is_none() && none.fg_stats().is_none());
        let (_receiver, target) = listener();
        let settings = LinkSettings {
            fg: Some(target),
            ..LinkSettings::default()
        };
        let links = Links::open::<Palmer>(&settings, origin, 30).unwrap();
        assert_eq!(links.fg_stats(), Some(LinkStats::default()));
    }

    /// A receiver on loopback and its address.
    fn listener() -> (std::net::UdpSocket, std::net::SocketAddrV4) {
        let socket = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
        let std::net::SocketAddr::V4(addr) = socket.local_addr().unwrap() else {
            unreachable!("bound to IPv4")
        };
        (socket, addr)
    }

    /// The links of a 30-frame Palmer run with the FlightGear link to `fg`
    /// and (feature `dis`) DIS, every frame, to `dis`; attached and flown.
    #[cfg_attr(not(feature = "dis"), allow(unused_variables))]
    fn flown(fg: std::net::SocketAddrV4, dis: std::net::SocketAddrV4) -> Links {
        let scenario = crate::Scenario::<Palmer>::new(crate::Start::thesis(), 30, 30).unwrap();
        let settings = LinkSettings {
            fg: Some(fg),
            #[cfg(feature = "dis")]
            dis: Some(FlightDis {
                settings: crate::dis::DisSettings {
                    target: dis.into(),
                    site: 1,
                    application: 1,
                    exercise: 1,
                    version: fdm_dis::DisVersion::V7,
                    dr: fdm_dis::DrAlgorithm::Rvw,
                    thresholds: fdm_dis::DrThresholds::default(),
                    every_frame: true,
                },
                entity: 7,
                callsign: None,
            }),
        };
        let links = Links::open::<Palmer>(&settings, scenario.origin, 30).unwrap();
        let mut run = Run::new(scenario).unwrap();
        links.attach_to(&mut run).unwrap();
        assert_eq!(run.run_to_end().unwrap().frames, 30);
        links
    }

    /// `attach_to` attaches every link (each sends once per flown frame,
    /// counted in its stats or report); with listeners there, no failure.
    #[test]
    fn attached_links_send_every_frame_and_report() {
        let ((_fg_rx, fg), (_dis_rx, dis)) = (listener(), listener());
        let links = flown(fg, dis);
        assert_eq!(
            links.fg_stats(),
            Some(LinkStats {
                sent: 30,
                failed: 0
            })
        );
        #[cfg(feature = "dis")]
        {
            let report = links.dis_report().expect("a DIS output");
            assert_eq!((report.pdus, report.failed, report.frames), (30, 0, 30));
            assert_eq!(report.first_entity, "1:1:7");
        }
        assert_eq!(links.take_failure(), None);
    }

    /// A link's first failure is given once, the FlightGear link's before
    /// DIS's, then DIS's; then nothing. The FlightGear link's socket is
    /// connected, so a port where nobody listens fails its sends; DIS's is
    /// not (it may broadcast), so its failing target is port 0, which the OS
    /// refuses for every send (`sim-cli --dis` refuses it before: a library
    /// caller gets the failures counted and the first one told).
    #[test]
    fn each_links_first_failure_is_taken_once() {
        let (_fg_rx, fg) = listener();
        // Nobody listens on a port just freed: the ICMP answer comes back
        // as the next send's error.
        let dead = listener().1;
        let port_0 = std::net::SocketAddrV4::new(std::net::Ipv4Addr::LOCALHOST, 0);
        let links = flown(dead, port_0);
        let first = links.take_failure().expect("the FlightGear link failed");
        assert!(
            first.starts_with(&format!("sending to {dead} failed on frame ")),
            "{first}"
        );
        #[cfg(feature = "dis")]
        {
            assert_eq!(links.dis_report().unwrap().failed, 30);
            let second = links.take_failure().expect("DIS failed too");
            assert!(second.contains("127.0.0.1:0"), "{second}");
        }
        assert_eq!(links.take_failure(), None);

        // DIS failing alone is still told.
        #[cfg(feature = "dis")]
        {
            let links = flown(fg, port_0);
            assert_eq!(links.fg_stats().unwrap().failed, 0);
            let only = links.take_failure().expect("DIS failed");
            assert!(only.contains("127.0.0.1:0"), "{only}");
            assert_eq!(links.take_failure(), None);
        }
    }
}
