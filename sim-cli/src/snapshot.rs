//! The state of the flown aircraft at one instant, as the JSON report and
//! the HUD are built from it: the run library's [`Snapshot`]
//! ([`fdm_run::report`]; the common part, `CommonState`, is the same for
//! every model, the model's own fields are its [`Details`](crate::models::Details)).

pub use fdm_run::report::Snapshot;
