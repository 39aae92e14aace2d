//! The models `sim-cli` flies: the run library's registry
//! (`fdm_run::model::MODELS`, `with_model`), then `sim-cli`'s own models,
//! outside the library crates (the `glider` feature's), one module and one
//! registry line each. What the CLI needs of a model is the run library's
//! data ([`PilotModel`]: what it flies, its start options as a table, its
//! keys, its HUD line): its subcommand is built from the table
//! (`crate::args`), its keys mapped by `crate::keys`. Everything in
//! `sim-cli` is generic over [`CliModel`] and names no model.
//!
//! A new model of the run library joins the CLI by itself; a model of the
//! CLI's own with one more module here and one more line in the registry
//! below: its subcommand (after the options every model shares,
//! `crate::args::CommonArgs`), its help, the `--model` and `fgfs-command`
//! values and the models a recording may name follow from it.

use clap::builder::PossibleValue;
use clap::ValueEnum;
use fdm_run::model::pilot::{ControlsLine, PilotModel};
use fdm_run::model::{ModelJob, RegisteredModel, MODELS};
use fdm_run::FleetModel;
use fdm_study::StudyModel;

pub use fdm_run::model::pilot::tenths;

// The own models' modules, declared here rather than by `own_models!` so that
// `cargo fmt` (which does not follow modules declared inside a macro) formats
// and checks them.
#[cfg(feature = "glider")]
pub mod glider;

/// The registry of `sim-cli`'s own models: one line per model, its module
/// (`models/<name>/`, declared above) and its model type, after the run
/// library's models.
macro_rules! own_models {
    ($($(#[$cfg:meta])* $module:ident :: $model:ident,)*) => {
        /// The names of `sim-cli`'s own models, in registry order.
        const OWN: &[&str] = &[$($(#[$cfg])* <$module::$model as fdm_core::model::Model>::NAME,)*];

        /// Runs `job` with the own model named `name`, or gives it back.
        fn with_own<W: WithModel>(name: &str, job: W) -> Result<W::Output, W> {
            $($(#[$cfg])* if name == <$module::$model as fdm_core::model::Model>::NAME {
                return Ok(job.call::<$module::$model>());
            })*
            let _ = name; // Without own models (a default build), nothing to compare.
            Err(job)
        }
    };
}

own_models! {
    #[cfg(feature = "glider")]
    glider::Glider,
}

/// Which model: one of the registry's, by its name
/// ([`Model::NAME`](fdm_core::model::Model::NAME)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModelKind(&'static str);

/// How many models the registry has.
const COUNT: usize = OWN.len() + MODELS.len();

/// The run library's models, then `sim-cli`'s own.
const fn all_kinds() -> [ModelKind; COUNT] {
    let mut all = [ModelKind(""); COUNT];
    let mut i = 0;
    let mut lists: &[&[&'static str]] = &[MODELS, OWN];
    while let [names, more @ ..] = lists {
        let mut names = *names;
        while let [name, rest @ ..] = names {
            all[i] = ModelKind(name);
            i += 1;
            names = rest;
        }
        lists = more;
    }
    all
}

impl ModelKind {
    /// Every model of the registry, in the order help texts list them.
    pub const ALL: &[Self] = &all_kinds();

    /// Runs `job` with this kind's model type.
    pub fn with<W: WithModel>(self, job: W) -> W::Output {
        /// A job for the run library's registry.
        struct Library<W>(W);
        impl<W: WithModel> ModelJob for Library<W> {
            type Output = W::Output;
            fn call<M: RegisteredModel>(self) -> W::Output {
                self.0.call::<M>()
            }
        }
        with_own(self.0, job).unwrap_or_else(|job| {
            fdm_run::model::with_model(self.0, Library(job))
                .expect("every kind is a model of the run library's registry or sim-cli's own")
        })
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
    /// The lowercase name used on the command line and in the JSON report
    /// ([`fdm_core::model::Model::NAME`]).
    #[must_use]
    pub fn name(self) -> &'static str {
        self.0
    }

    /// What the model flies, for help texts ([`PilotModel::AIRCRAFT`]).
    #[must_use]
    pub fn aircraft(self) -> &'static str {
        struct Aircraft;
        impl WithModel for Aircraft {
            type Output = &'static str;
            fn call<M: CliModel>(self) -> Self::Output {
                M::AIRCRAFT
            }
        }
        self.with(Aircraft)
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

/// A model as `sim-cli` flies it: a [`PilotModel`] (what the run library
/// needs to fly, record, replay and report it, its CSV columns, and what a
/// pilot's front end needs: its start options, keys and HUD line), a
/// [`FleetModel`] (its fleet kernel, formations and multiplayer model) and a
/// [`StudyModel`] (its studies' drawn inputs and measures, so `sim-cli study
/// --run I` picks it through [`ModelKind::with`]). Every model of the run
/// library's registry is one.
pub trait CliModel: PilotModel + FleetModel + StudyModel {}

impl<M: PilotModel + FleetModel + StudyModel> CliModel for M {}

/// A model's own report fields ([`fdm_run::report::Details`]: the JSON
/// fields and the summary line) and the HUD's control line made from them
/// ([`ControlsLine`]).
pub trait Details: fdm_run::report::Details {
    /// The HUD's control line.
    fn hud_controls(&self) -> String;
}

impl<D: fdm_run::report::Details + ControlsLine> Details for D {
    fn hud_controls(&self) -> String {
        self.controls_line()
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
