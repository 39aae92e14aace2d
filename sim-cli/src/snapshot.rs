//! The state of the flown aircraft at one instant, as the JSON report and
//! the HUD are built from it: the run library's [`Snapshot`]
//! ([`fdm_run::report`]; the common part, `CommonState`, is the same for
//! every model, the model's own fields are its [`Details`](crate::models::Details)).

pub use fdm_run::report::Snapshot;

#[cfg(test)]
pub(crate) mod samples {
    use super::*;
    use crate::models::bourg::BourgDetails;
    use crate::models::palmer::{PalmerControlsReport, PalmerDetails};
    use fdm_core::model::FlightStatus;
    use fdm_run::report::{AttitudeReport, CommonState, GeodeticReport};

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
