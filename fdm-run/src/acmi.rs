//! Tacview ACMI 2.2: the flight-recording text format air-combat and
//! flight-test users load into Tacview to debrief.
//!
//! [`AcmiWriter`] writes any number of aircraft as the frames are flown, in
//! plain text or zip-compressed ([`AcmiWriter::create`] with a name ending in
//! `.zip.acmi`). [`AcmiOutput`] is the single-aircraft [`Output`] of a
//! [`Run`](crate::Run); for fleets the writer itself is a
//! [`FleetOutput`](crate::fleet::FleetOutput).
//!
//! ```text
//! FileType=text/acmi/tacview
//! FileVersion=2.2
//! 0,ReferenceTime=2000-01-01T00:00:00Z
//! 0,ReferenceLongitude=-84
//! 0,ReferenceLatitude=40
//! 0,DataSource=afit-fdm
//! 0,Title=palmer
//! #0
//! 1,T=-0.0483|-0.1736|251|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1
//! #0.033333
//! 1,T=|-0.1735999|251.01|||
//! -1
//! ```
//!
//! * One object per aircraft, id = its index + 1 (hexadecimal, as ACMI
//!   wants), `T=lon|lat|alt|roll|pitch|yaw`: longitude and latitude as
//!   offsets from the integer `ReferenceLongitude`/`ReferenceLatitude`
//!   (degrees, rounded to 1e-7°, about 1 cm), altitude metres above the
//!   ellipsoid (rounded to 1 cm), roll, pitch and yaw (the heading) in
//!   degrees rounded to 0.01°. A field whose rounded value did not change
//!   since the object's last line is left empty; an object none of whose
//!   fields changed gets no line at all.
//! * `Name` (the aircraft type), `Type` and `CallSign` on the object's first
//!   line; `-id` when the aircraft crashes or diverges.
//! * A single flight's reset ([`AcmiOutput`], [`AcmiWriter::renew`]) starts a
//!   new object: the flight the reset ends is removed (if it was not
//!   already), and the next flight's id is the same index + 1 plus its flight
//!   number times 2^32 (`100000001`, `200000001`, … for the aircraft of id
//!   `1`), up to [`MAX_RENEWALS`] renewals of an index (a renewal more is
//!   refused: [`AcmiError::Renewals`]). An id is never written again after
//!   its removal: a reader may keep
//!   the removal (pyacmi does, so a flight after a crash under the old id
//!   would never show), and a reset would otherwise join the old flight's
//!   last place to the new start with a line at one instant.
//! * Times `#t` are the run's clock: frames flown / fps, in seconds rounded to
//!   the microsecond; a time line is written only before a line that needs it.
//! * No wall-clock time anywhere: the same flight gives the same bytes
//!   ([`DEFAULT_REFERENCE_TIME`] unless another is given).

use std::fmt::Write as _;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::marker::PhantomData;
use std::path::Path;
use std::str::FromStr;

use fdm_core::geodesy::{Geodetic, GeodeticOrigin};
use fdm_core::model::{FlightStatus, FlightView, LandingState};

use crate::model::RunModel;
use crate::outfile::WatchedFile;
use crate::output::{Event, Frame, Output, OutputError, Placement};

/// The `ReferenceTime` of files written without one: a fixed instant, so
/// that the same flight always gives the same file.
pub const DEFAULT_REFERENCE_TIME: &str = "2000-01-01T00:00:00Z";

/// A file name ending that asks for a zip-compressed ACMI file.
pub const ZIP_SUFFIX: &str = ".zip.acmi";

/// How many objects a writer holds: indices `0..MAX_OBJECTS`. An object's
/// id is its index + 1 in the id's low 32 bits and its flight number
/// ([`AcmiWriter::renew`]) in the high 32, so the largest index is the one
/// whose id still fits the low half.
pub const MAX_OBJECTS: usize = u32::MAX as usize;

/// Bytes of text gathered before they go to the file (or the compressor).
const CHUNK_BYTES: usize = 1 << 16;

/// An ACMI `ReferenceTime`: a UTC instant written
/// `YYYY-MM-DDTHH:MM:SS[.fraction]Z` (ISO 8601).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReferenceTime(String);

impl Default for ReferenceTime {
    fn default() -> Self {
        Self(DEFAULT_REFERENCE_TIME.to_owned())
    }
}

impl ReferenceTime {
    /// The text as written in the file.
    #[must_use]
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// Why a `ReferenceTime` was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{0}` is not a UTC time YYYY-MM-DDTHH:MM:SSZ (e.g. {DEFAULT_REFERENCE_TIME}), optionally with a fraction of a second before the Z")]
pub struct ReferenceTimeError(String);

impl FromStr for ReferenceTime {
    type Err = ReferenceTimeError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let refuse = || ReferenceTimeError(text.chars().take(64).collect());
        let b = text.as_bytes();
        if b.len() < 20 || b.len() > 30 || !text.is_ascii() {
            return Err(refuse());
        }
        let digits = |range: std::ops::Range<usize>| -> Option<u32> {
            b.get(range.clone())?
                .iter()
                .all(u8::is_ascii_digit)
                .then(|| text[range].parse().ok())?
        };
        let punctuation = [(4, b'-'), (7, b'-'), (10, b'T'), (13, b':'), (16, b':')];
        if punctuation.iter().any(|&(i, c)| b[i] != c) || b[b.len() - 1] != b'Z' {
            return Err(refuse());
        }
        let (Some(year), Some(month), Some(day), Some(hour), Some(minute), Some(second)) = (
            digits(0..4),
            digits(5..7),
            digits(8..10),
            digits(11..13),
            digits(14..16),
            digits(17..19),
        ) else {
            return Err(refuse());
        };
        let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
        let days = match month {
            1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
            4 | 6 | 9 | 11 => 30,
            2 if leap => 29,
            2 => 28,
            _ => return Err(refuse()),
        };
        if year < 1 || !(1..=days).contains(&day) || hour > 23 || minute > 59 || second > 59 {
            return Err(refuse());
        }
        let rest = &b[19..b.len() - 1];
        let fraction_ok = rest.is_empty()
            || (rest.len() >= 2 && rest[0] == b'.' && rest[1..].iter().all(u8::is_ascii_digit));
        if !fraction_ok {
            return Err(refuse());
        }
        Ok(Self(text.to_owned()))
    }
}

/// The file's global properties.
#[derive(Debug, Clone, PartialEq)]
pub struct AcmiHeader {
    /// `ReferenceTime`: the instant of time 0.
    pub reference_time: ReferenceTime,
    /// `Title`.
    pub title: String,
    /// The run's origin; the integer degrees nearest to it become
    /// `ReferenceLongitude`/`ReferenceLatitude`.
    pub origin: Geodetic,
}

/// What Tacview shows for one object.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObjectInfo {
    /// `Name`: the aircraft type, e.g. `C172`.
    pub name: String,
    /// `Type` tags, e.g. `Air+FixedWing`.
    pub type_tags: String,
    /// `CallSign`, e.g. `C172-1`.
    pub callsign: String,
}

impl ObjectInfo {
    /// Aircraft number `index` (0-based) of model `M`: callsign
    /// `{M::CALLSIGN}-{index + 1}`.
    #[must_use]
    pub fn of<M: RunModel>(index: usize) -> Self {
        Self {
            name: M::ACMI_NAME.to_owned(),
            type_tags: M::ACMI_TYPE.to_owned(),
            callsign: format!("{}-{}", M::CALLSIGN, index + 1),
        }
    }
}

/// One object's track as written so far.
#[derive(Debug, Clone)]
struct Track {
    /// How many times the object was renewed ([`AcmiWriter::renew`]): its
    /// id is `index + 1 + generation · 2^32`.
    generation: u64,
    info: ObjectInfo,
    /// Its declaration (name, type, callsign) is still to be written.
    fresh: bool,
    removed: bool,
    /// The fields of its last line, in their written units (fixed point).
    last: [i64; 6],
}

/// The ACMI id of object `index` after `generation` renewals: with `index`
/// below [`MAX_OBJECTS`] and `generation` at most [`MAX_RENEWALS`], a
/// different id for each pair (the low 32 bits `index + 1`, the high ones
/// `generation`).
fn object_id(index: usize, generation: u64) -> u64 {
    (index as u64 + 1) | (generation << 32)
}

/// Where the text goes.
enum Sink {
    Plain(Box<dyn Write + Send>),
    Zip(Box<zip::ZipWriter<BufWriter<WatchedFile>>>),
}

impl Sink {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        match self {
            Self::Plain(w) => w.write_all(bytes),
            Self::Zip(w) => w.write_all(bytes),
        }
    }
}

/// Writes an ACMI 2.2 file as the frames are flown (see the module docs for
/// the layout).
pub struct AcmiWriter {
    sink: Option<Sink>,
    text: String,
    written: u64,
    ref_lon_deg: f64,
    ref_lat_deg: f64,
    fps: u32,
    /// The frame of the time the next object line belongs to, and whether
    /// its `#` line is written.
    frame: u64,
    frame_written: bool,
    tracks: Vec<Option<Track>>,
}

impl std::fmt::Debug for AcmiWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AcmiWriter")
            .field("fps", &self.fps)
            .field("frame", &self.frame)
            .field("objects", &self.tracks.len())
            .field("bytes", &self.bytes_written())
            .finish_non_exhaustive()
    }
}

/// Why an ACMI file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum AcmiError {
    /// Creating, writing or compressing failed.
    #[error("writing the ACMI file: {0}")]
    Io(#[from] io::Error),
    /// The zip container failed.
    #[error("writing the ACMI file: {0}")]
    Zip(#[from] zip::result::ZipError),
    /// Written after [`AcmiWriter::finish`].
    #[error("the ACMI file is already finished")]
    Finished,
    /// An object index at or beyond [`MAX_OBJECTS`]: its id would take the
    /// place of another object's after a reset.
    #[error("ACMI object index {index} is out of range (an ACMI file holds objects 0 to {})", MAX_OBJECTS - 1)]
    ObjectIndex {
        /// The index asked for.
        index: usize,
    },
    /// The table of objects could not grow to `objects` entries: the
    /// allocator refused the memory.
    #[error("no memory for a table of {objects} ACMI objects")]
    OutOfMemory {
        /// The entries the table needed.
        objects: usize,
    },
    /// Object `index` was renewed [`MAX_RENEWALS`] times: every id it can
    /// take is used (a renewal more would write an id again, that of its
    /// first object).
    #[error(
        "ACMI object index {index} was renewed {} times: every id it can take is used",
        MAX_RENEWALS
    )]
    Renewals {
        /// The index renewed.
        index: usize,
    },
}

/// How many times one object index can be renewed ([`AcmiWriter::renew`]):
/// its ids are `index + 1 + k · 2^32` for `k` from 0 to this, every one a
/// 64-bit ACMI id of its own (one a frame, 30 frames a second: about 4.5
/// years).
pub const MAX_RENEWALS: u64 = u32::MAX as u64;

impl AcmiWriter {
    /// An ACMI file at `path` for a run at `fps`: zip-compressed (one entry,
    /// the file's name without `.zip`) when the name ends in
    /// [`ZIP_SUFFIX`], plain text otherwise. The header is written now.
    ///
    /// # Errors
    /// The file cannot be created or written.
    pub fn create(path: &Path, header: &AcmiHeader, fps: u32) -> Result<Self, AcmiError> {
        Self::on_file(WatchedFile::new(File::create(path)?), path, header, fps)
    }

    /// As [`AcmiWriter::create`], on `file` already opened (or created) at
    /// `path`: a file watched by a program that answers signals while a
    /// write waits ([`WatchedFile::watched_by`]).
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn on_file(
        file: WatchedFile,
        path: &Path,
        header: &AcmiHeader,
        fps: u32,
    ) -> Result<Self, AcmiError> {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let sink = match name.strip_suffix(ZIP_SUFFIX) {
            Some(stem) => {
                let mut zip = zip::ZipWriter::new(BufWriter::new(file));
                let options = zip::write::SimpleFileOptions::default()
                    .compression_method(zip::CompressionMethod::Deflated)
                    .last_modified_time(zip::DateTime::default())
                    .large_file(true);
                zip.start_file(format!("{stem}.txt.acmi"), options)?;
                Sink::Zip(Box::new(zip))
            }
            None => Sink::Plain(Box::new(BufWriter::new(file))),
        };
        Self::with_sink(sink, header, fps)
    }

    /// Plain ACMI text to `out`.
    ///
    /// # Errors
    /// Writing the header fails.
    pub fn new(
        out: impl Write + Send + 'static,
        header: &AcmiHeader,
        fps: u32,
    ) -> Result<Self, AcmiError> {
        Self::with_sink(Sink::Plain(Box::new(out)), header, fps)
    }

    fn with_sink(sink: Sink, header: &AcmiHeader, fps: u32) -> Result<Self, AcmiError> {
        let ref_lon_deg = round_reference(header.origin.lon_deg);
        let ref_lat_deg = round_reference(header.origin.lat_deg);
        let mut writer = Self {
            sink: Some(sink),
            text: String::with_capacity(CHUNK_BYTES * 2),
            written: 0,
            ref_lon_deg,
            ref_lat_deg,
            fps: fps.max(1),
            frame: 0,
            frame_written: false,
            tracks: Vec::new(),
        };
        let t = &mut writer.text;
        t.push_str("FileType=text/acmi/tacview\nFileVersion=2.2\n");
        let _ = writeln!(t, "0,ReferenceTime={}", header.reference_time.as_str());
        let _ = writeln!(t, "0,ReferenceLongitude={ref_lon_deg}");
        let _ = writeln!(t, "0,ReferenceLatitude={ref_lat_deg}");
        t.push_str("0,DataSource=afit-fdm\n");
        t.push_str("0,Title=");
        escape_into(t, &header.title);
        t.push('\n');
        writer.flush_text(false)?;
        Ok(writer)
    }

    /// Declares object `index` (0-based; its ACMI id is `index + 1`): its
    /// name, type and callsign go out with its first sample. Declaring an
    /// index again starts its track anew under the same id; to fly an
    /// aircraft again after a reset, [`Self::renew`] it instead. The writer
    /// keeps a table entry for every index up to the largest declared.
    ///
    /// # Errors
    /// [`AcmiError::ObjectIndex`] for an index at or beyond [`MAX_OBJECTS`];
    /// [`AcmiError::OutOfMemory`] when the table cannot grow to it.
    pub fn declare(&mut self, index: usize, info: ObjectInfo) -> Result<(), AcmiError> {
        self.declare_generation(index, 0, info)
    }

    /// Starts object `index` over as a new ACMI object (a flight after a
    /// reset), declared with `info`: the old object, if its track was
    /// written and it is not removed yet, is removed in the current frame,
    /// and the new one takes the next id of the index, `index + 1 + k ·
    /// 2^32` for its `k`-th renewal (an id whose track was never written is
    /// kept). No id is written again after its removal (see the [module
    /// docs](self)). An index never declared is declared.
    ///
    /// ```
    /// use fdm_core::geodesy::{Attitude, Geodetic};
    /// use fdm_run::acmi::{AcmiHeader, AcmiWriter, ObjectInfo, ReferenceTime};
    /// use fdm_run::Placement;
    ///
    /// # let at = |alt_m| Placement {
    /// #     geodetic: Geodetic { lat_deg: 0.0, lon_deg: 0.0, alt_m },
    /// #     attitude: Attitude { roll_deg: 0.0, pitch_deg: 0.0, heading_deg: 0.0 },
    /// # };
    /// let info = ObjectInfo {
    ///     name: "C172".into(),
    ///     type_tags: "Air+FixedWing".into(),
    ///     callsign: "C172-1".into(),
    /// };
    /// let header = AcmiHeader {
    ///     reference_time: ReferenceTime::default(),
    ///     title: "reset".into(),
    ///     origin: Geodetic { lat_deg: 0.0, lon_deg: 0.0, alt_m: 0.0 },
    /// };
    /// let path = std::env::temp_dir().join(format!("renew-{}.acmi", std::process::id()));
    /// let mut w = AcmiWriter::create(&path, &header, 1)?;
    /// w.declare(0, info.clone())?;
    /// w.sample(0, &at(100.0))?;
    /// w.begin_frame(1);
    /// w.sample(0, &at(200.0))?;
    /// w.renew(0, info)?; // a reset: back to the start in the same frame
    /// w.sample(0, &at(100.0))?;
    /// w.finish()?;
    /// let text = std::fs::read_to_string(&path)?;
    /// # std::fs::remove_file(&path)?;
    /// assert!(text.ends_with(
    ///     "#1\n1,T=||200|||\n-1\n100000001,T=0|0|100|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n"
    /// ));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`AcmiError::Renewals`] after [`MAX_RENEWALS`] renewals of the index
    /// (the object is then left as it was); writing the removal fails; or
    /// [`Self::declare`]'s errors.
    pub fn renew(&mut self, index: usize, info: ObjectInfo) -> Result<(), AcmiError> {
        let (written, generation) = match self.tracks.get(index) {
            Some(Some(track)) => (!track.fresh, track.generation),
            _ => (false, 0),
        };
        let next = if written {
            if generation >= MAX_RENEWALS {
                return Err(AcmiError::Renewals { index });
            }
            self.remove(index)?;
            generation + 1
        } else {
            generation
        };
        self.declare_generation(index, next, info)
    }

    fn declare_generation(
        &mut self,
        index: usize,
        generation: u64,
        info: ObjectInfo,
    ) -> Result<(), AcmiError> {
        if index >= MAX_OBJECTS {
            return Err(AcmiError::ObjectIndex { index });
        }
        let objects = index + 1;
        if let Some(more) = objects.checked_sub(self.tracks.len()) {
            // A refusal is an error, not the allocator's abort.
            self.tracks
                .try_reserve(more)
                .map_err(|_| AcmiError::OutOfMemory { objects })?;
            self.tracks.resize(objects, None);
        }
        self.tracks[index] = Some(Track {
            generation,
            info,
            fresh: true,
            removed: false,
            last: [0; 6],
        });
        Ok(())
    }

    /// The samples that follow belong to the run's frame `flown` (time =
    /// `flown` / fps).
    pub fn begin_frame(&mut self, flown: u64) {
        if flown != self.frame {
            self.frame = flown;
            self.frame_written = false;
        }
    }

    /// Writes object `index`'s placement in the current frame (only the
    /// fields that changed). Undeclared or removed objects are skipped.
    ///
    /// # Errors
    /// Writing fails.
    pub fn sample(&mut self, index: usize, placement: &Placement) -> Result<(), AcmiError> {
        let fields = self.fields(placement);
        let Some(Some(track)) = self.tracks.get_mut(index) else {
            return Ok(());
        };
        if track.removed {
            return Ok(());
        }
        let (fresh, generation) = (track.fresh, track.generation);
        if !fresh && fields == track.last {
            return Ok(());
        }
        let last = track.last;
        track.last = fields;
        track.fresh = false;
        let info = fresh.then(|| track.info.clone());
        self.time_line();
        let t = &mut self.text;
        let _ = write!(t, "{:x},T=", object_id(index, generation));
        for (k, (&value, decimals)) in fields.iter().zip([7, 7, 2, 2, 2, 2]).enumerate() {
            if k > 0 {
                t.push('|');
            }
            if fresh || value != last[k] {
                push_fixed(t, value, decimals);
            }
        }
        if let Some(info) = info {
            t.push_str(",Name=");
            escape_into(t, &info.name);
            t.push_str(",Type=");
            escape_into(t, &info.type_tags);
            t.push_str(",CallSign=");
            escape_into(t, &info.callsign);
        }
        t.push('\n');
        self.flush_text(false)
    }

    /// Removes object `index` in the current frame (`-id`), once; later
    /// samples are skipped until it is declared again.
    ///
    /// # Errors
    /// Writing fails.
    pub fn remove(&mut self, index: usize) -> Result<(), AcmiError> {
        let Some(Some(track)) = self.tracks.get_mut(index) else {
            return Ok(());
        };
        if track.removed {
            return Ok(());
        }
        track.removed = true;
        let (written, generation) = (!track.fresh, track.generation);
        if written {
            self.time_line();
            let _ = writeln!(self.text, "-{:x}", object_id(index, generation));
        }
        self.flush_text(false)
    }

    /// Writes frame `flown` of a fleet of model `M` placed at `origin`:
    /// item `i` of `aircraft` is aircraft `i`'s view and status (`None`:
    /// skip it this frame). Aircraft are declared on their first frame
    /// ([`ObjectInfo::of`]); a crashed one is written once more and removed,
    /// a diverged one removed.
    ///
    /// # Errors
    /// Writing fails.
    pub fn fleet_frame<M: RunModel>(
        &mut self,
        flown: u64,
        origin: &GeodeticOrigin,
        aircraft: impl IntoIterator<Item = Option<(FlightView, FlightStatus)>>,
    ) -> Result<(), AcmiError> {
        self.begin_frame(flown);
        for (i, item) in aircraft.into_iter().enumerate() {
            let Some((view, status)) = item else {
                continue;
            };
            if !matches!(self.tracks.get(i), Some(Some(_))) {
                self.declare(i, ObjectInfo::of::<M>(i))?;
            }
            if self.is_removed(i) {
                continue;
            }
            match status {
                FlightStatus::Diverged => self.remove(i)?,
                FlightStatus::Landed(LandingState::Crash) => {
                    self.sample(i, &Placement::of(&view, origin))?;
                    self.remove(i)?;
                }
                _ => self.sample(i, &Placement::of(&view, origin))?,
            }
        }
        Ok(())
    }

    /// Whether object `index` was removed.
    #[must_use]
    pub fn is_removed(&self, index: usize) -> bool {
        matches!(self.tracks.get(index), Some(Some(t)) if t.removed)
    }

    /// Ends the file: a last time line for the current frame if it has none
    /// yet (so the file lasts as long as the run), then flushes and closes
    /// the zip container. Later calls do nothing.
    ///
    /// # Errors
    /// Writing fails.
    pub fn finish(&mut self) -> Result<(), AcmiError> {
        if self.sink.is_none() {
            return Ok(());
        }
        self.time_line();
        self.flush_text(true)?;
        match self.sink.take() {
            Some(Sink::Plain(mut w)) => w.flush()?,
            Some(Sink::Zip(zip)) => {
                let mut inner = (*zip).finish()?;
                inner.flush()?;
            }
            None => {}
        }
        Ok(())
    }

    /// Bytes of text written so far (before compression).
    #[must_use]
    pub fn bytes_written(&self) -> u64 {
        self.written + self.text.len() as u64
    }

    /// The fields of `placement` in their written fixed-point units.
    fn fields(&self, p: &Placement) -> [i64; 6] {
        [
            fixed(p.geodetic.lon_deg - self.ref_lon_deg, 1e7),
            fixed(p.geodetic.lat_deg - self.ref_lat_deg, 1e7),
            fixed(p.geodetic.alt_m, 1e2),
            fixed(p.attitude.roll_deg, 1e2),
            fixed(p.attitude.pitch_deg, 1e2),
            fixed(p.attitude.heading_deg, 1e2),
        ]
    }

    /// The current frame's `#` line, if not written yet.
    fn time_line(&mut self) {
        if self.frame_written {
            return;
        }
        self.frame_written = true;
        // Microseconds, rounded half up, in integers: the same text on
        // every machine.
        let fps = u128::from(self.fps);
        let micros = (u128::from(self.frame) * 2_000_000 + fps) / (2 * fps);
        let micros = i64::try_from(micros).unwrap_or(i64::MAX);
        self.text.push('#');
        push_fixed(&mut self.text, micros, 6);
        self.text.push('\n');
    }

    fn flush_text(&mut self, force: bool) -> Result<(), AcmiError> {
        if !force && self.text.len() < CHUNK_BYTES {
            return Ok(());
        }
        let sink = self.sink.as_mut().ok_or(AcmiError::Finished)?;
        sink.write_all(self.text.as_bytes())?;
        self.written += self.text.len() as u64;
        self.text.clear();
        Ok(())
    }
}

/// The integer degree nearest to `deg` (0 for a non-finite value).
fn round_reference(deg: f64) -> f64 {
    if deg.is_finite() {
        deg.round()
    } else {
        0.0
    }
}

/// `value × scale` rounded to the nearest integer (half away from zero);
/// non-finite values become 0.
fn fixed(value: f64, scale: f64) -> i64 {
    let scaled = (value * scale).round();
    if scaled.is_finite() {
        // Saturating: far beyond any placement on Earth.
        #[allow(clippy::cast_possible_truncation)]
        let v = scaled as i64;
        v
    } else {
        0
    }
}

/// Appends `value / 10^decimals` in decimal, without trailing zeros or a
/// trailing point.
fn push_fixed(out: &mut String, value: i64, decimals: u32) {
    let scale = 10_u64.pow(decimals);
    if value < 0 {
        out.push('-');
    }
    let magnitude = value.unsigned_abs();
    let whole = magnitude / scale;
    let mut fraction = magnitude % scale;
    let _ = write!(out, "{whole}");
    if fraction != 0 {
        let mut width = decimals as usize;
        while fraction.is_multiple_of(10) {
            fraction /= 10;
            width -= 1;
        }
        let _ = write!(out, ".{fraction:0width$}");
    }
}

/// Appends `text` escaped for an ACMI property value: `\,` for commas,
/// `\` + newline for line breaks.
fn escape_into(out: &mut String, text: &str) {
    for c in text.chars() {
        match c {
            ',' => out.push_str("\\,"),
            '\n' => out.push_str("\\\n"),
            '\r' => {}
            '\\' => out.push_str("\\\\"),
            c => out.push(c),
        }
    }
}

/// The ACMI output of a single-aircraft [`Run`](crate::Run): object 1, the
/// model's name, type and callsign `{CALLSIGN}-1`; removed on a crash or a
/// divergence. A reset removes the flight it ends (if it flies on) and
/// starts the next as a new object ([`AcmiWriter::renew`]: ids `100000001`,
/// `200000001`, …, the same callsign).
pub struct AcmiOutput<M> {
    writer: AcmiWriter,
    _model: PhantomData<fn() -> M>,
}

impl<M> std::fmt::Debug for AcmiOutput<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("AcmiOutput").field(&self.writer).finish()
    }
}

impl<M: RunModel> AcmiOutput<M> {
    /// The output writing to `writer`.
    #[must_use]
    pub fn new(writer: AcmiWriter) -> Self {
        Self {
            writer,
            _model: PhantomData,
        }
    }

    /// The writer.
    #[must_use]
    pub fn writer(&self) -> &AcmiWriter {
        &self.writer
    }
}

impl<M: RunModel> Output<M> for AcmiOutput<M> {
    fn frame(&mut self, frame: &Frame<'_, M>) -> Result<(), OutputError> {
        let w = &mut self.writer;
        w.begin_frame(frame.flown);
        match frame.event {
            Event::Start => {
                w.declare(0, ObjectInfo::of::<M>(0))?;
                w.sample(0, frame.placement)?;
            }
            Event::Reset => {
                w.renew(0, ObjectInfo::of::<M>(0))?;
                w.sample(0, frame.placement)?;
            }
            Event::Step => match frame.status {
                FlightStatus::Diverged => w.remove(0)?,
                FlightStatus::Landed(LandingState::Crash) => {
                    w.sample(0, frame.placement)?;
                    w.remove(0)?;
                }
                _ => w.sample(0, frame.placement)?,
            },
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), OutputError> {
        Ok(self.writer.finish()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_text() {
        let mut s = String::new();
        for (v, d) in [
            (0, 7),
            (-483_000, 7),
            (1_234_567, 2),
            (-5, 2),
            (100, 2),
            (33_333, 6),
        ] {
            push_fixed(&mut s, v, d);
            s.push(' ');
        }
        assert_eq!(s, "0 -0.0483 12345.67 -0.05 1 0.033333 ");
    }

    /// A sink that keeps every write it is handed: its length and its bytes.
    #[derive(Clone, Default)]
    struct Recorder(std::sync::Arc<std::sync::Mutex<(Vec<usize>, Vec<u8>)>>);

    impl Recorder {
        /// The length of each write, in order.
        fn lengths(&self) -> Vec<usize> {
            self.0.lock().unwrap().0.clone()
        }
        /// Every byte written, as text.
        fn text(&self) -> String {
            String::from_utf8(self.0.lock().unwrap().1.clone()).unwrap()
        }
    }

    impl Write for Recorder {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            let mut kept = self.0.lock().unwrap();
            kept.0.push(buf.len());
            kept.1.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    /// A file's header: `title`, its origin at `lat_deg`, `lon_deg`, `alt_m`.
    fn header(title: &str, lat_deg: f64, lon_deg: f64, alt_m: f64) -> AcmiHeader {
        AcmiHeader {
            reference_time: ReferenceTime::default(),
            title: title.to_owned(),
            origin: Geodetic {
                lat_deg,
                lon_deg,
                alt_m,
            },
        }
    }

    /// A level placement (no roll, no pitch) at `lat_deg`, `lon_deg`,
    /// `alt_m`, heading `heading_deg`.
    fn level(lat_deg: f64, lon_deg: f64, alt_m: f64, heading_deg: f64) -> Placement {
        Placement {
            geodetic: Geodetic {
                lat_deg,
                lon_deg,
                alt_m,
            },
            attitude: fdm_core::geodesy::Attitude {
                roll_deg: 0.0,
                pitch_deg: 0.0,
                heading_deg,
            },
        }
    }

    /// An index renewed [`MAX_RENEWALS`] times has used every id it can
    /// take: the renewal after is refused and the object left as it was
    /// (not removed), where a wrapping id would have written the first
    /// object's id again. The last id's high 32 bits are all ones.
    #[test]
    fn renewals_end_before_an_id_comes_back() {
        let writes = Recorder::default();
        let header = header("renewals", 39.8, -84.0, 251.0);
        let mut w = AcmiWriter::new(writes.clone(), &header, 30).unwrap();
        let info = ObjectInfo::of::<fdm_core::palmer::Palmer>(0);
        let index = 0;
        w.declare(index, info.clone()).unwrap();
        w.sample(index, &level(39.8, -84.0, 300.0, 0.0)).unwrap();
        // As after MAX_RENEWALS - 1 renewals, each written.
        w.tracks[index].as_mut().unwrap().generation = MAX_RENEWALS - 1;
        w.begin_frame(1);
        w.renew(index, info.clone()).unwrap();
        w.sample(index, &level(39.8, -84.0, 310.0, 0.0)).unwrap();
        w.begin_frame(2);
        let refused = w.renew(index, info.clone()).unwrap_err();
        assert!(matches!(refused, AcmiError::Renewals { index: i } if i == index));
        assert_eq!(
            refused.to_string(),
            format!("ACMI object index {index} was renewed 4294967295 times: every id it can take is used")
        );
        // The object flies on under its last id.
        w.sample(index, &level(39.8, -84.0, 320.0, 0.0)).unwrap();
        w.finish().unwrap();
        let text = writes.text();
        let (last, before) = ("ffffffff00000001", "fffffffe00000001");
        assert!(text.contains(&format!("\n-{before}\n{last},T=")), "{text}");
        assert!(
            text.ends_with(&format!("#0.066667\n{last},T=||320|||\n")),
            "{text}"
        );
        assert_eq!(text.matches(&format!("-{last}")).count(), 0, "{text}");
    }

    /// The text goes to the sink in pieces of at least [`CHUNK_BYTES`]
    /// (one write per 64 KiB, not one per line), every byte of it by the
    /// end; after `finish` a write is refused.
    #[test]
    fn text_goes_out_in_chunks() {
        let writes = Recorder::default();
        let header = header("chunks", 39.8, -84.0, 251.0);
        let mut w = AcmiWriter::new(writes.clone(), &header, 30).unwrap();
        w.declare(0, ObjectInfo::of::<fdm_core::palmer::Palmer>(0))
            .unwrap();
        let placement =
            |k: u32| level(39.8 + f64::from(k) * 1e-6, -84.0, 300.0 + f64::from(k), 0.0);
        // Frame k samples placement(k) (every one moved) until `bytes`
        // bytes of text have been written or gathered.
        let mut k = 0;
        let mut fly_to = |w: &mut AcmiWriter, bytes: u64| {
            while w.bytes_written() < bytes {
                assert!(k < 100_000, "the samples write no text");
                w.begin_frame(u64::from(k));
                w.sample(0, &placement(k)).unwrap();
                k += 1;
            }
        };
        fly_to(&mut w, (CHUNK_BYTES as u64).saturating_sub(100));
        assert!(writes.lengths().is_empty(), "nothing written before 64 KiB");
        // Its `Debug` says where it is (the text is not printed).
        let shown = format!("{w:?}");
        let bytes = format!("bytes: {}", w.bytes_written());
        for part in ["AcmiWriter", "fps: 30", "objects: 1", &bytes] {
            assert!(shown.contains(part), "{shown}");
        }
        fly_to(&mut w, 3 * CHUNK_BYTES as u64);
        w.finish().unwrap();
        let lengths = writes.lengths();
        assert!(lengths.len() >= 3, "{lengths:?}");
        let (last, full) = lengths.split_last().unwrap();
        assert!(full.iter().all(|&n| n >= CHUNK_BYTES), "{lengths:?}");
        assert!(*last > 0);
        let total: usize = lengths.iter().sum();
        assert_eq!(total as u64, w.bytes_written());
        w.finish().unwrap();
        assert_eq!(
            writes.lengths().len(),
            lengths.len(),
            "a second finish writes nothing"
        );
        // Samples after the end gather text until a chunk would go out, and
        // that is refused: nothing reaches the sink.
        let refused = (1_000_000..1_100_000).find_map(|k| {
            w.begin_frame(u64::from(k));
            w.sample(0, &placement(k)).err()
        });
        assert!(matches!(refused, Some(AcmiError::Finished)), "{refused:?}");
        assert_eq!(writes.lengths().len(), lengths.len());
    }

    /// An object's first sample is written whole with its declaration, even
    /// at the reference point with every field 0; an unchanged placement
    /// writes nothing, not even its frame's time line; a changed one writes
    /// only the fields that changed.
    #[test]
    fn only_what_changed_is_written() {
        let out = Recorder::default();
        let header = header("t", 0.0, 0.0, 0.0);
        let mut w = AcmiWriter::new(out.clone(), &header, 2).unwrap();
        w.declare(0, ObjectInfo::of::<fdm_core::palmer::Palmer>(0))
            .unwrap();
        for (frame, (alt_m, heading_deg)) in [(0.0, 0.0), (0.0, 0.0), (5.0, 0.0), (5.0, 90.0)]
            .into_iter()
            .enumerate()
        {
            w.begin_frame(frame as u64);
            w.sample(0, &level(0.0, 0.0, alt_m, heading_deg)).unwrap();
        }
        w.finish().unwrap();
        let text = out.text();
        let body = text.split_once("0,Title=t\n").unwrap().1;
        assert_eq!(
            body,
            "#0\n1,T=0|0|0|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n\
             #1\n1,T=||5|||\n#1.5\n1,T=|||||90\n"
        );
    }

    /// An index whose id would leave the low 32 bits is refused with its
    /// message, by declare and by renew, and writes nothing; the table does
    /// not grow for it. The last index's id is `ffffffff`, the high half
    /// still the flight number's (not declared here: its table would take
    /// hundreds of gigabytes).
    #[test]
    fn an_index_beyond_the_ids_is_refused() {
        let out = Recorder::default();
        let header = header("t", 0.0, 0.0, 0.0);
        let mut w = AcmiWriter::new(out.clone(), &header, 1).unwrap();
        let info = || ObjectInfo::of::<fdm_core::palmer::Palmer>(0);
        for index in [MAX_OBJECTS, MAX_OBJECTS.saturating_add(1), usize::MAX] {
            let err = w.declare(index, info()).unwrap_err();
            assert!(matches!(err, AcmiError::ObjectIndex { index: i } if i == index));
            assert_eq!(
                err.to_string(),
                format!(
                    "ACMI object index {index} is out of range (an ACMI file holds objects 0 to 4294967294)"
                )
            );
            assert!(matches!(
                w.renew(index, info()),
                Err(AcmiError::ObjectIndex { index: i }) if i == index
            ));
            w.sample(index, &level(0.0, 0.0, 1.0, 0.0)).unwrap();
        }
        assert!(w.tracks.is_empty());
        assert_eq!(object_id(MAX_OBJECTS - 1, 0), 0xffff_ffff);
        assert_eq!(object_id(MAX_OBJECTS - 1, 1), 0x1_ffff_ffff);
        w.declare(3, info()).unwrap();
        assert_eq!(w.tracks.len(), 4);
        w.finish().unwrap();
        assert!(out.text().ends_with("0,Title=t\n#0\n"), "{}", out.text());
    }

    /// A fleet's frames: each aircraft declared (callsign by its index) at
    /// its first frame that has it, `None` skipped, a crashed one written
    /// once more and removed, a diverged one removed (with no line if it
    /// was never written), a removed one skipped after; a frame where
    /// nothing moved writes nothing but, as the file's end, its time.
    #[test]
    fn fleet_frames_declare_sample_and_remove() {
        use fdm_core::model::Model;
        use fdm_core::palmer::Palmer;
        let out = Recorder::default();
        let origin = GeodeticOrigin::new(39.8, -84.0, 251.0).unwrap();
        let header = header("fleet", 39.8, -84.0, 251.0);
        let mut w = AcmiWriter::new(out.clone(), &header, 30).unwrap();
        let (aircraft, controls) = (Palmer::default_aircraft(), Palmer::initial_controls());
        // In the air at 60 m/s, then 50 m further north and 10 m higher.
        let mut state = Palmer::initial_state();
        state.position_m = nalgebra::Vector3::new(0.0, 0.0, 500.0);
        state.velocity_mps = nalgebra::Vector3::new(60.0, 0.0, 0.0);
        let view = Palmer::view(&aircraft, &controls, &state);
        state.position_m += nalgebra::Vector3::new(50.0, 0.0, 10.0);
        let moved = Palmer::view(&aircraft, &controls, &state);
        let (up, crash) = (
            FlightStatus::Airborne,
            FlightStatus::Landed(LandingState::Crash),
        );
        let frames = [
            vec![
                Some((view, up)),
                None,
                Some((view, up)),
                Some((view, FlightStatus::Diverged)),
            ],
            vec![
                Some((moved, up)),
                Some((view, up)),
                Some((moved, crash)),
                Some((view, up)),
            ],
            vec![
                Some((moved, up)),
                Some((view, up)),
                Some((moved, up)),
                Some((view, up)),
            ],
        ];
        for (flown, frame) in frames.into_iter().enumerate() {
            w.fleet_frame::<Palmer>(flown as u64, &origin, frame)
                .unwrap();
        }
        let removed: Vec<bool> = (0..5).map(|i| w.is_removed(i)).collect();
        assert_eq!(removed, [false, false, true, true, false]);
        w.finish().unwrap();
        let text = out.text();
        let lines: Vec<&str> = text
            .split_once("0,Title=fleet\n")
            .unwrap()
            .1
            .lines()
            .collect();
        let ids: Vec<String> = lines
            .iter()
            .map(|l| {
                let (id, rest) = l.split_once(',').unwrap_or((l, ""));
                let named = rest.split(',').find_map(|p| p.strip_prefix("CallSign="));
                named.map_or_else(|| id.to_owned(), |c| format!("{id} {c}"))
            })
            .collect();
        assert_eq!(
            ids,
            [
                "#0",
                "1 C172-1",
                "3 C172-3",
                "#0.033333",
                "1",
                "2 C172-2",
                "3",
                "-3",
                // The end: the last frame's time (nothing moved in it).
                "#0.066667",
            ],
            "{text}"
        );
    }

    /// A single flight's output shows its writer in `Debug`, and hands it out.
    #[test]
    fn an_acmi_output_shows_its_writer() {
        let header = header("one", 0.0, 0.0, 0.0);
        let writer = AcmiWriter::new(Recorder::default(), &header, 25).unwrap();
        let output = AcmiOutput::<fdm_core::palmer::Palmer>::new(writer);
        // The header is gathered, not yet written: counted all the same.
        assert!(output.writer().bytes_written() > 100);
        let shown = format!("{output:?}");
        assert!(shown.starts_with("AcmiOutput(AcmiWriter {"), "{shown}");
        assert!(shown.contains("fps: 25"), "{shown}");
    }

    /// A single flight's frames, numbered as a [`Run`](crate::Run) numbers
    /// them: declared and written at the start, a step written, a
    /// divergence removes it (no sample of the diverged frame, nothing while
    /// it is removed), a reset starts a new object (the next id) at the
    /// clock of the frame before it (the run's clock, `flown`, goes on
    /// across a reset: the file's time never goes back), a crash is written
    /// once more and removed, and a reset of a flight still flying removes
    /// it first.
    #[test]
    fn a_flights_frames_declare_sample_remove_and_reset() {
        use fdm_core::model::Model;
        use fdm_core::palmer::Palmer;
        let out = Recorder::default();
        let header = header("one", 0.0, 0.0, 0.0);
        let mut output =
            AcmiOutput::<Palmer>::new(AcmiWriter::new(out.clone(), &header, 1).unwrap());
        let (controls, state) = (Palmer::initial_controls(), Palmer::initial_state());
        let view = Palmer::view(&Palmer::default_aircraft(), &controls, &state);
        let up = FlightStatus::Airborne;
        let crash = FlightStatus::Landed(LandingState::Crash);
        // (frame number since the start or the reset, frames flown, ...)
        for (number, flown, event, alt_m, status) in [
            (0, 0, Event::Start, 1.0, up),
            (1, 1, Event::Step, 2.0, up),
            (2, 2, Event::Step, 3.0, FlightStatus::Diverged),
            (3, 3, Event::Step, 4.0, up),
            (0, 3, Event::Reset, 1.0, up),
            (1, 4, Event::Step, 0.0, crash),
            (0, 4, Event::Reset, 1.0, up),
            (1, 5, Event::Step, 2.0, up),
            (0, 5, Event::Reset, 1.0, up),
        ] {
            let placement = level(0.0, 0.0, alt_m, 0.0);
            let frame = Frame::<Palmer> {
                event,
                number,
                flown,
                fps: 1,
                actions: &[],
                controls: &controls,
                state: &state,
                view: &view,
                placement: &placement,
                status,
            };
            output.frame(&frame).unwrap();
        }
        Output::<Palmer>::finish(&mut output).unwrap();
        let text = out.text();
        let body = text.split_once("0,Title=one\n").unwrap().1;
        assert_eq!(
            body,
            "#0\n1,T=0|0|1|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n\
             #1\n1,T=||2|||\n#2\n-1\n\
             #3\n100000001,T=0|0|1|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n\
             #4\n100000001,T=||0|||\n-100000001\n\
             200000001,T=0|0|1|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n\
             #5\n200000001,T=||2|||\n-200000001\n\
             300000001,T=0|0|1|0|0|0,Name=C172,Type=Air+FixedWing,CallSign=C172-1\n",
            "{body}"
        );
    }

    #[test]
    fn reference_times() {
        for ok in [
            "2000-01-01T00:00:00Z",
            "2024-02-29T23:59:59Z",
            "2011-06-02T05:00:00.5Z",
            // The longest taken: nine digits of fraction, 30 bytes.
            "2011-06-02T05:00:00.123456789Z",
            // The last day of each month length, and the ends of each field.
            "2000-02-29T00:00:00Z",
            "2023-02-28T12:00:00Z",
            "2001-04-30T00:00:00Z",
            "2001-12-31T23:59:59Z",
            "0001-01-01T00:00:00Z",
        ] {
            assert_eq!(ok.parse::<ReferenceTime>().unwrap().as_str(), ok);
        }
        for bad in [
            "",
            "2023-02-29T00:00:00Z",
            "2000-01-01 00:00:00Z",
            "2000-01-01T00:00:00",
            "2000-13-01T00:00:00Z",
            "2000-01-01T24:00:00Z",
            "2000-01-01T00:00:00.Z",
            "2000-01-01T00:00:00+01:00",
            "0000-01-01T00:00:00Z",
            // 31 bytes: one digit of fraction too many.
            "2011-06-02T05:00:00.1234567890Z",
            // Not ASCII (a full-width digit), though of the right length.
            "2000-01-01T00:00:0\u{ff11}Z",
            "1900-02-29T00:00:00Z",
            "2001-04-31T00:00:00Z",
            "2001-01-00T00:00:00Z",
            "2001-00-01T00:00:00Z",
            "2001-01-01T00:60:00Z",
            "2001-01-01T00:00:60Z",
            "2001-01-01T00:00:00.5",
        ] {
            assert!(bad.parse::<ReferenceTime>().is_err(), "{bad}");
        }
    }
}
