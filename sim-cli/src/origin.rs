//! `--origin LAT,LON,ALT_M`: where the model's earth-frame origin sits on the WGS-84 ellipsoid.
//!
//! Kept to one parsing function, [`parse_origin`], on purpose: `fdm_ecs::geodesy` will
//! provide `Geodetic`/`GeodeticOrigin` with their own `FromStr`, and the integrator should
//! be able to swap this module for that type by changing one function.

use std::fmt;
use std::str::FromStr;

/// The default origin: the Wright-Patterson AFB runway the thesis flew from (cli.md).
pub const DEFAULT_ORIGIN: &str = "39.8264,-84.0483,251";

/// Lowest accepted origin altitude in metres (below the deepest ocean trench, so any
/// place on Earth fits; anything lower is a typo).
pub const MIN_ALT_M: f64 = -12_000.0;
/// Highest accepted origin altitude in metres (the Kármán line).
pub const MAX_ALT_M: f64 = 100_000.0;

/// A geodetic position: latitude and longitude in degrees, altitude in metres above the ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Origin {
    /// Geodetic latitude, degrees north, in [-90, 90].
    pub lat_deg: f64,
    /// Longitude, degrees east, in [-180, 180].
    pub lon_deg: f64,
    /// Altitude in metres.
    pub alt_m: f64,
}

impl Default for Origin {
    fn default() -> Self {
        Self {
            lat_deg: 39.8264,
            lon_deg: -84.0483,
            alt_m: 251.0,
        }
    }
}

impl fmt::Display for Origin {
    /// Formats as `LAT,LON,ALT_M`, which [`parse_origin`] reads back exactly.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.lat_deg, self.lon_deg, self.alt_m)
    }
}

impl FromStr for Origin {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_origin(s)
    }
}

/// Parses and validates `LAT,LON,ALT_M` (degrees, degrees, metres). Whitespace around
/// the numbers is allowed. The error is a one-line message without the option name,
/// because clap adds that.
pub fn parse_origin(text: &str) -> Result<Origin, String> {
    const FORMAT: &str =
        "expected LAT,LON,ALT_M in degrees, degrees, metres (e.g. 39.8264,-84.0483,251)";
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [lat, lon, alt] = parts.as_slice() else {
        return Err(FORMAT.to_owned());
    };
    let number = |name: &str, s: &str| -> Result<f64, String> {
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("{name} `{s}` is not a finite number; {FORMAT}")),
        }
    };
    let lat_deg = number("latitude", lat)?;
    let lon_deg = number("longitude", lon)?;
    let alt_m = number("altitude", alt)?;
    if !(-90.0..=90.0).contains(&lat_deg) {
        return Err(format!("latitude {lat_deg} is outside -90..90 degrees"));
    }
    if !(-180.0..=180.0).contains(&lon_deg) {
        return Err(format!("longitude {lon_deg} is outside -180..180 degrees"));
    }
    if !(MIN_ALT_M..=MAX_ALT_M).contains(&alt_m) {
        return Err(format!(
            "altitude {alt_m} m is outside {MIN_ALT_M}..{MAX_ALT_M} m"
        ));
    }
    Ok(Origin {
        lat_deg,
        lon_deg,
        alt_m,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_string_matches_default_value() {
        assert_eq!(parse_origin(DEFAULT_ORIGIN), Ok(Origin::default()));
    }

    #[test]
    fn display_round_trips() {
        let o = Origin {
            lat_deg: -33.946_111_111_111_11,
            lon_deg: 151.177_222_222_222_2,
            alt_m: 6.1,
        };
        assert_eq!(o.to_string().parse::<Origin>(), Ok(o));
    }

    #[test]
    fn accepts_spaces_and_extremes() {
        let o = parse_origin(" -90 , 180 ,0").unwrap();
        assert_eq!((o.lat_deg, o.lon_deg, o.alt_m), (-90.0, 180.0, 0.0));
    }

    #[test]
    fn rejects_bad_input() {
        for bad in [
            "",
            "1,2",
            "1,2,3,4",
            "a,2,3",
            "1,,3",
            "NaN,0,0",
            "0,inf,0",
            "90.5,0,0",
            "0,-180.1,0",
            "0,0,1e9",
        ] {
            let err = parse_origin(bad).expect_err(bad);
            assert!(!err.contains('\n'), "{err}");
        }
    }
}
