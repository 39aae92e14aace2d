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
//! blocks, each: payload length (u32 LE) | events (bincode 2 standard) | FNV-1a 64 of every byte
//!         of the file before this checksum (u64 LE)
//!   events: Frames { count, actions } | Reset
//! end block: one event End { frames, checksum }  -- FNV-1a 64 of every byte before the end block
//!         (version 3: Sealed { frames, checksum, state, maths }, the same plus the flight's
//!         fingerprint: a hash of the final state's bits and fdm_core::fingerprint::maths())
//! ```
//!
//! Crash safety (version 2): the writer closes a block after every second of
//! flight (fps frames) and hands it to the OS, so a recording cut anywhere (the
//! process killed, the machine stopped) still holds every block before the cut.
//! [`Recording::parse_salvaging`] replays those and says where the file was cut
//! ([`Cut`]); [`Recording::parse`] takes only complete recordings. Version 1
//! files (one event stream, no blocks) are still read, complete only.
//!
//! The fingerprint (version 3): the end marker also carries the hash of the
//! flight's final state ([`RunModel::state_fingerprint`]) and of the maths
//! that flew it ([`fdm_core::fingerprint::maths`]), so that `sim-cli replay`
//! can tell a replay that flew another flight (other maths, another build,
//! another machine whose bits differ) from one that flew the recorded one
//! ([`Recording::fingerprint`]). Versions 1 and 2 have none.
//!
//! Reading is bounded and total: `sim-cli replay` reads at most
//! [`MAX_RECORDING_BYTES`] (`crate::input::read_bytes`: a regular file or a pipe);
//! [`parse_recording`] and [`Recording::parse`] take a byte slice, decode with a
//! [`DECODE_LIMIT`] on what any one length field may claim, and return a
//! [`RecordingError`] naming the problem for anything that is not a complete,
//! intact recording of this format version; they never panic.
//!
//! Writing goes through [`RecordWriter`], which is also an
//! [`Output`]: attached to a [`Run`](crate::Run), it logs every
//! frame's actions and every reset as the run flies them.

use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::marker::PhantomData;
use std::time::{Duration, Instant};

use bincode::config::{Configuration, Limit, LittleEndian, Varint};
use bincode::error::DecodeError;
use fdm_core::fingerprint::{self, Fingerprint};
use fdm_core::geodesy::{Geodetic, GeodeticOrigin};
use fdm_core::script::{Echo, ScriptAction};
use serde::{Deserialize, Serialize};

use crate::model::{with_model, ModelJob, RunModel, MODELS};
use crate::outfile::WatchedFile;
use crate::output::{self, Frame, Output, OutputError};
use crate::scenario::{Start, MAX_FPS, MAX_FRAMES};

/// The first eight bytes of every recording.
pub const MAGIC: [u8; 8] = *b"SIMCLIRC";

/// The format version this `sim-cli` writes (the two bytes after [`MAGIC`],
/// little-endian). Any change to the layout bumps it.
pub const FORMAT_VERSION: u16 = 3;

/// The format versions this `sim-cli` reads: 1 (no blocks, complete files
/// only), 2 (blocks: see the module docs) and 3 (version 2 with the flight's
/// fingerprint in the end marker).
pub const READABLE_VERSIONS: [u16; 3] = [1, 2, 3];

/// Largest recording `sim-cli` writes or reads, bytes (64 MiB). Hours of
/// interactive flying with a key change every frame take a few MB; a longer
/// recording stops the flight with an error rather than produce a file that
/// could not be replayed.
pub const MAX_RECORDING_BYTES: u64 = 64 * 1024 * 1024;

/// Most bytes one header or one event may claim for its variable-length
/// fields (strings, action lists): the whole file's limit,
/// [`MAX_RECORDING_BYTES`], so that whatever the writer writes the reader
/// reads (a frame of a million script actions included). A length field
/// beyond it is refused before anything is allocated, and a claim beyond the
/// bytes actually left ends in "truncated" without allocating it: vectors
/// grow only as their elements are read.
#[allow(clippy::cast_possible_truncation)] // 64 MiB fits every usize of 32 bits and more
pub const DECODE_LIMIT: usize = MAX_RECORDING_BYTES as usize;

/// A block is closed after this many bytes of events even within a second of
/// flight (a frame of many actions, many resets), so that a cut loses little.
const BLOCK_TARGET_BYTES: usize = 64 * 1024;

/// Bytes of a block's frame: the payload length before it and the checksum
/// after it.
const BLOCK_FRAME_BYTES: u64 = 4 + 8;

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
    /// The aircraft's parameters ([`RunModel::AircraftRecord`]).
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
    /// byte before this event (version 1) or before the end block it is
    /// alone in (version 2).
    End {
        /// Frames in all [`Event::Frames`] together.
        frames: u64,
        /// FNV-1a 64 of the file up to this event (version 1) or up to its
        /// block (version 2).
        checksum: u64,
    },
    /// Version 3's end marker: [`Event::End`] and the flight's fingerprint.
    /// (Last, so that the other events keep their variant numbers.)
    Sealed {
        /// Frames in all [`Event::Frames`] together.
        frames: u64,
        /// FNV-1a 64 of the file up to the end block.
        checksum: u64,
        /// [`RunModel::state_fingerprint`] of the state after the last
        /// frame (or reset).
        state: u64,
        /// [`fdm_core::fingerprint::maths`] of the build that flew it.
        maths: u64,
    },
}

impl Event {
    /// The end marker's frame total, checksum and fingerprint (`None` for
    /// other events; the fingerprint is `None` in a plain [`Event::End`]).
    fn end(&self) -> Option<(u64, u64, Option<Fingerprint>)> {
        match *self {
            Self::End { frames, checksum } => Some((frames, checksum, None)),
            Self::Sealed {
                frames,
                checksum,
                state,
                maths,
            } => Some((frames, checksum, Some(Fingerprint { state, maths }))),
            Self::Frames { .. } | Self::Reset => None,
        }
    }
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
    #[error("recording format version {found}; this sim-cli reads versions 1, 2 and 3")]
    WrongVersion {
        /// The version in the file.
        found: u16,
    },
    /// A model the run library's registry ([`MODELS`]) does not have (the
    /// name as stored). A program with models of its own looks the name up
    /// in its list first ([`recorded_model_name`]) and says so in its own
    /// words (`sim-cli replay`: "which this sim-cli does not have").
    #[error("recorded with model `{}`, which the run library's registry does not have ({})", Echo::short(.0), MODELS.join(", "))]
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
            other => Self::Corrupt(format!("{what}: {}", plain_decode_error(other))),
        }
    }
}

/// A bincode decoding error in words. bincode's own `Display` prints its
/// `Debug` form (`Utf8 { inner: Utf8Error { .. } }`), which says nothing to a
/// user holding a damaged file.
fn plain_decode_error(error: &DecodeError) -> String {
    match error {
        DecodeError::UnexpectedEnd { .. } => "the bytes end inside it".to_owned(),
        DecodeError::LimitExceeded => {
            format!("a length field claims more than {DECODE_LIMIT} bytes")
        }
        DecodeError::InvalidIntegerType { .. } => {
            "a number is not stored in the form this format uses".to_owned()
        }
        DecodeError::NonZeroTypeIsZero { .. } => "a value that cannot be 0 is 0".to_owned(),
        DecodeError::UnexpectedVariant { found, .. } => {
            format!("kind number {found} is not one this format has")
        }
        DecodeError::Utf8 { .. } => "a name is not valid UTF-8 text".to_owned(),
        DecodeError::InvalidCharEncoding(_) => "a character is not valid UTF-8".to_owned(),
        DecodeError::InvalidBooleanValue(value) => {
            format!("a yes/no value is {value}, neither 0 nor 1")
        }
        DecodeError::ArrayLengthMismatch { required, found } => {
            format!("a list has {found} items where {required} belong")
        }
        DecodeError::OutsideUsizeRange(value) => format!("a length of {value} is too large"),
        // serde's own messages ("invalid value: ..., expected ...") are words already.
        DecodeError::OtherString(message) => Echo::short(message).to_string(),
        DecodeError::Other(message) => (*message).to_owned(),
        _ => "a value is not valid for this format".to_owned(),
    }
}

/// Reads magic, version and model name; returns the model, the version and
/// the bytes after the version.
fn prefix(bytes: &[u8]) -> Result<(String, u16, &[u8]), RecordingError> {
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
    if !READABLE_VERSIONS.contains(&version) {
        return Err(RecordingError::WrongVersion { found: version });
    }
    let rest = &bytes[PREFIX_LEN..];
    let (model, _) = bincode::serde::decode_from_slice::<String, _>(rest, format())
        .map_err(|e| RecordingError::decode(&e, "model name", "inside the header"))?;
    Ok((model, version, rest))
}

/// The model a recording was made with, from its first bytes: its name in
/// the registry ([`MODELS`]).
///
/// # Errors
/// As [`parse_recording`], for the prefix only.
pub fn recorded_model(bytes: &[u8]) -> Result<&'static str, RecordingError> {
    let model = recorded_model_name(bytes)?;
    MODELS
        .iter()
        .copied()
        .find(|&name| name == model)
        .ok_or(RecordingError::UnknownModel(model))
}

/// The name of the model a recording was made with, from its first bytes,
/// whether or not this library's registry has it: a program with models of
/// its own ([`RunModel`]s outside the registry, such as `sim-cli`'s
/// `glider` feature) looks it up in its own list and parses the recording
/// with [`Recording::parse`].
///
/// # Errors
/// As [`parse_recording`], for the prefix only.
pub fn recorded_model_name(bytes: &[u8]) -> Result<String, RecordingError> {
    prefix(bytes).map(|(model, _, _)| model)
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

impl ModelJob for ParseJob<'_> {
    type Output = Result<RecordingInfo, RecordingError>;

    fn call<M: RunModel>(self) -> Self::Output {
        Recording::<M>::parse(self.0).map(|r| r.info())
    }
}

/// Checks a whole recording of any model, as `sim-cli replay` does before
/// flying it: pure, total (never panics) and bounded, for tests and fuzzing.
///
/// # Errors
/// A [`RecordingError`] naming the first problem.
pub fn parse_recording(bytes: &[u8]) -> Result<RecordingInfo, RecordingError> {
    let name = recorded_model(bytes)?;
    with_model(name, ParseJob(bytes))
        .unwrap_or_else(|| Err(RecordingError::UnknownModel(name.to_owned())))
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

/// Where a recording without its end marker was cut: what
/// [`Recording::parse_salvaging`] could still replay.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cut {
    /// The file's byte offset where the intact blocks end (the first byte of
    /// the missing, torn or damaged block).
    pub at_byte: u64,
    /// Frames in the intact blocks, across resets: all a replay can fly.
    pub frames: u64,
}

impl fmt::Display for Cut {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "cut at byte {} before its end marker; the {} frames before the cut are intact",
            self.at_byte, self.frames
        )
    }
}

/// A validated recording of model `M`, borrowing the file's bytes.
#[derive(Debug)]
pub struct Recording<'a, M: RunModel> {
    /// Frames per second.
    pub fps: u32,
    /// The earth-frame origin.
    pub origin: GeodeticOrigin,
    /// Aircraft, controls and state at frame 0.
    pub start: Start<M>,
    /// Frames in total, across resets (before the cut, for a salvaged one).
    pub frames: u64,
    /// Resets.
    pub resets: u64,
    /// Events (runs and resets).
    pub events: u64,
    /// The flight's fingerprint from the end marker (version 3): the hash of
    /// the state after the last frame and of the maths that flew it. `None`
    /// for versions 1 and 2, a cut recording, or a writer that saw no state
    /// (see [`RecordWriter::finish`]).
    pub fingerprint: Option<Fingerprint>,
    table: Vec<M::Action>,
    /// The validated events, as the byte ranges they are stored in (the one
    /// event stream of version 1; each block's payload of version 2), with
    /// the file offset of each range's first byte.
    payloads: Vec<(usize, &'a [u8])>,
}

impl<'a, M: RunModel> Recording<'a, M> {
    /// The scenario a replay starts from: the recorded start, origin and
    /// frame rate, no frames or script of its own (the recorded events drive
    /// it, [`crate::replay::replay`]).
    #[must_use]
    pub fn scenario(&self) -> crate::Scenario<M> {
        crate::Scenario {
            start: self.start.clone(),
            origin: self.origin,
            fps: self.fps,
            frames: 0,
            script: fdm_core::script::Script::default(),
        }
    }

    /// Parses and validates a whole recording: prefix, header (model `M`,
    /// fps, origin, aircraft, action names), every event, the end marker and
    /// its checksum, and that nothing follows it. A recording cut before its
    /// end marker is refused as [`RecordingError::Truncated`].
    ///
    /// # Errors
    /// A [`RecordingError`] naming the first problem.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, RecordingError> {
        match Self::parse_salvaging(bytes)? {
            (recording, None) => Ok(recording),
            (_, Some(_)) => Err(RecordingError::Truncated("before its end marker")),
        }
    }

    /// As [`Self::parse`], but a version-2 recording cut before its end
    /// marker (the recording process killed, the machine stopped, the tail
    /// torn or zeroed) is accepted up to its last intact block: the
    /// recording then holds the frames before the cut, and [`Cut`] says
    /// where it was. Damage before the last block, and any cut of a
    /// version-1 file (which has no blocks to check), is still an error.
    ///
    /// # Errors
    /// A [`RecordingError`] naming the first problem.
    pub fn parse_salvaging(bytes: &'a [u8]) -> Result<(Self, Option<Cut>), RecordingError> {
        let (model, version, rest) = prefix(bytes)?;
        if model != M::NAME {
            return Err(RecordingError::WrongModel {
                expected: M::NAME,
                found: model,
            });
        }
        type H<M> = Header<
            <M as RunModel>::AircraftRecord,
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
        let body_start = PREFIX_LEN + used;
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
            fingerprint: None,
            table,
            payloads: Vec::new(),
        };
        let cut = if version == 1 {
            recording.validate_stream(bytes, body_start)?;
            None
        } else {
            recording.validate_blocks(bytes, body_start, version)?
        };
        Ok((recording, cut))
    }

    /// Version 1: one stream of events up to the end marker, whose checksum
    /// covers every byte before it; nothing after it.
    fn validate_stream(
        &mut self,
        whole: &'a [u8],
        body_start: usize,
    ) -> Result<(), RecordingError> {
        let mut offset = body_start;
        let mut frames = 0_u64;
        loop {
            let (event, used) = decode_event(&whole[offset..], offset)?;
            if let Some((total, checksum, fingerprint)) = event.end() {
                if fingerprint.is_some() {
                    return Err(RecordingError::corrupt(format!(
                        "event at byte {offset}: a version 3 end marker in a version 1 recording"
                    )));
                }
                let mut hash = Fnv64::new();
                hash.update(&whole[..offset]);
                self.check_end(total, checksum, hash.0, frames)?;
                let trailing = whole.len() - offset - used;
                if trailing != 0 {
                    return Err(RecordingError::corrupt(format!(
                        "{trailing} bytes after the end marker"
                    )));
                }
                self.frames = frames;
                self.payloads = vec![(body_start, &whole[body_start..offset])];
                return Ok(());
            }
            frames = self.count(&event, frames, offset)?;
            offset += used;
        }
    }

    /// Version 2: blocks, each checked against its checksum, then the end
    /// block. Returns where the file was cut when it has no end block and
    /// everything before the cut is intact.
    fn validate_blocks(
        &mut self,
        whole: &'a [u8],
        body_start: usize,
        version: u16,
    ) -> Result<Option<Cut>, RecordingError> {
        let mut hash = Fnv64::new();
        hash.update(&whole[..body_start]);
        let mut offset = body_start;
        let mut frames = 0_u64;
        loop {
            let cut = Cut {
                at_byte: offset as u64,
                frames,
            };
            let rest = &whole[offset..];
            // The tail of a file whose last writes never reached the disk
            // reads as zeros on many file systems: a cut, not damage.
            if rest.iter().all(|&b| b == 0) {
                self.frames = frames;
                return Ok(Some(cut));
            }
            let Some((len_bytes, after_len)) = rest.split_first_chunk::<4>() else {
                self.frames = frames;
                return Ok(Some(cut));
            };
            let len = u32::from_le_bytes(*len_bytes) as usize;
            if after_len.len() < len.saturating_add(8) {
                // The block runs past the end of the file: torn by the cut.
                self.frames = frames;
                return Ok(Some(cut));
            }
            let (payload, after_payload) = after_len.split_at(len);
            let (stored, after_block) = after_payload.split_at(8);
            let stored = u64::from_le_bytes(stored.try_into().unwrap_or([0; 8]));
            let checksum_at = offset + 4 + len;
            let mut block_hash = hash;
            block_hash.update(&whole[offset..checksum_at]);
            if block_hash.0 != stored {
                if after_block.is_empty() || after_block.iter().all(|&b| b == 0) {
                    // The last block did not reach the disk whole.
                    self.frames = frames;
                    return Ok(Some(cut));
                }
                return Err(RecordingError::corrupt(format!(
                    "the block at byte {offset} does not match its checksum (stored {stored:#018x}, computed {:#018x})",
                    block_hash.0
                )));
            }
            if len == 0 {
                return Err(RecordingError::corrupt(format!(
                    "the block at byte {offset} is empty"
                )));
            }
            let payload_start = offset + 4;
            // An intact block: its events must decode exactly.
            let mut at = 0;
            while at < payload.len() {
                let event_offset = payload_start + at;
                let (event, used) =
                    decode_event(&payload[at..], event_offset).map_err(|e| match e {
                        RecordingError::Truncated(_) => RecordingError::corrupt(format!(
                            "event at byte {event_offset}: it runs past the end of its block"
                        )),
                        other => other,
                    })?;
                if let Some((total, checksum, fingerprint)) = event.end() {
                    if fingerprint.is_some() && version < 3 {
                        return Err(RecordingError::corrupt(format!(
                            "event at byte {event_offset}: a version 3 end marker in a version \
                             {version} recording"
                        )));
                    }
                    if at != 0 || used != payload.len() {
                        return Err(RecordingError::corrupt(format!(
                            "event at byte {event_offset}: the end marker shares its block"
                        )));
                    }
                    self.check_end(total, checksum, hash.0, frames)?;
                    if !after_block.is_empty() {
                        return Err(RecordingError::corrupt(format!(
                            "{} bytes after the end marker",
                            after_block.len()
                        )));
                    }
                    self.frames = frames;
                    self.fingerprint = fingerprint;
                    return Ok(None);
                }
                frames = self.count(&event, frames, event_offset)?;
                at += used;
            }
            self.payloads.push((payload_start, payload));
            block_hash.update(&whole[checksum_at..checksum_at + 8]);
            hash = block_hash;
            offset = checksum_at + 8;
        }
    }

    /// Counts one event (not the end marker) into the totals; returns the
    /// frame total after it.
    fn count(&mut self, event: &Event, frames: u64, offset: usize) -> Result<u64, RecordingError> {
        self.events += 1;
        match event {
            Event::Frames { count, actions } => {
                self.check_frames(*count, actions, offset)?;
                frames.checked_add(*count).ok_or_else(|| {
                    RecordingError::corrupt(format!(
                        "event at byte {offset}: the frame count overflows"
                    ))
                })
            }
            Event::Reset => {
                self.resets += 1;
                Ok(frames)
            }
            Event::End { .. } | Event::Sealed { .. } => Err(RecordingError::corrupt(format!(
                "event at byte {offset}: an end marker before the end"
            ))),
        }
    }

    /// The end marker's checksum (against `computed`) and frame total
    /// (against the events' `frames`, at most a run's).
    fn check_end(
        &self,
        total: u64,
        stored: u64,
        computed: u64,
        frames: u64,
    ) -> Result<(), RecordingError> {
        if computed != stored {
            return Err(RecordingError::corrupt(format!(
                "checksum mismatch (stored {stored:#018x}, computed {computed:#018x})"
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
        Ok(())
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
        let mut payloads = self.payloads.iter();
        let (mut offset, mut cursor): (usize, &[u8]) = (0, &[]);
        std::iter::from_fn(move || {
            while cursor.is_empty() {
                let &(start, payload) = payloads.next()?;
                (offset, cursor) = (start, payload);
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
                    Event::End { .. } | Event::Sealed { .. } => {
                        Err(RecordingError::corrupt("end marker inside the body"))
                    }
                }
            });
            if item.is_err() {
                cursor = &[];
                payloads = [].iter();
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

/// Why writing a recording failed. The messages read as one line each
/// (the cause is part of the message, not a separate source).
#[derive(Debug, thiserror::Error)]
pub enum RecordWriteError {
    /// The header does not encode.
    #[error("encoding the recording's header: {0}")]
    Header(bincode::error::EncodeError),
    /// An event does not encode.
    #[error("encoding a recording event: {0}")]
    Event(bincode::error::EncodeError),
    /// The recording would outgrow [`MAX_RECORDING_BYTES`].
    #[error(
        "the recording would exceed {MAX_RECORDING_BYTES} bytes, the most `sim-cli replay` reads"
    )]
    TooLarge,
    /// Writing or flushing failed.
    #[error("writing the recording: {0}")]
    Io(std::io::Error),
    /// An action the model's action list does not have.
    #[error("an action outside the model's action list")]
    UnknownAction,
}

/// Writes a recording as a flight goes: header first, then runs of identical
/// frames and resets in blocks, and the end block on [`Self::finish`].
///
/// A block is closed, checksummed and handed to `out` (then flushed) after
/// every second of flight (fps frames), and sooner when it holds 64 KiB, so
/// that a flight killed at any point leaves a recording whose blocks up to
/// the last second replay ([`Recording::parse_salvaging`]). A run of
/// identical frames that spans a block boundary is stored as one event per
/// block. (For durability against power loss, give it a writer whose
/// `flush` also syncs the file, such as [`SyncedFile`].)
#[derive(Debug)]
pub struct RecordWriter<A, W: Write> {
    out: W,
    /// FNV-1a 64 of every byte handed to `out`.
    hash: Fnv64,
    /// Bytes handed to `out`, plus the open block's.
    written: u64,
    /// The open block's events.
    block: Vec<u8>,
    /// Frames recorded in the open block.
    block_frames: u64,
    /// Frames per block: one second of flight.
    frames_per_block: u64,
    /// The current run: its action indices and length (0: no run yet).
    run: Vec<u16>,
    run_count: u64,
    scratch: Vec<u16>,
    frames: u64,
    /// [`RunModel::state_fingerprint`] of the latest state seen (as an
    /// [`Output`]): the final state's at [`Self::finish`].
    final_state: Option<u64>,
    finished: bool,
    _actions: PhantomData<A>,
}

impl<A: ScriptAction + PartialEq, W: Write> RecordWriter<A, W> {
    /// Starts a recording of model `M` flown at `fps` from `origin` and
    /// `start`: writes the magic, the version and the header.
    ///
    /// # Errors
    /// Encoding or writing fails.
    pub fn new<M: RunModel<Action = A>>(
        out: W,
        fps: u32,
        origin: &GeodeticOrigin,
        start: &Start<M>,
    ) -> Result<Self, RecordWriteError> {
        let mut writer = Self {
            out,
            hash: Fnv64::new(),
            written: 0,
            block: Vec::new(),
            block_frames: 0,
            frames_per_block: u64::from(fps.max(1)),
            run: Vec::new(),
            run_count: 0,
            scratch: Vec::new(),
            frames: 0,
            final_state: None,
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
        let bytes =
            bincode::serde::encode_to_vec(&header, format()).map_err(RecordWriteError::Header)?;
        writer.put(&bytes)?;
        Ok(writer)
    }

    /// Counts `bytes` more towards the file's size limit.
    fn grow(&mut self, bytes: u64) -> Result<(), RecordWriteError> {
        self.written += bytes;
        if self.written > MAX_RECORDING_BYTES {
            return Err(RecordWriteError::TooLarge);
        }
        Ok(())
    }

    fn put(&mut self, bytes: &[u8]) -> Result<(), RecordWriteError> {
        self.grow(bytes.len() as u64)?;
        self.hash.update(bytes);
        self.out.write_all(bytes).map_err(RecordWriteError::Io)
    }

    /// Adds an event to the open block (closing the block when it is full).
    fn put_event(&mut self, event: &Event) -> Result<(), RecordWriteError> {
        let bytes =
            bincode::serde::encode_to_vec(event, format()).map_err(RecordWriteError::Event)?;
        if self.block.is_empty() {
            self.grow(BLOCK_FRAME_BYTES)?;
        }
        self.grow(bytes.len() as u64)?;
        self.block.extend_from_slice(&bytes);
        if self.block.len() >= BLOCK_TARGET_BYTES {
            self.close_block()?;
        }
        Ok(())
    }

    /// Writes the open block (length, events, checksum) and flushes `out`.
    fn close_block(&mut self) -> Result<(), RecordWriteError> {
        if self.block.is_empty() {
            return Ok(());
        }
        // The size limit (64 MiB) keeps every block's length within a u32.
        let len = u32::try_from(self.block.len()).map_err(|_| RecordWriteError::TooLarge)?;
        let block = std::mem::take(&mut self.block);
        for bytes in [&len.to_le_bytes()[..], &block] {
            self.hash.update(bytes);
            self.out.write_all(bytes).map_err(RecordWriteError::Io)?;
        }
        let checksum = self.hash.0.to_le_bytes();
        self.hash.update(&checksum);
        self.out
            .write_all(&checksum)
            .and_then(|()| self.out.flush())
            .map_err(RecordWriteError::Io)?;
        self.block = block;
        self.block.clear();
        self.block_frames = 0;
        Ok(())
    }

    fn flush_run(&mut self) -> Result<(), RecordWriteError> {
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
    pub fn frame(&mut self, actions: &[A]) -> Result<(), RecordWriteError> {
        self.scratch.clear();
        for action in actions {
            let index = A::ALL
                .iter()
                .position(|a| a == action)
                .and_then(|i| u16::try_from(i).ok())
                .ok_or(RecordWriteError::UnknownAction)?;
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
        self.block_frames += 1;
        if self.block_frames >= self.frames_per_block {
            // A second of flight: on its way to the disk.
            self.flush_run()?;
            self.close_block()?;
        }
        Ok(())
    }

    /// Records a reset.
    ///
    /// # Errors
    /// As [`Self::frame`].
    pub fn reset(&mut self) -> Result<(), RecordWriteError> {
        self.flush_run()?;
        self.put_event(&Event::Reset)
    }

    /// The state the recorded flight is in after its latest frame (or
    /// reset), as [`RunModel::state_fingerprint`] hashes it: [`Self::finish`]
    /// seals the recording with it. The [`Output`] implementation calls this
    /// every frame; a writer driven by hand calls it before `finish`.
    pub fn set_final_state(&mut self, state_fingerprint: u64) {
        self.final_state = Some(state_fingerprint);
    }

    /// Writes the last run, closes its block, writes the end block and
    /// flushes. Later calls do nothing. The end marker carries the flight's
    /// fingerprint (the last [`Self::set_final_state`] and
    /// [`fdm_core::fingerprint::maths`]) when a state was set; without one it
    /// is version 2's plain end marker, and a replay says it cannot check.
    ///
    /// # Errors
    /// As [`Self::frame`], and flushing.
    pub fn finish(&mut self) -> Result<(), RecordWriteError> {
        if self.finished {
            return Ok(());
        }
        self.flush_run()?;
        self.close_block()?;
        let end = match self.final_state {
            Some(state) => Event::Sealed {
                frames: self.frames,
                checksum: self.hash.0,
                state,
                maths: fingerprint::maths(),
            },
            None => Event::End {
                frames: self.frames,
                checksum: self.hash.0,
            },
        };
        self.put_event(&end)?;
        self.close_block()?;
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

/// A recording's file, created before the run (locked against a second
/// writer, [`crate::outfile::create_locked`]) so that an unwritable path is
/// refused before anything flies.
#[derive(Debug)]
pub struct RecordFile {
    /// The path, for messages.
    pub path: std::path::PathBuf,
    /// The file; its flushes (once a second of flight) also sync it to the
    /// disk, at most every two seconds ([`SyncedFile`]).
    pub out: SyncedFile,
}

impl RecordFile {
    /// Creates (and locks) the file at `path`.
    ///
    /// # Errors
    /// The OS error, or the file being written by another process
    /// ([`crate::outfile::create_locked`]).
    pub fn create(path: &std::path::Path) -> std::io::Result<Self> {
        Ok(Self {
            path: path.to_owned(),
            out: SyncedFile::new(crate::outfile::create_locked(path)?),
        })
    }
}

/// A recording file whose `flush` (once a block, from [`RecordWriter`]) also
/// asks the OS to put the data on the disk (`sync_data`), at most once per
/// [`SyncedFile::SYNC_INTERVAL`] of wall-clock time and again when it is
/// dropped: a machine that loses power keeps the recording up to a few
/// seconds before, and a fast headless run does not wait on the disk every
/// block. A file that is not a regular file (a pipe such as `/dev/stdout`
/// piped into another program, `/dev/null`) has no disk to sync to (the OS
/// refuses with "Invalid argument"): it is only written.
#[derive(Debug)]
pub struct SyncedFile {
    out: BufWriter<WatchedFile>,
    last_sync: Option<Instant>,
    /// Whether the file is a regular file, synced.
    syncs: bool,
}

impl SyncedFile {
    /// The shortest wall-clock time between two syncs.
    pub const SYNC_INTERVAL: Duration = Duration::from_secs(2);

    /// Wraps `file` with a 64 KiB buffer.
    #[must_use]
    pub fn new(file: File) -> Self {
        Self::watched(WatchedFile::new(file))
    }

    /// Wraps `file` (watched by a program that answers signals while a
    /// write waits: [`WatchedFile::watched_by`]) with a 64 KiB buffer.
    #[must_use]
    pub fn watched(file: WatchedFile) -> Self {
        // A file whose kind cannot be read is synced (and its sync's error
        // reported), as before this check.
        let syncs = file.file().metadata().map_or(true, |m| m.is_file());
        Self {
            out: BufWriter::with_capacity(64 * 1024, file),
            last_sync: None,
            syncs,
        }
    }
}

impl Write for SyncedFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.out.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()?;
        let now = Instant::now();
        if self.syncs
            && self
                .last_sync
                .is_none_or(|last| now.duration_since(last) >= Self::SYNC_INTERVAL)
        {
            self.out.get_ref().file().sync_data()?;
            self.last_sync = Some(now);
        }
        Ok(())
    }
}

impl Drop for SyncedFile {
    fn drop(&mut self) {
        // Best effort, as BufWriter's own drop: errors were reported by flush.
        if self.out.flush().is_ok() && self.syncs {
            let _ = self.out.get_ref().file().sync_data();
        }
    }
}

impl<M: RunModel, W: Write> Output<M> for RecordWriter<M::Action, W> {
    /// Logs every flown frame's actions and every reset; the start is the
    /// header, written by [`RecordWriter::new`].
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        self.set_final_state(M::state_fingerprint(frame.state));
        match frame.event {
            output::Event::Start => Ok(()),
            output::Event::Step => Ok(RecordWriter::frame(self, frame.actions)?),
            output::Event::Reset => Ok(self.reset()?),
        }
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(RecordWriter::finish(self)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::{Palmer, PalmerAction};

    /// A well-formed recording of more frames than any run may have (here
    /// 2^40, written by hand) is refused rather than replayed for ever.
    /// (Moved here from `sim-cli` with the format: it sets private fields.)
    /// The library's message for a model outside its registry names no
    /// program (`sim-cli replay` prints its own, from its registry).
    #[test]
    fn an_unknown_model_message_names_no_program() {
        let message = RecordingError::UnknownModel("glider".to_owned()).to_string();
        assert_eq!(
            message,
            "recorded with model `glider`, which the run library's registry does not have \
             (palmer, bourg)"
        );
    }

    /// docs/recording.md: anything that is not truncation is `corrupt
    /// recording: ...` "in words" (its examples: `a name is not valid UTF-8
    /// text`, `kind number 7 is not one this format has`), not bincode's
    /// `Debug` form: every kind of decoding error has words of its own (none
    /// is the catch-all's, no two the same), with the numbers it carries,
    /// and no braces of a `Debug` form.
    #[test]
    fn every_decoding_error_is_said_in_its_own_words() {
        use bincode::error::{AllowedEnumVariants, IntegerType};
        let bytes = vec![b'a', 0xff];
        let not_utf8 = std::str::from_utf8(&bytes).unwrap_err();
        let catch_all = plain_decode_error(&DecodeError::EmptyEnum { type_name: "Event" });
        let kinds: [(DecodeError, &[&str]); 12] = [
            (DecodeError::UnexpectedEnd { additional: 3 }, &[]),
            (DecodeError::LimitExceeded, &["67108864"]),
            (
                DecodeError::InvalidIntegerType {
                    expected: IntegerType::U16,
                    found: IntegerType::U64,
                },
                &[],
            ),
            (
                DecodeError::NonZeroTypeIsZero {
                    non_zero_type: IntegerType::U32,
                },
                &["0"],
            ),
            (
                DecodeError::UnexpectedVariant {
                    type_name: "Event",
                    allowed: &AllowedEnumVariants::Range { min: 0, max: 3 },
                    found: 7,
                },
                &["7"],
            ),
            (DecodeError::Utf8 { inner: not_utf8 }, &["UTF-8"]),
            (
                DecodeError::InvalidCharEncoding([0xff, 0, 0, 0]),
                &["UTF-8"],
            ),
            (DecodeError::InvalidBooleanValue(9), &["9"]),
            (
                DecodeError::ArrayLengthMismatch {
                    required: 3,
                    found: 2,
                },
                &["3", "2"],
            ),
            (DecodeError::OutsideUsizeRange(1 << 40), &["1099511627776"]),
            (
                DecodeError::OtherString("invalid value: integer `9`".to_owned()),
                &["invalid value: integer `9`"],
            ),
            (
                DecodeError::Other("a message of its own"),
                &["a message of its own"],
            ),
        ];
        let mut seen = vec![catch_all.clone()];
        for (error, numbers) in &kinds {
            let words = plain_decode_error(error);
            assert!(!seen.contains(&words), "{error:?}: {words:?} again");
            assert!(
                words.len() > 10 && !words.contains('{'),
                "{error:?}: {words:?}"
            );
            for number in *numbers {
                assert!(
                    words.contains(number),
                    "{error:?}: {words:?} without {number}"
                );
            }
            seen.push(words);
        }
        assert_eq!(
            plain_decode_error(&kinds[5].0),
            "a name is not valid UTF-8 text"
        );
        assert_eq!(
            plain_decode_error(&kinds[4].0),
            "kind number 7 is not one this format has"
        );
    }

    /// A recording is read up to [`MAX_RECORDING_BYTES`] ("at most 64 MiB",
    /// docs/recording.md): a file of exactly 64 MiB is read (this one then
    /// refused for its version, 0), one byte more is too large, with its
    /// size.
    #[test]
    fn sixty_four_mib_is_the_largest_recording_read() {
        let mut bytes = vec![0_u8; usize::try_from(MAX_RECORDING_BYTES).unwrap()];
        bytes[..MAGIC.len()].copy_from_slice(&MAGIC);
        assert_eq!(
            parse_recording(&bytes),
            Err(RecordingError::WrongVersion { found: 0 })
        );
        bytes.push(0);
        assert_eq!(
            parse_recording(&bytes),
            Err(RecordingError::TooLarge {
                size: MAX_RECORDING_BYTES + 1
            })
        );
    }

    /// A recording's file holds each second of flight once its block is
    /// closed, while the writer is still open (docs/recording.md: every
    /// second "it closes the block with a checksum and hands it to the
    /// operating system"): 45 frames at 30 fps read back from the path are
    /// the header and the first second, a cut of 30 frames; finished and
    /// dropped, all 45.
    #[test]
    fn a_recording_file_holds_each_second_once_its_block_is_closed() {
        let dir = std::env::temp_dir().join(format!("fdm-run-record-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("flight.rec");
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let file = RecordFile::create(&path).unwrap();
        let mut writer = RecordWriter::new(file.out, 30, &origin, &start).unwrap();
        for _ in 0..45 {
            writer.frame(&[]).unwrap();
        }
        let bytes = std::fs::read(&path).unwrap();
        let (recording, cut) = Recording::<Palmer>::parse_salvaging(&bytes).unwrap();
        assert_eq!((recording.frames, cut.map(|c| c.frames)), (30, Some(30)));
        writer.finish().unwrap();
        drop(writer);
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(Recording::<Palmer>::parse(&bytes).unwrap().frames, 45);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A recording into a pipe (`sim-cli --record /dev/stdout` piped into
    /// another program) is written whole and finished: a pipe has no disk
    /// to sync to, and the sync's "Invalid argument" used to end the run
    /// after its first second. The reader gets the recording a file holds.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_recording_into_a_pipe_is_written_whole() {
        use std::io::Read as _;
        let (mut cat, path) = crate::outfile::pipe_into_cat();
        let file = RecordFile::create(std::path::Path::new(&path)).unwrap();
        drop(cat.stdin.take());
        // The reader drains the pipe on a thread while the writer writes.
        let mut stdout = cat.stdout.take().unwrap();
        let reader = std::thread::spawn(move || {
            let mut bytes = Vec::new();
            stdout.read_to_end(&mut bytes).unwrap();
            bytes
        });
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let mut writer = RecordWriter::new(file.out, 30, &origin, &start).unwrap();
        for _ in 0..45 {
            writer.frame(&[]).unwrap();
        }
        writer.finish().unwrap();
        drop(writer);
        let bytes = reader.join().unwrap();
        assert!(cat.wait().unwrap().success());
        assert_eq!(Recording::<Palmer>::parse(&bytes).unwrap().frames, 45);
    }

    /// The writer's side of the 64 MiB limit (`RecordWriteError::TooLarge`:
    /// "the recording would exceed 64 MiB, the most `sim-cli replay`
    /// reads"): a recording that ends at exactly [`MAX_RECORDING_BYTES`] is
    /// written, one that would end a byte past it is refused. (The bytes
    /// before are counted, not written: `written` is set by hand, as in
    /// `endless_recordings_are_refused`.)
    #[test]
    fn a_recording_may_reach_64_mib_and_not_one_byte_more() {
        use fdm_core::palmer::PalmerAction::ThrottleUp;
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let writer = || {
            let mut writer =
                RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin, &start).unwrap();
            writer.frame(&[ThrottleUp]).unwrap();
            writer.set_final_state(7);
            writer
        };
        // What finishing adds: the frame's event, the end marker and their blocks.
        let mut probe = writer();
        let before = probe.bytes_written();
        probe.finish().unwrap();
        let added = probe.bytes_written() - before;
        let mut exactly = writer();
        exactly.written = MAX_RECORDING_BYTES - added;
        exactly.finish().unwrap();
        assert_eq!(exactly.bytes_written(), MAX_RECORDING_BYTES);
        let mut over = writer();
        over.written = MAX_RECORDING_BYTES - added + 1;
        assert!(matches!(over.finish(), Err(RecordWriteError::TooLarge)));
    }

    /// docs/recording.md: "a file that ends, or turns to zeros, before its
    /// end block is a cut", but "a block that fails its checksum while
    /// intact data follows it is damage, not a cut", whatever its bytes: a
    /// body none of whose bytes is zero (a whole block of 0x01 bytes, its
    /// length 0x01010101 and its checksum wrong, then one more byte) is
    /// refused, not salvaged.
    #[test]
    fn a_damaged_block_of_nonzero_bytes_is_not_a_cut() {
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let writer = RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin, &start).unwrap();
        let mut bytes = writer.into_inner();
        let body = bytes.len();
        let len = 0x0101_0101_usize;
        bytes.resize(body + 4 + len + 8 + 1, 0x01);
        let err = Recording::<Palmer>::parse_salvaging(&bytes).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "corrupt recording: the block at byte {body} does not match its checksum \
                 (stored 0x0101010101010101, computed {:#018x})",
                {
                    let mut hash = Fnv64::new();
                    hash.update(&bytes[..body + 4 + len]);
                    hash.0
                }
            )
        );
    }

    /// A writer of a Palmer recording whose prefix says `version` (its
    /// running checksum taken again over the patched bytes, so that every
    /// block it closes is intact), with the file offset of its body.
    fn writer_of_version(version: u16) -> (RecordWriter<PalmerAction, Vec<u8>>, usize) {
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let mut writer = RecordWriter::new(Vec::new(), 30, &origin, &start).unwrap();
        writer.out[MAGIC.len()..PREFIX_LEN].copy_from_slice(&version.to_le_bytes());
        writer.hash = Fnv64::new();
        writer.hash.update(&writer.out);
        let body = writer.out.len();
        (writer, body)
    }

    /// docs/recording.md's checks of the events of intact blocks: "count ≥
    /// 1; indices below the number of header actions", each refused naming
    /// the event's byte offset in the file (here the second event of the
    /// first block: after the block's 4-byte length and a first event of 3
    /// bytes).
    #[test]
    fn intact_events_with_no_frames_or_unknown_actions_are_refused_at_their_byte() {
        for (event, problem) in [
            (
                Event::Frames {
                    count: 0,
                    actions: vec![],
                },
                "a run of 0 frames".to_owned(),
            ),
            (
                Event::Frames {
                    count: 1,
                    actions: vec![1, 10],
                },
                format!(
                    "action index 10 is not below the header's {} actions",
                    PalmerAction::ALL.len()
                ),
            ),
        ] {
            let (mut writer, body) = writer_of_version(FORMAT_VERSION);
            let first = Event::Frames {
                count: 1,
                actions: vec![],
            };
            writer.put_event(&first).unwrap();
            writer.put_event(&event).unwrap();
            writer.close_block().unwrap();
            writer.set_final_state(7);
            writer.finish().unwrap();
            let err = Recording::<Palmer>::parse(&writer.into_inner()).unwrap_err();
            assert_eq!(
                err.to_string(),
                format!(
                    "corrupt recording: event at byte {}: {problem}",
                    body + 4 + 3
                )
            );
        }
    }

    /// The end block holds the end marker alone (docs/recording.md: "end
    /// block: a block holding one event"), and version 3's end marker, with
    /// the fingerprint, is refused in a version 2 recording.
    #[test]
    fn the_end_marker_is_alone_in_its_block_and_sealed_only_in_version_3() {
        let frame = Event::Frames {
            count: 1,
            actions: vec![],
        };
        let sealed = |writer: &RecordWriter<PalmerAction, Vec<u8>>, frames| Event::Sealed {
            frames,
            checksum: writer.hash.0,
            state: 7,
            maths: 8,
        };
        // [end marker, frame] and [frame, end marker] in the end block.
        for marker_first in [true, false] {
            let (mut writer, _) = writer_of_version(FORMAT_VERSION);
            writer.put_event(&frame).unwrap();
            writer.close_block().unwrap();
            let end = sealed(&writer, 2);
            if marker_first {
                writer.put_event(&end).unwrap();
                writer.put_event(&frame).unwrap();
            } else {
                writer.put_event(&frame).unwrap();
                writer.put_event(&end).unwrap();
            }
            writer.close_block().unwrap();
            let err = Recording::<Palmer>::parse(&writer.into_inner()).unwrap_err();
            assert!(
                err.to_string().ends_with("the end marker shares its block"),
                "{err}"
            );
        }
        for version in [2, 3] {
            let (mut writer, _) = writer_of_version(version);
            writer.frame(&[]).unwrap();
            writer.set_final_state(7);
            writer.finish().unwrap();
            let bytes = writer.into_inner();
            let parsed = Recording::<Palmer>::parse(&bytes);
            if version == 3 {
                assert_eq!(parsed.unwrap().frames, 1);
            } else {
                assert!(parsed
                    .unwrap_err()
                    .to_string()
                    .ends_with("a version 3 end marker in a version 2 recording"),);
            }
        }
    }

    /// At most 10^9 frames, "as any run" (docs/recording.md's checks of the
    /// end marker, [`MAX_FRAMES`]): a recording of exactly that many is
    /// read, one more is refused.
    #[test]
    fn a_recording_may_hold_as_many_frames_as_a_run() {
        for (frames, readable) in [(MAX_FRAMES, true), (MAX_FRAMES + 1, false)] {
            let (mut writer, _) = writer_of_version(FORMAT_VERSION);
            writer.run_count = frames;
            writer.frames = frames;
            writer.finish().unwrap();
            let parsed = parse_recording(&writer.into_inner());
            if readable {
                assert_eq!(parsed.unwrap().frames, MAX_FRAMES);
            } else {
                assert!(parsed
                    .unwrap_err()
                    .to_string()
                    .ends_with("1000000001 frames, more than the 1000000000 a run can have"),);
            }
        }
    }

    /// The blocks of a recording's body as docs/recording.md lays them out
    /// (a `u32` little-endian length, that many bytes of events, a `u64`
    /// checksum), from `body` (the first byte after the header) to the end:
    /// each block's length.
    fn block_lengths(bytes: &[u8], body: usize) -> Vec<usize> {
        let mut lengths = Vec::new();
        let mut at = body;
        while at < bytes.len() {
            let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
            lengths.push(len);
            at += 4 + len + 8;
        }
        assert_eq!(at, bytes.len(), "the last block ends with the file");
        lengths
    }

    /// docs/recording.md: the writer closes a block "every second of flight
    /// (fps frames), and sooner when a block reaches 64 KiB"; and
    /// `bytes_written` is the file's size. Frames of 100 actions (an event
    /// of 103 bytes: variant, count 1, length 100, 100 one-byte indices;
    /// bincode 2's variable-length integers) alternating between two lists,
    /// so that no two neighbours are one run: a second of 30 of them
    /// (3 090 bytes) is one block. Frames of 3 000 actions (3 005 bytes: the
    /// length takes 3) fill 64 KiB after 22 events (66 110 bytes): that
    /// block closes there and the second's other 8 frames make the next.
    #[test]
    fn blocks_close_every_second_or_at_64_kib() {
        use fdm_core::palmer::PalmerAction::{AlphaDown, AlphaUp};
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        for (actions, seconds, expected) in [
            (100, 2, vec![30 * 103, 30 * 103]),
            (3000, 1, vec![22 * 3005, 8 * 3005]),
        ] {
            let mut writer =
                RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin, &start).unwrap();
            let body = usize::try_from(writer.bytes_written()).unwrap();
            let (up, down) = (vec![AlphaUp; actions], vec![AlphaDown; actions]);
            for frame in 0..30 * seconds {
                writer
                    .frame(if frame % 2 == 0 { &up } else { &down })
                    .unwrap();
            }
            writer.set_final_state(7);
            writer.finish().unwrap();
            let written = writer.bytes_written();
            let bytes = writer.into_inner();
            assert_eq!(written, bytes.len() as u64, "{actions} actions a frame");
            let mut lengths = block_lengths(&bytes, body);
            lengths.pop(); // the end block
            assert_eq!(lengths, expected, "{actions} actions a frame");
        }
    }

    #[test]
    fn endless_recordings_are_refused() {
        let start = Start::<Palmer>::thesis();
        let origin: GeodeticOrigin = "37.6,-122.4,4".parse().unwrap();
        let mut writer = RecordWriter::<_, Vec<u8>>::new(Vec::new(), 30, &origin, &start).unwrap();
        writer.run_count = 1 << 40;
        writer.frames = 1 << 40;
        writer.finish().unwrap();
        let err = parse_recording(&writer.into_inner()).unwrap_err();
        assert!(
            err.to_string().contains("more than the 1000000000"),
            "{err}"
        );
    }
}
