//! `--acmi FILE`: the Tacview ACMI writer of the run library
//! ([`fdm_run::acmi`]), created before the run like the CSV, so that an
//! unwritable path is a usage error (exit status 2) before anything flies.

use std::path::Path;

use fdm_core::geodesy::GeodeticOrigin;
use fdm_run::acmi::{AcmiHeader, AcmiWriter};

use crate::args::AcmiArgs;
use crate::error::CliError;
use crate::input::show_path;

/// The ACMI writer for `--acmi` (`None` without it) with
/// `--acmi-reference-time` (default
/// [`fdm_run::acmi::DEFAULT_REFERENCE_TIME`]): `title` and the run's `fps`
/// and `origin` go into the header. `others` are the run's other files with
/// their option names; none may be the ACMI file.
///
/// # Errors
/// [`CliError::Usage`]: the file is one of `others`, or cannot be created.
pub fn create(
    args: &AcmiArgs,
    title: &str,
    fps: u32,
    origin: &GeodeticOrigin,
    others: &[(Option<&Path>, &str)],
) -> Result<Option<AcmiWriter>, CliError> {
    let Some(path) = args.acmi.as_deref() else {
        return Ok(None);
    };
    crate::input::refuse_clash(path, others, |name| {
        format!("--acmi {} is also the {name} file", show_path(path))
    })?;
    let header = AcmiHeader {
        reference_time: args.acmi_reference_time.clone().unwrap_or_default(),
        title: title.to_owned(),
        origin: origin.geodetic(),
    };
    AcmiWriter::create(path, &header, fps)
        .map(Some)
        .map_err(|e| CliError::usage(format!("cannot create ACMI file {}: {e}", show_path(path))))
}
