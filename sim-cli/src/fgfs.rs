//! `sim-cli fgfs-command`: the FlightGear 2020.3 command line matching a run.
//!
//! The line itself (flags, the model's aircraft and options, the start
//! preset where the aircraft starts, the start-up Nasal script, the
//! multiplayer input) is the run library's ([`fdm_run::fgfs`]); here are the
//! arguments' mapping and the error messages. The named origins `phli` and
//! `bikf` have their scenery in the Debian data package, see
//! [`crate::origin`].

use fdm_run::fgfs::{command_line, with_multiplayer, FgfsCommand};

use crate::args::FgfsArgs;
use crate::error::CliError;
use crate::models::{CliModel, WithModel};

/// The command line of a model chosen at run time.
struct Line<'a>(&'a FgfsArgs);

impl WithModel for Line<'_> {
    type Output = Result<String, CliError>;

    fn call<M: CliModel>(self) -> Self::Output {
        let args = self.0;
        let command = FgfsCommand {
            program: &args.fgfs,
            fps: args.fps,
            fg: args.fg.as_ref(),
            view_number: args.view as u8,
        };
        command_line::<M>(&command, &args.origin, &args.start.options())
            .map_err(crate::start::refused)
    }
}

/// The line `sim-cli fgfs-command` prints for its arguments: FlightGear
/// starts where the aircraft does; with `--fg-mp PORT` it also shows a
/// fleet's multiplayer aircraft, read at [`crate::args::FLEET_FPS`].
///
/// # Errors
/// [`CliError::Usage`] when the model cannot start there (e.g. an
/// untrimmable speed).
pub fn fgfs_command_line(args: &FgfsArgs) -> Result<String, CliError> {
    let line = args.model.with(Line(args))?;
    Ok(match args.fg_mp {
        Some(port) => with_multiplayer(&line, port, crate::args::FLEET_FPS),
        None => line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(argv: &[&str]) -> FgfsArgs {
        let argv = ["sim-cli", "fgfs-command"].iter().chain(argv).copied();
        match <crate::args::Cli as clap::Parser>::try_parse_from(argv)
            .unwrap()
            .command
        {
            crate::args::Command::FgfsCommand(a) => a,
            _ => unreachable!(),
        }
    }

    fn line(argv: &[&str]) -> String {
        fgfs_command_line(&args(argv)).unwrap()
    }

    #[test]
    fn the_ufo_shows_itself_and_views_and_program_are_options() {
        let cmd = line(&["bourg"]);
        assert!(
            cmd.ends_with(
                " '--prop:/nasal/afitfdm/script=setlistener(\"/sim/signals/fdm-initialized\", \
                 func { settimer(func { setprop(\"/sim/current-view/view-number\", 2); }, 1); });' \
                 --prop:bool:/sim/model/always-show-in-MP=true"
            ),
            "{cmd}"
        );
        assert!(!cmd.contains("fuel"), "{cmd}");
        let line_ = line(&["bourg", "--view", "cockpit", "--fgfs", "/usr/games/fgfs"]);
        assert!(line_.starts_with("/usr/games/fgfs --fdm=null "), "{line_}");
        assert!(
            line_.contains(r#"setprop("/sim/current-view/view-number", 0);"#),
            "{line_}"
        );
        let line_ = line(&["bourg", "--view", "helicopter", "--fgfs", "/opt/my fg/fgfs"]);
        assert!(line_.starts_with("'/opt/my fg/fgfs' --fdm"), "{line_}");
        assert!(line_.contains(r#"view-number", 1);"#), "{line_}");
    }

    #[test]
    fn multiplayer_input_keeps_ai_models_on() {
        let plain = line(&["palmer"]);
        let mp = line(&["palmer", "--fg-mp", "5000"]);
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
        assert!(line(&["palmer", "--fg-mp", "32766"]).contains("out,10,127.0.0.1,32767 "));
        assert_eq!(fdm_run::values::parse_mp_port("32766"), Ok(32766));
        for bad in ["0", "32767", "35606", "65535", "x"] {
            assert!(fdm_run::values::parse_mp_port(bad).is_err(), "{bad}");
        }
        assert!(fdm_run::values::parse_mp_port("35606")
            .unwrap_err()
            .to_string()
            .contains("signed 16-bit"));
    }

    #[test]
    fn named_origins_start_on_their_runway() {
        let cmd = line(&["palmer", "--origin", "phli"]);
        // 26.94 m = 88.4 ft.
        assert!(
            cmd.contains("--lat=21.963792 --lon=-159.335883 --altitude=88.4 "),
            "{cmd}"
        );
    }

    /// A start the model refuses is a usage error naming the option.
    #[test]
    fn a_refused_start_is_a_usage_error() {
        let err = fgfs_command_line(&args(&["palmer", "--trim"])).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert_eq!(
            err.to_string(),
            "--trim: cannot trim on the ground; give --altitude-ft above 0"
        );
    }
}
