//! The geodetic origin of a model's earth frame and the conversions between the
//! model frame (x north, y west, z up, a tangent plane at the origin) and
//! WGS-84 geodetic coordinates.

use core::fmt;

use crate::message::ShortNumber;

#[cfg(feature = "alloc")]
use alloc::{borrow::ToOwned, string::String};

use nalgebra::{Matrix3, Vector3};

use super::attitude::Attitude;
use super::wgs84::{ecef_to_geodetic, enu_to_ecef_rotation, geodetic_to_ecef};

/// A WGS-84 geodetic position.
///
/// A plain value: any numbers are accepted here; [`GeodeticOrigin::new`]
/// validates the ones used as an origin.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Geodetic {
    /// Geodetic latitude, degrees, north positive, in `[-90, 90]`.
    pub lat_deg: f64,
    /// Longitude, degrees, east positive, in `[-180, 180]`.
    pub lon_deg: f64,
    /// Height above the WGS-84 ellipsoid, metres.
    ///
    /// No geoid model is applied: FlightGear's `altitude` field means height
    /// above sea level, and the origin's altitude (e.g. the `--origin` default
    /// of 251 m, the Wright-Patterson runway's elevation above sea level) is
    /// passed through unchanged as the altitude of the model's `z = 0` there.
    /// Treating a sea-level height as an ellipsoidal one only scales the
    /// horizontal geometry by (geoid undulation / Earth radius); undulations
    /// stay within about ±110 m worldwide, so that is below 1.7e-5, i.e.
    /// under 1.7 m at 100 km from the origin.
    pub alt_m: f64,
}

impl fmt::Display for Geodetic {
    /// Formats as `LAT,LON,ALT_M`, the `--origin` syntax, with the shortest
    /// digits that parse back to the same `f64`s.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.lat_deg, self.lon_deg, self.alt_m)
    }
}

/// Why a geodetic origin was rejected.
#[derive(Debug, Clone, PartialEq)]
pub enum GeodesyError {
    /// The `LAT,LON,ALT_M` text did not have exactly three comma-separated fields.
    #[cfg(feature = "alloc")]
    WrongFieldCount {
        /// Number of comma-separated fields found.
        found: usize,
        /// The text that was parsed.
        text: String,
    },
    /// A field of the `LAT,LON,ALT_M` text is not a number.
    #[cfg(feature = "alloc")]
    NotANumber {
        /// Which field: `"latitude"`, `"longitude"` or `"altitude"`.
        field: &'static str,
        /// The offending field, trimmed.
        text: String,
    },
    /// A coordinate is NaN or infinite.
    NonFinite {
        /// Which field: `"latitude"`, `"longitude"` or `"altitude"`.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// Latitude outside `[-90, 90]` degrees.
    LatitudeOutOfRange {
        /// The latitude given, degrees.
        lat_deg: f64,
    },
    /// Longitude outside `[-180, 180]` degrees.
    LongitudeOutOfRange {
        /// The longitude given, degrees.
        lon_deg: f64,
    },
    /// Altitude outside [`GeodeticOrigin::ALT_RANGE_M`].
    AltitudeOutOfRange {
        /// The altitude given, metres.
        alt_m: f64,
    },
}

impl fmt::Display for GeodesyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            #[cfg(feature = "alloc")]
            Self::WrongFieldCount { found, text } => write!(
                f,
                "expected LAT,LON,ALT_M (three comma-separated numbers), found {found} field(s) in {text:?}"
            ),
            #[cfg(feature = "alloc")]
            Self::NotANumber { field, text } => write!(f, "{field} is not a number: {text:?}"),
            Self::NonFinite { field, value } => {
                write!(f, "{field} must be finite, got {}", ShortNumber(*value))
            }
            Self::LatitudeOutOfRange { lat_deg } => {
                write!(f, "latitude must be within [-90, 90] degrees, got {}", ShortNumber(*lat_deg))
            }
            Self::LongitudeOutOfRange { lon_deg } => {
                write!(f, "longitude must be within [-180, 180] degrees, got {}", ShortNumber(*lon_deg))
            }
            Self::AltitudeOutOfRange { alt_m } => write!(
                f,
                "altitude must be within [{}, {}] metres, got {}",
                GeodeticOrigin::ALT_RANGE_M.start(),
                GeodeticOrigin::ALT_RANGE_M.end(),
                ShortNumber(*alt_m)
            ),
        }
    }
}

impl core::error::Error for GeodesyError {}

/// The geodetic point where a model's earth-frame origin sits, with the local
/// tangent plane there: the model's x axis points to true north at the origin,
/// y to west, z up along the ellipsoid normal (so the model frame is ENU with
/// `east = -y`, `north = x`, `up = z`).
///
/// Precomputes the origin's ECEF position and the ENU-to-ECEF rotation, so each
/// conversion is one matrix-vector product plus [`ecef_to_geodetic`].
///
/// The flat model frame is mapped rigidly onto the tangent plane: a model
/// point at height `z` and horizontal distance `d` from the origin is
/// about `z + d²/(2R)` above the ellipsoid (R ≈ 6 380 km; 783 to 786 m at
/// 100 km from Wright-Patterson), its local vertical is tilted by about `d/R`
/// (0.90° at 100 km) from the model's z, and its model-frame north differs
/// from true north there by the meridian convergence (about
/// `Δlon · sin(lat)`, 0.75° at 100 km east of Wright-Patterson). [`GeodeticOrigin::attitude_at`] and
/// [`GeodeticOrigin::local_ned`] correct attitude and velocity for that.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeodeticOrigin {
    geodetic: Geodetic,
    ecef_m: Vector3<f64>,
    enu_to_ecef: Matrix3<f64>,
}

impl GeodeticOrigin {
    /// Accepted origin altitudes, metres above the ellipsoid: from below the
    /// deepest ocean floor (about -11 km) to the edge of space (100 km).
    pub const ALT_RANGE_M: core::ops::RangeInclusive<f64> = -12_000.0..=100_000.0;

    /// The `--origin` default: Wright-Patterson AFB runway, 39.8264° N,
    /// 84.0483° W, 251 m.
    pub const WRIGHT_PATTERSON: Geodetic = Geodetic {
        lat_deg: 39.8264,
        lon_deg: -84.0483,
        alt_m: 251.0,
    };

    /// An origin at `lat_deg` (degrees, `[-90, 90]`), `lon_deg` (degrees,
    /// `[-180, 180]`), `alt_m` (metres above the ellipsoid, within
    /// [`Self::ALT_RANGE_M`]).
    ///
    /// # Errors
    /// [`GeodesyError::NonFinite`] for NaN or infinite values, otherwise the
    /// matching `*OutOfRange` variant.
    ///
    /// At a pole true north is undefined; the tangent plane's "north" (+x) is
    /// then the limit of true north on approaching the pole along meridian
    /// `lon_deg` (at the north pole it points down meridian `lon_deg + 180`,
    /// at the south pole up meridian `lon_deg`).
    pub fn new(lat_deg: f64, lon_deg: f64, alt_m: f64) -> Result<Self, GeodesyError> {
        for (field, value) in [
            ("latitude", lat_deg),
            ("longitude", lon_deg),
            ("altitude", alt_m),
        ] {
            if !value.is_finite() {
                return Err(GeodesyError::NonFinite { field, value });
            }
        }
        if !(-90.0..=90.0).contains(&lat_deg) {
            return Err(GeodesyError::LatitudeOutOfRange { lat_deg });
        }
        if !(-180.0..=180.0).contains(&lon_deg) {
            return Err(GeodesyError::LongitudeOutOfRange { lon_deg });
        }
        if !Self::ALT_RANGE_M.contains(&alt_m) {
            return Err(GeodesyError::AltitudeOutOfRange { alt_m });
        }
        let geodetic = Geodetic {
            lat_deg,
            lon_deg,
            alt_m,
        };
        Ok(Self {
            geodetic,
            ecef_m: geodetic_to_ecef(geodetic),
            enu_to_ecef: enu_to_ecef_rotation(lat_deg, lon_deg),
        })
    }

    /// [`GeodeticOrigin::new`] from a [`Geodetic`].
    ///
    /// # Errors
    /// As [`GeodeticOrigin::new`].
    pub fn from_geodetic(geodetic: Geodetic) -> Result<Self, GeodesyError> {
        Self::new(geodetic.lat_deg, geodetic.lon_deg, geodetic.alt_m)
    }

    /// The origin's geodetic coordinates, as given.
    #[must_use]
    pub fn geodetic(&self) -> Geodetic {
        self.geodetic
    }

    /// The origin's ECEF position, metres.
    #[must_use]
    pub fn ecef_m(&self) -> Vector3<f64> {
        self.ecef_m
    }

    /// The rotation from ENU components at the origin to ECEF components
    /// (columns: east, north, up unit vectors in ECEF).
    #[must_use]
    pub fn enu_to_ecef(&self) -> Matrix3<f64> {
        self.enu_to_ecef
    }

    /// Model-frame position, metres (x north, y west, z up), to ECEF metres.
    #[must_use]
    pub fn model_to_ecef(&self, position_m: Vector3<f64>) -> Vector3<f64> {
        self.ecef_m + self.enu_to_ecef * enu_from_model(position_m)
    }

    /// ECEF metres to a model-frame position, metres (x north, y west, z up).
    #[must_use]
    pub fn ecef_to_model(&self, ecef_m: Vector3<f64>) -> Vector3<f64> {
        model_from_enu(self.enu_to_ecef.transpose() * (ecef_m - self.ecef_m))
    }

    /// Model-frame position, metres (x north, y west, z up; Bourg's feet times
    /// [`METRES_PER_FOOT`](super::METRES_PER_FOOT)), to WGS-84 geodetic
    /// coordinates.
    ///
    /// Exact (tangent plane → ECEF by rotation and translation, then the
    /// closed-form [`ecef_to_geodetic`]); round trips through
    /// [`GeodeticOrigin::geodetic_to_model`] agree to nanometres. Any
    /// non-finite component gives a [`Geodetic`] of three NaNs, and so can a
    /// finite position so large (beyond about 1e308 m) that the ECEF sum
    /// overflows; never panics.
    #[must_use]
    pub fn model_to_geodetic(&self, position_m: Vector3<f64>) -> Geodetic {
        ecef_to_geodetic(self.model_to_ecef(position_m))
    }

    /// WGS-84 geodetic coordinates to a model-frame position, metres (x north,
    /// y west, z up): the inverse of [`GeodeticOrigin::model_to_geodetic`].
    /// Non-finite input gives non-finite output; never panics.
    #[must_use]
    pub fn geodetic_to_model(&self, geodetic: Geodetic) -> Vector3<f64> {
        self.ecef_to_model(geodetic_to_ecef(geodetic))
    }

    /// The rotation taking north-east-down components along the model's axes
    /// (north = model +x) to north-east-down components of the local frame at
    /// the model-frame position `position_m` (true north and the ellipsoid
    /// normal there). Identity at the origin; elsewhere the tilt of the
    /// vertical (about distance / Earth radius) combined with the meridian
    /// convergence: at Wright-Patterson a rotation by 0.90° at 100 km north,
    /// 1.17° at 100 km east.
    #[must_use]
    pub fn model_ned_to_local_ned(&self, position_m: Vector3<f64>) -> Matrix3<f64> {
        self.model_ned_to_local_ned_at(&self.model_to_geodetic(position_m))
    }

    /// [`GeodeticOrigin::model_ned_to_local_ned`] at a position whose geodetic
    /// coordinates `here` are already known (e.g. the ECS's Place system and
    /// the FlightGear bridge, which have just computed them): saves converting
    /// the position a second time, about a third of the placement's cost.
    #[must_use]
    pub fn model_ned_to_local_ned_at(&self, here: &Geodetic) -> Matrix3<f64> {
        let local_enu_to_ecef = enu_to_ecef_rotation(here.lat_deg, here.lon_deg);
        // NED = P · ENU with P swapping east/north and negating up (P = Pᵀ = P⁻¹).
        let p = Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0);
        p * local_enu_to_ecef.transpose() * self.enu_to_ecef * p
    }

    /// Re-expresses an attitude given relative to the model's axes (as returned
    /// by [`palmer_attitude`](super::palmer_attitude) and
    /// [`bourg_attitude`](super::bourg_attitude)) relative to true north and the
    /// local horizontal at the model-frame position `position_m` (metres):
    /// what FlightGear means by heading and pitch at the aircraft's latitude
    /// and longitude.
    ///
    /// The correction is zero at the origin and grows with distance: the
    /// heading changes by the meridian convergence (about
    /// `Δlon · sin(lat)`, 0.75° at 100 km east of Wright-Patterson), pitch and
    /// roll by the tilt of the local vertical (up to distance / Earth radius,
    /// 0.9° at 100 km). With it, the heading and pitch of the velocity vector
    /// equal the direction of travel and climb angle computed from successive
    /// geodetic positions to within 4e-8° (measured in
    /// `tests/geodesy_attitude.rs`); without it the heading 80 km east of the
    /// origin is off by 0.60° at Wright-Patterson and 1.54° at 65° N.
    ///
    /// A consequence of putting a flat-earth model on a curved one: away from
    /// the origin the model's horizontal is tilted against the local one, so
    /// an aircraft with its wings level in the model frame shows a small bank
    /// (up to the tilt) and, with angle of attack alpha, a nose heading off
    /// its track by about tilt · tan(alpha). That is the same airframe seen
    /// from the local frame; angle of attack and sideslip relative to the
    /// direction of travel are unchanged.
    #[must_use]
    pub fn attitude_at(&self, position_m: Vector3<f64>, attitude: Attitude) -> Attitude {
        Attitude::from_body_to_ned(
            &(self.model_ned_to_local_ned(position_m) * attitude.body_to_ned()),
        )
    }

    /// Rotates a model-frame vector (x north, y west, z up; e.g. a velocity in
    /// m/s or ft/s, units pass through) at the model-frame position
    /// `position_m` (metres) into local north-east-down components at that
    /// position (true north, ellipsoid normal). At the origin this equals
    /// [`ned_from_model`](super::ned_from_model).
    #[must_use]
    pub fn local_ned(&self, position_m: Vector3<f64>, v: Vector3<f64>) -> Vector3<f64> {
        self.model_ned_to_local_ned(position_m) * super::ned_from_model(v)
    }
}

impl Default for GeodeticOrigin {
    /// [`GeodeticOrigin::WRIGHT_PATTERSON`]: 39.8264° N, 84.0483° W, 251 m.
    fn default() -> Self {
        let g = Self::WRIGHT_PATTERSON;
        // Built directly: these constants satisfy every check in `new`
        // (tested in `tests/geodesy_origin.rs`).
        Self {
            geodetic: g,
            ecef_m: geodetic_to_ecef(g),
            enu_to_ecef: enu_to_ecef_rotation(g.lat_deg, g.lon_deg),
        }
    }
}

#[cfg(feature = "alloc")]
impl core::str::FromStr for GeodeticOrigin {
    type Err = GeodesyError;

    /// Parses the CLI's `LAT,LON,ALT_M` (degrees, degrees, metres), e.g.
    /// `"39.8264,-84.0483,251"`. Whitespace around each field is ignored;
    /// numbers use Rust's `f64` syntax (`1e3` is accepted). Then validates as
    /// [`GeodeticOrigin::new`].
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let fields: alloc::vec::Vec<&str> = text.split(',').map(str::trim).collect();
        let [lat, lon, alt] = fields.as_slice() else {
            return Err(GeodesyError::WrongFieldCount {
                found: fields.len(),
                text: text.to_owned(),
            });
        };
        let number = |field: &'static str, s: &str| {
            s.parse::<f64>().map_err(|_| GeodesyError::NotANumber {
                field,
                text: s.to_owned(),
            })
        };
        Self::new(
            number("latitude", lat)?,
            number("longitude", lon)?,
            number("altitude", alt)?,
        )
    }
}

/// Model-frame vector (x north, y west, z up) to east-north-up components:
/// `(-y, x, z)`. Units pass through.
#[must_use]
pub fn enu_from_model(v: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(-v.y, v.x, v.z)
}

/// East-north-up components to the model frame (x north, y west, z up):
/// `(north, -east, up)`. Units pass through.
#[must_use]
pub fn model_from_enu(enu: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(enu.y, -enu.x, enu.z)
}
