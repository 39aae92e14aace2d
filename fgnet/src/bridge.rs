//! The bridge from a model to FlightGear: any model's common
//! [`FlightView`] placed on WGS-84 and mapped to FlightGear's display fields.
//!
//! This is the only place that knows both sides: the models speak
//! [`FlightView`] (SI units, a flat earth frame x north, y west, z up), the
//! datagram speaks [`DisplayState`] (geodetic radians, ft/s, knots). Every
//! model gets the same mapping; nothing here names a model.

use fdm_core::geodesy::{ned_from_model, Attitude, Geodetic, GeodeticOrigin};
use fdm_core::model::FlightView;
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use nalgebra::Matrix3;

use crate::{DisplayState, EngineState, FgNetFdm};

/// What the mapping derives from one aircraft: its geodetic position, its
/// attitude as sent to FlightGear, and the datagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Display {
    /// WGS-84 position of the aircraft.
    pub geodetic: Geodetic,
    /// Roll (right wing down +), pitch (nose up +) and heading (clockwise from
    /// true north, `[0, 360)`) relative to the local frame at the aircraft,
    /// degrees, before rounding to the datagram's `f32` radians.
    pub attitude: Attitude,
    /// The FGNetFDM datagram.
    pub packet: FgNetFdm,
}

/// Rotates a model-frame attitude into the local north-east-down frame at the
/// aircraft with `to_local` ([`GeodeticOrigin::model_ned_to_local_ned_at`]):
/// what [`GeodeticOrigin::attitude_at`] computes.
fn local_attitude(to_local: &Matrix3<f64>, attitude: Attitude) -> Attitude {
    Attitude::from_body_to_ned(&(to_local * attitude.body_to_ned()))
}

/// The display fields of one aircraft seen through `view`, with its model
/// frame placed at `origin`:
///
/// * position: [`GeodeticOrigin::model_to_geodetic`] of `position_m`;
/// * attitude: the view's attitude made local (true north and the local
///   horizontal at the aircraft) as [`GeodeticOrigin::attitude_at`] does;
/// * velocities: local NED and body (forward, right, down), ft/s; airspeed
///   in knots; climb rate `velocity_mps.z` in ft/s;
/// * alpha, beta, flaps, engine state and rpm as the view gives them.
///
/// ```
/// use fdm_core::geodesy::GeodeticOrigin;
/// use fdm_core::model::Model;
/// use fdm_core::palmer::Palmer;
///
/// let aircraft = Palmer::default_aircraft();
/// let view = Palmer::view(&aircraft, &Palmer::initial_controls(), &Palmer::initial_state());
/// let display = fgnet::bridge::display(&view, &GeodeticOrigin::default());
/// assert_eq!(display.packet.version, 24);
/// assert!((display.geodetic.lat_deg - 39.8264).abs() < 1e-9);
/// ```
#[must_use]
pub fn display(view: &FlightView, origin: &GeodeticOrigin) -> Display {
    let geodetic = origin.model_to_geodetic(view.position_m);
    let to_local = origin.model_ned_to_local_ned_at(&geodetic);
    let attitude = local_attitude(&to_local, view.attitude);
    let ned_fps = to_local * ned_from_model(view.velocity_mps) / METRES_PER_FOOT;
    let body_fps = view.velocity_body_mps / METRES_PER_FOOT;
    let display = DisplayState {
        latitude_deg: geodetic.lat_deg,
        longitude_deg: geodetic.lon_deg,
        altitude_m: geodetic.alt_m,
        roll_deg: attitude.roll_deg,
        pitch_deg: attitude.pitch_deg,
        heading_deg: attitude.heading_deg,
        alpha_deg: view.alpha_deg,
        beta_deg: view.beta_deg,
        v_north_fps: ned_fps.x,
        v_east_fps: ned_fps.y,
        v_down_fps: ned_fps.z,
        u_body_fps: body_fps.x,
        v_body_fps: body_fps.y,
        w_body_fps: body_fps.z,
        airspeed_kt: view.airspeed_mps * KNOTS_PER_MPS,
        climb_rate_fps: view.velocity_mps.z / METRES_PER_FOOT,
        flaps_norm: view.flaps_norm,
        engine_state: if view.engine_running {
            EngineState::Running
        } else {
            EngineState::Off
        },
        engine_rpm: view.engine_rpm,
        ..DisplayState::default()
    };
    Display {
        geodetic,
        attitude,
        packet: FgNetFdm::from_display(&display),
    }
}
