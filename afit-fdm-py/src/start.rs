//! Where an aircraft starts, as `sim-cli`'s `--altitude-ft`, `--speed-kt`,
//! `--heading-deg` and `--trim` define it (docs/cli.md, "Initial conditions
//! and trim"): the run library's [`StartOptions`], worded for Python (the
//! keyword arguments' names).

use fdm_core::model::Model;
use fdm_run::StartRefused;

pub use fdm_run::scenario::{
    StartOptions as StartSpec, MAX_ALTITUDE_FT, MAX_HEADING_DEG, MAX_SPEED_KT,
};

/// Model `M`'s controls and state: the thesis's state when nothing is given;
/// else flying level at the conditions (the missing ones from the model's own
/// start), trimmed when asked (`controls` then keep only what the trim does
/// not set).
///
/// # Errors
/// A range error naming the keyword, or why the model cannot start or trim
/// there.
pub fn start<M: Model>(
    spec: &StartSpec,
    aircraft: M::Aircraft,
    controls: M::Controls,
) -> Result<(M::Controls, M::State), String> {
    match spec.start::<M>(aircraft, controls) {
        Ok((start, _report)) => Ok((start.controls, start.state)),
        Err(StartRefused::TrimOnGround) => {
            Err("trim: cannot trim on the ground; give altitude_ft above 0".to_owned())
        }
        Err(refused) => Err(refused.to_string()),
    }
}
