//! How much memory this process can still allocate: the run library's
//! ([`fdm_run::memory`]), which `sim-cli fleet` and `sim-cli study` check
//! before they allocate.

pub use fdm_run::memory::*;
