//! What differs between the models in the CLI, one module per model: the
//! HUD's control line, the keys and the starting controls from the command
//! line. What the run library needs of a model (its recording, CSV columns,
//! report fields, FlightGear models, fleet kernel) is its adapter module in
//! `fdm_run::model`. Everything else in `sim-cli` is generic over
//! [`CliModel`].
//!
//! A new model joins the CLI with one more module here (the HUD line of its
//! report fields, [`Details`], and its keys) and one more subcommand in
//! [`crate::args`].

pub mod bourg;
pub mod palmer;

use fdm_run::{FleetModel, ReportModel};
use fdm_study::StudyModel;

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

/// A model as `sim-cli` flies it: a [`ReportModel`] (what the run library
/// needs to fly, record, replay and report it, and its CSV columns), a
/// [`FleetModel`] (its fleet kernel, formations and multiplayer model) and a
/// [`StudyModel`] (its studies' drawn inputs and measures, so `sim-cli study
/// --run I` picks it through [`ModelKind::with`]) with the CLI's own parts:
/// its keys and its report fields' HUD line ([`Details`]).
pub trait CliModel:
    ReportModel<Action: KeyAction, Details: Details> + FleetModel + StudyModel
{
}

impl<M> CliModel for M where
    M: ReportModel<Action: KeyAction, Details: Details> + FleetModel + StudyModel
{
}

/// A model's own report fields ([`fdm_run::report::Details`]: the JSON
/// fields and the summary line) and the HUD's control line made from them.
pub trait Details: fdm_run::report::Details {
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
