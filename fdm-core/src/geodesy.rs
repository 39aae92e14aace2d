//! Geodesy: from the models' local earth frame to WGS-84 geodetic coordinates
//! and FlightGear's attitude conventions.
//!
//! # Frames and units
//!
//! * **Model frame** (both models): x north, y west, z up, a flat earth.
//!   Palmer works in metres, Bourg in feet; every position taken here is in
//!   metres (multiply Bourg's feet by [`METRES_PER_FOOT`] = 0.3048, exact).
//! * **Tangent plane**: the model frame is placed rigidly on the plane tangent
//!   to the WGS-84 ellipsoid at a [`GeodeticOrigin`]: `east = -y`,
//!   `north = x`, `up = z` (see [`enu_from_model`]). So model `z` is height
//!   above that plane, not above the ellipsoid (at 100 km from the origin the
//!   plane is about 784 m above the ellipsoid).
//! * **Geodetic** ([`Geodetic`]): latitude and longitude in degrees, height
//!   above the ellipsoid in metres. FlightGear wants radians and metres; the
//!   datagram encoder converts.
//! * **Attitude** ([`Attitude`]): roll (right wing down +), pitch (nose up +),
//!   heading (clockwise from north, `[0, 360)`), degrees, as FlightGear's
//!   `phi`/`theta`/`psi`. [`palmer_attitude`] and [`bourg_attitude`] give it
//!   relative to the model's axes; [`GeodeticOrigin::attitude_at`] turns that
//!   into true north and the local horizontal at the aircraft.
//! * **Velocity**: FlightGear's `v_north`/`v_east`/`v_down` are
//!   [`ned_from_model`] (along the model's axes) or
//!   [`GeodeticOrigin::local_ned`] (true local NED), in ft/s.
//!
//! # Implementation choice
//!
//! The conversions are implemented here (about 100 lines), not taken from a
//! crate. Candidates looked at (crates.io, 2026):
//!
//! * `map_3d` 0.1.7: small and dependency-free, but its ECEF → geodetic is a
//!   single non-iterated Bowring-type step. Measured against its own exact
//!   forward conversion it is at the nanometre level near the surface but
//!   degrades away from it: 9 mm at 1 000 km height, 8 m at 10 000 km, 0.8 km
//!   at 5 000 km depth. Fine for aircraft, but not "exact"; it also works in
//!   radians and tuples.
//! * `nav-types` 0.5.2: depends on nalgebra 0.32 (a second copy next to the
//!   workspace's 0.35) and uses Heikkinen's closed form, which loses accuracy
//!   near the Earth's centre.
//! * `geographiclib-rs` 0.2.7 (georust, maintained): geodesics only, no
//!   geocentric conversion. Used as the *independent* check in the tests
//!   (Karney's geodesic distances and azimuths), as a dev-dependency.
//!
//! [`ecef_to_geodetic`] is Vermeille's closed-form solution as arranged in
//! Karney's GeographicLib `Geocentric` class (cited there), accurate to
//! nanometres everywhere from the Earth's centre to far space, with no
//! iteration, no special cases to miss and no panics. It is checked against
//! the published worked examples of IOGP/EPSG Guidance Note 7-2 and against
//! independent geodesic computations (see `tests/geodesy_*.rs`).
//!
//! # Example
//!
//! ```
//! use fdm_core::geodesy::{palmer_attitude, GeodeticOrigin};
//! use nalgebra::Vector3;
//!
//! let origin: GeodeticOrigin = "39.8264,-84.0483,251".parse()?;
//! assert_eq!(origin, GeodeticOrigin::default());
//!
//! // 1 km north, 500 m east (y = -500 west), 300 m up in the model frame.
//! let position_m = Vector3::new(1000.0, -500.0, 300.0);
//! let here = origin.model_to_geodetic(position_m);
//! assert!(here.lat_deg > 39.8264 && here.lon_deg > -84.0483);
//! assert!((here.alt_m - 551.1).abs() < 0.1); // 300 m above the plane, plane 0.1 m above the ellipsoid
//!
//! // And back, to nanometres.
//! assert!((origin.geodetic_to_model(here) - position_m).norm() < 1e-6);
//!
//! // Flying east (-y) at 50 m/s, 4° angle of attack, wings level.
//! let attitude = palmer_attitude(Vector3::new(0.0, -50.0, 0.0), 4.0, 0.0);
//! assert!((attitude.heading_deg - 90.0).abs() < 1e-12);
//! assert!((attitude.pitch_deg - 4.0).abs() < 1e-12);
//! // Relative to true north at the aircraft (here: a tiny correction).
//! let sent = origin.attitude_at(position_m, attitude);
//! assert!((sent.heading_deg - 90.0).abs() < 0.01);
//! # Ok::<(), fdm_core::geodesy::GeodesyError>(())
//! ```

mod attitude;
mod origin;
mod wgs84;

pub use attitude::{
    bourg_attitude, ground_track_deg, ned_from_model, normalize_heading_deg, palmer_attitude,
    Attitude,
};
pub use origin::{enu_from_model, model_from_enu, GeodesyError, Geodetic, GeodeticOrigin};
pub use wgs84::{
    ecef_to_geodetic, enu_to_ecef_rotation, geodetic_to_ecef, WGS84_A_M, WGS84_B_M, WGS84_F,
};

pub use crate::units::METRES_PER_FOOT;
