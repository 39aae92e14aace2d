//! `sim-cli`: fly Palmer's Cessna 172 or Bourg's 6-DoF aircraft from the keyboard
//! into FlightGear, or headless from scripts. The contract is `spec/cli.md`.
//!
//! Library part of the binary, so the pieces can be unit-tested (work in progress).

pub mod args;
pub mod csv;
pub mod error;
pub mod fgaddr;
pub mod fgfs;
pub mod hud;
pub mod keys;
pub mod origin;
pub mod pacer;
pub mod progress;
pub mod report;
pub mod terminal;
