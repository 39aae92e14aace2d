//! Flight recordings: the binary flight log `--record FILE` writes and
//! `sim-cli replay FILE` reads (format: docs/recording.md).
//!
//! A recording holds what reproduces a flight bit for bit: the model, its
//! aircraft parameters, the frame rate, the origin, the controls and state at
//! frame 0, then per frame the actions the model applied (script and keys
//! together, in order) and every reset. Consecutive frames with the same
//! actions are stored once with a count, so a scripted or idle flight takes a
//! few bytes per script rule, not per frame.
//!
//! ```text
//! magic "SIMCLIRC" (8 bytes) | format version (u16, little-endian)
//! header  (bincode 2 standard: model name, fps, origin, aircraft, controls, state, action names)
//! events  (bincode 2 standard): Frames { count, actions } | Reset
//! end     (bincode 2 standard): End { frames, checksum }  -- FNV-1a 64 of every byte before it
//! ```
//!
//! Reading is bounded and total: `sim-cli replay` reads at most
//! [`MAX_RECORDING_BYTES`] (`crate::input::read_bytes`: a regular file or a pipe);
//! [`parse_recording`] and [`Recording::parse`] take a byte slice, decode with a
//! [`DECODE_LIMIT`] on what any one length field may claim, and return a
//! [`RecordingError`] naming the problem for anything that is not a complete,
//! intact recording of this format version; they never panic.
//!
//! Writing goes through [`Recorded`], a [`Flight`] wrapper that logs every
//! step and reset of the flight it wraps, so the headless and interactive
//! loops record without knowing it.

use std::fmt;
use std::io::Write;
use std::marker::PhantomData;

use anyhow::Context as _;
use bincode::config::{Configuration, Limit, LittleEndian, Varint};
use bincode::error::DecodeError;
use fdm_core::geodesy::{Geodetic, GeodeticOrigin};
use fdm_core::script::{Echo, ScriptAction};
use serde::{Deserialize, Serialize};

use crate::args::{ModelKind, MAX_FPS, MAX_FRAMES};
use crate::config::Start;
use crate::hud::LinkStats;
use crate::models::{CliModel, WithModel};
use crate::run::Flight;
use crate::snapshot::Snapshot;

/// The first eight bytes of every recording.
pub const MAGIC: [u8; 8] = *b"SIMCLIRC";

/// The format version this `sim-cli` writes and reads (the two bytes after
/// [`MAGIC`], little-endian). Any change to the layout bumps it.
pub const FORMAT_VERSION: u16 = 1;

/// Largest recording `sim-cli` writes or reads, bytes (64 MiB). Hours of
/// interactive flying with a key change every frame take a few MB; a longer
/// recording stops the flight with an error rather than produce a file that
/// could not be replayed.
pub const MAX_RECORDING_BYTES: u64 = 64 * 1024 * 1024;

/// Most bytes one header or one event may claim for its variable-length
/// fields (strings, action lists): 1 MiB. A length field beyond it is refused
/// before anything is allocated.
pub const DECODE_LIMIT: usize = 1 << 20;

/// The bincode configuration of every header and event: bincode 2's standard
/// (little-endian, variable-length integers), with [`DECODE_LIMIT`].
type Format = Configuration<LittleEndian, Varint, Limit<DECODE_LIMIT>>;

fn format() -> Format {
    bincode::config::standard().with_limit::<DECODE_LIMIT>()
}

/// Length of the fixed prefix: magic and version.
const PREFIX_LEN: usize = MAGIC.len() + 2;

/// The header as stored (owned, for decoding and encoding alike).
#[derive(Debug, Serialize, Deserialize)]
struct Header<A, C, S> {
    /// The model's name ([`fdm_core::model::Model::NAME`]), first so that a
    /// reader can pick the model before decoding the rest.
    model: String,
    /// Frames per second.
    fps: u32,
    /// The earth-frame origin.
    origin: Geodetic,
    /// The aircraft's parameters ([`CliModel::AircraftRecord`]).
    aircraft: A,
    /// Controls at frame 0 (and after every reset).
    controls: C,
    /// State at frame 0 (and after every reset).
    state: S,
    /// The names of the actions the events index, in index order.
    actions: Vec<String>,
}

/// One event of the log as stored.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
enum Event {
    /// `count` (>= 1) consecutive frames, each applying `actions` (indices
    /// into the header's action names) in order before its step.
    Frames {
        /// How many frames.
        count: u64,
        /// The frame's actions.
        actions: Vec<u16>,
    },
    /// The flight went back to the header's controls and state (frame 0).
    Reset,
    /// The last event: the total number of frames and the checksum of every
    /// byte before this event.
    End {
        /// Frames in all [`Event::Frames`] together.
        frames: u64,
        /// FNV-1a 64 of the file up to this event.
        checksum: u64,
    },
}

/// FNV-1a, 64 bits: any change of a single byte changes the result (each
/// step is a bijection of the state for a given byte).
#[derive(Debug, Clone, Copy)]
struct Fnv64(u64);

impl Fnv64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    fn new() -> Self {
        Self(Self::OFFSET)
    }

    fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(Self::PRIME);
        }
    }
}

/// Why a recording was refused. Every message names the problem in one line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RecordingError {
    /// Larger than [`MAX_RECORDING_BYTES`].
    #[error(
        "the file is {size} bytes, more than the {MAX_RECORDING_BYTES}-byte limit for recordings"
    )]
    TooLarge {
        /// The size seen (at least).
        size: u64,
    },
    /// Does not start with [`MAGIC`].
    #[error("not a sim-cli recording (it does not start with the bytes \"SIMCLIRC\")")]
    NotARecording,
    /// Another format version.
    #[error("recording format version {found}; this sim-cli reads version {FORMAT_VERSION}")]
    WrongVersion {
        /// The version in the file.
        found: u16,
    },
    /// A model this `sim-cli` does not have (the name as stored).
    #[error("recorded with model `{}`, which this sim-cli does not have (palmer, bourg)", Echo::short(.0))]
    UnknownModel(String),
    /// A recording of another model than the one asked for.
    #[error("a recording of model `{}`, not `{expected}`", Echo::short(.found))]
    WrongModel {
        /// The model asked for.
        expected: &'static str,
        /// The model in the file.
        found: String,
    },
    /// The file ends early.
    #[error("truncated: the file ends {0}")]
    Truncated(&'static str),
    /// Anything else that is not a well-formed recording.
    #[error("corrupt recording: {0}")]
    Corrupt(String),
}

impl RecordingError {
    fn corrupt(message: impl fmt::Display) -> Self {
        Self::Corrupt(message.to_string())
    }

    /// A bincode error while decoding `what`: running out of bytes is a
    /// truncation, anything else corruption.
    fn decode(error: &DecodeError, what: &'static str, truncated: &'static str) -> Self {
        match error {
            DecodeError::UnexpectedEnd { .. } => Self::Truncated(truncated),
            DecodeError::LimitExceeded => Self::Corrupt(format!(
                "{what}: a length field claims more than {DECODE_LIMIT} bytes"
            )),
            other => Self::Corrupt(format!("{what}: {other}")),
        }
    }
}

/// Reads magic, version and model name.
fn prefix(bytes: &[u8]) -> Result<(String, &[u8]), RecordingError> {
    if bytes.len() as u64 > MAX_RECORDING_BYTES {
        return Err(RecordingError::TooLarge {
            size: bytes.len() as u64,
        });
    }
    let Some(magic) = bytes.get(..MAGIC.len()) else {
        return Err(if MAGIC.starts_with(bytes) {
            RecordingError::Truncated("inside the magic bytes")
        } else {
            RecordingError::NotARecording
        });
    };
    if magic != MAGIC {
        return Err(RecordingError::NotARecording);
    }
    let Some(&[lo, hi]) = bytes.get(MAGIC.len()..PREFIX_LEN) else {
        return Err(RecordingError::Truncated("inside the format version"));
    };
    let version = u16::from_le_bytes([lo, hi]);
    if version != FORMAT_VERSION {
        return Err(RecordingError::WrongVersion { found: version });
    }
    let rest = &bytes[PREFIX_LEN..];
    let (model, _) = bincode::serde::decode_from_slice::<String, _>(rest, format())
        .map_err(|e| RecordingError::decode(&e, "model name", "inside the header"))?;
    Ok((model, rest))
}

/// The model a recording was made with, from its first bytes.
///
/// # Errors
/// As [`parse_recording`], for the prefix only.
pub fn recorded_model(bytes: &[u8]) -> Result<ModelKind, RecordingError> {
    let (model, _) = prefix(bytes)?;
    <ModelKind as clap::ValueEnum>::value_variants()
        .iter()
        .copied()
        .find(|kind| kind.name() == model)
        .ok_or(RecordingError::UnknownModel(model))
}

/// What [`parse_recording`] found in a valid recording.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordingInfo {
    /// The model's name.
    pub model: &'static str,
    /// Frames per second.
    pub fps: u32,
    /// Frames in total, across resets.
    pub frames: u64,
    /// Resets.
    pub resets: u64,
    /// Events (runs of identical frames and resets).
    pub events: u64,
}

struct ParseJob<'a>(&'a [u8]);

impl WithModel for ParseJob<'_> {
    type Output = Result<RecordingInfo, RecordingError>;

    fn call<M: CliModel>(self) -> Self::Output {
        Recording::<M>::parse(self.0).map(|r| r.info())
    }
}

/// Checks a whole recording of any model, as `sim-cli replay` does before
/// flying it: pure, total (never panics) and bounded, for tests and fuzzing.
///
/// # Errors
/// A [`RecordingError`] naming the first problem.
pub fn parse_recording(bytes: &[u8]) -> Result<RecordingInfo, RecordingError> {
    recorded_model(bytes)?.with(ParseJob(bytes))
}

/// One step of a replay.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Replayed<A> {
    /// `count` frames, each applying `actions` in order.
    Frames {
        /// How many frames (>= 1).
        count: u64,
        /// The actions of each of those frames.
        actions: Vec<A>,
    },
    /// Back to the recording's start (frame 0).
    Reset,
}

/// A validated recording of model `M`, borrowing the file's bytes.
#[derive(Debug)]
pub struct Recording<'a, M: CliModel> {
    /// Frames per second.
    pub fps: u32,
    /// The earth-frame origin.
    pub origin: GeodeticOrigin,
    /// Aircraft, controls and state at frame 0.
    pub start: Start<M>,
    /// Frames in total, across resets.
    pub frames: u64,
    /// Resets.
    pub resets: u64,
    /// Events (runs and resets).
    pub events: u64,
    table: Vec<M::Action>,
    body: &'a [u8],
}

impl<'a, M: CliModel> Recording<'a, M> {
    /// Parses and validates a whole recording: prefix, header (model `M`,
    /// fps, origin, aircraft, action names), every event, the end marker and
    /// its checksum, and that nothing follows it.
    ///
    /// # Errors
    /// A [`RecordingError`] naming the first problem.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, RecordingError> {
        let (model, rest) = prefix(bytes)?;
        if model != M::NAME {
            return Err(RecordingError::WrongModel {
                expected: M::NAME,
                found: model,
            });
        }
        type H<M> = Header<
            <M as CliModel>::AircraftRecord,
            <M as fdm_core::model::Model>::Controls,
            <M as fdm_core::model::Model>::State,
        >;
        let (header, used) = bincode::serde::decode_from_slice::<H<M>, _>(rest, format())
            .map_err(|e| RecordingError::decode(&e, "header", "inside the header"))?;
        if !(1..=MAX_FPS).contains(&header.fps) {
            return Err(RecordingError::corrupt(format!(
                "header: fps {} is not in 1..={MAX_FPS}",
                header.fps
            )));
        }
        let origin = GeodeticOrigin::from_geodetic(header.origin)
            .map_err(|e| RecordingError::corrupt(format!("header: origin: {e}")))?;
        let aircraft = M::aircraft_from_record(header.aircraft)
            .map_err(|e| RecordingError::corrupt(format!("header: aircraft: {e}")))?;
        let table = header
            .actions
            .iter()
            .map(|name| {
                <M::Action as ScriptAction>::from_name(name).ok_or_else(|| {
                    RecordingError::corrupt(format!(
                        "header: `{}` is not an action of {}",
                        Echo::short(name),
                        M::NAME
                    ))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let body = &rest[used..];
        let mut recording = Self {
            fps: header.fps,
            origin,
            start: Start {
                aircraft,
                controls: header.controls,
                state: header.state,
            },
            frames: 0,
            resets: 0,
            events: 0,
            table,
            body,
        };
        recording.validate(bytes)?;
        Ok(recording)
    }

    /// Walks the events once: indices in range, counts >= 1, the end
    /// marker's frame count and checksum, nothing after it.
    fn validate(&mut self, whole: &[u8]) -> Result<(), RecordingError> {
        let mut cursor = self.body;
        let mut frames = 0_u64;
        loop {
            let offset = whole.len() - cursor.len();
            let (event, used) = decode_event(cursor, offset)?;
            match event {
                Event::Frames { count, actions } => {
                    self.check_frames(count, &actions, offset)?;
                    frames = frames.checked_add(count).ok_or_else(|| {
                        RecordingError::corrupt(format!(
                            "event at byte {offset}: the frame count overflows"
                        ))
                    })?;
                    self.events += 1;
                }
                Event::Reset => {
                    self.resets += 1;
                    self.events += 1;
                }
                Event::End {
                    frames: total,
                    checksum,
                } => {
                    let mut hash = Fnv64::new();
                    hash.update(&whole[..offset]);
                    if hash.0 != checksum {
                        return Err(RecordingError::corrupt(format!(
                            "checksum mismatch (stored {checksum:#018x}, computed {:#018x})",
                            hash.0
                        )));
                    }
                    if total != frames {
                        return Err(RecordingError::corrupt(format!(
                            "the end marker counts {total} frames, the events {frames}"
                        )));
                    }
                    if frames > MAX_FRAMES {
                        return Err(RecordingError::corrupt(format!(
                            "{frames} frames, more than the {MAX_FRAMES} a run can have"
                        )));
                    }
                    let trailing = cursor.len() - used;
                    if trailing != 0 {
                        return Err(RecordingError::corrupt(format!(
                            "{trailing} bytes after the end marker"
                        )));
                    }
                    self.frames = frames;
                    // The body the iterator walks stops before the end marker.
                    self.body = &self.body[..self.body.len() - cursor.len()];
                    return Ok(());
                }
            }
            cursor = &cursor[used..];
        }
    }

    fn check_frames(
        &self,
        count: u64,
        actions: &[u16],
        offset: usize,
    ) -> Result<(), RecordingError> {
        if count == 0 {
            return Err(RecordingError::corrupt(format!(
                "event at byte {offset}: a run of 0 frames"
            )));
        }
        if let Some(&bad) = actions
            .iter()
            .find(|&&i| usize::from(i) >= self.table.len())
        {
            return Err(RecordingError::corrupt(format!(
                "event at byte {offset}: action index {bad} is not below the header's {} actions",
                self.table.len()
            )));
        }
        Ok(())
    }

    /// What a summary needs.
    #[must_use]
    pub fn info(&self) -> RecordingInfo {
        RecordingInfo {
            model: M::NAME,
            fps: self.fps,
            frames: self.frames,
            resets: self.resets,
            events: self.events,
        }
    }

    /// The events in order (already validated by [`Self::parse`]; each item is
    /// still a `Result`, so that nothing here can panic).
    pub fn events(&self) -> impl Iterator<Item = Result<Replayed<M::Action>, RecordingError>> + '_ {
        let mut cursor = self.body;
        let mut offset = 0;
        std::iter::from_fn(move || {
            if cursor.is_empty() {
                return None;
            }
            let item = decode_event(cursor, offset).and_then(|(event, used)| {
                cursor = &cursor[used..];
                offset += used;
                match event {
                    Event::Frames { count, actions } => Ok(Replayed::Frames {
                        count,
                        actions: actions
                            .iter()
                            .map(|&i| {
                                self.table.get(usize::from(i)).copied().ok_or_else(|| {
                                    RecordingError::corrupt(format!("action index {i}"))
                                })
                            })
                            .collect::<Result<_, _>>()?,
                    }),
                    Event::Reset => Ok(Replayed::Reset),
                    Event::End { .. } => Err(RecordingError::corrupt("end marker inside the body")),
                }
            });
            if item.is_err() {
                cursor = &[];
            }
            Some(item)
        })
    }
}

fn decode_event(bytes: &[u8], offset: usize) -> Result<(Event, usize), RecordingError> {
    if bytes.is_empty() {
        return Err(RecordingError::Truncated("before its end marker"));
    }
    bincode::serde::decode_from_slice::<Event, _>(bytes, format()).map_err(|e| match e {
        DecodeError::UnexpectedEnd { .. } => RecordingError::Truncated("before its end marker"),
        other => {
            RecordingError::decode(&other, "event", "before its end marker").with_offset(offset)
        }
    })
}

impl RecordingError {
    fn with_offset(self, offset: usize) -> Self {
        match self {
            Self::Corrupt(message) => Self::Corrupt(format!("{message} (at byte {offset})")),
            other => other,
        }
    }
}

/// Writes a recording as a flight goes: header first, then runs of identical
/// frames and resets, and the end marker on [`Self::finish`].
#[derive(Debug)]
pub struct RecordWriter<A, W: Write> {
    out: W,
    hash: Fnv64,
    written: u64,
    /// The current run: its action indices and length (0: no run yet).
    run: Vec<u16>,
    run_count: u64,
    scratch: Vec<u16>,
    frames: u64,
    finished: bool,
    _actions: PhantomData<A>,
}

impl<A: ScriptAction + PartialEq, W: Write> RecordWriter<A, W> {
    /// Starts a recording of model `M` flown at `fps` from `origin` and
    /// `start`: writes the magic, the version and the header.
    ///
    /// # Errors
    /// Encoding or writing fails.
    pub fn new<M: CliModel<Action = A>>(
        out: W,
        fps: u32,
        origin: &GeodeticOrigin,
        start: &Start<M>,
    ) -> anyhow::Result<Self> {
        let mut writer = Self {
            out,
            hash: Fnv64::new(),
            written: 0,
            run: Vec::new(),
            run_count: 0,
            scratch: Vec::new(),
            frames: 0,
            finished: false,
            _actions: PhantomData,
        };
        writer.put(&MAGIC)?;
        writer.put(&FORMAT_VERSION.to_le_bytes())?;
        let header = Header {
            model: M::NAME.to_owned(),
            fps,
            origin: origin.geodetic(),
            aircraft: M::aircraft_record(&start.aircraft),
            controls: start.controls,
            state: start.state,
            actions: A::NAMES.iter().map(|&n| n.to_owned()).collect(),
        };
        let bytes = bincode::serde::encode_to_vec(&header, format())
            .context("encoding the recording's header")?;
        writer.put(&bytes)?;
        Ok(writer)
    }

    fn put(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        self.written += bytes.len() as u64;
        if self.written > MAX_RECORDING_BYTES {
            anyhow::bail!("the recording would exceed {MAX_RECORDING_BYTES} bytes, the most `sim-cli replay` reads");
        }
        self.hash.update(bytes);
        self.out.write_all(bytes).context("writing the recording")
    }

    fn put_event(&mut self, event: &Event) -> anyhow::Result<()> {
        let bytes =
            bincode::serde::encode_to_vec(event, format()).context("encoding a recording event")?;
        self.put(&bytes)
    }

    fn flush_run(&mut self) -> anyhow::Result<()> {
        if self.run_count > 0 {
            let event = Event::Frames {
                count: self.run_count,
                actions: std::mem::take(&mut self.run),
            };
            self.put_event(&event)?;
            if let Event::Frames { actions, .. } = event {
                self.run = actions;
            }
            self.run_count = 0;
        }
        Ok(())
    }

    /// Records one frame that applied `actions` in order.
    ///
    /// # Errors
    /// Writing fails, or the recording outgrows [`MAX_RECORDING_BYTES`].
    pub fn frame(&mut self, actions: &[A]) -> anyhow::Result<()> {
        self.scratch.clear();
        for action in actions {
            let index = A::ALL
                .iter()
                .position(|a| a == action)
                .and_then(|i| u16::try_from(i).ok())
                .context("an action outside the model's action list")?;
            self.scratch.push(index);
        }
        if self.run_count > 0 && self.scratch != self.run {
            self.flush_run()?;
        }
        if self.run_count == 0 {
            std::mem::swap(&mut self.run, &mut self.scratch);
        }
        self.run_count += 1;
        self.frames += 1;
        Ok(())
    }

    /// Records a reset.
    ///
    /// # Errors
    /// As [`Self::frame`].
    pub fn reset(&mut self) -> anyhow::Result<()> {
        self.flush_run()?;
        self.put_event(&Event::Reset)
    }

    /// Writes the last run and the end marker and flushes. Later calls do
    /// nothing.
    ///
    /// # Errors
    /// As [`Self::frame`], and flushing.
    pub fn finish(&mut self) -> anyhow::Result<()> {
        if self.finished {
            return Ok(());
        }
        self.flush_run()?;
        let end = Event::End {
            frames: self.frames,
            checksum: self.hash.0,
        };
        self.put_event(&end)?;
        self.out.flush().context("writing the recording")?;
        self.finished = true;
        Ok(())
    }

    /// Bytes written so far.
    #[must_use]
    pub fn bytes_written(&self) -> u64 {
        self.written
    }

    /// The underlying writer (finish first).
    pub fn into_inner(self) -> W {
        self.out
    }
}

/// A [`Flight`] that records every step and reset of the flight it wraps.
#[derive(Debug)]
pub struct Recorded<F: Flight, W: Write> {
    flight: F,
    writer: RecordWriter<F::Action, W>,
}

impl<F: Flight, W: Write> Recorded<F, W>
where
    F::Action: PartialEq,
{
    /// Wraps `flight`; `writer` has written the header of the flight's start.
    pub fn new(flight: F, writer: RecordWriter<F::Action, W>) -> Self {
        Self { flight, writer }
    }

    /// The wrapped flight.
    #[must_use]
    pub fn flight(&self) -> &F {
        &self.flight
    }

    /// The flight and the writer, for tests and callers that finish themselves.
    pub fn into_parts(self) -> (F, RecordWriter<F::Action, W>) {
        (self.flight, self.writer)
    }
}

impl<F: Flight, W: Write> Flight for Recorded<F, W>
where
    F::Action: PartialEq,
{
    type Action = F::Action;
    type Details = F::Details;

    const TITLE: &'static str = F::TITLE;

    fn step(&mut self, actions: &[Self::Action]) -> anyhow::Result<()> {
        self.writer.frame(actions)?;
        self.flight.step(actions)
    }

    fn reset(&mut self) -> anyhow::Result<()> {
        self.writer.reset()?;
        self.flight.reset()
    }

    fn snapshot(&self) -> Snapshot<Self::Details> {
        self.flight.snapshot()
    }

    fn link_stats(&self) -> Option<LinkStats> {
        self.flight.link_stats()
    }

    fn take_link_failure(&mut self) -> Option<String> {
        self.flight.take_link_failure()
    }

    fn dis_report(&self) -> Option<crate::dis::DisReport> {
        self.flight.dis_report()
    }

    fn finish(&mut self) -> anyhow::Result<()> {
        self.flight.finish()?;
        self.writer.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Mode, RunConfig};
    use crate::csv::CsvWriter;
    use crate::flight::ModelFlight;
    use crate::keys::{AppCommand, Input};
    use crate::progress::StderrProgress;
    use crate::replay::replay_flight;
    use crate::report::Report;
    use crate::run::{run_headless, Flow, Session};
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::{Palmer, PalmerControls};
    use fdm_core::script::Script;
    use proptest::prelude::*;

    const PALMER_SCRIPT: &str = "1-20 throttle-up\n1-5 alpha-up\n300-310 bank-right\n\
                                 400-410 bank-left\n500-501 flaps-down\n";
    const BOURG_SCRIPT: &str = "1-5 thrust-up\n6-246 pitch-up\n247-307 roll-right\n\
                                400-420 yaw-left\n430-431 flaps-down\n";

    fn origin() -> GeodeticOrigin {
        "37.6,-122.4,4".parse().unwrap()
    }

    fn run_config(fps: u32) -> RunConfig {
        RunConfig {
            fps,
            mode: Mode::Headless {
                frames: 0,
                json: true,
                realtime: false,
            },
            csv: None,
            fg: None,
            origin: origin(),
            plot: None,
            dis: None,
        }
    }

    fn quiet(frames: u64) -> StderrProgress {
        StderrProgress::with_enabled(frames, false)
    }

    /// What a flight produced: the JSON report, the CSV, and the recording.
    struct Outcome {
        json: String,
        csv: Vec<u8>,
        recording: Vec<u8>,
    }

    /// A headless flight of `frames` frames with `script`, recorded.
    fn headless<M: CliModel>(start: Start<M>, fps: u32, script: &str, frames: u64) -> Outcome {
        let run = run_config(fps);
        let writer = RecordWriter::new(Vec::new(), fps, &run.origin, &start).unwrap();
        let flight = ModelFlight::new(&run, start).unwrap();
        let mut flight = Recorded::new(flight, writer);
        let script = Script::parse(script).unwrap();
        let mut csv = CsvWriter::new(Vec::new(), "csv");
        let report = run_headless(
            &mut flight,
            &script,
            fps,
            frames,
            false,
            Some(&mut csv),
            &mut quiet(frames),
        )
        .unwrap();
        flight.finish().unwrap();
        Outcome {
            json: report.to_json().unwrap(),
            csv: csv.finish().unwrap(),
            recording: flight.into_parts().1.into_inner(),
        }
    }

    /// An interactive-style flight: `frames` frames of the interactive
    /// [`Session`] with synthetic key presses (every action of the model,
    /// pauses and resets, from a fixed pseudo-random sequence) on top of
    /// `script`, recorded. The report is what a headless run of the same
    /// frames would print.
    fn interactive<M: CliModel>(start: Start<M>, fps: u32, script: &str, frames: u64) -> Outcome {
        let run = run_config(fps);
        let writer = RecordWriter::new(Vec::new(), fps, &run.origin, &start).unwrap();
        let flight = ModelFlight::new(&run, start).unwrap();
        let mut flight = Recorded::new(flight, writer);
        let script = Script::parse(script).unwrap();
        let mut csv = CsvWriter::new(Vec::new(), "csv");
        csv.write_record(0, &flight.snapshot()).unwrap();
        let mut session = Session::new();
        let actions = <M::Action as ScriptAction>::ALL;
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut resets = 0;
        for frame in 0..frames {
            if frame == frames / 2 {
                session
                    .handle(Input::App(AppCommand::Reset), &mut flight, Some(&mut csv))
                    .unwrap();
                resets += 1;
            }
            // xorshift64: a fixed, model-independent key sequence.
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let keys = seed % 4;
            for k in 0..keys {
                let pick = (seed >> (8 + 8 * k)) % 200;
                let input = match pick {
                    0 => Input::App(AppCommand::Reset),
                    1 | 2 => Input::App(AppCommand::Pause),
                    n => Input::Action(actions[n as usize % actions.len()]),
                };
                resets += u32::from(input == Input::App(AppCommand::Reset));
                let flow = session.handle(input, &mut flight, Some(&mut csv)).unwrap();
                assert_eq!(flow, Flow::Continue);
            }
            session
                .advance(&mut flight, &script, Some(&mut csv))
                .unwrap();
        }
        assert!(resets > 0, "the key sequence should reset at least once");
        flight.finish().unwrap();
        let report = Report::new(fps, session.total_frames(), &flight.snapshot());
        Outcome {
            json: report.to_json().unwrap(),
            csv: csv.finish().unwrap(),
            recording: flight.into_parts().1.into_inner(),
        }
    }

    /// Replays `bytes` as `sim-cli replay --json --csv` does.
    fn replay<M: CliModel>(bytes: &[u8]) -> (String, Vec<u8>) {
        let recording = Recording::<M>::parse(bytes).unwrap();
        let run = RunConfig {
            origin: recording.origin,
            ..run_config(recording.fps)
        };
        let mut flight = ModelFlight::new(&run, recording.start.clone()).unwrap();
        let mut csv = CsvWriter::new(Vec::new(), "csv");
        let report = replay_flight(
            &mut flight,
            recording.events(),
            recording.fps,
            recording.frames,
            false,
            Some(&mut csv),
            &mut quiet(recording.frames),
        )
        .unwrap();
        (report.to_json().unwrap(), csv.finish().unwrap())
    }

    fn palmer_start() -> Start<Palmer> {
        Start {
            controls: PalmerControls {
                throttle: 0.5,
                alpha_deg: 2.0,
                ..PalmerControls::default()
            },
            ..Start::thesis()
        }
    }

    /// Bit-identical: the JSON prints every f64 in its shortest round-trip
    /// form (so equal text is equal bits) and the CSV likewise; tolerance 0.
    #[test]
    fn scripted_flights_replay_to_the_same_json_and_csv() {
        let p = headless(palmer_start(), 30, PALMER_SCRIPT, 1800);
        assert_eq!(replay::<Palmer>(&p.recording), (p.json, p.csv));
        let b = headless(Start::<Bourg>::thesis(), 30, BOURG_SCRIPT, 900);
        assert_eq!(replay::<Bourg>(&b.recording), (b.json, b.csv));
    }

    #[test]
    fn interactive_flights_with_pauses_and_resets_replay_to_the_same_json_and_csv() {
        let p = interactive(palmer_start(), 30, PALMER_SCRIPT, 2000);
        let info = parse_recording(&p.recording).unwrap();
        assert!(info.resets > 0 && info.frames > 0, "{info:?}");
        assert_eq!(replay::<Palmer>(&p.recording), (p.json, p.csv));
        let b = interactive(Start::<Bourg>::thesis(), 60, BOURG_SCRIPT, 2000);
        assert!(parse_recording(&b.recording).unwrap().resets > 0);
        assert_eq!(replay::<Bourg>(&b.recording), (b.json, b.csv));
    }

    #[test]
    fn the_header_carries_fps_origin_and_start() {
        let p = headless(palmer_start(), 25, "", 10);
        let r = Recording::<Palmer>::parse(&p.recording).unwrap();
        assert_eq!((r.fps, r.origin, r.frames, r.resets), (25, origin(), 10, 0));
        assert_eq!(r.start.controls, palmer_start().controls);
        assert_eq!(r.start.state, palmer_start().state);
        assert_eq!(r.start.aircraft, palmer_start().aircraft);
        let b = headless(Start::<Bourg>::thesis(), 30, "", 1);
        let r = Recording::<Bourg>::parse(&b.recording).unwrap();
        assert_eq!(r.start.aircraft, Bourg::default_aircraft());
        assert_eq!(r.start.state, Bourg::initial_state());
    }

    /// Identical frames are stored once: an idle flight is one event, a
    /// scripted one an event per change of the frame's actions.
    #[test]
    fn runs_of_identical_frames_are_one_event() {
        let idle = headless(palmer_start(), 30, "", 100_000);
        let info = parse_recording(&idle.recording).unwrap();
        assert_eq!((info.events, info.frames), (1, 100_000));
        let short = headless(palmer_start(), 30, "", 1);
        // Only the run's count and the end marker's total grow, each from 1
        // byte of varint to 5 (tag 251 + u32).
        assert_eq!(idle.recording.len(), short.recording.len() + 8);
        let scripted = headless(palmer_start(), 30, PALMER_SCRIPT, 1800);
        // 1-5 (2 actions), 6-20, 21-299 idle, 300-310, idle, 400-410, idle, 500-501, idle.
        assert_eq!(parse_recording(&scripted.recording).unwrap().events, 9);
    }

    /// An interactive-style Palmer recording with resets (made once).
    fn sample() -> Vec<u8> {
        static SAMPLE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
        SAMPLE
            .get_or_init(|| interactive(palmer_start(), 30, PALMER_SCRIPT, 300).recording)
            .clone()
    }

    #[test]
    fn every_truncation_is_refused() {
        let bytes = sample();
        for len in 0..bytes.len() {
            let err = parse_recording(&bytes[..len]).unwrap_err();
            assert!(matches!(err, RecordingError::Truncated(_)), "{len}: {err}");
        }
    }

    /// FNV-1a detects any single-byte change before the end marker, and the
    /// marker's own bytes are checked against the events: every one-byte
    /// change anywhere is refused.
    #[test]
    fn every_single_byte_change_is_refused() {
        let bytes = sample();
        for i in 0..bytes.len() {
            for mask in [0x01, 0x80, 0xff] {
                let mut bad = bytes.clone();
                bad[i] ^= mask;
                assert!(parse_recording(&bad).is_err(), "byte {i} ^ {mask:#x}");
            }
        }
    }

    #[test]
    fn wrong_version_model_magic_and_trailing_bytes_are_named() {
        let bytes = sample();
        let mut v2 = bytes.clone();
        v2[8] = 2;
        assert_eq!(
            parse_recording(&v2).unwrap_err().to_string(),
            "recording format version 2; this sim-cli reads version 1"
        );
        assert_eq!(
            Recording::<Bourg>::parse(&bytes).unwrap_err(),
            RecordingError::WrongModel {
                expected: "bourg",
                found: "palmer".to_owned()
            }
        );
        // A model name this sim-cli does not know (same length as "palmer").
        let mut glider = bytes.clone();
        let at = bytes.windows(6).position(|w| w == b"palmer").unwrap();
        glider[at..at + 6].copy_from_slice(b"glider");
        assert_eq!(
            parse_recording(&glider).unwrap_err(),
            RecordingError::UnknownModel("glider".to_owned())
        );
        // Control characters in a stored name are escaped in the message.
        let mut bell = bytes.clone();
        bell[at + 2] = 0x07;
        let message = parse_recording(&bell).unwrap_err().to_string();
        assert!(message.contains("`pa\\u{7}mer`"), "{message}");
        let mut magic = bytes.clone();
        magic[0] = b'X';
        assert_eq!(parse_recording(&magic), Err(RecordingError::NotARecording));
        let mut trailing = bytes.clone();
        trailing.push(0);
        assert!(parse_recording(&trailing)
            .unwrap_err()
            .to_string()
            .contains("1 bytes after the end marker"));
        assert!(parse_recording(&bytes).is_ok());
    }

    /// A well-formed recording of more frames than any run may have (here
    /// 2^40, written by hand) is refused rather than replayed for ever.
    #[test]
    fn endless_recordings_are_refused() {
        let start = palmer_start();
        let mut writer =
            RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin(), &start).unwrap();
        writer.run_count = 1 << 40;
        writer.frames = 1 << 40;
        writer.finish().unwrap();
        let err = parse_recording(&writer.into_inner()).unwrap_err();
        assert!(
            err.to_string().contains("more than the 1000000000"),
            "{err}"
        );
    }

    #[test]
    fn lengths_beyond_the_limits_are_refused_without_allocating() {
        // A header whose model name claims 2^60 bytes.
        let mut huge = MAGIC.to_vec();
        huge.extend(FORMAT_VERSION.to_le_bytes());
        huge.push(253); // varint tag: u64 follows
        huge.extend((1_u64 << 60).to_le_bytes());
        assert!(matches!(
            parse_recording(&huge),
            Err(RecordingError::Corrupt(_) | RecordingError::Truncated(_))
        ));
        let too_big = vec![0_u8; usize::try_from(MAX_RECORDING_BYTES).unwrap() + 1];
        assert!(matches!(
            parse_recording(&too_big),
            Err(RecordingError::TooLarge { .. })
        ));
    }

    #[test]
    fn an_unfinished_recording_is_truncated() {
        let start = palmer_start();
        let mut writer =
            RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin(), &start).unwrap();
        writer.frame(&[]).unwrap();
        writer.reset().unwrap();
        let bytes = writer.into_inner();
        assert_eq!(
            parse_recording(&bytes),
            Err(RecordingError::Truncated("before its end marker"))
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Mangled recordings (cut, bytes overwritten, inserted or removed)
        /// never panic the parser, and a mangled file that still parses is
        /// the original (nothing else gets past the checksum).
        #[test]
        fn mangled_recordings_never_panic(
            cut in any::<prop::sample::Index>(),
            edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0..3_u8), 0..6),
        ) {
            let original = sample();
            let mut bytes = original.clone();
            for (at, byte, kind) in edits {
                if bytes.is_empty() {
                    break;
                }
                let i = at.index(bytes.len());
                match kind {
                    0 => bytes[i] = byte,
                    1 => bytes.insert(i, byte),
                    _ => { bytes.remove(i); }
                }
            }
            let keep = cut.index(bytes.len() + 1);
            if keep < bytes.len() && keep % 2 == 0 {
                bytes.truncate(keep);
            }
            if let Ok(info) = parse_recording(&bytes) {
                prop_assert_eq!(&bytes, &original);
                prop_assert_eq!(info.model, "palmer");
            }
        }

        /// Arbitrary bytes after a valid prefix never panic either.
        #[test]
        fn arbitrary_bodies_never_panic(body in prop::collection::vec(any::<u8>(), 0..512)) {
            let mut bytes = MAGIC.to_vec();
            bytes.extend(FORMAT_VERSION.to_le_bytes());
            bytes.extend(&body);
            let _ = parse_recording(&bytes);
            let mut bytes = sample();
            let header_end = bytes.len().saturating_sub(20);
            bytes.truncate(header_end);
            bytes.extend(&body);
            let _ = parse_recording(&bytes);
        }
    }
}
