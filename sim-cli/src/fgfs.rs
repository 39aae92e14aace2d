//! `sim-cli fgfs-command`: the FlightGear 2020.3 command line matching a run.
//!
//! Flags: the thesis's appendix A command (`--fdm=null`, `--native-fdm=socket,in,...`,
//! `--disable-panel --enable-hud --disable-sound --disable-random-objects
//! --timeofday=noon`), plus the cheap ones from docs/fgnetfdm.md §7 that do not hurt an
//! interactive viewer (`--disable-real-weather-fetch --disable-ai-models
//! --disable-splash-screen`). `--disable-terrasync` is left out on purpose: scenery
//! for the default origin (Ohio) is not in the Debian data package, so TerraSync is
//! what loads it (the named origins `phli` and `bikf` are, see [`crate::origin`]).
//!
//! Then what a user needs to see the aircraft: the model's [`CliModel::FG_OPTIONS`]
//! (the UFO draws itself only with `/sim/model/always-show-in-MP` set) and a Nasal
//! start-up script, [`startup_nasal`], that sets the start view (chase by default,
//! so the aircraft is seen from outside) and the model's
//! [`CliModel::FG_STARTUP_NASAL`] (the c172p's fuel, so that its scripts do not pop
//! up "Out of fuel!") once the FDM is initialised. A `--prop:` option cannot do
//! that: FlightGear 2020.3 resets the view number while it starts, and keeps the
//! c172p's tank levels at 0 (both measured, docs/flightgear-check.md).
//!
//! The start preset (`--lat/--lon/--altitude/--heading`) is where the ECS places the
//! model before its first frame, computed by the same functions the ECS's Place
//! system uses (the model's `view`, then the placement [`fgnet::bridge::display`]
//! also computes):
//! FlightGear only loads terrain near the preset and drops packets until the FDM is
//! initialised there (docs/fgnetfdm.md §7). Palmer stands at rest on the runway at the
//! origin; Bourg starts at model (−5000, 0, 2000) ft, 5000 ft south of the origin and
//! 2000 ft above it. Both start pointing north (heading 0), the direction they fly.

use fdm_core::geodesy::{Attitude, Geodetic, GeodeticOrigin};
use fgnet::bridge::{display, Display};

use crate::args::{FgView, FgfsArgs, ModelKind};
use crate::error::CliError;
use crate::models::{CliModel, WithModel};
use crate::start::StartArgs;
use fgnet::address::FgTarget;

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

/// The aircraft name, extra options and start pose of a model chosen at run
/// time, starting from the initial-condition options (the thesis's start
/// without any).
struct Preset<'a>(&'a GeodeticOrigin, &'a StartArgs);

impl WithModel for Preset<'_> {
    type Output = Result<
        (
            &'static str,
            &'static [&'static str],
            &'static str,
            Geodetic,
            Attitude,
        ),
        CliError,
    >;

    fn call<M: CliModel>(self) -> Self::Output {
        let (geodetic, attitude) = if self.1.is_thesis() {
            start_pose::<M>(self.0)
        } else {
            let (start, _) =
                crate::start::start_for::<M>(M::default_aircraft(), M::initial_controls(), self.1)?;
            start_pose_of::<M>(&start, self.0)
        };
        Ok((
            M::FG_AIRCRAFT,
            M::FG_OPTIONS,
            M::FG_STARTUP_NASAL,
            geodetic,
            attitude,
        ))
    }
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
/// The program is `fgfs` and the start view the chase view; see [`fgfs_command_line`].
#[must_use]
pub fn fgfs_command(
    model: ModelKind,
    fps: u32,
    fg: Option<&FgTarget>,
    origin: &GeodeticOrigin,
) -> String {
    // The thesis start cannot fail: no trim, no initial conditions to check.
    command(
        "fgfs",
        model,
        fps,
        fg,
        origin,
        FgView::Chase,
        &StartArgs::default(),
    )
    .unwrap_or_default()
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
    start: &StartArgs,
) -> Result<String, CliError> {
    command("fgfs", model, fps, fg, origin, FgView::Chase, start)
}

/// The line `sim-cli fgfs-command` prints for its arguments.
///
/// # Errors
/// As [`fgfs_command_from`].
pub fn fgfs_command_line(args: &FgfsArgs) -> Result<String, CliError> {
    let line = command(
        &args.fgfs,
        args.model,
        args.fps,
        args.fg.as_ref(),
        &args.origin,
        args.view,
        &args.start,
    )?;
    Ok(match args.fg_mp {
        Some(port) => with_multiplayer(&line, port),
        None => line,
    })
}

/// The viewer's own multiplayer callsign: FlightGear drops datagrams carrying
/// its own, so it must differ from every fleet callsign (`SIM...`).
pub const VIEWER_CALLSIGN: &str = "viewer";

/// `line` set up to show multiplayer aircraft too (docs/fg-multiplayer.md):
/// FlightGear's multiplayer input on `port` (all interfaces, read at
/// [`crate::fleet::FLEET_FPS`]), the output channel FlightGear needs before it
/// listens (to the next port on 127.0.0.1, where nothing has to listen), the
/// viewer's callsign, no `--disable-ai-models`, because multiplayer
/// aircraft are AI models, and [`MP_DETAIL_OPTIONS`].
#[must_use]
pub fn with_multiplayer(line: &str, port: u16) -> String {
    let line = line.replacen(" --disable-ai-models", "", 1);
    // PORT + 1, or PORT - 1 at the top of the range FlightGear reads
    // ([`crate::args::MAX_FG_MP_PORT`]).
    let out = if port > crate::args::MAX_FG_MP_PORT {
        port - 1
    } else {
        port + 1
    };
    format!(
        "{line} --multiplay=in,{},,{port} --multiplay=out,10,127.0.0.1,{out} \
         --callsign={VIEWER_CALLSIGN} {MP_DETAIL_OPTIONS}",
        crate::fleet::FLEET_FPS
    )
}

/// FlightGear 2020.3 draws a multiplayer aircraft with its own model only while
/// it covers at least `aimp-detailed` = 400 pixels of the screen, and as its
/// fallback glider otherwise, so a fleet a few hundred metres away shows as
/// gliders (seen live). These options switch the test to distance and draw the
/// real models within 5 km.
pub const MP_DETAIL_OPTIONS: &str =
    "--prop:bool:/sim/rendering/static-lod/aimp-range-mode-distance=true \
     --prop:double:/sim/rendering/static-lod/aimp-detailed=5000";

/// `program` as one shell word: itself when it has only safe characters, else
/// single-quoted.
fn shell_word(program: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "/._-+:=,".contains(c);
    if !program.is_empty() && program.chars().all(safe) {
        program.to_owned()
    } else {
        format!("'{}'", program.replace('\'', r"'\''"))
    }
}

/// The `--prop:` option holding the Nasal script that FlightGear loads as
/// module `afitfdm` at start-up (every `/nasal/NAME/script` property is one):
/// one second after each `/sim/signals/fdm-initialized` (FlightGear's
/// aircraft scripts have run by then), it selects `view` and runs
/// `model_nasal`. Returned as one shell word.
#[must_use]
pub fn startup_nasal(view: FgView, model_nasal: &str) -> String {
    let mut body = format!(
        "setprop(\"/sim/current-view/view-number\", {});",
        view.number()
    );
    if !model_nasal.is_empty() {
        body.push(' ');
        body.push_str(model_nasal);
    }
    shell_word(&format!(
        "--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
         func {{ settimer(func {{ {body} }}, 1); }});"
    ))
}

fn command(
    program: &str,
    model: ModelKind,
    fps: u32,
    fg: Option<&FgTarget>,
    origin: &GeodeticOrigin,
    view: FgView,
    start: &StartArgs,
) -> Result<String, CliError> {
    let (host, port) = match fg {
        // 0.0.0.0 means "any" to us; fgfs spells that as an empty host.
        Some(t) if t.host != "0.0.0.0" => (t.host.as_str(), t.port),
        Some(t) => ("", t.port),
        None => ("", 5500),
    };
    // The thesis showed Bourg's aircraft as the UFO (`CliModel::FG_AIRCRAFT`).
    let (aircraft, options, nasal, start, attitude) = model.with(Preset(origin, start))?;
    let mut line = format!(
        "{} --fdm=null --native-fdm=socket,in,{fps},{host},{port},udp --aircraft={aircraft} \
         --lat={} --lon={} --altitude={:.1} --heading={} --timeofday=noon \
         --disable-panel --enable-hud --disable-sound --disable-random-objects \
         --disable-real-weather-fetch --disable-ai-models --disable-splash-screen {}",
        shell_word(program),
        degrees(start.lat_deg),
        degrees(start.lon_deg),
        start.alt_m * FT_PER_M,
        heading(attitude.heading_deg),
        startup_nasal(view, nasal),
    );
    for option in options {
        line.push(' ');
        line.push_str(option);
    }
    Ok(line)
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
             --disable-real-weather-fetch --disable-ai-models --disable-splash-screen \
             '--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
             func { settimer(func { setprop(\"/sim/current-view/view-number\", 2); \
             var refuel = func { foreach (var tank; [0, 1]) { \
             var path = \"/consumables/fuel/tank[\" ~ tank ~ \"]/\"; \
             if (getprop(path ~ \"level-gal_us\") < 1) { setprop(path ~ \"capacity-gal_us\", 28); \
             setprop(path ~ \"density-ppg\", 6); setprop(path ~ \"level-gal_us\", 20); } } \
             settimer(refuel, 2); }; refuel(); }, 1); });'"
        );
    }

    #[test]
    fn the_ufo_shows_itself_and_views_and_program_are_options() {
        let cmd = fgfs_command(ModelKind::Bourg, 30, None, &GeodeticOrigin::default());
        assert!(
            cmd.ends_with(
                " '--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
                 func { settimer(func { setprop(\"/sim/current-view/view-number\", 2); }, 1); });' \
                 --prop:bool:/sim/model/always-show-in-MP=true"
            ),
            "{cmd}"
        );
        assert!(!cmd.contains("fuel"), "{cmd}");
        let args = |extra: &[&str]| {
            let argv = ["sim-cli", "fgfs-command", "bourg"]
                .iter()
                .chain(extra)
                .copied();
            match <crate::args::Cli as clap::Parser>::try_parse_from(argv)
                .unwrap()
                .command
            {
                crate::args::Command::FgfsCommand(a) => a,
                _ => unreachable!(),
            }
        };
        assert_eq!(fgfs_command_line(&args(&[])).unwrap(), cmd);
        let line =
            fgfs_command_line(&args(&["--view", "cockpit", "--fgfs", "/usr/games/fgfs"])).unwrap();
        assert!(line.starts_with("/usr/games/fgfs --fdm=null "), "{line}");
        assert!(
            line.contains(r#"setprop("/sim/current-view/view-number", 0);"#),
            "{line}"
        );
        let line = fgfs_command_line(&args(&[
            "--view",
            "helicopter",
            "--fgfs",
            "/opt/my fg/fgfs",
        ]))
        .unwrap();
        assert!(line.starts_with("'/opt/my fg/fgfs' --fdm"), "{line}");
        assert!(line.contains(r#"view-number", 1);"#), "{line}");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
    }

    #[test]
    fn multiplayer_input_keeps_ai_models_on() {
        let plain = fgfs_command(ModelKind::Palmer, 30, None, &GeodeticOrigin::default());
        let mp = with_multiplayer(&plain, 5000);
        assert!(plain.contains(" --disable-ai-models "));
        assert!(!mp.contains("--disable-ai-models"), "{mp}");
        let added = " --multiplay=in,30,,5000 --multiplay=out,10,127.0.0.1,5001 --callsign=viewer \
             --prop:bool:/sim/rendering/static-lod/aimp-range-mode-distance=true \
             --prop:double:/sim/rendering/static-lod/aimp-detailed=5000";
        assert!(mp.ends_with(added), "{mp}");
        assert_eq!(
            mp.len(),
            plain.len() - " --disable-ai-models".len() + added.len()
        );
        assert!(with_multiplayer(&plain, 32766).contains("out,10,127.0.0.1,32767 "));
        assert!(with_multiplayer(&plain, 32767).contains("out,10,127.0.0.1,32766 "));
        assert_eq!(crate::args::parse_fg_mp_port("32766"), Ok(32766));
        for bad in ["0", "32767", "35606", "65535", "x"] {
            assert!(crate::args::parse_fg_mp_port(bad).is_err(), "{bad}");
        }
        assert!(crate::args::parse_fg_mp_port("35606")
            .unwrap_err()
            .contains("signed 16-bit"));
    }

    #[test]
    fn named_origins_start_on_their_runway() {
        let phli = crate::origin::parse_origin("phli").unwrap();
        let cmd = fgfs_command(ModelKind::Palmer, 30, None, &phli);
        // 26.94 m = 88.4 ft.
        assert!(
            cmd.contains("--lat=21.963792 --lon=-159.335883 --altitude=88.4 "),
            "{cmd}"
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
            );
            let bourg = sim.spawn::<Bourg>(
                Arc::new(Bourg::default_aircraft()),
                Bourg::initial_controls(),
                Bourg::initial_state(),
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
