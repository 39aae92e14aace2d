//! What a study needs of a model beyond flying it: the names of the controls
//! and physical parameters a study file can set, and cheap reads of a state
//! (the run library's [`NamedInputs`], implemented in each model's adapter
//! module of `fdm_run::model`), on a model that flies in fleets.

use fdm_fleet::FleetKernel;
use fdm_run::model::{ModelJob, RegisteredModel, MODELS};
use fdm_run::NamedInputs;

/// A model a study can fly: a fleet model ([`FleetKernel`]) that runs can
/// also fly alone and record ([`fdm_run::RunModel`]), with the settings a
/// study file names ([`NamedInputs`]). Implemented for every such model:
/// a model outside the library crates implements those two traits.
pub trait StudyModel: FleetKernel + NamedInputs {}

impl<M: FleetKernel + NamedInputs> StudyModel for M {}

/// Something to do with a study's model type.
pub(crate) trait StudyJob {
    type Output;
    fn call<M: StudyModel>(self) -> Self::Output;
}

/// Work done once with each model of the run library's registry, with its
/// type: what the study's model list of the registry is made of.
pub(crate) trait EachModel {
    /// Does the work with model `M`.
    fn model<M: StudyModel>(&mut self);
}

/// Calls `each` with the run library's registry's models
/// ([`fdm_run::model::MODELS`]), in its order, through the registry's own
/// map from names to types (`fdm_run::model::with_model`): this crate names
/// no model.
pub(crate) fn registry_models(each: &mut impl EachModel) {
    /// The registry's job: hands its model type to `each`.
    struct Visit<'a, E>(&'a mut E);
    impl<E: EachModel> ModelJob for Visit<'_, E> {
        type Output = ();
        fn call<M: RegisteredModel>(self) {
            self.0.model::<M>();
        }
    }
    for name in MODELS {
        // Every name of MODELS is the registry's.
        let _ = fdm_run::model::with_model(name, Visit(&mut *each));
    }
}
