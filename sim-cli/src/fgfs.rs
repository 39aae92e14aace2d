//! `sim-cli fgfs-command`: the FlightGear 2020.3 command line matching a run.
//!
//! Flags: the thesis's appendix A command (`--fdm=null`, `--native-fdm=socket,in,...`,
//! `--disable-panel --enable-hud --disable-sound --disable-random-objects
//! --timeofday=noon`), plus the cheap ones from fgnetfdm.md §7 that do not hurt an
//! interactive viewer (`--disable-real-weather-fetch --disable-ai-models
//! --disable-splash-screen`). `--disable-terrasync` is left out on purpose: scenery
//! for the default origin (Ohio) is not in the Debian data package, so TerraSync is
//! what loads it.
//!
//! The start preset (`--lat/--lon/--altitude/--heading`) is where the model starts,
//! because FlightGear only loads terrain near the preset and drops packets until
//! the FDM is initialised there (fgnetfdm.md §7).

use crate::args::ModelKind;
use crate::fgaddr::FgTarget;
use crate::origin::Origin;

/// Feet per metre as FlightGear converts (`SG_METER_TO_FEET`).
pub const FT_PER_M: f64 = 3.280_839_895_013_123_4;

/// Bourg's initial position in its earth frame (x north, y west, z up), feet
/// (bourg.md "Initial conditions").
pub const BOURG_START_FT: [f64; 3] = [-5000.0, 0.0, 2000.0];

/// WGS-84 semi-major axis, m.
const WGS84_A: f64 = 6_378_137.0;
/// WGS-84 first eccentricity squared.
const WGS84_E2: f64 = 6.694_379_990_141_317e-3;

/// Moves `origin` by a small local offset (metres north, west, up) on the WGS-84
/// ellipsoid using the meridian and prime-vertical radii of curvature at the origin.
/// Accurate to centimetres for the few kilometres used here; only used for the
/// fgfs start preset (the packets carry the exact position from the geodesy code).
#[must_use]
pub fn offset_origin(origin: &Origin, north_m: f64, west_m: f64, up_m: f64) -> Origin {
    let phi = origin.lat_deg.to_radians();
    let w = 1.0 - WGS84_E2 * phi.sin().powi(2);
    let meridian = WGS84_A * (1.0 - WGS84_E2) / (w * w.sqrt());
    let prime_vertical = WGS84_A / w.sqrt();
    let lat_deg = (origin.lat_deg + (north_m / meridian).to_degrees()).clamp(-90.0, 90.0);
    let cos_phi = phi.cos();
    let lon_deg = if cos_phi.abs() < 1e-12 {
        origin.lon_deg
    } else {
        let lon = origin.lon_deg - (west_m / (prime_vertical * cos_phi)).to_degrees();
        (lon + 180.0).rem_euclid(360.0) - 180.0
    };
    Origin {
        lat_deg,
        lon_deg,
        alt_m: origin.alt_m + up_m,
    }
}

/// Rounds to 1e-7 degrees (about 1 cm) and prints the shortest form.
fn degrees(x: f64) -> f64 {
    (x * 1e7).round() / 1e7
}

/// The fgfs command line (one line, no trailing newline) that receives packets from
/// `sim-cli <model> --fps <fps> [--fg <fg>] --origin <origin>`. Without `--fg`,
/// FlightGear listens on all interfaces (empty host, as in the thesis) port 5500.
#[must_use]
pub fn fgfs_command(model: ModelKind, fps: f64, fg: Option<&FgTarget>, origin: &Origin) -> String {
    let (host, port) = match fg {
        // 0.0.0.0 means "any" to us; fgfs spells that as an empty host.
        Some(t) if t.host != "0.0.0.0" => (t.host.as_str(), t.port),
        Some(t) => ("", t.port),
        None => ("", 5500),
    };
    let (aircraft, start) = match model {
        // Palmer starts at rest on the runway at the origin.
        ModelKind::Palmer => ("c172p", *origin),
        // The thesis showed Bourg's aircraft as the UFO; it starts 5000 ft south of
        // the origin, 2000 ft up.
        ModelKind::Bourg => (
            "ufo",
            offset_origin(
                origin,
                BOURG_START_FT[0] * 0.3048,
                BOURG_START_FT[1] * 0.3048,
                BOURG_START_FT[2] * 0.3048,
            ),
        ),
    };
    // Both models start flying along +x = north, so heading 0.
    format!(
        "fgfs --fdm=null --native-fdm=socket,in,{fps},{host},{port},udp --aircraft={aircraft} \
         --lat={} --lon={} --altitude={:.1} --heading=0 --timeofday=noon \
         --disable-panel --enable-hud --disable-sound --disable-random-objects \
         --disable-real-weather-fetch --disable-ai-models --disable-splash-screen",
        degrees(start.lat_deg),
        degrees(start.lon_deg),
        start.alt_m * FT_PER_M,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palmer_default() {
        assert_eq!(
            fgfs_command(ModelKind::Palmer, 30.0, None, &Origin::default()),
            "fgfs --fdm=null --native-fdm=socket,in,30,,5500,udp --aircraft=c172p \
             --lat=39.8264 --lon=-84.0483 --altitude=823.5 --heading=0 --timeofday=noon \
             --disable-panel --enable-hud --disable-sound --disable-random-objects \
             --disable-real-weather-fetch --disable-ai-models --disable-splash-screen"
        );
    }

    #[test]
    fn bourg_starts_south_and_up() {
        let cmd = fgfs_command(
            ModelKind::Bourg,
            60.0,
            Some(&"127.0.0.1:5501".parse().unwrap()),
            &Origin::default(),
        );
        assert!(cmd.contains("--native-fdm=socket,in,60,127.0.0.1,5501,udp"));
        assert!(cmd.contains("--aircraft=ufo"));
        // 1524 m south at 39.8 N is about 0.01373 degrees; 251 m + 2000 ft.
        assert!(cmd.contains("--lat=39.81267"), "{cmd}");
        assert!(cmd.contains("--lon=-84.0483 "), "{cmd}");
        assert!(cmd.contains("--altitude=2823.5"), "{cmd}");
    }

    #[test]
    fn any_address_prints_empty_host() {
        let cmd = fgfs_command(
            ModelKind::Palmer,
            30.0,
            Some(&"0.0.0.0:6000".parse().unwrap()),
            &Origin::default(),
        );
        assert!(cmd.contains("socket,in,30,,6000,udp"));
    }

    #[test]
    fn offset_matches_known_radii() {
        // At the equator one degree of latitude is 110 574 m, of longitude 111 320 m.
        let o = Origin {
            lat_deg: 0.0,
            lon_deg: 179.9,
            alt_m: 0.0,
        };
        let north = offset_origin(&o, 110_574.3, 0.0, 0.0);
        assert!((north.lat_deg - 1.0).abs() < 1e-5, "{}", north.lat_deg);
        // Moving east (negative west) across the antimeridian wraps.
        let east = offset_origin(&o, 0.0, -2.0 * 11_132.0, 0.0);
        assert!((east.lon_deg - -179.9).abs() < 1e-3, "{}", east.lon_deg);
    }
}
