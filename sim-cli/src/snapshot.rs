//! The state of the flown aircraft as the CLI sees it at one instant
//! ([`Snapshot`]): what the JSON report and the HUD are built from (the CSV
//! rows are the run library's `fdm_run::csv::FlightRow`). The common part ([`CommonState`]) is the same for every model; the
//! model's own fields are its [`Details`].

use fdm_core::model::{DisplayStatus, FlightStatus};
use fdm_core::units::METRES_PER_FOOT;
use serde::{Deserialize, Serialize};

use crate::models::Details;

/// Geodetic position as sent to FlightGear.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GeodeticReport {
    /// Latitude, degrees north.
    pub lat_deg: f64,
    /// Longitude, degrees east.
    pub lon_deg: f64,
    /// Altitude above the WGS-84 ellipsoid, metres.
    pub alt_m: f64,
}

/// Attitude as sent to FlightGear, degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AttitudeReport {
    /// Roll, right wing down positive.
    pub roll: f64,
    /// Pitch, nose up positive.
    pub pitch: f64,
    /// Heading, clockwise from true north, in [0, 360).
    pub heading: f64,
}

/// The part of the state every model has.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CommonState {
    /// Simulated time, seconds: the model's own clock, the sum of its time
    /// steps (Palmer's `f64` steps: 600 steps of 0.1 s give
    /// 60.00000000000058; Bourg's `f32` steps widened: 900 steps of
    /// `1.0f32 / 30.0` give 30.000001430511475).
    pub time_s: f64,
    /// Position [x, y, z] in the model's earth frame (x north, y west, z up),
    /// in the model's own unit (Palmer metres, Bourg feet).
    pub position: [f64; 3],
    /// Velocity [vx, vy, vz] in the same frame and unit per second.
    pub velocity: [f64; 3],
    /// Geodetic position.
    pub geodetic: GeodeticReport,
    /// Attitude as sent to FlightGear.
    pub attitude_deg: AttitudeReport,
}

/// Everything the CLI needs to know about the aircraft at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot<D> {
    /// State every model has.
    pub common: CommonState,
    /// The model's own fields.
    pub details: D,
    /// Where the aircraft is in its flight (on the ground, flying, landed).
    pub status: FlightStatus,
    /// Whether the model reports a stall.
    pub stalling: bool,
    /// Airspeed, m/s.
    pub airspeed_mps: f64,
}

impl<D> Snapshot<D> {
    /// The status and stall as displayed: the one vocabulary of labels
    /// (HUD, plot), codes (JSON report) and numbers (CSV `status` column),
    /// [`DisplayStatus`].
    #[must_use]
    pub fn display_status(&self) -> DisplayStatus {
        DisplayStatus::new(self.status, self.stalling)
    }

    /// The status as one word, for the JSON report's `status`
    /// ([`DisplayStatus::code`]).
    #[must_use]
    pub fn status_code(&self) -> &'static str {
        self.display_status().code()
    }
}

/// The flight status and stall flag of a CSV `status` number
/// ([`DisplayStatus::from_number`]); `None` for any other number.
#[must_use]
pub fn status_from_number(x: f64) -> Option<(FlightStatus, bool)> {
    DisplayStatus::from_number(x).map(|d| (d.status, d.stalling))
}

impl<D: Details> Snapshot<D> {
    /// Metres per unit of the native position ([`Details::POSITION_UNIT`]):
    /// 1 for `"m"`, [`METRES_PER_FOOT`] for `"ft"`, NaN for an unknown unit
    /// (shown as a gap rather than in the wrong unit).
    #[must_use]
    pub fn metres_per_unit() -> f64 {
        match D::POSITION_UNIT {
            "m" => 1.0,
            "ft" => METRES_PER_FOOT,
            _ => f64::NAN,
        }
    }

    /// Height above the ground plane through the origin, m.
    #[must_use]
    pub fn height_m(&self) -> f64 {
        self.common.position[2] * Self::metres_per_unit()
    }

    /// Vertical speed, m/s, positive up.
    #[must_use]
    pub fn climb_rate_mps(&self) -> f64 {
        self.common.velocity[2] * Self::metres_per_unit()
    }
}

/// Sample snapshots for tests of the modules built on [`Snapshot`].
#[cfg(test)]
pub(crate) mod samples {
    use super::*;
    use crate::models::bourg::BourgDetails;
    use crate::models::palmer::{PalmerControlsReport, PalmerDetails};

    fn common() -> CommonState {
        CommonState {
            time_s: 60.000000000000746,
            position: [1234.5678901234567, -0.1, 98.76],
            velocity: [55.5, 1e-20, -0.25],
            geodetic: GeodeticReport {
                lat_deg: 39.8375,
                lon_deg: -84.0483,
                alt_m: 349.76,
            },
            attitude_deg: AttitudeReport {
                roll: 5.0,
                pitch: 2.5,
                heading: 359.5,
            },
        }
    }

    pub(crate) fn palmer() -> Snapshot<PalmerDetails> {
        Snapshot {
            common: common(),
            details: PalmerDetails {
                airspeed: 55.6,
                controls: PalmerControlsReport {
                    throttle: 0.75,
                    alpha_deg: 4.0,
                    bank_deg: 5.0,
                    flaps_deg: 20.0,
                    brakes: false,
                },
                climb_angle_deg: 3.1,
                climb_rate: 2.9,
                heading_deg: 0.5,
            },
            status: FlightStatus::Airborne,
            stalling: false,
            airspeed_mps: 55.6,
        }
    }

    pub(crate) fn bourg() -> Snapshot<BourgDetails> {
        Snapshot {
            common: common(),
            details: BourgDetails {
                speed: f64::from(183.123_46_f32),
                euler_deg: [0.1_f32, -2.5, -0.3].map(f64::from),
                thrust_lb: 3000.0,
                flaps: true,
                stalling: false,
                pitch_trim: 0.0,
            },
            status: FlightStatus::Airborne,
            stalling: false,
            airspeed_mps: f64::from(183.123_46_f32) * 0.3048,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::samples;

    /// Height and vertical speed are in metres whatever the model's own unit:
    /// Bourg's feet are converted (0.3048 m per foot, exact), Palmer's metres
    /// pass through. The samples share position z = 98.76 and vz = -0.25 in
    /// their own units.
    #[test]
    fn heights_and_climb_rates_are_in_metres_for_every_model() {
        let bourg = samples::bourg();
        assert_eq!(bourg.height_m(), 98.76 * 0.3048);
        assert_eq!(bourg.climb_rate_mps(), -0.25 * 0.3048);
        let palmer = samples::palmer();
        assert_eq!(palmer.height_m(), 98.76);
        assert_eq!(palmer.climb_rate_mps(), -0.25);
    }
}
