//! The `--headless --json` final report and the human summary: the run
//! library's ([`fdm_run::report`], built from [`fdm_run::Run::snapshot`]).

pub use fdm_run::report::{RealtimeReport, Report};
