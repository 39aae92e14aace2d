//! The bridge from a model to FlightGear: any model's common
//! [`FlightView`] placed on WGS-84 and mapped to FlightGear's display fields
//! ([`display`]: the native-FDM datagram; [`packet_at`] for a view already
//! placed), or to a multiplayer position
//! message ([`multiplayer_position`]: one of a fleet shown in FlightGear).
//!
//! This is the only place that knows both sides: the models speak
//! [`FlightView`] (SI units, a flat earth frame x north, y west, z up), the
//! datagram speaks [`DisplayState`] (geodetic radians, ft/s, knots). Every
//! model gets the same mapping; nothing here names a model.

use fdm_core::geodesy::{geodetic_to_ecef, ned_from_model, Attitude, Geodetic, GeodeticOrigin};
use fdm_core::model::FlightView;
use fdm_core::units::{KNOTS_PER_MPS, METRES_PER_FOOT};
use nalgebra::Matrix3;

use crate::{
    DisplayState, EngineState, FgNetFdm, HorizontalAttitudeDeg, MultiplayerPosition, NameError,
};

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
    Display {
        geodetic,
        attitude,
        packet: fill(view, &to_local, geodetic, attitude),
    }
}

/// The datagram of `view` for an aircraft already placed at `geodetic` with
/// local `attitude` (what [`display`] computes, e.g. once per frame by the
/// ECS for every output): the same bytes as [`display`]`(view,
/// origin).packet` when `geodetic` and `attitude` are [`display`]'s. The
/// local frame at `geodetic` is computed again for the velocities.
///
/// ```
/// use fdm_core::geodesy::GeodeticOrigin;
/// use fdm_core::model::Model;
/// use fdm_core::palmer::Palmer;
///
/// let aircraft = Palmer::default_aircraft();
/// let view = Palmer::view(&aircraft, &Palmer::initial_controls(), &Palmer::initial_state());
/// let origin = GeodeticOrigin::default();
/// let shown = fgnet::bridge::display(&view, &origin);
/// let packet = fgnet::bridge::packet_at(&view, &origin, shown.geodetic, shown.attitude);
/// assert_eq!(packet.encode(), shown.packet.encode());
/// ```
#[must_use]
pub fn packet_at(
    view: &FlightView,
    origin: &GeodeticOrigin,
    geodetic: Geodetic,
    attitude: Attitude,
) -> FgNetFdm {
    let to_local = origin.model_ned_to_local_ned_at(&geodetic);
    fill(view, &to_local, geodetic, attitude)
}

/// The datagram's fields from a placed view; `to_local` is the model-to-local
/// rotation at `geodetic`.
fn fill(
    view: &FlightView,
    to_local: &Matrix3<f64>,
    geodetic: Geodetic,
    attitude: Attitude,
) -> FgNetFdm {
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
    FgNetFdm::from_display(&display)
}

/// Who an aircraft is in FlightGear's multiplayer: its callsign and the model
/// FlightGear draws for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MultiplayerIdentity<'a> {
    /// The callsign (1 to 7 characters for FlightGear).
    pub callsign: &'a str,
    /// The model file, relative to FlightGear's data directory (e.g.
    /// `Aircraft/c172p/Models/c172p.xml`).
    pub model_path: &'a str,
}

/// The multiplayer position message of one aircraft at `time_s` (seconds of
/// the sender's clock; `lag_s` is the receiver's interpolation lag, one
/// frame): the ECEF position of `geodetic`, the orientation of `attitude`
/// (relative to the local north-east-down frame at `geodetic`, as
/// [`display`] computes both), and the body velocity (forward, right, down,
/// m/s) of `view`, rounded to the wire's `f32`.
///
/// # Errors
/// [`NameError`] when the callsign or model path does not fit the message.
pub fn multiplayer_position(
    who: MultiplayerIdentity<'_>,
    (time_s, lag_s): (f64, f64),
    geodetic: Geodetic,
    attitude: Attitude,
    view: &FlightView,
) -> Result<MultiplayerPosition, NameError> {
    let mut msg = MultiplayerPosition::new(who.callsign, who.model_path)?;
    msg.time_s = time_s;
    msg.lag_s = lag_s;
    msg.position_ecef_m = geodetic_to_ecef(geodetic).into();
    msg.set_orientation_from_attitude(
        geodetic.lat_deg,
        geodetic.lon_deg,
        HorizontalAttitudeDeg {
            heading_deg: attitude.heading_deg,
            pitch_deg: attitude.pitch_deg,
            roll_deg: attitude.roll_deg,
        },
    );
    #[allow(clippy::cast_possible_truncation)] // the wire field is f32
    let body = view.velocity_body_mps.map(|v| v as f32);
    msg.linear_velocity_body_mps = body.into();
    Ok(msg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::geodesy::ecef_to_geodetic;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;

    /// A message made from a flown Palmer's display, encoded and decoded by
    /// this crate's codec (tested against FlightGear's own layout in
    /// `tests/multiplayer.rs`), gives back the display's position within
    /// 1e-9 degrees and 1 mm (the ECEF round trip is exact to nanometres),
    /// the attitude within 1e-4 degrees (the orientation is an `f32` angle
    /// and axis on the wire: a few 1e-6 degrees), the body velocity as
    /// `f32`, and the callsign, model, time and lag as given.
    #[test]
    fn a_message_reads_back_as_the_display() {
        let origin = GeodeticOrigin::default();
        let aircraft = Palmer::default_aircraft();
        let (controls, mut state) = Palmer::fleet_member(5);
        for _ in 0..450 {
            state = Palmer::step(&aircraft, &controls, &state, 1.0 / 30.0);
        }
        let view = Palmer::view(&aircraft, &controls, &state);
        let shown = display(&view, &origin);
        let who = MultiplayerIdentity {
            callsign: "SIM006",
            model_path: "Aircraft/c172p/Models/c172p.xml",
        };
        let msg = multiplayer_position(
            who,
            (15.0, 1.0 / 30.0),
            shown.geodetic,
            shown.attitude,
            &view,
        )
        .unwrap();
        let back = MultiplayerPosition::decode(&msg.encode().unwrap()).unwrap();
        assert_eq!(back.callsign, "SIM006");
        assert_eq!(back.model_path, who.model_path);
        assert_eq!((back.time_s, back.lag_s), (15.0, 1.0 / 30.0));
        let g = ecef_to_geodetic(back.position_ecef_m.into());
        let here = shown.geodetic;
        assert!((g.lat_deg - here.lat_deg).abs() < 1e-9, "{g:?} {here:?}");
        assert!((g.lon_deg - here.lon_deg).abs() < 1e-9, "{g:?} {here:?}");
        assert!((g.alt_m - here.alt_m).abs() < 1e-3, "{g:?} {here:?}");
        let read = back.attitude(here.lat_deg, here.lon_deg);
        let att = shown.attitude;
        let d = |a: f64, b: f64| ((a - b + 540.0).rem_euclid(360.0) - 180.0).abs();
        assert!(
            d(read.heading_deg, att.heading_deg) < 1e-4,
            "{read:?} {att:?}"
        );
        assert!(d(read.pitch_deg, att.pitch_deg) < 1e-4, "{read:?} {att:?}");
        assert!(d(read.roll_deg, att.roll_deg) < 1e-4, "{read:?} {att:?}");
        #[allow(clippy::cast_possible_truncation)]
        let body = view.velocity_body_mps.map(|v| v as f32);
        assert_eq!(back.linear_velocity_body_mps, <[f32; 3]>::from(body));
        assert!(view.velocity_body_mps.norm() > 10.0, "the aircraft moves");
        assert!(multiplayer_position(
            MultiplayerIdentity {
                callsign: "",
                ..who
            },
            (0.0, 0.0),
            here,
            att,
            &view
        )
        .is_err());
    }

    /// `packet_at` for an aircraft placed by `display` gives the same bytes as
    /// `display`'s own packet (its documented contract), for a flown Palmer
    /// away from the origin, moving and banked, and for one at rest at the
    /// origin. Exact: the same computation from the same placement.
    #[test]
    fn a_packet_for_a_placed_aircraft_is_the_displays_packet() {
        let origin = GeodeticOrigin::default();
        let aircraft = Palmer::default_aircraft();
        let (controls, mut state) = Palmer::fleet_member(7);
        let at_rest = Palmer::view(&aircraft, &controls, &Palmer::initial_state());
        for _ in 0..300 {
            state = Palmer::step(&aircraft, &controls, &state, 1.0 / 30.0);
        }
        let flown = Palmer::view(&aircraft, &controls, &state);
        assert!(flown.velocity_mps.norm() > 10.0, "the aircraft moves");
        for view in [flown, at_rest] {
            let shown = display(&view, &origin);
            let packet = packet_at(&view, &origin, shown.geodetic, shown.attitude);
            assert_eq!(packet.encode(), shown.packet.encode());
        }
    }
}
