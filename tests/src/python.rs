//! Independent decoders in Python for the interop tests: a pinned virtualenv
//! built once per target directory, and Python scripts run as child
//! processes that talk over stdin/stdout.
//!
//! A test names its environment with a [`PythonEnv`] (packages pinned by
//! version, the module whose version proves the install, an environment
//! variable that can point at a ready Python instead). [`PythonEnv::python`]
//! builds the venv under the test's `CARGO_TARGET_TMPDIR` with `python3 -m
//! venv` and `pip install` the first time, in a private directory renamed into
//! place (an interrupted or concurrent setup never leaves a half-made venv in
//! use). When that is impossible the error says why; the tests fail with it,
//! they never skip.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::Mutex;

/// Open-DIS for Python (PyPI `opendis` 1.0) and the numpy it works with,
/// pinned: the independent DIS decoder of fdm-dis's and sim-cli's interop
/// tests (one venv for both). `$DIS_PYTHON` can name a ready Python.
pub const OPENDIS: PythonEnv = PythonEnv {
    name: "opendis-1.0",
    override_var: "DIS_PYTHON",
    packages: &["opendis==1.0", "numpy==1.26.4"],
    distribution: "opendis",
    version: "1.0",
    imports: &["opendis"],
};

/// The Python scripts of the DIS interop tests (`decode_udp.py` receives
/// datagrams on 127.0.0.1 and prints what opendis decodes, with its own
/// geodetic and roll/pitch/yaw conversions; `build_udp.py` builds and sends
/// PDUs with opendis).
pub const OPENDIS_SCRIPT_DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fdm-dis/tests/opendis_interop"
);

/// flightgear-python (PyPI `flightgear-python` 2.1.0) and its construct,
/// pinned: the independent FGNetFDM decoder of fgnet's interop tests and of
/// the Python package's `Flight.flightgear_to` test. `$FGNET_PYTHON` can
/// name a ready Python.
pub const FGPY: PythonEnv = PythonEnv {
    name: "fgpy-2.1.0",
    override_var: "FGNET_PYTHON",
    packages: &["flightgear-python==2.1.0", "construct==2.10.70"],
    distribution: "flightgear-python",
    version: "2.1.0",
    imports: &["flightgear_python.fdm_v24", "flightgear_python.fg_if"],
};

/// pyacmi (PyPI `pyacmi` 1.2.4, a Tacview ACMI parser) and what it imports,
/// pinned (`constantly` is imported by pyacmi without being declared as its
/// dependency): the independent ACMI reader of fdm-run's and sim-cli's
/// `--acmi` tests. `$ACMI_PYTHON` can name a ready Python.
pub const PYACMI: PythonEnv = PythonEnv {
    name: "pyacmi-1.2.4",
    override_var: "ACMI_PYTHON",
    packages: &[
        "pyacmi==1.2.4",
        "constantly==23.10.4",
        "sortedcontainers==2.4.0",
        "tqdm==4.67.1",
    ],
    distribution: "pyacmi",
    version: "1.2.4",
    imports: &["pyacmi"],
};

/// The ACMI reader script (`read_acmi.py`: every object's track, frame by
/// frame, as pyacmi reads it).
pub const PYACMI_SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fdm-run/tests/acmi_interop/read_acmi.py"
);

/// A pinned Python environment for one interop test suite.
#[derive(Debug, Clone, Copy)]
pub struct PythonEnv {
    /// Short name, used for the venv directory (e.g. `"fgpy-2.1.0"`).
    pub name: &'static str,
    /// Environment variable naming a ready Python to use instead.
    pub override_var: &'static str,
    /// `pip install` arguments, pinned (`"package==version"`).
    pub packages: &'static [&'static str],
    /// The distribution whose installed version proves the environment.
    pub distribution: &'static str,
    /// Its pinned version.
    pub version: &'static str,
    /// Modules the tests import (checked at setup).
    pub imports: &'static [&'static str],
}

impl PythonEnv {
    /// The Python to run, building the venv under `cache_dir` (the test's
    /// `CARGO_TARGET_TMPDIR`) on first use.
    ///
    /// # Errors
    /// Why no such Python can be had (no `python3`, no venv module, no PyPI,
    /// a wrong version behind the override variable), with what to do.
    pub fn python(&self, cache_dir: &Path) -> Result<PathBuf, String> {
        if let Some(p) = std::env::var_os(self.override_var) {
            let p = PathBuf::from(p);
            self.check(&p)
                .map_err(|e| format!("{}={}: {e}", self.override_var, p.display()))?;
            return Ok(p);
        }
        let venv = cache_dir.join(format!("{}-venv", self.name));
        let marker = ".interop-ready";
        let ready = |dir: &Path| dir.join(marker).exists();
        let venv_python = venv.join("bin").join("python");
        if ready(&venv) && self.check(&venv_python).is_ok() {
            return Ok(venv_python);
        }
        std::fs::create_dir_all(cache_dir).map_err(|e| format!("{}: {e}", cache_dir.display()))?;
        let tmp = cache_dir.join(format!("{}-venv.tmp-{}", self.name, std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        run(
            Command::new("python3").arg("-m").arg("venv").arg(&tmp),
            "python3 -m venv",
        )?;
        let tmp_python = tmp.join("bin").join("python");
        let mut pip = Command::new(&tmp_python);
        pip.args([
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--no-input",
            "--quiet",
        ])
        .args(self.packages);
        run(&mut pip, "pip install")?;
        self.check(&tmp_python)?;
        std::fs::write(tmp.join(marker), self.version).map_err(|e| e.to_string())?;
        if !ready(&venv) {
            let _ = std::fs::remove_dir_all(&venv);
        }
        if std::fs::rename(&tmp, &venv).is_err() {
            // Another process finished first; use its venv.
            let _ = std::fs::remove_dir_all(&tmp);
        }
        self.check(&venv_python)?;
        Ok(venv_python)
    }

    /// [`python`](Self::python), set up once per test process and
    /// environment (tests running in parallel wait for the first setup
    /// rather than building the venv twice).
    ///
    /// # Panics
    /// When no such Python can be had: a test failure saying why and what to
    /// do.
    #[must_use]
    pub fn ready(&self, cache_dir: &Path) -> PathBuf {
        static READY: Mutex<Vec<(&str, Result<PathBuf, String>)>> = Mutex::new(Vec::new());
        let mut ready = READY
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let found = match ready.iter().find(|(name, _)| *name == self.name) {
            Some((_, found)) => found.clone(),
            None => {
                let found = self.python(cache_dir);
                ready.push((self.name, found.clone()));
                found
            }
        };
        found.unwrap_or_else(|e| {
            panic!(
                "these interop tests need Python with {}=={}:\n{e}\n\
                 Install python3 (with the venv module and access to PyPI), or set {} to a \
                 Python that has it.",
                self.distribution, self.version, self.override_var
            )
        })
    }

    /// Checks that `python` imports the modules and has the pinned version.
    fn check(&self, python: &Path) -> Result<(), String> {
        let imports = self.imports.join(", ");
        let code = format!(
            "import importlib.metadata as m, {imports}; print(m.version('{}'))",
            self.distribution
        );
        let out = Command::new(python)
            .args(["-c", &code])
            .output()
            .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
        if !out.status.success() {
            return Err(format!(
                "{} cannot import {imports}: {}",
                python.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        let version = String::from_utf8_lossy(&out.stdout).trim().to_owned();
        if version != self.version {
            return Err(format!(
                "{} has {} {version}, these tests pin {}",
                python.display(),
                self.distribution,
                self.version
            ));
        }
        Ok(())
    }
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

/// A Python script the test started, talking line by line on stdout; killed
/// if the test panics.
#[derive(Debug)]
pub struct PyScript {
    child: Child,
    stdout: BufReader<ChildStdout>,
    name: String,
}

impl PyScript {
    /// Starts `script` with `python` and `args`, stdin, stdout and stderr piped.
    ///
    /// # Panics
    /// If the process cannot be started (a test failure).
    #[must_use]
    pub fn start(python: &Path, script: &Path, args: &[String]) -> Self {
        let name = script.display().to_string();
        let mut child = Command::new(python)
            .arg(script)
            .args(args)
            .env("PYTHONDONTWRITEBYTECODE", "1")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {name}: {e}"));
        let stdout = BufReader::new(child.stdout.take().expect("stdout"));
        Self {
            child,
            stdout,
            name,
        }
    }

    /// Kills the script and returns what it wrote on stderr.
    pub fn stderr(&mut self) -> String {
        let _ = self.child.kill();
        let mut s = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut s);
        }
        s
    }

    /// The script's next stdout line, without its line end.
    ///
    /// # Panics
    /// If the script ended first (with its stderr in the message).
    pub fn line(&mut self) -> String {
        let mut line = String::new();
        match self.stdout.read_line(&mut line) {
            Ok(n) if n > 0 => line.trim_end().to_owned(),
            _ => {
                let err = self.stderr();
                panic!("{} ended early; stderr:\n{err}", self.name)
            }
        }
    }

    /// Reads a `PORT n` line: the UDP port the script bound.
    ///
    /// # Panics
    /// If the line is something else.
    pub fn port(&mut self) -> u16 {
        let line = self.line();
        line.strip_prefix("PORT ")
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("{}: expected 'PORT n', got {line:?}", self.name))
    }

    /// Closes the script's stdin (its signal to finish).
    pub fn close_stdin(&mut self) {
        drop(self.child.stdin.take());
    }

    /// The script's stdin, to send it lines.
    pub fn stdin(&mut self) -> Option<&mut std::process::ChildStdin> {
        self.child.stdin.as_mut()
    }

    /// Closes stdin and waits for a successful exit.
    ///
    /// # Panics
    /// If the script fails (with its stderr in the message).
    pub fn finish(mut self) {
        self.close_stdin();
        let status = self.child.wait().expect("wait");
        if !status.success() {
            let err = self.stderr();
            panic!("{} exited with {status}; stderr:\n{err}", self.name);
        }
    }
}

impl Drop for PyScript {
    fn drop(&mut self) {
        if std::thread::panicking() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
