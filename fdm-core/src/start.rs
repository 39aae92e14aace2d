//! Starting somewhere else than the thesis's start: initial conditions
//! ([`InitialConditions`]: altitude, true airspeed, true heading) and trim
//! (steady, wings-level, unaccelerated flight), for every model through
//! [`Model::state_at`](crate::model::Model::state_at) and
//! [`Model::trim`](crate::model::Model::trim).
//!
//! ```
//! use fdm_core::model::Model;
//! use fdm_core::palmer::Palmer;
//! use fdm_core::start::InitialConditions;
//!
//! let cruise = InitialConditions::from_feet_knots(2000.0, 100.0, 90.0);
//! let trimmed = Palmer::trim(&Palmer::default_aircraft(), &Palmer::initial_controls(), &cruise)
//!     .unwrap();
//! assert!((trimmed.state.position_m.z - 609.6).abs() < 1e-9);
//! assert!(trimmed.state.velocity_mps.y < 0.0); // east is -y
//! assert!(trimmed.controls.throttle > 0.0 && trimmed.controls.throttle < 1.0);
//! ```

use core::fmt;

use crate::units::{KNOTS_PER_MPS, METRES_PER_FOOT};

/// Where and how fast an aircraft starts: straight and level, wings level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialConditions {
    /// Height above the earth frame's origin (the ground plane), m.
    pub altitude_m: f64,
    /// True airspeed (no wind: the speed), m/s.
    pub speed_mps: f64,
    /// True heading, degrees clockwise from north (the earth frame's +x);
    /// 90 is east (−y).
    pub heading_deg: f64,
}

impl InitialConditions {
    /// From the CLI's units: feet, knots, degrees.
    #[must_use]
    pub fn from_feet_knots(altitude_ft: f64, speed_kt: f64, heading_deg: f64) -> Self {
        Self {
            altitude_m: altitude_ft * METRES_PER_FOOT,
            speed_mps: speed_kt / KNOTS_PER_MPS,
            heading_deg,
        }
    }

    /// Whether every number is finite, the altitude and speed not negative.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.altitude_m.is_finite()
            && self.altitude_m >= 0.0
            && self.speed_mps.is_finite()
            && self.speed_mps >= 0.0
            && self.heading_deg.is_finite()
    }

    /// The velocity `[north, west, up]`, m/s: `(V cos h, 0 − V sin h, 0)`;
    /// exactly zero (no `−0.0`) at zero speed or heading 0.
    #[must_use]
    pub fn velocity_nwu_mps(&self) -> [f64; 3] {
        if self.speed_mps == 0.0 {
            return [0.0; 3];
        }
        let h = self.heading_deg.to_radians();
        [
            self.speed_mps * crate::math::cos(h),
            0.0 - self.speed_mps * crate::math::sin(h),
            0.0,
        ]
    }
}

/// Why a model could not start as asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartError {
    /// A number of the [`InitialConditions`] is not finite, or the altitude
    /// or speed is negative.
    InvalidConditions,
    /// The model cannot start anywhere but its own initial state.
    Unsupported,
    /// The speed is too low to fly level: the lift needed exceeds the most
    /// the wing gives before its stall (or the trim's angle range).
    BelowStall {
        /// The speed asked, m/s.
        speed_mps: f64,
    },
    /// The speed is too high to hold: the drag exceeds full power.
    AboveMaxPower {
        /// The speed asked, m/s.
        speed_mps: f64,
    },
    /// The controls cannot balance the pitching moment at this speed (the
    /// elevator trim would have to go beyond its range).
    OutOfTrim {
        /// The speed asked, m/s.
        speed_mps: f64,
    },
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kt = |mps: f64| mps * KNOTS_PER_MPS;
        match *self {
            Self::InvalidConditions => f.write_str(
                "initial conditions must be finite, with altitude and speed not negative",
            ),
            Self::Unsupported => f.write_str("this model can only start at its initial state"),
            Self::BelowStall { speed_mps } => write!(
                f,
                "cannot trim at {:.1} kt: below the stall speed (the wing cannot carry the weight)",
                kt(speed_mps)
            ),
            Self::AboveMaxPower { speed_mps } => write!(
                f,
                "cannot trim at {:.1} kt: above the speed full power can hold",
                kt(speed_mps)
            ),
            Self::OutOfTrim { speed_mps } => write!(
                f,
                "cannot trim at {:.1} kt: the elevator trim cannot balance the pitching moment",
                kt(speed_mps)
            ),
        }
    }
}

impl core::error::Error for StartError {}

/// What a trim found, as name, value and unit triples for people to read
/// (e.g. `("throttle", 0.42, "")`, `("alpha", 3.1, "deg")`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrimReport {
    /// The trimmed quantities.
    pub values: [(&'static str, f64, &'static str); 3],
}

impl fmt::Display for TrimReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (name, value, unit)) in self.values.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{name} {value:.4}")?;
            if !unit.is_empty() {
                write!(f, " {unit}")?;
            }
        }
        Ok(())
    }
}

/// A trimmed start: controls and state for steady, wings-level,
/// unaccelerated flight at the initial conditions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trimmed<C, S> {
    /// The controls to fly with.
    pub controls: C,
    /// The state to start from.
    pub state: S,
    /// What was found, for people.
    pub report: TrimReport,
}
