//! The FlightGear 2020.3 command line (`fgfs ...`) that shows a run: the
//! program receives the run's native-FDM datagrams ([`crate::flightgear`])
//! and starts where the aircraft does. `sim-cli fgfs-command` prints it.
//!
//! Flags: the thesis's appendix A command (`--fdm=null`, `--native-fdm=socket,in,...`,
//! `--disable-panel --enable-hud --disable-sound --disable-random-objects
//! --timeofday=noon`), plus the cheap ones from docs/fgnetfdm.md §7 that do not hurt an
//! interactive viewer (`--disable-real-weather-fetch --disable-ai-models
//! --disable-splash-screen`). `--disable-terrasync` is left out on purpose: scenery
//! for the default origin (Ohio) is not in the Debian data package, so TerraSync is
//! what loads it.
//!
//! Then what a user needs to see the aircraft: the model's
//! [`RunModel::FG_OPTIONS`] (the UFO draws itself only with
//! `/sim/model/always-show-in-MP` set) and a Nasal start-up script,
//! [`startup_nasal`], that sets the start view (chase by default, so the
//! aircraft is seen from outside) and the model's
//! [`RunModel::FG_STARTUP_NASAL`] (the c172p's fuel, so that its scripts do
//! not pop up "Out of fuel!") once the FDM is initialised. A `--prop:`
//! option cannot do that: FlightGear 2020.3 resets the view number while it
//! starts, and keeps the c172p's tank levels at 0 (both measured,
//! docs/flightgear-check.md).
//!
//! The start preset (`--lat/--lon/--altitude/--heading`) is where the ECS
//! places the model before its first frame ([`start_pose`]), computed by the
//! same functions the ECS's Place system uses (the model's `view`, then the
//! placement [`fgnet::bridge::display`] also computes): FlightGear only
//! loads terrain near the preset and drops packets until the FDM is
//! initialised there (docs/fgnetfdm.md §7).
//!
//! ```
//! use fdm_core::geodesy::GeodeticOrigin;
//! use fdm_core::palmer::Palmer;
//! use fdm_run::fgfs::{command_line, FgfsCommand};
//! use fdm_run::StartOptions;
//!
//! let line = command_line::<Palmer>(
//!     &FgfsCommand::new(30),
//!     &GeodeticOrigin::default(),
//!     &StartOptions::default(),
//! )?;
//! assert!(line.starts_with("fgfs --fdm=null --native-fdm=socket,in,30,,5500,udp --aircraft=c172p "));
//! # Ok::<(), fdm_run::StartRefused>(())
//! ```

use fdm_core::geodesy::{Attitude, Geodetic, GeodeticOrigin};
use fdm_core::model::Model;
use fgnet::address::FgTarget;
use fgnet::bridge::{display, Display};

use crate::model::RunModel;
use crate::scenario::{Start, StartOptions, StartRefused};

/// Feet per metre as FlightGear converts (`SG_METER_TO_FEET`).
pub const FT_PER_M: f64 = 3.280_839_895_013_123_4;

/// The port FlightGear listens on for native-FDM datagrams when no target
/// is given (the thesis's 5500).
pub const DEFAULT_FG_PORT: u16 = 5500;

/// Largest multiplayer input port FlightGear 2020.3 accepts (defined with
/// the port's parser, [`crate::values::parse_mp_port`]).
pub use crate::values::MAX_MP_PORT;

/// The viewer's own multiplayer callsign: FlightGear drops datagrams carrying
/// its own, so it must differ from every fleet callsign (`SIM...`).
pub const VIEWER_CALLSIGN: &str = "viewer";

/// FlightGear 2020.3 draws a multiplayer aircraft with its own model only while
/// it covers at least `aimp-detailed` = 400 pixels of the screen, and as its
/// fallback glider otherwise, so a fleet a few hundred metres away shows as
/// gliders (seen live). These options switch the test to distance and draw the
/// real models within 5 km.
pub const MP_DETAIL_OPTIONS: &str =
    "--prop:bool:/sim/rendering/static-lod/aimp-range-mode-distance=true \
     --prop:double:/sim/rendering/static-lod/aimp-detailed=5000";

/// FlightGear's start view (`/sim/current-view/view-number`) the chase
/// view (0 is the cockpit, 1 the helicopter view).
pub const CHASE_VIEW: u8 = 2;

/// What the command line is for, beside the model and its start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FgfsCommand<'a> {
    /// The program to run (`fgfs`, or a path; shell-quoted when needed).
    pub program: &'a str,
    /// Frames per second of the run (the native-FDM input's rate).
    pub fps: u32,
    /// Where the run sends its datagrams; `None`: FlightGear listens on all
    /// interfaces (empty host, as in the thesis), port [`DEFAULT_FG_PORT`].
    pub fg: Option<&'a FgTarget>,
    /// The start view's number (`/sim/current-view/view-number`).
    pub view_number: u8,
}

impl FgfsCommand<'static> {
    /// `fgfs` at `fps` frames per second, listening on all interfaces on
    /// port [`DEFAULT_FG_PORT`], in the chase view.
    #[must_use]
    pub fn new(fps: u32) -> Self {
        Self {
            program: "fgfs",
            fps,
            fg: None,
            view_number: CHASE_VIEW,
        }
    }
}

/// Where the ECS puts an aircraft starting at `start` (its parameters,
/// controls and state) before its first frame, and its attitude there, as
/// the FlightGear output sends them.
#[must_use]
pub fn start_pose<M: Model>(start: &Start<M>, origin: &GeodeticOrigin) -> (Geodetic, Attitude) {
    let view = M::view(&start.aircraft, &start.controls, &start.state);
    let Display {
        geodetic, attitude, ..
    } = display(&view, origin);
    (geodetic, attitude)
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
/// aircraft scripts have run by then), it selects view `view_number` and
/// runs `model_nasal`. Returned as one shell word.
#[must_use]
pub fn startup_nasal(view_number: u8, model_nasal: &str) -> String {
    let mut body = format!("setprop(\"/sim/current-view/view-number\", {view_number});");
    if !model_nasal.is_empty() {
        body.push(' ');
        body.push_str(model_nasal);
    }
    shell_word(&format!(
        "--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
         func {{ settimer(func {{ {body} }}, 1); }});"
    ))
}

/// The fgfs command line (one line, no trailing newline) that shows a run
/// of model `M` ([`RunModel::FG_AIRCRAFT`]) described by `command`, with
/// the origin `origin`, starting from `start` (FlightGear starts where the
/// aircraft does; without options, at the thesis's start).
///
/// # Errors
/// When the model cannot start there (e.g. an untrimmable speed).
pub fn command_line<M: RunModel>(
    command: &FgfsCommand<'_>,
    origin: &GeodeticOrigin,
    start: &StartOptions,
) -> Result<String, StartRefused> {
    let pose_start = if start.is_thesis() {
        Start::<M>::thesis()
    } else {
        start
            .start::<M>(M::default_aircraft(), M::initial_controls())?
            .0
    };
    let (geodetic, attitude) = start_pose(&pose_start, origin);
    let (host, port) = match command.fg {
        // 0.0.0.0 means "any" to us; fgfs spells that as an empty host.
        Some(t) if t.host != "0.0.0.0" => (t.host.as_str(), t.port),
        Some(t) => ("", t.port),
        None => ("", DEFAULT_FG_PORT),
    };
    let mut line = format!(
        "{} --fdm=null --native-fdm=socket,in,{},{host},{port},udp --aircraft={} \
         --lat={} --lon={} --altitude={:.1} --heading={} --timeofday=noon \
         --disable-panel --enable-hud --disable-sound --disable-random-objects \
         --disable-real-weather-fetch --disable-ai-models --disable-splash-screen {}",
        shell_word(command.program),
        command.fps,
        M::FG_AIRCRAFT,
        degrees(geodetic.lat_deg),
        degrees(geodetic.lon_deg),
        geodetic.alt_m * FT_PER_M,
        heading(attitude.heading_deg),
        startup_nasal(command.view_number, M::FG_STARTUP_NASAL),
    );
    for option in M::FG_OPTIONS {
        line.push(' ');
        line.push_str(option);
    }
    Ok(line)
}

/// `line` set up to show multiplayer aircraft too (docs/fg-multiplayer.md):
/// FlightGear's multiplayer input on `port` (all interfaces, read at `fps`
/// per second), the output channel FlightGear needs before it listens (to
/// the next port on 127.0.0.1, where nothing has to listen; the previous one
/// above [`MAX_MP_PORT`]), the viewer's callsign, no `--disable-ai-models`,
/// because multiplayer aircraft are AI models, and [`MP_DETAIL_OPTIONS`].
#[must_use]
pub fn with_multiplayer(line: &str, port: u16, fps: u32) -> String {
    let line = line.replacen(" --disable-ai-models", "", 1);
    let out = if port > MAX_MP_PORT {
        port - 1
    } else {
        port + 1
    };
    format!(
        "{line} --multiplay=in,{fps},,{port} --multiplay=out,10,127.0.0.1,{out} \
         --callsign={VIEWER_CALLSIGN} {MP_DETAIL_OPTIONS}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::bourg::Bourg;
    use fdm_core::palmer::Palmer;
    use fdm_ecs::{Resources, Simulation};
    use std::sync::Arc;

    fn thesis_line<M: RunModel>(
        fps: u32,
        fg: Option<&FgTarget>,
        origin: &GeodeticOrigin,
    ) -> String {
        let command = FgfsCommand {
            fg,
            ..FgfsCommand::new(fps)
        };
        command_line::<M>(&command, origin, &StartOptions::default()).unwrap()
    }

    #[test]
    fn palmer_default() {
        assert_eq!(
            thesis_line::<Palmer>(30, None, &GeodeticOrigin::default()),
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
    fn the_ufo_shows_itself_and_program_and_view_are_options() {
        let cmd = thesis_line::<Bourg>(30, None, &GeodeticOrigin::default());
        assert!(
            cmd.ends_with(
                " '--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
                 func { settimer(func { setprop(\"/sim/current-view/view-number\", 2); }, 1); });' \
                 --prop:bool:/sim/model/always-show-in-MP=true"
            ),
            "{cmd}"
        );
        assert!(!cmd.contains("fuel"), "{cmd}");
        let command = FgfsCommand {
            program: "/opt/my fg/fgfs",
            view_number: 1,
            ..FgfsCommand::new(30)
        };
        let line = command_line::<Bourg>(
            &command,
            &GeodeticOrigin::default(),
            &StartOptions::default(),
        )
        .unwrap();
        assert!(line.starts_with("'/opt/my fg/fgfs' --fdm"), "{line}");
        assert!(line.contains(r#"view-number", 1);"#), "{line}");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
    }

    #[test]
    fn multiplayer_input_keeps_ai_models_on() {
        let plain = thesis_line::<Palmer>(30, None, &GeodeticOrigin::default());
        let mp = with_multiplayer(&plain, 5000, 30);
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
        assert!(with_multiplayer(&plain, 32766, 30).contains("out,10,127.0.0.1,32767 "));
        assert!(with_multiplayer(&plain, 32767, 30).contains("out,10,127.0.0.1,32766 "));
        assert!(with_multiplayer(&plain, u16::MAX, 30).contains("out,10,127.0.0.1,65534 "));
    }

    #[test]
    fn bourg_starts_south_and_up() {
        let target: FgTarget = "127.0.0.1:5501".parse().unwrap();
        let cmd = thesis_line::<Bourg>(60, Some(&target), &GeodeticOrigin::default());
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
                (
                    "palmer",
                    palmer,
                    start_pose(&Start::<Palmer>::thesis(), &origin),
                ),
                (
                    "bourg",
                    bourg,
                    start_pose(&Start::<Bourg>::thesis(), &origin),
                ),
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
        let any: FgTarget = "0.0.0.0:6000".parse().unwrap();
        let cmd = thesis_line::<Palmer>(30, Some(&any), &GeodeticOrigin::default());
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
