//! Open-DIS for Python (the PyPI package `opendis`), the independent DIS
//! decoder the interop tests check our PDUs against: a Python that imports
//! it, made once per target directory.
//!
//! Python: `$DIS_PYTHON` if set (it must import opendis [`OPENDIS_VERSION`]);
//! otherwise a virtualenv made once under the caller's `base` directory
//! (tests pass their `CARGO_TARGET_TMPDIR`, so every test crate of the
//! workspace shares one) with `python3 -m venv` and
//! `pip install opendis==1.0 numpy==1.26.4`. If that is not possible the
//! error says why; callers fail with it (they never skip).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The opendis release the tests pin.
pub const OPENDIS_VERSION: &str = "1.0";
/// numpy pinned with it (opendis 1.0 requires >=1.26.4,<2).
pub const NUMPY_VERSION: &str = "1.26.4";

/// The Python helper scripts of the interop tests (`decode_udp.py`:
/// receive datagrams on 127.0.0.1 and print what opendis decodes, with its
/// own geodetic and roll/pitch/yaw conversions; `build_udp.py`: build and
/// send PDUs with opendis).
pub const SCRIPT_DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fdm-dis/tests/opendis_interop"
);

/// Checks that `python` imports opendis [`OPENDIS_VERSION`].
///
/// # Errors
/// Why not, in words.
pub fn check_python(python: &Path) -> Result<(), String> {
    let out = Command::new(python)
        .args([
            "-c",
            "import importlib.metadata as m, opendis.PduFactory, opendis.RangeCoordinates; \
             print(m.version('opendis'))",
        ])
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} cannot import opendis: {}",
            python.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let version = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    if version != OPENDIS_VERSION {
        return Err(format!(
            "{} has opendis {version}, these tests pin {OPENDIS_VERSION}",
            python.display()
        ));
    }
    Ok(())
}

fn run(cmd: &mut Command, what: &str) -> Result<(), String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot start {cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{what} failed ({}):\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// A Python with opendis: `$DIS_PYTHON`, or the virtualenv under `base`
/// (made if missing; built in a private directory and renamed into place,
/// so an interrupted or concurrent setup never leaves a half-made venv in
/// use).
///
/// # Errors
/// Why no such Python can be had.
pub fn python(base: &Path) -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("DIS_PYTHON") {
        let p = PathBuf::from(p);
        check_python(&p).map_err(|e| format!("DIS_PYTHON={}: {e}", p.display()))?;
        return Ok(p);
    }
    let name = format!("opendis-venv-{OPENDIS_VERSION}");
    let venv = base.join(&name);
    let ready = |dir: &Path| dir.join(".opendis-ready").exists();
    let venv_python = venv.join("bin").join("python");
    if ready(&venv) && check_python(&venv_python).is_ok() {
        return Ok(venv_python);
    }
    std::fs::create_dir_all(base).map_err(|e| format!("{}: {e}", base.display()))?;
    let tmp = base.join(format!("{name}.tmp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    run(
        Command::new("python3").arg("-m").arg("venv").arg(&tmp),
        "python3 -m venv",
    )?;
    let tmp_python = tmp.join("bin").join("python");
    run(
        Command::new(&tmp_python).args([
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--no-input",
            "--quiet",
            &format!("opendis=={OPENDIS_VERSION}"),
            &format!("numpy=={NUMPY_VERSION}"),
        ]),
        "pip install opendis",
    )?;
    check_python(&tmp_python)?;
    std::fs::write(tmp.join(".opendis-ready"), OPENDIS_VERSION).map_err(|e| e.to_string())?;
    if !ready(&venv) {
        let _ = std::fs::remove_dir_all(&venv);
    }
    if std::fs::rename(&tmp, &venv).is_err() {
        // Another process finished first; use its venv.
        let _ = std::fs::remove_dir_all(&tmp);
    }
    check_python(&venv_python)?;
    Ok(venv_python)
}
