//! The outputs of a `Flight` (`Flight.acmi_to`, `Flight.csv_to`,
//! `Flight.dis_to`): the run library's [`Output`]s, as `sim-cli` attaches
//! them to its run, handed each frame by the flight ([`Outputs::emit`]).
//!
//! * ACMI: [`fdm_run::acmi::AcmiOutput`] on an [`AcmiWriter`] (plain text, or
//!   zip-compressed for a name ending in `.zip.acmi`), title the model's
//!   name as `sim-cli --acmi` writes it;
//! * CSV: [`fdm_run::csv::CsvOutput`] of [`FlightRow`]s, the rows of
//!   `sim-cli --csv`;
//! * DIS (feature `dis`): [`fdm_run::dis::DisOutput`], one entity;
//! * FlightGear: [`FlightGearOutput`], one native-FDM datagram per flown
//!   frame, the target checked as `sim-cli --fg` checks it
//!   ([`fgnet::address::parse_fg_target`]).
//!
//! Each output has its own earth-frame origin (the placement on WGS-84 is
//! computed per origin, as [`Placement::of`] computes it for the ECS's
//! MakePacket: the same bits).

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::sync::Arc;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_core::model::{FlightStatus, FlightView};
use fdm_run::acmi::{AcmiHeader, AcmiOutput, AcmiWriter, ReferenceTime};
use fdm_run::csv::{CsvOutput, CsvWriter, FlightRow};
use fdm_run::flightgear::FlightGearOutput;
use fdm_run::output::error_text;
use fdm_run::{Event, Frame, LinkStats, Output, Placement, SharedOutput};
use fgnet::address::{parse_fg_target, FgAddressError};

use crate::models::BindModel;
use crate::pipes::SignalWatch;

/// A failure to attach an output: `(is_os_error, message)`.
pub type AttachError = (bool, String);

/// One output attached to a flight.
struct Attached<M: BindModel> {
    /// What and where, e.g. `acmi /tmp/f.acmi` (shown in messages and by
    /// `Flight.outputs`).
    label: String,
    /// The file it writes, for a file output.
    file: Option<String>,
    origin: GeodeticOrigin,
    output: Box<dyn Output<M> + Send + Sync>,
}

/// What a frame's outputs are handed, besides the frame's counters.
pub struct FrameData<'a, M: BindModel> {
    /// Why this call.
    pub event: Event,
    /// Frames since the start or the last reset.
    pub number: u64,
    /// Frames flown since the flight began.
    pub flown: u64,
    /// Frames per second.
    pub fps: u32,
    /// The frame's actions, in order.
    pub actions: &'a [M::Action],
    /// The controls after the frame.
    pub controls: &'a M::Controls,
    /// The state after the frame.
    pub state: &'a M::State,
    /// The common view.
    pub view: &'a FlightView,
    /// The status after the frame.
    pub status: FlightStatus,
}

/// A flight's outputs, in the order attached.
pub struct Outputs<M: BindModel> {
    list: Vec<Attached<M>>,
    /// The FlightGear link's handle, for its counters.
    fg: Option<SharedOutput<FlightGearOutput>>,
    /// The DIS output's handle, for its report.
    #[cfg(feature = "dis")]
    dis: Option<SharedOutput<fdm_run::dis::DisOutput>>,
}

impl<M: BindModel> Default for Outputs<M> {
    fn default() -> Self {
        Self {
            list: Vec::new(),
            fg: None,
            #[cfg(feature = "dis")]
            dis: None,
        }
    }
}

impl<M: BindModel> std::fmt::Debug for Outputs<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.list.iter().map(|a| &a.label))
            .finish()
    }
}

impl<M: BindModel> Drop for Outputs<M> {
    /// A flight dropped with outputs still finishes them (best effort: an
    /// error here has no one to go to; `close_outputs` reports it).
    fn drop(&mut self) {
        let _ = self.close();
    }
}

impl<M: BindModel> Outputs<M> {
    /// Whether no output is attached.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The outputs' labels, in the order attached.
    pub fn labels(&self) -> Vec<String> {
        self.list.iter().map(|a| a.label.clone()).collect()
    }

    /// The files the file outputs write, with their labels.
    pub fn files(&self) -> impl Iterator<Item = (&str, &str)> {
        self.list
            .iter()
            .filter_map(|a| Some((a.file.as_deref()?, a.label.as_str())))
    }

    /// Attaches `output` and hands it `start` (frame 0 or the frame the
    /// flight is at: [`Event::Start`]).
    fn attach(
        &mut self,
        label: String,
        file: Option<&str>,
        origin: GeodeticOrigin,
        output: impl Output<M> + Send + 'static,
        start: &FrameData<'_, M>,
    ) -> Result<(), AttachError> {
        let mut attached = Attached {
            label,
            file: file.map(str::to_owned),
            origin,
            output: Box::new(SharedOutput::new(output)),
        };
        if let Err(e) = hand(&mut attached, start) {
            let _ = attached.output.finish();
            return Err((true, format!("{}: {e}", attached.label)));
        }
        self.list.push(attached);
        Ok(())
    }

    /// Attaches a Tacview ACMI file at `path` (zip-compressed when the name
    /// ends in `.zip.acmi`).
    ///
    /// # Errors
    /// A bad reference time, or the file cannot be created or written.
    pub fn attach_acmi(
        &mut self,
        path: &str,
        origin: GeodeticOrigin,
        reference_time: Option<&str>,
        title: Option<&str>,
        watch: &Arc<SignalWatch>,
        start: &FrameData<'_, M>,
    ) -> Result<(), AttachError> {
        let reference_time = match reference_time {
            Some(text) => text
                .parse::<ReferenceTime>()
                .map_err(|e| (false, format!("reference_time: {e}")))?,
            None => ReferenceTime::default(),
        };
        let header = AcmiHeader {
            reference_time,
            title: title.unwrap_or(M::NAME).to_owned(),
            origin: origin.geodetic(),
        };
        let cannot =
            |e: &dyn std::fmt::Display| (true, format!("cannot create ACMI file {path}: {e}"));
        let file = File::create(path).map_err(|e| cannot(&e))?;
        let file = SignalWatch::file(watch, file);
        let writer = AcmiWriter::on_file(file, Path::new(path), &header, start.fps)
            .map_err(|e| cannot(&e))?;
        self.attach(
            format!("acmi {path}"),
            Some(path),
            origin,
            AcmiOutput::<M>::new(writer),
            start,
        )
    }

    /// Attaches a CSV file at `path`: the rows of `sim-cli --csv`.
    ///
    /// # Errors
    /// The file cannot be created or written.
    pub fn attach_csv(
        &mut self,
        path: &str,
        origin: GeodeticOrigin,
        watch: &Arc<SignalWatch>,
        start: &FrameData<'_, M>,
    ) -> Result<(), AttachError> {
        let file = File::create(path)
            .map_err(|e| (true, format!("cannot create CSV file {path}: {e}")))?;
        let writer = CsvWriter::new(BufWriter::new(SignalWatch::file(watch, file)), path);
        let output = CsvOutput::new(writer, FlightRow::<M>::of as fn(&Frame<'_, M>) -> _);
        self.attach(format!("csv {path}"), Some(path), origin, output, start)
    }

    /// Attaches a FlightGear native-FDM link to `target` (`HOST:PORT`, as
    /// `sim-cli --fg` takes it): one datagram per flown frame.
    ///
    /// # Errors
    /// A target `sim-cli --fg` refuses (IPv6, broadcast, unspecified, bad
    /// syntax), a host that does not resolve, the socket cannot be made, or
    /// a FlightGear link is already attached.
    pub fn attach_flightgear(
        &mut self,
        target: &str,
        origin: GeodeticOrigin,
        start: &FrameData<'_, M>,
    ) -> Result<(), AttachError> {
        if self.fg.is_some() {
            return Err((
                false,
                "flightgear_to: a FlightGear link is already attached (close_outputs() first)"
                    .to_owned(),
            ));
        }
        let addr = parse_fg_target(target)
            .and_then(|t| t.resolve())
            .map_err(|e| {
                let os = matches!(e, FgAddressError::Resolve { .. });
                (os, format!("flightgear_to: {e}"))
            })?;
        let output = FlightGearOutput::connect(&addr.to_string(), origin)
            .map_err(|e| (true, format!("flightgear_to: {e}")))?;
        let shared = SharedOutput::new(output);
        self.attach(
            format!("flightgear {addr}"),
            None,
            origin,
            shared.clone(),
            start,
        )?;
        self.fg = Some(shared);
        Ok(())
    }

    /// The FlightGear link's datagrams sent and failed so far (the JSON
    /// report's `fg` object of `sim-cli --fg`), or `None` without one.
    pub fn flightgear_report(&self) -> Option<LinkStats> {
        self.fg
            .as_ref()
            .and_then(|f| f.with(|o| o.map(|o| o.stats())))
    }

    /// Attaches a DIS output: one entity, as `sim-cli --dis` publishes it.
    ///
    /// # Errors
    /// A setting fdm-dis refuses, the socket cannot be made, or a DIS
    /// output is already attached.
    #[cfg(feature = "dis")]
    pub fn attach_dis(
        &mut self,
        config: &fdm_run::dis::FlightDis,
        origin: GeodeticOrigin,
        start: &FrameData<'_, M>,
    ) -> Result<(), AttachError> {
        use fdm_run::dis::{DisError, DisOutput};
        if self.dis.is_some() {
            return Err((
                false,
                "dis_to: a DIS output is already attached (close_outputs() first)".to_owned(),
            ));
        }
        let output = DisOutput::open::<M>(config, origin, start.fps).map_err(|e| match e {
            DisError::Refused(message) => (false, format!("dis_to: {message}")),
            e => (true, format!("dis_to: {e}")),
        })?;
        let shared = SharedOutput::new(output);
        self.attach(
            format!("dis {}", config.settings.target),
            None,
            origin,
            shared.clone(),
            start,
        )?;
        self.dis = Some(shared);
        Ok(())
    }

    /// The DIS output's report so far (the JSON report's `dis` object of
    /// `sim-cli --dis`), or `None` without one.
    #[cfg(feature = "dis")]
    pub fn dis_report(&self) -> Option<fdm_run::dis::DisReport> {
        self.dis
            .as_ref()
            .and_then(|d| d.with(|o| o.map(|o| o.report())))
    }

    /// Hands every output `frame`. An output that fails is finished and
    /// removed; the first failure is returned (the others still get the
    /// frame).
    ///
    /// # Errors
    /// `label: message (the output is closed)`.
    pub fn emit(&mut self, frame: &FrameData<'_, M>) -> Result<(), String> {
        let mut first = None;
        let mut i = 0;
        while i < self.list.len() {
            match hand(&mut self.list[i], frame) {
                Ok(()) => i += 1,
                Err(e) => {
                    let mut failed = self.list.remove(i);
                    let _ = failed.output.finish();
                    first.get_or_insert(format!(
                        "{}: {} (the output is closed)",
                        failed.label,
                        error_text(&*e)
                    ));
                }
            }
        }
        first.map_or(Ok(()), Err)
    }

    /// Finishes and removes every output (ACMI's last time line, the CSV
    /// flushed, the DIS socket closed); all are finished even when one
    /// fails.
    ///
    /// # Errors
    /// The first failure, `label: message`.
    pub fn close(&mut self) -> Result<(), String> {
        let mut first = None;
        for mut attached in self.list.drain(..) {
            if let Err(e) = attached.output.finish() {
                first.get_or_insert(format!("{}: {}", attached.label, error_text(&*e)));
            }
        }
        self.fg = None;
        #[cfg(feature = "dis")]
        {
            self.dis = None;
        }
        first.map_or(Ok(()), Err)
    }
}

/// Hands one output its frame, placed at the output's origin.
fn hand<M: BindModel>(
    attached: &mut Attached<M>,
    f: &FrameData<'_, M>,
) -> Result<(), fdm_run::OutputError> {
    let placement = Placement::of(f.view, &attached.origin);
    attached.output.frame(&Frame {
        event: f.event,
        number: f.number,
        flown: f.flown,
        fps: f.fps,
        actions: f.actions,
        controls: f.controls,
        state: f.state,
        view: f.view,
        placement: &placement,
        status: f.status,
    })
}
