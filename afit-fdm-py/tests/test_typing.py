"""The package's types, checked by mypy (pinned in the suite's virtualenv):
its sources, stubs and examples type-check in strict mode (``pyproject.toml``,
``[tool.mypy]``), and mypy's ``stubtest`` finds the shipped stubs of the
extension module (``_afit_fdm.pyi``) to be what the built module has: every
class, function, method and parameter, their kinds and defaults, and nothing
the module has left out of the stubs."""

from __future__ import annotations

import pathlib
import subprocess
import sys
from typing import List

from conftest import REPO

PACKAGE = REPO / "afit-fdm-py"


def run(args: List[str], cwd: pathlib.Path) -> subprocess.CompletedProcess[str]:
    """``python -m ARGS`` (mypy or its stubtest) in ``cwd``."""
    return subprocess.run(
        [sys.executable, "-m", *args], cwd=cwd, capture_output=True, text=True, timeout=600
    )


def test_the_package_and_its_examples_type_check_strictly(tmp_path: pathlib.Path) -> None:
    # In the package's directory (its pyproject.toml's [tool.mypy]), with the
    # cache in the test's own directory, not in the checkout.
    result = run(["mypy", "--cache-dir", str(tmp_path), "python/afit_fdm", "examples"], PACKAGE)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.startswith("Success: no issues found"), result.stdout


def test_the_stubs_are_what_the_extension_module_has(tmp_path: pathlib.Path) -> None:
    # From an empty directory: the installed package's module and its
    # shipped stubs, not the checkout's.
    result = run(["mypy.stubtest", "afit_fdm._afit_fdm"], tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success: no issues found in 1 module" in result.stdout, result.stdout
