//! What differs between the models in the CLI, one module per model: the
//! report and CSV fields, the HUD's control line, the keys, the starting
//! controls from the command line and FlightGear's multiplayer model (the
//! native-FDM aircraft is the run library's, `fdm_run::RunModel::FG_AIRCRAFT`).
//! Everything else in `sim-cli` is generic over [`CliModel`].
//!
//! A new model joins the CLI with one more module here implementing
//! [`CliModel`] (and [`Details`] for its report fields) and one more
//! subcommand in [`crate::args`].

pub mod bourg;
pub mod palmer;

use std::fmt::Debug;

use fdm_run::csv::CsvModel;
use fdm_run::FleetModel;
use fdm_study::StudyModel;
use serde::de::DeserializeOwned;
use serde::Serialize;

use clap::ValueEnum;

use crate::keys::KeyAction;

/// Which model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelKind {
    /// Palmer's Cessna 172.
    Palmer,
    /// Bourg's 6-DoF aircraft.
    Bourg,
}

impl ModelKind {
    /// The lowercase name used on the command line and in the JSON report.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Palmer => "palmer",
            Self::Bourg => "bourg",
        }
    }
}

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
    /// The kind of the model named `name` (its [`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        <Self as clap::ValueEnum>::value_variants()
            .iter()
            .copied()
            .find(|kind| kind.name() == name)
    }

    /// Runs `job` with this kind's model type.
    pub fn with<W: WithModel>(self, job: W) -> W::Output {
        match self {
            Self::Palmer => job.call::<fdm_core::palmer::Palmer>(),
            Self::Bourg => job.call::<fdm_core::bourg::Bourg>(),
        }
    }
}

/// A model as `sim-cli` flies it: a [`RunModel`](fdm_run::RunModel) (what the run library
/// needs to fly, record and replay it), a [`FleetModel`] (its fleet
/// kernel, formations and multiplayer model) and a [`StudyModel`] (its
/// studies' drawn inputs and measures, so `sim-cli study --run I` picks it
/// through [`ModelKind::with`]) with the CLI's own parts.
pub trait CliModel: CsvModel<Action: KeyAction> + FleetModel + StudyModel {
    /// The model's own report fields (JSON next to the common ones, CSV
    /// columns after them, a summary line, the HUD's control line).
    type Details: Details;

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
