//! The Python package's test suite, run by `cargo test --workspace` (the
//! README's test command), so that a fresh clone's two commands cover it too.
//!
//! One test, in order:
//! 1. a pinned virtualenv (maturin, NumPy, pytest, Hypothesis, Gymnasium),
//!    built once per target directory like the interop tests' ([`PythonEnv`]);
//! 2. `pip install` of this directory into it: the one command a user runs
//!    from a clone, building the extension in release with maturin (in its
//!    own target directory under the test's `CARGO_TARGET_TMPDIR`, so it
//!    never waits for the cargo that runs this test);
//! 3. `pytest` on `tests/` (warnings are errors: `pyproject.toml`), with
//!    `AFIT_FDM_SIM_CLI` naming a `sim-cli` built from this checkout (in the
//!    same directory), for the bit-for-bit comparisons.
//!
//! `AFIT_FDM_PYTHON` can name a ready Python that has the pinned packages
//! (the package is still installed into it). Nothing is skipped: a missing
//! Python, PyPI or Rust toolchain fails the test with what to do.

use std::path::{Path, PathBuf};
use std::process::Command;

use fdm_tests::python::PythonEnv;

/// The suite's pinned environment.
const SUITE: PythonEnv = PythonEnv {
    name: "afit-fdm-suite-1",
    override_var: "AFIT_FDM_PYTHON",
    packages: &[
        "maturin==1.16.0",
        "numpy==2.4.6",
        "pytest==9.2.0",
        "hypothesis==6.170.17",
        "gymnasium==1.4.0",
    ],
    distribution: "maturin",
    version: "1.16.0",
    imports: &["numpy", "pytest", "hypothesis", "gymnasium"],
};

const CRATE_DIR: &str = env!("CARGO_MANIFEST_DIR");

/// A `sim-cli` built from this checkout, in `build_dir` (not the one next to
/// this test's executable: a shared target directory may hold another
/// checkout's).
fn sim_cli(build_dir: &Path) -> PathBuf {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let status = Command::new(cargo)
        // Release, in the directory maturin built the extension in: the two
        // builds share their dependencies. (The package is `afit-fdm-cli`.)
        .args([
            "build",
            "-q",
            "--release",
            "-p",
            "afit-fdm-cli",
            "--bin",
            "sim-cli",
        ])
        .current_dir(CRATE_DIR)
        .env("CARGO_TARGET_DIR", build_dir)
        .status()
        .expect("cannot run cargo to build sim-cli");
    assert!(status.success(), "cargo build -p afit-fdm-cli failed");
    build_dir.join("release").join("sim-cli")
}

fn with_path(venv_bin: &Path) -> std::ffi::OsString {
    let mut paths = vec![venv_bin.to_path_buf()];
    if let Some(p) = std::env::var_os("PATH") {
        paths.extend(std::env::split_paths(&p));
    }
    std::env::join_paths(paths).expect("PATH")
}

#[test]
fn python_package_installs_and_its_suite_passes() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let python = SUITE.ready(tmp);
    let bin = python.parent().expect("venv bin").to_path_buf();
    let build_dir = tmp.join("afit-fdm-py-build");
    let path = with_path(&bin);

    let out = Command::new(&python)
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
        .env("PATH", &path)
        .env("CARGO_TARGET_DIR", &build_dir)
        .output()
        .expect("cannot run pip");
    assert!(
        out.status.success(),
        "pip install {CRATE_DIR} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );

    let sim_cli = sim_cli(&build_dir);
    let out = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider", "tests"])
        .current_dir(CRATE_DIR)
        .env("PATH", &path)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .env("AFIT_FDM_SIM_CLI", &sim_cli)
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
