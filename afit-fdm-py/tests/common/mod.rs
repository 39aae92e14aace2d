//! What the Python suites share: installing this directory into a pinned
//! virtualenv and building the `sim-cli` the comparisons run.

use std::path::{Path, PathBuf};
use std::process::Command;

use fdm_tests::python::PythonEnv;

/// This crate's directory (the Python package's project).
pub const CRATE_DIR: &str = env!("CARGO_MANIFEST_DIR");

/// A `sim-cli` built from this checkout, in the target directory this test
/// runs from (the parent of `CARGO_TARGET_TMPDIR`), by what the README's test
/// command builds (`cargo test --workspace --no-run`; cargo holds no lock on
/// the directory while tests run). Run from that command, everything is
/// built already and this only checks it. A build of `sim-cli` alone
/// (`cargo build -p afit-fdm-cli`) resolves other features for the crates it
/// shares with the tests (the tests' dev-dependencies turn some on), so it
/// compiled 31 crates again; a build of its own directory compiled all of
/// them again. Run alone, this suite builds the workspace's tests first.
///
/// A debug build: the comparisons fly a few thousand frames at most. The
/// wheel is a release build, so every bit-for-bit comparison of the suite
/// also checks that the debug and release builds fly the same bits.
pub fn sim_cli() -> PathBuf {
    let target_dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR is inside the target directory");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let status = Command::new(cargo)
        .args(["test", "-q", "--workspace", "--no-run"])
        .current_dir(CRATE_DIR)
        .env("CARGO_TARGET_DIR", target_dir)
        .status()
        .expect("cannot run cargo to build sim-cli");
    assert!(status.success(), "cargo test --workspace --no-run failed");
    let sim_cli = target_dir
        .join("debug")
        .join(format!("sim-cli{}", std::env::consts::EXE_SUFFIX));
    assert!(sim_cli.is_file(), "no sim-cli at {}", sim_cli.display());
    sim_cli
}

/// `PATH` with the virtualenv's `bin` first.
pub fn with_path(venv_bin: &Path) -> std::ffi::OsString {
    let mut paths = vec![venv_bin.to_path_buf()];
    if let Some(p) = std::env::var_os("PATH") {
        paths.extend(std::env::split_paths(&p));
    }
    std::env::join_paths(paths).expect("PATH")
}

/// `pip install` of this directory into `python`'s virtualenv: the one
/// command a user runs from a clone, building the extension in release with
/// maturin in `build_dir`.
pub fn install(python: &Path, path: &std::ffi::OsStr, build_dir: &Path) {
    let out = Command::new(python)
        .args([
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--no-input",
            "--quiet",
            "--no-build-isolation",
            "--no-deps",
            "--force-reinstall",
            CRATE_DIR,
        ])
        .env("PATH", path)
        .env("CARGO_TARGET_DIR", build_dir)
        .output()
        .expect("cannot run pip");
    assert!(
        out.status.success(),
        "pip install {CRATE_DIR} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `env`'s pinned virtualenv (built once per target directory, under
/// `tmp`), with this directory installed into it ([`install`], building in
/// `tmp/afit-fdm-py-build`, which the suites share): its Python and the
/// `PATH` with its `bin` first.
pub fn installed(env: &PythonEnv, tmp: &Path) -> (PathBuf, std::ffi::OsString) {
    let python = env.ready(tmp);
    let bin = python.parent().expect("venv bin").to_path_buf();
    let path = with_path(&bin);
    install(&python, &path, &tmp.join("afit-fdm-py-build"));
    (python, path)
}

/// `pytest -q ARGS` in this directory with `AFIT_FDM_SIM_CLI` and `env`
/// set; fails the test when pytest does.
pub fn pytest(
    python: &Path,
    path: &std::ffi::OsStr,
    sim_cli: &Path,
    env: &[(&str, &Path)],
    args: &[&str],
) {
    let out = Command::new(python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .args(args)
        .current_dir(CRATE_DIR)
        .env("PATH", path)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .env("AFIT_FDM_SIM_CLI", sim_cli)
        .envs(env.iter().copied())
        .output()
        .expect("cannot run pytest");
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "pytest failed:\n{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
