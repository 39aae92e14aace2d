//! The Python package's test suite, run by `cargo test --workspace` (the
//! README's test command), so that a fresh clone's two commands cover it too.
//!
//! One test, in order:
//! 1. a pinned virtualenv (maturin, NumPy, pytest, Hypothesis, Gymnasium,
//!    mypy for `tests/test_typing.py`),
//!    built once per target directory like the interop tests' ([`PythonEnv`]);
//! 2. `pip install` of this directory into it: the one command a user runs
//!    from a clone, building the extension in release with maturin (in its
//!    own target directory under the test's `CARGO_TARGET_TMPDIR`, kept
//!    between runs);
//! 3. `pytest` on `tests/` (warnings are errors: `pyproject.toml`), with
//!    `AFIT_FDM_SIM_CLI` naming a debug `sim-cli` built from this checkout
//!    (in the test's own target directory: [`common::sim_cli`]), for the
//!    bit-for-bit comparisons, and `ACMI_PYTHON` and
//!    `DIS_PYTHON` and `FGNET_PYTHON` the interop tests' pinned Pythons with
//!    the independent readers (pyacmi, Open-DIS, flightgear-python:
//!    `fdm_tests::python`) for `test_outputs.py`.
//!
//! `AFIT_FDM_PYTHON` can name a ready Python that has the pinned packages
//! (the package is still installed into it). Nothing is skipped: a missing
//! Python, PyPI or Rust toolchain fails the test with what to do.
//!
//! An ignored second test, [`warm_up_for_ci`], does steps 1 and 2 alone
//! (and builds the interop tests' virtualenvs): `.ci/run` runs it in the
//! background beside the steps before the tests step, so that the tests
//! step finds the wheel's release build done (`docs/testing.md`, "CI time").

use std::path::Path;

use fdm_tests::python::{PythonEnv, FGPY, OPENDIS, PYACMI};

mod common;

/// The suite's pinned environment.
const SUITE: PythonEnv = PythonEnv {
    name: "afit-fdm-suite-2",
    override_var: "AFIT_FDM_PYTHON",
    packages: &[
        "maturin==1.16.0",
        "numpy==2.4.6",
        "pytest==9.2.0",
        "hypothesis==6.170.17",
        "gymnasium==1.4.0",
        "mypy==2.4.1",
    ],
    distribution: "maturin",
    version: "1.16.0",
    imports: &["numpy", "pytest", "hypothesis", "gymnasium", "mypy"],
};

#[test]
fn python_package_installs_and_its_suite_passes() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let (python, path) = common::installed(&SUITE, tmp);
    let sim_cli = common::sim_cli();
    let acmi_python = PYACMI.ready(tmp);
    let dis_python = OPENDIS.ready(tmp);
    let fgnet_python = FGPY.ready(tmp);
    common::pytest(
        &python,
        &path,
        &sim_cli,
        &[
            ("ACMI_PYTHON", acmi_python.as_path()),
            ("DIS_PYTHON", dis_python.as_path()),
            ("FGNET_PYTHON", fgnet_python.as_path()),
        ],
        &["tests"],
    );
}

/// Steps 1 and 2 of [`python_package_installs_and_its_suite_passes`] and
/// the interop tests' virtualenvs, nothing tested: what `.ci/run` starts in
/// the background (`--ignored --exact warm_up_for_ci`), so that its work
/// (about 450 s of the tests step, which keeps about 1.3 of the 2 cores
/// busy) is done beside the steps before the tests step. The suite itself
/// still runs `pip install` (the command a user runs): it finds the build
/// up to date in the same directory and packs the wheel.
#[test]
#[ignore = "CI's warm-up (.ci/run): the suite's virtualenvs and the wheel's release build, nothing tested"]
fn warm_up_for_ci() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let _ = common::installed(&SUITE, tmp);
    for env in [PYACMI, OPENDIS, FGPY] {
        let _ = env.ready(tmp);
    }
}
