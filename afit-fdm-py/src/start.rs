//! Where an aircraft starts, as `sim-cli`'s `--altitude-ft`, `--speed-kt`,
//! `--heading-deg` and `--trim` define it (docs/cli.md, "Initial conditions
//! and trim"), through the library's `Model::state_at` and `Model::trim`.

use fdm_core::model::Model;
use fdm_core::start::{InitialConditions, StartError};
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};

/// Highest accepted altitude, ft (as the CLI).
pub const MAX_ALTITUDE_FT: f64 = 100_000.0;
/// Highest accepted speed, kt (as the CLI).
pub const MAX_SPEED_KT: f64 = 1000.0;

/// A start as asked: each of the three may be missing.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StartSpec {
    /// Feet above the origin.
    pub altitude_ft: Option<f64>,
    /// True airspeed, knots.
    pub speed_kt: Option<f64>,
    /// True heading, degrees clockwise from north.
    pub heading_deg: Option<f64>,
    /// Trim for steady level flight.
    pub trim: bool,
}

/// Why a start was refused: a message naming the argument.
#[derive(Debug, Clone, PartialEq)]
pub struct StartRefused(pub String);

fn check(name: &str, value: Option<f64>, lo: f64, hi: f64) -> Result<(), StartRefused> {
    match value {
        Some(v) if !(v.is_finite() && (lo..=hi).contains(&v)) => {
            Err(StartRefused(format!("{name}: {v} is not in {lo}..{hi}")))
        }
        _ => Ok(()),
    }
}

impl StartSpec {
    /// Whether this is the thesis's start (nothing given).
    pub fn is_thesis(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the ranges (the CLI's).
    ///
    /// # Errors
    /// The first value out of range, by name.
    pub fn validate(&self) -> Result<(), StartRefused> {
        check("altitude_ft", self.altitude_ft, 0.0, MAX_ALTITUDE_FT)?;
        check("speed_kt", self.speed_kt, 0.0, MAX_SPEED_KT)?;
        check("heading_deg", self.heading_deg, -360.0, 360.0)
    }

    /// Model `M`'s controls and state: the thesis's state when nothing is
    /// given; else flying level at the conditions (the missing ones from the
    /// model's own start), trimmed when asked (`controls` then keep only what
    /// the trim does not set).
    ///
    /// # Errors
    /// A range error, or why the model cannot start or trim there.
    pub fn start<M: Model>(
        &self,
        aircraft: &M::Aircraft,
        controls: M::Controls,
    ) -> Result<(M::Controls, M::State), StartRefused> {
        self.validate()?;
        if self.is_thesis() {
            return Ok((controls, M::initial_state()));
        }
        let own = M::view(aircraft, &M::initial_controls(), &M::initial_state());
        let conditions = InitialConditions {
            altitude_m: self
                .altitude_ft
                .map_or(own.height_m(), |ft| ft * METRES_PER_FOOT),
            speed_mps: self
                .speed_kt
                .map_or(own.airspeed_mps, |kt| kt / KNOTS_PER_MPS),
            heading_deg: self.heading_deg.unwrap_or(0.0),
        };
        if self.trim {
            return M::trim(aircraft, &controls, &conditions)
                .map(|t| (t.controls, t.state))
                .map_err(|e| {
                    StartRefused(match e {
                        StartError::InvalidConditions if conditions.altitude_m <= 0.0 => {
                            "trim: cannot trim on the ground; give altitude_ft above 0".to_owned()
                        }
                        e => format!("trim: {e}"),
                    })
                });
        }
        M::state_at(aircraft, &conditions)
            .map(|s| (controls, s))
            .map_err(|e| StartRefused(format!("initial conditions: {e}")))
    }
}
