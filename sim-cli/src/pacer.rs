//! Real-time pacing: the run library's [`fdm_run::pacer`], re-exported.

pub use fdm_run::pacer::*;
