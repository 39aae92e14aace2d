//! Where a run's earth-frame origin sits on the WGS-84 ellipsoid, given as
//! `LAT,LON,ALT_M` or by name ([`parse_origin`], what `sim-cli --origin`
//! takes).
//!
//! Names ([`NAMED_ORIGINS`]) stand for runway thresholds, so that FlightGear shows the
//! aircraft on a real runway. Both models fly north (the earth frame's x axis), so the
//! runways chosen for an offline start point north. Where the coordinates come from is
//! in docs/cli.md "Named origins".
//!
//! The value is the geodesy's own [`GeodeticOrigin`], parsed with its `FromStr`, so a
//! front end and the geodesy that places the aircraft can never disagree about what an
//! origin is or which ones are valid (latitude -90..90°, longitude -180..180°,
//! altitude [`GeodeticOrigin::ALT_RANGE_M`], all finite).
//!
//! ```
//! use fdm_run::origin::{parse_origin, OriginError};
//!
//! let phli = parse_origin("PHLI")?;
//! assert_eq!(phli.geodetic().lat_deg, 21.963792);
//! let typed = parse_origin("1, 2 ,3")?;
//! assert_eq!(typed.geodetic().alt_m, 3.0);
//! let err = parse_origin("kord").unwrap_err();
//! assert!(matches!(err, OriginError::NotAnOrigin(_)));
//! assert!(err.to_string().ends_with("or a named origin: wpafb, phli, bikf, ksfo"));
//! # Ok::<(), OriginError>(())
//! ```

use fdm_core::geodesy::{GeodesyError, GeodeticOrigin};
use fdm_core::message::ShortNumber;

/// A named origin: a runway threshold FlightGear has scenery for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NamedOrigin {
    /// The name an origin is given by (lower case; matched case-insensitively).
    pub name: &'static str,
    /// What and where it is, for help texts and the docs.
    pub description: &'static str,
    /// Latitude of the threshold, degrees.
    pub lat_deg: f64,
    /// Longitude of the threshold, degrees.
    pub lon_deg: f64,
    /// Height of the runway surface at the threshold above the WGS-84 ellipsoid as
    /// FlightGear's scenery has it, m.
    pub alt_m: f64,
    /// Whether Debian's `flightgear-data-base` 2020.3.16 ships the scenery (so
    /// FlightGear shows it without TerraSync, offline).
    pub scenery_offline: bool,
}

/// The named origins [`parse_origin`] accepts (docs/cli.md "Named origins").
pub const NAMED_ORIGINS: &[NamedOrigin] = &[
    NamedOrigin {
        name: "wpafb",
        description: "Wright-Patterson AFB, the thesis's runway (the default)",
        lat_deg: 39.8264,
        lon_deg: -84.0483,
        alt_m: 251.0,
        scenery_offline: false,
    },
    NamedOrigin {
        name: "phli",
        description: "Lihue, Kauai (Hawaii), runway 35 threshold, runway heading 0.01 deg true",
        lat_deg: 21.963792,
        lon_deg: -159.335883,
        alt_m: 26.94,
        scenery_offline: true,
    },
    NamedOrigin {
        name: "bikf",
        description: "Keflavik (Iceland), runway 02 threshold, runway heading 0.02 deg true",
        lat_deg: 63.96448319,
        lon_deg: -22.60544552,
        alt_m: 33.81,
        scenery_offline: true,
    },
    NamedOrigin {
        name: "ksfo",
        description: "San Francisco, runway 28R threshold (runway heading 298 deg: the models \
                      fly north, across it); scenery through TerraSync only",
        lat_deg: 37.61351918,
        lon_deg: -122.35716907,
        alt_m: 3.96,
        scenery_offline: false,
    },
];

/// The named origin called `name` (case-insensitive, surrounding whitespace ignored).
#[must_use]
pub fn named_origin(name: &str) -> Option<&'static NamedOrigin> {
    NAMED_ORIGINS
        .iter()
        .find(|o| o.name.eq_ignore_ascii_case(name.trim()))
}

/// The names of [`NAMED_ORIGINS`], comma-separated.
#[must_use]
pub fn origin_names() -> String {
    NAMED_ORIGINS
        .iter()
        .map(|o| o.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why a text is not an origin. Displays as one line (values in the short
/// number form, [`ShortNumber`]: `1e300`, not 301 digits), without an option
/// name: a front end adds its own.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OriginError {
    /// `LAT,LON,ALT_M` text (it has a comma) that the geodesy refuses.
    #[error("{}", geodesy_message(.0))]
    Geodesy(GeodesyError),
    /// Text with no comma that names no origin: neither coordinates nor a
    /// name. Display lists the names.
    #[error("{}; or a named origin: {}", geodesy_message(.0), origin_names())]
    NotAnOrigin(GeodesyError),
}

/// Parses and validates `LAT,LON,ALT_M` (degrees, degrees, metres; whitespace
/// around the numbers is allowed) or the name of a [`NamedOrigin`].
///
/// # Errors
/// [`OriginError::Geodesy`] for coordinates the geodesy refuses,
/// [`OriginError::NotAnOrigin`] for text without a comma that is no name.
pub fn parse_origin(text: &str) -> Result<GeodeticOrigin, OriginError> {
    if let Some(named) = named_origin(text) {
        return GeodeticOrigin::new(named.lat_deg, named.lon_deg, named.alt_m)
            .map_err(OriginError::Geodesy);
    }
    text.parse::<GeodeticOrigin>().map_err(|e| {
        if text.contains(',') {
            OriginError::Geodesy(e)
        } else {
            OriginError::NotAnOrigin(e)
        }
    })
}

/// The geodesy's message, with the value given in the short number form.
fn geodesy_message(e: &GeodesyError) -> String {
    match e {
        GeodesyError::LatitudeOutOfRange { lat_deg } => format!(
            "latitude must be within [-90, 90] degrees, got {}",
            ShortNumber(*lat_deg)
        ),
        GeodesyError::LongitudeOutOfRange { lon_deg } => format!(
            "longitude must be within [-180, 180] degrees, got {}",
            ShortNumber(*lon_deg)
        ),
        GeodesyError::AltitudeOutOfRange { alt_m } => format!(
            "altitude must be within [{}, {}] metres, got {}",
            GeodeticOrigin::ALT_RANGE_M.start(),
            GeodeticOrigin::ALT_RANGE_M.end(),
            ShortNumber(*alt_m)
        ),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `parse_origin`'s message, as a front end shows it.
    fn message(text: &str) -> String {
        parse_origin(text).unwrap_err().to_string()
    }

    #[test]
    fn named_origins_parse_to_their_coordinates() {
        for named in NAMED_ORIGINS {
            for text in [
                named.name.to_owned(),
                named.name.to_uppercase(),
                format!(" {} ", named.name),
            ] {
                let g = parse_origin(&text).unwrap().geodetic();
                assert_eq!(
                    (g.lat_deg, g.lon_deg, g.alt_m),
                    (named.lat_deg, named.lon_deg, named.alt_m)
                );
            }
        }
        assert_eq!(parse_origin("wpafb"), Ok(GeodeticOrigin::default()));
        let err = message("kord");
        assert!(
            err.ends_with("or a named origin: wpafb, phli, bikf, ksfo"),
            "{err}"
        );
        assert!(!message("1,2").contains("named"));
    }

    /// The named origins are docs/cli.md's table ("Named origins"), row by
    /// row: the name, the threshold's latitude, longitude and altitude (as
    /// written there, from FlightGear's own airport data), and whether
    /// Debian's scenery has it.
    #[test]
    fn named_origins_are_the_documented_ones() {
        let doc = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/cli.md"),
        )
        .unwrap();
        let table = doc
            .split_once("### Named origins")
            .and_then(|(_, rest)| rest.split_once("\n\n|"))
            .map(|(_, table)| table.split("\n\n").next().unwrap_or(""))
            .unwrap();
        let rows: Vec<Vec<String>> = table
            .lines()
            .filter(|l| l.starts_with("| `"))
            .map(|l| {
                l.trim_matches('|')
                    .split('|')
                    .map(|cell| cell.trim().replace('\u{2212}', "-"))
                    .collect()
            })
            .collect();
        assert_eq!(rows.len(), NAMED_ORIGINS.len(), "{table}");
        for (row, named) in rows.iter().zip(NAMED_ORIGINS) {
            assert_eq!(row[0], format!("`{}`", named.name));
            let (lat, lon) = row[2].split_once(", ").unwrap();
            let number = |text: &str| text.parse::<f64>().unwrap();
            assert_eq!(
                (number(lat), number(lon), number(&row[3])),
                (named.lat_deg, named.lon_deg, named.alt_m),
                "{row:?}"
            );
            assert_eq!(row[5] == "yes", named.scenery_offline, "{row:?}");
        }
    }

    #[test]
    fn the_default_origin_is_the_thesis_runway() {
        assert_eq!(
            GeodeticOrigin::default().geodetic(),
            GeodeticOrigin::WRIGHT_PATTERSON
        );
    }

    #[test]
    fn display_round_trips() {
        let o = parse_origin("-33.94611111111111, 151.1772222222222 ,6.1").unwrap();
        assert_eq!(parse_origin(&o.geodetic().to_string()), Ok(o));
    }

    #[test]
    fn accepts_extremes() {
        let g = parse_origin(" -90 , 180 ,0").unwrap().geodetic();
        assert_eq!((g.lat_deg, g.lon_deg, g.alt_m), (-90.0, 180.0, 0.0));
    }

    #[test]
    fn rejects_bad_input_with_one_line() {
        for (bad, needle) in [
            ("", "LAT,LON,ALT_M"),
            ("1,2", "found 2 field"),
            ("1,2,3,4", "found 4 field"),
            ("a,2,3", "latitude is not a number"),
            ("1,,3", "longitude is not a number"),
            ("NaN,0,0", "latitude must be finite"),
            ("0,inf,0", "longitude must be finite"),
            ("90.5,0,0", "latitude must be within"),
            ("0,-180.1,0", "longitude must be within"),
            ("0,0,1e9", "altitude must be within"),
            ("1,2,3\nx", "altitude is not a number"),
        ] {
            let err = message(bad);
            assert!(!err.contains('\n'), "{err}");
            assert!(err.contains(needle), "{bad:?}: {err}");
        }
    }

    /// Huge values are echoed in the short number form, not hundreds of digits.
    #[test]
    fn out_of_range_values_are_shown_short() {
        for (bad, got) in [
            ("1e300,0,0", "got 1e300"),
            ("0,-1e300,0", "got -1e300"),
            ("0,0,1e308", "got 1e308"),
            ("90.5,0,0", "got 90.5"),
        ] {
            let err = message(bad);
            assert!(err.ends_with(got) && err.len() < 80, "{bad:?}: {err}");
        }
    }
}
