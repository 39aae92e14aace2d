//! `--origin LAT,LON,ALT_M` or `--origin NAME`: where the model's earth-frame origin
//! sits on the WGS-84 ellipsoid. The named origins (runway thresholds) and the
//! parsing are the run library's ([`fdm_run::origin`]); the
//! CLI adds the default's text and the clap value parser.

pub use fdm_ecs::geodesy::GeodeticOrigin;

/// The default origin: the Wright-Patterson AFB runway the thesis flew from (docs/cli.md),
/// [`GeodeticOrigin::WRIGHT_PATTERSON`].
pub const DEFAULT_ORIGIN: &str = "39.8264,-84.0483,251";

/// `--origin`'s value parser: [`fdm_run::origin::parse_origin`], its error's
/// one-line message without the option name (clap adds that).
///
/// # Errors
/// The [`fdm_run::origin::OriginError`]'s message.
pub fn parse_origin(text: &str) -> Result<GeodeticOrigin, String> {
    fdm_run::origin::parse_origin(text).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_string_matches_default_value() {
        assert_eq!(parse_origin(DEFAULT_ORIGIN), Ok(GeodeticOrigin::default()));
        assert_eq!(parse_origin("wpafb"), parse_origin(DEFAULT_ORIGIN));
        assert_eq!(
            GeodeticOrigin::default().geodetic(),
            GeodeticOrigin::WRIGHT_PATTERSON
        );
    }
}
