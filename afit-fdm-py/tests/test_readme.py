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
