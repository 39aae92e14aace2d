"""Shared fixtures: the repository's reference cases and the ``sim-cli`` binary.

``AFIT_FDM_SIM_CLI`` names the binary (the Rust runner ``python_suite.rs`` sets
it); without it the suite looks in ``$CARGO_TARGET_DIR`` or the repository's
``target/`` (debug, then release). The comparison tests fail, never skip, when
it cannot be found.
"""

from __future__ import annotations

import csv
import io
import json
import os
import pathlib
import subprocess
from typing import Dict, List, Sequence

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def _find_sim_cli() -> pathlib.Path:
    given = os.environ.get("AFIT_FDM_SIM_CLI")
    if given:
        return pathlib.Path(given)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("debug", "release"):
        candidate = target / profile / "sim-cli"
        if candidate.exists():
            return candidate
    raise FileNotFoundError(
        "sim-cli not found: build it (cargo build -p afit-fdm-cli) or set AFIT_FDM_SIM_CLI"
    )


@pytest.fixture(scope="session")
def sim_cli() -> pathlib.Path:
    return _find_sim_cli()


def reference(name: str) -> dict:
    with open(REPO / "reference" / name, encoding="utf-8") as f:
        return json.load(f)


def csv_rows(text: str, model: str) -> List[Dict[str, str]]:
    """A flight CSV's rows by column name. Its first line must be the model
    line ``# model: MODEL`` (docs/cli.md, "CSV output"); the header follows."""
    first, _, body = text.partition("\n")
    assert first == f"# model: {model}", first
    assert body.startswith("frame,time_s,"), body[:80]
    return list(csv.DictReader(io.StringIO(body)))


def run_csv(sim_cli: pathlib.Path, args: Sequence[str], tmp: pathlib.Path) -> List[Dict[str, float]]:
    """Runs ``sim-cli ARGS --headless --csv FILE`` (``ARGS[0]`` the model) and
    returns its rows, every number parsed with ``float`` (``sim-cli`` prints
    the shortest form that round-trips, so ``float`` recovers the exact
    bits)."""
    out = tmp / "run.csv"
    proc = subprocess.run(
        [str(sim_cli), *args, "--headless", "--csv", str(out)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, f"{sim_cli} {' '.join(args)}: exit {proc.returncode}: {proc.stderr}"
    text = out.read_text(encoding="utf-8")
    return [{k: float(v) for k, v in row.items()} for row in csv_rows(text, args[0])]


# No example database in the source tree: every run draws afresh (and the
# failing example is printed in the report).
from hypothesis import settings as _settings  # noqa: E402

_settings.register_profile("afit_fdm", database=None)
_settings.load_profile("afit_fdm")
