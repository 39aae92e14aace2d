//! The Python package on a real Ray cluster (`tests_ray/`), run by `cargo
//! test --workspace` like the main suite (`python_suite.rs`), in its own
//! pinned virtualenv: Ray is a large install (about 400 MB) that the main
//! suite does not need, and a separate environment is built once per target
//! directory and kept.
//!
//! The test installs this directory into the environment (maturin, release,
//! in the same build directory as the main suite, so the two share the
//! build), then runs `pytest tests_ray`: a two-node Ray cluster started on
//! this machine by the test itself (`ray.cluster_utils.Cluster`), studies
//! split into shards over both nodes, and a node killed mid-study.
//! `AFIT_FDM_RAY_PYTHON` can name a ready Python with the pinned packages.

use std::path::Path;

use fdm_tests::python::PythonEnv;

mod common;

/// The Ray suite's pinned environment.
const RAY_SUITE: PythonEnv = PythonEnv {
    name: "afit-fdm-ray-1",
    override_var: "AFIT_FDM_RAY_PYTHON",
    packages: &[
        "maturin==1.16.0",
        "numpy==2.4.6",
        "pytest==9.2.0",
        "hypothesis==6.170.17",
        "ray==2.60.0",
    ],
    distribution: "ray",
    version: "2.60.0",
    imports: &["numpy", "pytest", "ray"],
};

#[test]
fn python_package_studies_on_a_two_node_ray_cluster() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let (python, path) = common::installed(&RAY_SUITE, tmp);
    let sim_cli = common::sim_cli();
    common::pytest(&python, &path, &sim_cli, &[], &["-s", "tests_ray"]);
}

/// The Ray suite's virtualenv alone, nothing tested: `.ci/run` builds it in
/// the background (`--ignored --exact warm_up_for_ci`) with the main suite's
/// warm-up, so the tests step does not wait for Ray's download.
#[test]
#[ignore = "CI's warm-up (.ci/run): the Ray suite's virtualenv, nothing tested"]
fn warm_up_for_ci() {
    let _ = RAY_SUITE.ready(Path::new(env!("CARGO_TARGET_TMPDIR")));
}
