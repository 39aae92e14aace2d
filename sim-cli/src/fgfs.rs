//! `sim-cli fgfs-command`: the FlightGear 2020.3 command line matching a run.
//!
//! Flags: the thesis's appendix A command (`--fdm=null`, `--native-fdm=socket,in,...`,
//! `--disable-panel --enable-hud --disable-sound --disable-random-objects
//! --timeofday=noon`), plus the cheap ones from docs/fgnetfdm.md §7 that do not hurt an
//! interactive viewer (`--disable-real-weather-fetch --disable-ai-models
//! --disable-splash-screen`). `--disable-terrasync` is left out on purpose: scenery
//! for the default origin (Ohio) is not in the Debian data package, so TerraSync is
//! what loads it.
//!
//! The start preset (`--lat/--lon/--altitude/--heading`) is where the ECS places the
//! model before its first frame, computed by the same functions MakePacket uses
//! (the model's `view`, then [`fgnet::bridge::display`]):
//! FlightGear only loads terrain near the preset and drops packets until the FDM is
//! initialised there (docs/fgnetfdm.md §7). Palmer stands at rest on the runway at the
//! origin; Bourg starts at model (−5000, 0, 2000) ft, 5000 ft south of the origin and
//! 2000 ft above it. Both start pointing north (heading 0), the direction they fly.

use fdm_core::geodesy::{Attitude, Geodetic, GeodeticOrigin};
use fgnet::bridge::{display, Display};

use crate::args::ModelKind;
use crate::error::CliError;
use crate::fgaddr::FgTarget;
use crate::models::{CliModel, WithModel};

/// Feet per metre as FlightGear converts (`SG_METER_TO_FEET`).
pub const FT_PER_M: f64 = 3.280_839_895_013_123_4;

/// Where the ECS puts an aircraft of model `M` before its first frame, and its
/// attitude there, as MakePacket would send them (with the model's initial
/// controls and state).
#[must_use]
pub fn start_pose<M: CliModel>(origin: &GeodeticOrigin) -> (Geodetic, Attitude) {
    let view = M::view(
        &M::default_aircraft(),
        &M::initial_controls(),
        &M::initial_state(),
    );
    let Display {
        geodetic, attitude, ..
    } = display(&view, origin);
    (geodetic, attitude)
}

/// Where the ECS puts an aircraft of model `M` starting at `start` (its
/// controls and state), as MakePacket would send it.
#[must_use]
pub fn start_pose_of<M: CliModel>(
    start: &crate::config::Start<M>,
    origin: &GeodeticOrigin,
) -> (Geodetic, Attitude) {
    let view = M::view(&start.aircraft, &start.controls, &start.state);
    let Display {
        geodetic, attitude, ..
    } = display(&view, origin);
    (geodetic, attitude)
}

/// The aircraft name and start pose of a model chosen at run time.
struct Preset<'a>(&'a GeodeticOrigin);

impl WithModel for Preset<'_> {
    type Output = (&'static str, Geodetic, Attitude);

    fn call<M: CliModel>(self) -> Self::Output {
        let (geodetic, attitude) = start_pose::<M>(self.0);
        (M::FG_AIRCRAFT, geodetic, attitude)
    }
}

/// The aircraft name and start pose of a model chosen at run time, starting
/// from initial-condition options.
struct PresetAt<'a>(&'a GeodeticOrigin, &'a crate::start::StartArgs);

impl WithModel for PresetAt<'_> {
    type Output = Result<(&'static str, Geodetic, Attitude), CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        let (start, _) =
            crate::start::start_for::<M>(M::default_aircraft(), M::initial_controls(), self.1)?;
        let (geodetic, attitude) = start_pose_of::<M>(&start, self.0);
        Ok((M::FG_AIRCRAFT, geodetic, attitude))
    }
}

/// [`fgfs_command`] for an aircraft that starts from the initial-condition
/// options `start` (`--altitude-ft`, `--speed-kt`, `--heading-deg`,
/// `--trim`): FlightGear starts where the aircraft does. Without options it
/// is exactly [`fgfs_command`].
///
/// # Errors
/// [`CliError::Usage`] when the model cannot start there (e.g. an
/// untrimmable speed).
pub fn fgfs_command_from(
    model: ModelKind,
    fps: u32,
    fg: Option<&FgTarget>,
    origin: &GeodeticOrigin,
    start: &crate::start::StartArgs,
) -> Result<String, CliError> {
    let (aircraft, geodetic, attitude) = model.with(PresetAt(origin, start))?;
    Ok(command_line(fps, fg, aircraft, &geodetic, &attitude))
}

/// Rounds to 1e-7 degrees (about 1 cm) and prints the shortest form.
fn degrees(x: f64) -> f64 {
    (x * 1e7).round() / 1e7
}

/// A heading rounded to 0.1 degree in `[0, 360)` (so 359.99 prints as 0).
fn heading(x: f64) -> f64 {
    let h = (x * 10.0).round() / 10.0;
    if h >= 360.0 || h == 0.0 {
        0.0
    } else {
        h
    }
}

/// The fgfs command line (one line, no trailing newline) that receives packets from
/// `sim-cli <model> --fps <fps> [--fg <fg>] --origin <origin>`. Without `--fg`,
/// FlightGear listens on all interfaces (empty host, as in the thesis) port 5500.
#[must_use]
pub fn fgfs_command(
    model: ModelKind,
    fps: u32,
    fg: Option<&FgTarget>,
    origin: &GeodeticOrigin,
) -> String {
    // The thesis showed Bourg's aircraft as the UFO (`CliModel::FG_AIRCRAFT`).
    let (aircraft, start, attitude) = model.with(Preset(origin));
    command_line(fps, fg, aircraft, &start, &attitude)
}

/// The command line for `aircraft` starting at `start` with `attitude`.
fn command_line(
    fps: u32,
    fg: Option<&FgTarget>,
    aircraft: &str,
    start: &Geodetic,
    attitude: &Attitude,
) -> String {
    let (host, port) = match fg {
        // 0.0.0.0 means "any" to us; fgfs spells that as an empty host.
        Some(t) if t.host != "0.0.0.0" => (t.host.as_str(), t.port),
        Some(t) => ("", t.port),
        None => ("", 5500),
    };
    format!(
        "fgfs --fdm=null --native-fdm=socket,in,{fps},{host},{port},udp --aircraft={aircraft} \
         --lat={} --lon={} --altitude={:.1} --heading={} --timeofday=noon \
         --disable-panel --enable-hud --disable-sound --disable-random-objects \
         --disable-real-weather-fetch --disable-ai-models --disable-splash-screen",
        degrees(start.lat_deg),
        degrees(start.lon_deg),
        start.alt_m * FT_PER_M,
        heading(attitude.heading_deg),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::model::Model;
    use fdm_core::palmer::Palmer;
    use fdm_ecs::{Resources, Simulation};
    use std::sync::Arc;

    #[test]
    fn palmer_default() {
        assert_eq!(
            fgfs_command(ModelKind::Palmer, 30, None, &GeodeticOrigin::default()),
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
            60,
            Some(&"127.0.0.1:5501".parse().unwrap()),
            &GeodeticOrigin::default(),
        );
        assert!(cmd.contains("--native-fdm=socket,in,60,127.0.0.1,5501,udp"));
        assert!(cmd.contains("--aircraft=ufo"));
        // 1524 m south at 39.8 N is about 0.01373 degrees; 251 m + 2000 ft + 0.18 m
        // of tangent-plane curvature.
        assert!(cmd.contains("--lat=39.81267"), "{cmd}");
        assert!(cmd.contains("--lon=-84.0483 "), "{cmd}");
        assert!(cmd.contains("--altitude=2824.1"), "{cmd}");
        assert!(cmd.contains("--heading=0 "), "{cmd}");
    }

    /// The preset is exactly where the simulation puts the aircraft before frame 1.
    #[test]
    fn start_pose_is_the_simulations_initial_position() {
        for origin in ["39.8264,-84.0483,251", "-33.9,151.2,6", "64.1,-21.9,50"] {
            let origin: GeodeticOrigin = origin.parse().unwrap();
            let mut sim = Simulation::new(Resources::new(30.0).unwrap().with_origin(origin));
            let palmer = sim.spawn::<Palmer>(
                Arc::new(Palmer::default_aircraft()),
                Palmer::initial_controls(),
                Palmer::initial_state(),
                None,
            );
            let bourg = sim.spawn::<Bourg>(
                Arc::new(Bourg::default_aircraft()),
                Bourg::initial_controls(),
                Bourg::initial_state(),
                None,
            );
            for (model, entity, (geodetic, attitude)) in [
                ("palmer", palmer, start_pose::<Palmer>(&origin)),
                ("bourg", bourg, start_pose::<Bourg>(&origin)),
            ] {
                assert_eq!(Some(geodetic), sim.geodetic(entity));
                assert_eq!(Some(attitude), sim.attitude(entity));
                // Both start flying north: heading 0 up to rounding.
                assert_eq!(heading(attitude.heading_deg), 0.0, "{model:?} {attitude:?}");
            }
            // Palmer stands at the origin (to the geodesy's round trip through ECEF).
            let here = sim.geodetic(palmer).unwrap();
            assert!((here.lat_deg - origin.geodetic().lat_deg).abs() < 1e-12);
            assert!((here.lon_deg - origin.geodetic().lon_deg).abs() < 1e-12);
            assert!((here.alt_m - origin.geodetic().alt_m).abs() < 1e-6);
        }
    }

    #[test]
    fn any_address_prints_empty_host() {
        let cmd = fgfs_command(
            ModelKind::Palmer,
            30,
            Some(&"0.0.0.0:6000".parse().unwrap()),
            &GeodeticOrigin::default(),
        );
        assert!(cmd.contains("socket,in,30,,6000,udp"));
    }

    #[test]
    fn headings_round_into_range() {
        assert_eq!(heading(359.97), 0.0);
        assert_eq!(heading(-0.0), 0.0);
        assert_eq!(heading(1e-12), 0.0);
        assert_eq!(heading(90.04), 90.0);
    }
}
