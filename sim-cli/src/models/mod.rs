//! What differs between the models in the CLI, one module per model: its
//! subcommand's own options and help, its controls at frame 0 from them,
//! its keys and the HUD's control line ([`CliModel`]). What the run library
//! needs of a model (its recording, CSV columns, report fields, FlightGear
//! models, fleet kernel) is its adapter module in `fdm_run::model` (or, for a
//! model outside the library crates such as the `glider` feature's, its
//! module here). Everything else in `sim-cli` is generic over [`CliModel`].
//!
//! A new model joins the CLI with one more module here and one more line in
//! the registry below: its subcommand (after the options every model shares,
//! `crate::args::CommonArgs`), its help, the `--model` and `fgfs-command`
//! values and the models a recording may name follow from it.

use clap::builder::PossibleValue;
use clap::{Args, FromArgMatches, ValueEnum};
use fdm_run::{FleetModel, ReportModel};
use fdm_study::StudyModel;

use crate::error::CliError;
use crate::keys::KeyAction;

/// The registry: one line per model, its module (`models/<name>.rs`) and its
/// model type. The subcommands, their help, the `--model` values and the
/// models a recording may name all come from it.
macro_rules! registry {
    ($($(#[$cfg:meta])* $module:ident :: $model:ident,)*) => {
        $($(#[$cfg])* pub mod $module;)*

        /// Which model: one of the registry's.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum ModelKind {
            $($(#[$cfg])* #[doc = concat!("`", stringify!($module), "`")] $model,)*
        }

        impl ModelKind {
            /// Every model of the registry, in the order help texts list them.
            pub const ALL: &[Self] = &[$($(#[$cfg])* Self::$model,)*];

            /// Runs `job` with this kind's model type.
            pub fn with<W: WithModel>(self, job: W) -> W::Output {
                match self {
                    $($(#[$cfg])* Self::$model => job.call::<$module::$model>(),)*
                }
            }
        }
    };
}

registry! {
    palmer::Palmer,
    bourg::Bourg,
    #[cfg(feature = "glider")]
    glider::Glider,
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

/// A model's name and what it flies, as a [`WithModel`] job.
struct Name;
impl WithModel for Name {
    type Output = (&'static str, &'static str);
    fn call<M: CliModel>(self) -> Self::Output {
        (M::NAME, M::AIRCRAFT)
    }
}

impl ModelKind {
    /// The lowercase name used on the command line and in the JSON report
    /// ([`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn name(self) -> &'static str {
        self.with(Name).0
    }

    /// What the model flies, for help texts (`CliModel::AIRCRAFT`).
    #[must_use]
    pub fn aircraft(self) -> &'static str {
        self.with(Name).1
    }

    /// The kind of the model named `name` (its [`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|kind| kind.name() == name)
    }

    /// The CSV layouts of the registry's models, in registry order: the
    /// models whose CSVs `sim-cli plot` reads ([`fdm_plot::csv::read_trace_among`]).
    #[must_use]
    pub fn csv_layouts() -> Vec<fdm_plot::csv::CsvLayout> {
        struct Layout;
        impl WithModel for Layout {
            type Output = fdm_plot::csv::CsvLayout;
            fn call<M: CliModel>(self) -> Self::Output {
                fdm_plot::csv::CsvLayout::of::<M>()
            }
        }
        Self::ALL.iter().map(|kind| kind.with(Layout)).collect()
    }

    /// The registry's models as a study may name them, in registry order:
    /// what `sim-cli study` reads a study file with
    /// ([`fdm_study::Study::from_path_among`]).
    #[must_use]
    pub fn study_models() -> Vec<fdm_study::StudyEntry> {
        struct Entry;
        impl WithModel for Entry {
            type Output = fdm_study::StudyEntry;
            fn call<M: CliModel>(self) -> Self::Output {
                fdm_study::StudyEntry::of::<M>()
            }
        }
        Self::ALL.iter().map(|kind| kind.with(Entry)).collect()
    }

    /// The registry's models as text: `a, b or c`, each shown by `show`.
    pub fn list(show: impl Fn(Self) -> String) -> String {
        let shown: Vec<String> = Self::ALL.iter().map(|&kind| show(kind)).collect();
        match shown.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        }
    }
}

/// `--model palmer|bourg` and `fgfs-command <MODEL>`: the registry's names,
/// with what each flies as their help.
impl ValueEnum for ModelKind {
    fn value_variants<'a>() -> &'a [Self] {
        Self::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.aircraft()))
    }
}

/// A model as `sim-cli` flies it: a [`ReportModel`] (what the run library
/// needs to fly, record, replay and report it, and its CSV columns), a
/// [`FleetModel`] (its fleet kernel, formations and multiplayer model) and a
/// [`StudyModel`] (its studies' drawn inputs and measures, so `sim-cli study
/// --run I` picks it through [`ModelKind::with`]) with the CLI's own parts:
/// its subcommand's options and help, its keys and its report fields' HUD
/// line ([`Details`]).
pub trait CliModel:
    ReportModel<Action: KeyAction, Details: Details> + FleetModel + StudyModel
{
    /// What the model flies, in a few words for help texts: `Palmer's Cessna 172`.
    const AIRCRAFT: &'static str;
    /// Its subcommand's help line.
    const ABOUT: &'static str;
    /// Its subcommand's own options, after those every model shares
    /// (`crate::args::CommonArgs`).
    type Args: Args + FromArgMatches;

    /// The controls at frame 0 from the model's own options.
    ///
    /// # Errors
    /// [`CliError::Usage`] for options the model refuses.
    fn controls(args: &Self::Args) -> Result<Self::Controls, CliError>;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The registry in its documented order (docs/cli.md's subcommand
    /// table: palmer, bourg, then the `glider` feature's glider), by name,
    /// with what each flies as docs/cli.md words it.
    fn documented() -> Vec<(&'static str, &'static str)> {
        let mut models = vec![
            ("palmer", "Palmer's Cessna 172"),
            ("bourg", "Bourg's 6-DoF aircraft"),
        ];
        if cfg!(feature = "glider") {
            models.push(("glider", "a point-mass glider"));
        }
        models
    }

    /// Each kind's name and what it flies (the help texts' "Fly Palmer's
    /// Cessna 172, ..." and the `--model` values' help), and `named` finds
    /// each kind by its name and nothing by another.
    #[test]
    fn each_model_is_named_and_says_what_it_flies() {
        let kinds: Vec<(&str, &str)> = ModelKind::ALL
            .iter()
            .map(|kind| (kind.name(), kind.aircraft()))
            .collect();
        assert_eq!(kinds, documented());
        for &kind in ModelKind::ALL {
            assert_eq!(ModelKind::named(kind.name()), Some(kind));
            let value = kind.to_possible_value().unwrap();
            assert_eq!(value.get_name(), kind.name());
            assert_eq!(
                value.get_help().map(ToString::to_string),
                Some(kind.aircraft().to_owned())
            );
        }
        assert_eq!(ModelKind::named("cessna"), None);
        assert_eq!(ModelKind::value_variants(), ModelKind::ALL);
    }

    /// `list` is "a, b or c" (commas, then "or" before the last), each
    /// model shown by the caller's function, in registry order.
    #[test]
    fn the_list_of_models_reads_a_b_or_c() {
        let names: Vec<&str> = documented().iter().map(|(name, _)| *name).collect();
        let (last, rest) = names.split_last().unwrap();
        let want = format!("{} or {last}", rest.join(", "));
        assert_eq!(ModelKind::list(|kind| kind.name().to_owned()), want);
        assert_eq!(
            ModelKind::list(|kind| format!("<{}>", kind.name())),
            want.replace("palmer", "<palmer>")
                .replace("bourg", "<bourg>")
                .replace("glider", "<glider>")
        );
    }

    /// The CSV layouts `sim-cli plot` reads and the study models `sim-cli
    /// study` reads: one per model of the registry, in registry order.
    #[test]
    fn plot_and_study_take_every_model_of_the_registry_in_order() {
        let names: Vec<&str> = ModelKind::ALL.iter().map(|kind| kind.name()).collect();
        let layouts: Vec<&str> = ModelKind::csv_layouts()
            .iter()
            .map(fdm_plot::csv::CsvLayout::name)
            .collect();
        assert_eq!(layouts, names);
        let studies: Vec<&str> = ModelKind::study_models()
            .iter()
            .map(fdm_study::StudyEntry::name)
            .collect();
        assert_eq!(studies, names);
    }
}
