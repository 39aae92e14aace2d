//! `--origin LAT,LON,ALT_M`: where the model's earth-frame origin sits on the WGS-84
//! ellipsoid.
//!
//! The value is the ECS's own [`GeodeticOrigin`], parsed with its `FromStr`, so the
//! CLI and the geodesy that places the aircraft can never disagree about what an
//! origin is or which ones are valid (latitude -90..90°, longitude -180..180°,
//! altitude [`GeodeticOrigin::ALT_RANGE_M`], all finite).

pub use fdm_ecs::geodesy::GeodeticOrigin;

/// The default origin: the Wright-Patterson AFB runway the thesis flew from (docs/cli.md),
/// [`GeodeticOrigin::WRIGHT_PATTERSON`].
pub const DEFAULT_ORIGIN: &str = "39.8264,-84.0483,251";

/// Parses and validates `LAT,LON,ALT_M` (degrees, degrees, metres); whitespace
/// around the numbers is allowed. The error is the geodesy module's one-line
/// message, without the option name, because clap adds that.
///
/// # Errors
/// The text of the [`fdm_ecs::geodesy::GeodesyError`].
pub fn parse_origin(text: &str) -> Result<GeodeticOrigin, String> {
    text.parse::<GeodeticOrigin>().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_string_matches_default_value() {
        assert_eq!(parse_origin(DEFAULT_ORIGIN), Ok(GeodeticOrigin::default()));
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
            let err = parse_origin(bad).expect_err(bad);
            assert!(!err.contains('\n'), "{err}");
            assert!(err.contains(needle), "{bad:?}: {err}");
        }
    }
}
