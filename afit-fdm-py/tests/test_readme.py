"""The README's Python example runs as written (so it cannot go stale)."""

from __future__ import annotations

import re

from conftest import REPO


def test_readme_python_example_runs(capsys) -> None:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## From Python"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    exec(compile(code, "README.md", "exec"), {})  # noqa: S102
    out = capsys.readouterr().out.split("\n")
    assert out[0].endswith("airborne")


def test_the_extension_is_built_for_the_stable_abi() -> None:
    import afit_fdm._afit_fdm as ext

    assert ext.__file__.endswith(".abi3.so"), ext.__file__


def test_readme_recording_example_runs(capsys, tmp_path, monkeypatch) -> None:
    """The second example (record, then replay) runs as written, in a
    scratch directory, and its replay ends where the flight ended."""
    text = (REPO / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## From Python"):text.index("## Versions and stability")]
    code = re.findall(r"```python\n(.*?)```", section, re.S)[1]
    monkeypatch.chdir(tmp_path)
    import afit_fdm

    scope: dict = {"afit_fdm": afit_fdm}  # a continuation of the first example
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102
    frames, same_final_state, z_trajectory, z_flight = capsys.readouterr().out.split()
    assert (frames, same_final_state) == ("70", "True")
    assert z_trajectory == z_flight
    assert (tmp_path / "climb.rec").exists()


def test_readme_outputs_example_runs(tmp_path, monkeypatch) -> None:
    """The third example (ACMI, CSV and DIS outputs) runs as written, in a
    scratch directory (its DIS datagrams go to a closed port: counted as
    failed sends, never raised)."""
    text = (REPO / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## From Python"):text.index("## Versions and stability")]
    code = re.findall(r"```python\n(.*?)```", section, re.S)[2]
    monkeypatch.chdir(tmp_path)
    import afit_fdm

    scope: dict = {"afit_fdm": afit_fdm}
    exec(compile(code, "README.md", "exec"), scope)  # noqa: S102
    f = scope["f"]
    assert f.outputs == [] and f.frame == 900
    lines = (tmp_path / "flight.csv").read_text(encoding="utf-8").splitlines()
    assert lines[0] == "# model: palmer" and lines[1].startswith("frame,time_s,")
    assert len(lines) == 2 + 901
    assert (tmp_path / "flight.zip.acmi").stat().st_size > 0
