//! What differs between the models in the CLI, one module per model: the
//! report and CSV fields, the HUD's control line, the keys, the starting
//! controls from the command line and FlightGear's aircraft. Everything else
//! in `sim-cli` is generic over [`CliModel`].
//!
//! A new model joins the CLI with one more module here implementing
//! [`CliModel`] (and [`Details`] for its report fields) and one more
//! subcommand in [`crate::args`].

pub mod bourg;
pub mod palmer;

use std::fmt::Debug;

use fdm_core::model::Model;
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::args::ModelKind;
use crate::keys::KeyAction;

/// Something to do with a model type chosen at run time: the one place that
/// maps the command line's [`ModelKind`] to the model types
/// ([`ModelKind::with`]).
pub trait WithModel {
    /// What it returns.
    type Output;
    /// Does it for model `M`.
    fn call<M: CliModel>(self) -> Self::Output;
}

impl ModelKind {
    /// Runs `job` with this kind's model type.
    pub fn with<W: WithModel>(self, job: W) -> W::Output {
        match self {
            Self::Palmer => job.call::<fdm_core::palmer::Palmer>(),
            Self::Bourg => job.call::<fdm_core::bourg::Bourg>(),
        }
    }
}

/// A model as `sim-cli` flies it.
///
/// State and controls are serde types so that `--record` can store them
/// (docs/recording.md); the aircraft goes through [`Self::AircraftRecord`].
pub trait CliModel:
    Model<
    Action: KeyAction,
    State: Serialize + DeserializeOwned,
    Controls: Serialize + DeserializeOwned,
>
{
    /// The model's own report fields (JSON next to the common ones, CSV
    /// columns after them, a summary line, the HUD's control line).
    type Details: Details;

    /// The model's structure-of-arrays fleet (`sim-cli fleet --kernel
    /// lanes`): `fdm_fleet::Fleet<Self>` for any model whose step is written
    /// over `fdm_core::real`'s number type (no hand-written kernel).
    type Lanes: fdm_fleet::LaneFleet<Model = Self>;

    /// The aircraft's parameters as a recording stores them: everything
    /// needed to rebuild an identical [`Model::Aircraft`].
    type AircraftRecord: Serialize + DeserializeOwned + Debug;

    /// The record of `aircraft`.
    fn aircraft_record(aircraft: &Self::Aircraft) -> Self::AircraftRecord;

    /// Rebuilds (and validates) the aircraft from its record.
    ///
    /// # Errors
    /// A one-line message naming what is wrong with the parameters.
    fn aircraft_from_record(record: Self::AircraftRecord) -> Result<Self::Aircraft, String>;

    /// FlightGear's aircraft for this model (`--aircraft=...`).
    const FG_AIRCRAFT: &'static str;

    /// The model's DIS entity type (`--dis`, [`crate::dis`]).
    const DIS_KIND: fdm_dis::AircraftKind;

    /// The start of its DIS callsigns (markings): `C172-1`, `C172-2`, ...
    const DIS_CALLSIGN: &'static str;

    /// Further fgfs options that aircraft needs with `--fdm=null` (printed by
    /// `sim-cli fgfs-command`, already shell-quoted where needed).
    const FG_OPTIONS: &'static [&'static str] = &[];

    /// Nasal statements FlightGear runs once its FDM is initialised (after the
    /// aircraft's own scripts, which reset properties given as `--prop:`
    /// options): property settings the aircraft needs with `--fdm=null`.
    /// Double quotes only (the whole script is one single-quoted shell word).
    const FG_STARTUP_NASAL: &'static str = "";

    /// The model file FlightGear loads for this model as a multiplayer
    /// aircraft (relative to its data directory).
    const FG_MP_MODEL: &'static str;

    /// `state` moved by `north_m`, `west_m` and `up_m` (the earth frame's x, y,
    /// z, metres), everything else unchanged: fleet spawn patterns.
    fn offset_state(state: &Self::State, north_m: f64, west_m: f64, up_m: f64) -> Self::State;

    /// Position `[x, y, z]` in the model's earth frame (x north, y west, z
    /// up) in the model's own unit ([`Details::POSITION_UNIT`]), widened to
    /// `f64` exactly.
    fn native_position(state: &Self::State) -> [f64; 3];

    /// Velocity in the same frame and unit per second.
    fn native_velocity(state: &Self::State) -> [f64; 3];

    /// The model's report fields now.
    fn details(
        aircraft: &Self::Aircraft,
        controls: &Self::Controls,
        state: &Self::State,
    ) -> Self::Details;
}

/// A model's own report fields.
pub trait Details: Serialize + DeserializeOwned + Copy + Debug + PartialEq {
    /// The JSON `model` field and the CLI subcommand: `"palmer"`, `"bourg"`.
    const MODEL: &'static str;
    /// The unit of the native position: `"m"` or `"ft"`.
    const POSITION_UNIT: &'static str;
    /// CSV column names of these fields, after the common ones.
    const CSV_COLUMNS: &'static [&'static str];

    /// Appends one value per [`Self::CSV_COLUMNS`] entry, in order.
    fn csv_values(&self, out: &mut Vec<f64>);

    /// The human summary's model-specific line(s), without a trailing newline.
    fn summary(&self) -> String;

    /// The HUD's control line.
    fn hud_controls(&self) -> String;
}

/// `x` for a display with one decimal, except that values that show as zero are
/// +0.0, so a tiny negative roll does not flicker as "-0.0".
#[must_use]
pub fn tenths(x: f64) -> f64 {
    if (x * 10.0).round() == 0.0 {
        0.0
    } else {
        x
    }
}
