//! The one error type of `sim-cli` and its mapping to exit statuses (docs/cli.md "Exit status").

use std::fmt;

/// Everything that can stop `sim-cli`, split by who is to blame, because the exit
/// status tells scripts whether retrying with other arguments can help.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad arguments or a bad input file (unreadable script, bad script line,
    /// CSV path that cannot be created, ...). Exit status 2; nothing has run.
    #[error("{0}")]
    Usage(String),
    /// Anything that went wrong after the input was accepted. Exit status 1.
    /// The `anyhow` context chain on one line (`outer: inner`,
    /// [`fdm_run::output::error_text`]: a cause already at the end is not
    /// repeated).
    #[error("{}", fdm_run::output::error_text(.0.as_ref()))]
    Runtime(anyhow::Error),
    /// The input was incomplete but what it held was used to the end: a
    /// recording cut before its end marker, replayed up to the cut. Exit
    /// status 3; every output is complete for what was replayed.
    #[error("{0}")]
    Incomplete(String),
    /// A replay flew another flight than the recorded one: its final state's
    /// fingerprint differs from the one the recording carries (other maths,
    /// another build, a machine whose bits differ). Exit status 4; every
    /// output of the replay is complete, but it is not the recorded flight.
    #[error("{0}")]
    DifferentFlight(String),
}

impl CliError {
    /// A usage error (exit status 2) with the given one-line message.
    pub fn usage(message: impl fmt::Display) -> Self {
        Self::Usage(message.to_string())
    }

    /// A runtime error (exit status 1) with the given message.
    pub fn runtime(message: impl fmt::Display) -> Self {
        Self::Runtime(anyhow::anyhow!("{message}"))
    }

    /// The process exit status for this error: 2 for usage, 1 for runtime,
    /// 3 for an incomplete input used to its end, 4 for a different flight.
    #[must_use]
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Usage(_) => 2,
            Self::Runtime(_) => 1,
            Self::Incomplete(_) => 3,
            Self::DifferentFlight(_) => 4,
        }
    }

    /// The message squeezed onto one line, because the contract promises one line
    /// on stderr and OS or library messages occasionally contain newlines.
    #[must_use]
    pub fn one_line(&self) -> String {
        one_line(&self.to_string())
    }
}

impl From<anyhow::Error> for CliError {
    fn from(error: anyhow::Error) -> Self {
        Self::Runtime(error)
    }
}

impl From<fgnet::address::FgAddressError> for CliError {
    /// A FlightGear address that does not resolve is a usage error.
    fn from(e: fgnet::address::FgAddressError) -> Self {
        Self::usage(e)
    }
}

/// Joins the non-empty lines of `text` with single spaces.
#[must_use]
pub fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_exit_status_is_in_the_help() {
        use clap::CommandFactory;
        let help = crate::args::Cli::command().render_long_help().to_string();
        let line = &help[help.find("Exit status:").expect("an exit-status line")..];
        let statuses = [
            CliError::usage("x"),
            CliError::runtime("x"),
            CliError::Incomplete("x".to_owned()),
            CliError::DifferentFlight("x".to_owned()),
        ]
        .map(|e| e.exit_code());
        for status in [0, 128].into_iter().chain(statuses) {
            assert!(
                line.contains(&format!(" {status}")),
                "{status} missing from: {line}"
            );
        }
    }

    #[test]
    fn exit_codes() {
        assert_eq!(CliError::usage("x").exit_code(), 2);
        assert_eq!(CliError::runtime("x").exit_code(), 1);
        assert_eq!(CliError::Incomplete("x".to_owned()).exit_code(), 3);
        assert_eq!(CliError::DifferentFlight("x".to_owned()).exit_code(), 4);
    }

    #[test]
    fn runtime_context_chain_is_one_line() {
        let e: CliError = anyhow::anyhow!("inner\nreason")
            .context("writing out.csv")
            .into();
        assert_eq!(e.one_line(), "writing out.csv: inner reason");
    }

    /// `sim-cli palmer --headless --acmi /dev/full` printed "writing the ACMI
    /// file: No space left on device (os error 28): No space left on device
    /// (os error 28)": the ACMI error prints its source and returns it.
    #[test]
    fn a_cause_the_message_already_ends_with_is_not_repeated() {
        let full = std::io::Error::other("No space left on device (os error 28)");
        let e: CliError = anyhow::Error::from(fdm_run::acmi::AcmiError::Io(full)).into();
        assert_eq!(
            e.one_line(),
            "writing the ACMI file: No space left on device (os error 28)"
        );
        let e: CliError = anyhow::Error::from(fdm_run::acmi::AcmiError::Io(std::io::Error::other(
            "disk full",
        )))
        .context("finishing out.acmi")
        .into();
        assert_eq!(
            e.one_line(),
            "finishing out.acmi: writing the ACMI file: disk full"
        );
        // Causes that add something are all kept, in order.
        let e: CliError = anyhow::anyhow!("c").context("b").context("a").into();
        assert_eq!(e.one_line(), "a: b: c");
    }
}
