"""Studies from Python: the same bits as ``sim-cli study`` (``runs.csv``,
``summary.json``, ``--run I``), shards merged in run order the same as the
whole, pickling, and clear errors for bad input."""

from __future__ import annotations

import csv
import json
import pathlib
import pickle
import statistics
import subprocess
from typing import Dict, List, Sequence

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import afit_fdm
from afit_fdm.study import shard_ranges

# A small landing study: some runs touch down within the 40 s, some do not
# (their touchdown measures do not apply), dispersed speed, mass and height.
STUDY = """
model = "palmer"
runs = 24
seed = 7
fps = 30
duration_s = 40.0
stop = "touchdown"
measures = ["touchdown_x_m", "touchdown_sink_rate_mps", "max_height_m", "final_x_m", "time_to_height_s"]
target_height_m = 200.0
script = \"\"\"
1-5 throttle-down
\"\"\"

[initial]
altitude_ft = 300.0
speed_kt = 65.0
heading_deg = 0.0
trim = true

[[dispersion]]
key = "initial.speed_kt"
distribution = "normal"
mean = 65.0
sd = 2.5

[[dispersion]]
key = "aircraft.mass_kg"
distribution = "truncated_normal"
mean = 1050.0
sd = 40.0
low = 950.0
high = 1114.0

[[dispersion]]
key = "initial.altitude_ft"
distribution = "choice"
values = [150.0, 300.0, 900.0]
"""


@pytest.fixture(scope="module")
def study_file(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    path = tmp_path_factory.mktemp("study") / "landing.toml"
    path.write_text(STUDY, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def whole() -> afit_fdm.RunTable:
    return afit_fdm.study(STUDY, threads=2)


def read_runs_csv(path: pathlib.Path) -> List[Dict[str, str]]:
    with open(path, encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def assert_rows_match(table: afit_fdm.RunTable, rows: List[Dict[str, str]]) -> None:
    """Every cell of ``rows`` (``runs.csv``) is the table's, bit for bit
    (the CSV holds the shortest decimal that reads back to the same f64; an
    empty cell is a measure that does not apply)."""
    assert len(rows) == len(table)
    status = table.status
    for i, row in enumerate(rows):
        assert int(row["run"]) == int(table.run[i])
        assert row["status"] == status[i]
        for name in table.measure_names:
            cell = row[name]
            if cell == "":
                assert not table.applies(name)[i], (i, name)
            else:
                assert table.applies(name)[i], (i, name)
                want = np.float64(float(cell))
                assert want.view(np.uint64) == table.values(name)[i].view(np.uint64), (i, name, cell)
        for name in table.input_names:
            want = np.float64(float(row[name]))
            assert want.view(np.uint64) == table.input(name)[i].view(np.uint64), (i, name, row[name])
        if row["fingerprint"] == "":
            assert not table.has_fingerprint[i], i
        else:
            assert table.has_fingerprint[i], i
            assert int(row["fingerprint"], 16) == int(table.fingerprint[i]), (i, row["fingerprint"])
            assert table.fingerprint_text[i] == row["fingerprint"]


def test_the_table_is_sim_cli_studys_runs_csv_and_summary(
    sim_cli: pathlib.Path, study_file: pathlib.Path, whole: afit_fdm.RunTable, tmp_path: pathlib.Path
) -> None:
    out = tmp_path / "out"
    proc = subprocess.run(
        [str(sim_cli), "study", str(study_file), "--out", str(out), "--threads", "1"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    rows = read_runs_csv(out / "runs.csv")
    assert list(rows[0]) == ["run", "status", *whole.measure_names, *whole.input_names, "fingerprint"]
    assert whole.input_names == ("input.initial.speed_kt", "input.aircraft.mass_kg", "input.initial.altitude_ft")
    # Different runs end in different states: different fingerprints.
    assert whole.has_fingerprint.all() and len(set(whole.fingerprint.tolist())) == len(whole)
    assert_rows_match(whole, rows)
    with open(out / "summary.json", encoding="utf-8") as f:
        assert whole.summarize() == json.load(f)
    # The study exercises both sides of "applies".
    applies = whole.applies("touchdown_x_m")
    assert applies.any() and not applies.all()


# An independent Philox4x32-10 (Random123's description; docs/studies.md,
# "Random numbers"), to check the study's draws from outside the Rust code.
_PHILOX_M = (0xD2511F53, 0xCD9E8D57)
_PHILOX_W = (0x9E3779B9, 0xBB67AE85)
_U32 = 0xFFFFFFFF


def philox4x32_10(counter: Sequence[int], key: Sequence[int]) -> List[int]:
    x, k = list(counter), list(key)
    for round_ in range(10):
        if round_:
            k = [(k[0] + _PHILOX_W[0]) & _U32, (k[1] + _PHILOX_W[1]) & _U32]
        p0, p1 = _PHILOX_M[0] * x[0], _PHILOX_M[1] * x[2]
        x = [(p1 >> 32) ^ x[1] ^ k[0], p1 & _U32, (p0 >> 32) ^ x[3] ^ k[1], p0 & _U32]
    return x


def study_uniform(seed: int, run: int, draw: int) -> float:
    """The uniform of dispersion ``draw`` of run ``run``: 53 bits of the
    block at counter (run's words, draw, 0) under the seed's words, as
    (bits + 1/2) / 2^53."""
    block = philox4x32_10([run & _U32, run >> 32, draw, 0], [seed & _U32, seed >> 32])
    bits = ((block[0] << 32) | block[1]) >> 11
    return (bits + 0.5) / 2.0**53


def test_an_independent_philox_gives_random123s_answer() -> None:
    assert philox4x32_10([0, 0, 0, 0], [0, 0]) == [0x6627E8D5, 0xE169C58D, 0xBC57AC4C, 0x9B00DBD8]
    assert philox4x32_10([_U32] * 4, [_U32] * 2) == [0x408F276D, 0x41C83B0E, 0xA20BC7C6, 0x6D5451FD]


def test_dispersions_are_their_distributions_quantiles(whole: afit_fdm.RunTable) -> None:
    """Each run's inputs are the documented draws, computed here without the
    package: the independent Philox's uniform u, then the distribution's
    quantile at u from Python's own ``statistics.NormalDist`` (its ``cdf``
    through ``erf``, its ``inv_cdf`` its own code of Wichura's AS 241): the
    normal's mean + sd·Φ⁻¹(u), the truncated normal's Φ⁻¹(Φ(α) + u·(Φ(β) −
    Φ(α))) (interval around its mean: not mirrored), the choice's value
    whose cumulative weight first exceeds u. Tolerance 1e-12 relative: the
    two Φ differ by an ulp or two (erf against erfc), and Φ⁻¹'s slope here
    (at most 1/φ(2.5) = 57) keeps that far below it, while any change to a
    distribution's formula moves a draw by far more. The choice exactly."""
    nd = statistics.NormalDist()
    a, b = nd.cdf((950.0 - 1050.0) / 40.0), nd.cdf((1114.0 - 1050.0) / 40.0)
    speed = whole.input("input.initial.speed_kt")
    mass = whole.input("input.aircraft.mass_kg")
    altitude = whole.input("input.initial.altitude_ft")
    for run in range(len(whole)):
        u = [study_uniform(7, run, draw) for draw in range(3)]
        want_speed = 65.0 + 2.5 * nd.inv_cdf(u[0])
        want_mass = 1050.0 + 40.0 * nd.inv_cdf(a + u[1] * (b - a))
        want_altitude = next(v for v, c in zip((150.0, 300.0, 900.0), (1 / 3, 2 / 3, 1.0)) if u[2] < c)
        assert speed[run] == pytest.approx(want_speed, rel=1e-12, abs=0.0), run
        assert mass[run] == pytest.approx(want_mass, rel=1e-12, abs=0.0), run
        assert 950.0 <= mass[run] <= 1114.0
        assert altitude[run] == want_altitude, run
    # The draws spread: the three choices all occur in 24 runs.
    assert set(altitude.tolist()) == {150.0, 300.0, 900.0}


def test_the_summary_is_numpys_statistics_of_the_table(whole: afit_fdm.RunTable) -> None:
    """``summary.json``'s numbers against NumPy's of the same values: count,
    min and max exactly; the mean, the sample standard deviation
    (``ddof=1``), the 95 % interval mean ± 1.96·sd/√n and the percentiles
    (``method="linear"``, NumPy's default) within 1e-12 relative to the
    values' scale (NumPy sums pairwise, the summary in run order, and its
    interpolation rounds differently for fractions above 1/2: a few ulps)."""
    summary = whole.summarize()
    for name in whole.measure_names:
        values = whole.values(name)[whole.applies(name)]
        got = summary["measures"][name]
        assert got["count"] == len(values)
        assert len(values) >= 2, name
        scale = float(np.max(np.abs(values)))

        def close(x: float, want: float) -> bool:
            return abs(x - want) <= 1e-12 * scale

        mean, sd = float(np.mean(values)), float(np.std(values, ddof=1))
        assert close(got["mean"], mean), (name, got["mean"], mean)
        assert close(got["sd"], sd), (name, got["sd"], sd)
        half = 1.96 * sd / np.sqrt(len(values))
        assert close(got["ci95"][0], mean - half) and close(got["ci95"][1], mean + half), name
        assert got["min"] == float(np.min(values)) and got["max"] == float(np.max(values)), name
        for key, q in (("p1", 1), ("p5", 5), ("p50", 50), ("p95", 95), ("p99", 99)):
            want = float(np.percentile(values, q, method="linear"))
            assert close(got[key], want), (name, key, got[key], want)
    assert sum(summary["statuses"].values()) == len(whole)


def test_a_path_a_study_and_the_text_give_the_same_table(
    study_file: pathlib.Path, whole: afit_fdm.RunTable
) -> None:
    assert afit_fdm.study(study_file, threads=1).identical(whole)
    assert afit_fdm.study(str(study_file)).identical(whole)
    s = afit_fdm.Study(study_file)
    assert (s.runs, s.seed, s.model) == (24, 7, "palmer")
    assert s.measure_names == whole.measure_names
    assert afit_fdm.study(s).identical(whole)


@pytest.mark.parametrize("run", [0, 5, 23])
def test_a_row_is_sim_cli_study_run_i(
    sim_cli: pathlib.Path, study_file: pathlib.Path, whole: afit_fdm.RunTable, tmp_path: pathlib.Path, run: int
) -> None:
    proc = subprocess.run(
        [str(sim_cli), "study", str(study_file), "--run", str(run), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    row = _rows(whole, run, run + 1)
    assert_rows_match(row, read_runs_csv(tmp_path / f"run-{run}.csv"))
    # The same row flown alone from Python.
    assert afit_fdm.Study.from_toml(STUDY).fly(run, run + 1).identical(row)


def _rows(table: afit_fdm.RunTable, first: int, end: int) -> afit_fdm.RunTable:
    cols = table.to_columns()
    return afit_fdm.RunTable(
        {
            "run": cols["run"][first:end],
            "status_code": cols["status_code"][first:end],
            "frames": cols["frames"][first:end],
            "measures": [(n, v[first:end], a[first:end]) for n, v, a in cols["measures"]],
            "inputs": [(n, v[first:end]) for n, v in cols["inputs"]],
            "fingerprint": cols["fingerprint"][first:end],
            "has_fingerprint": cols["has_fingerprint"][first:end],
        },
        seed=table.seed,
    )


@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_any_shards_of_any_subrange_merge_to_the_whole(data: st.DataObject, whole: afit_fdm.RunTable) -> None:
    study = afit_fdm.Study.from_toml(STUDY)
    first = data.draw(st.integers(0, study.runs - 1), label="first")
    end = data.draw(st.integers(first + 1, study.runs), label="end")
    shards = data.draw(st.integers(1, end - first), label="shards")
    threads = data.draw(st.integers(1, 3), label="threads")
    parts = [
        study.fly(first + a, first + b, threads=threads) for a, b in shard_ranges(end - first, shards)
    ]
    merged = afit_fdm.RunTable.concat(parts)
    assert merged.identical(_rows(whole, first, end))


def test_shard_ranges_cover_the_runs_in_order() -> None:
    assert shard_ranges(10, 3) == [(0, 4), (4, 7), (7, 10)]
    assert shard_ranges(5, 5) == [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)]
    for bad in (0, 6, -1, True, 2.0):
        with pytest.raises(ValueError, match="shards"):
            shard_ranges(5, bad)  # type: ignore[arg-type]


def test_overrides_and_pickling(whole: afit_fdm.RunTable) -> None:
    s = afit_fdm.Study.from_toml(STUDY, runs=30, seed=8)
    assert (s.runs, s.seed) == (30, 8)
    back = pickle.loads(pickle.dumps(s))
    assert (back.runs, back.seed, back.text) == (30, 8, STUDY)
    # Another seed, other values; the first 24 runs of a 30-run study with the
    # same seed are the 24-run study's.
    assert not afit_fdm.study(STUDY, seed=8).identical(whole)
    longer = afit_fdm.study(STUDY, runs=30)
    assert _rows(longer, 0, 24).identical(whole)


def test_the_table_is_numpy_and_pandas_ready(whole: afit_fdm.RunTable) -> None:
    assert whole.run.dtype == np.uint64 and whole.status_code.dtype == np.uint8
    assert list(whole.run) == list(range(24))
    assert set(whole.status) <= set(afit_fdm.STATUS_CODES)
    d = whole.to_dict()
    assert list(d) == ["run", "status", "frames", *whole.measure_names, *whole.input_names, "fingerprint"]
    assert afit_fdm.Study.from_toml(STUDY).input_names == whole.input_names
    assert whole.input("input.aircraft.mass_kg").dtype == np.float64
    assert set(whole.input("input.initial.altitude_ft").tolist()) <= {150.0, 300.0, 900.0}
    assert all(isinstance(f, str) and len(f) == 18 for f in d["fingerprint"])
    m = d["touchdown_x_m"]
    assert isinstance(m, np.ma.MaskedArray)
    assert np.array_equal(m.mask, ~whole.applies("touchdown_x_m"))
    for name in whole.measure_names:
        assert np.isfinite(whole.values(name)).all()
        assert (whole.values(name)[~whole.applies(name)] == 0.0).all()
    with pytest.raises(ValueError):
        whole.run[0] = 1


def test_bad_input_is_a_clear_error(tmp_path: pathlib.Path) -> None:
    with pytest.raises(ValueError, match="line"):
        afit_fdm.Study.from_toml(STUDY.replace('model = "palmer"', 'model = "glider"'))
    with pytest.raises(ValueError, match="runs"):
        afit_fdm.Study.from_toml(STUDY, runs=0)
    with pytest.raises(ValueError, match="runs"):
        afit_fdm.Study.from_toml(STUDY, runs=-1)
    with pytest.raises(ValueError, match="seed"):
        afit_fdm.Study.from_toml(STUDY, seed=2**64)
    with pytest.raises(ValueError, match="shards"):
        afit_fdm.ray_study(STUDY, shards=25)  # checked before Ray is imported
    with pytest.raises(OSError, match="cannot read"):
        afit_fdm.Study(tmp_path / "missing.toml")
    # Read as sim-cli reads it: a device is refused unread (it was read until
    # memory ran out), a directory too.
    with pytest.raises(OSError, match="^cannot read study file /dev/zero: it is a character device"):
        afit_fdm.Study("/dev/zero")
    with pytest.raises(OSError, match="it is a directory"):
        afit_fdm.Study(tmp_path)
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.truncate(16 * 1024 * 1024 + 1)
    with pytest.raises(ValueError, match="larger than the 16 MiB limit"):
        afit_fdm.Study(big)
    s = afit_fdm.Study.from_toml(STUDY)
    with pytest.raises(ValueError, match="not within"):
        s.fly(0, 25)
    with pytest.raises(ValueError, match="not within"):
        s.fly(5, 4)
    with pytest.raises(ValueError, match="not a run index"):
        s.fly(-1, 3)
    with pytest.raises(ValueError, match="threads"):
        s.fly(0, 2, threads=0)
    # A table that cannot fit (2^40 runs: petabytes) is refused before
    # anything flies, not grown until the machine runs out of memory; a
    # range of the same study that fits is flown.
    huge = afit_fdm.Study.from_toml(STUDY, runs=2**40)
    with pytest.raises(MemoryError, match=r"^runs 0\.\.1099511627776: their table needs about \d+ MiB"):
        huge.fly()
    assert len(huge.fly(2**40 - 2)) == 2
    with pytest.raises(ValueError, match="precision"):
        s.fly(0, 2, precision="sloppy")
    with pytest.raises(TypeError):
        afit_fdm.study(42)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="measures differ"):
        afit_fdm.RunTable.concat([s.fly(0, 1), afit_fdm.study(STUDY.replace('"final_x_m", ', ""), runs=1)])
    with pytest.raises(ValueError, match="status code"):
        cols = s.fly(0, 1).to_columns()
        cols["status_code"] = np.array([9], dtype=np.uint8)
        afit_fdm.RunTable(cols, seed=7)


def test_a_run_is_in_a_table_at_most_once() -> None:
    """A run is one row of its study: tables of overlapping ranges are not
    concatenated (their summary counted the shared runs twice), and a table
    is not made from columns that repeat a run; tables of ranges with a gap
    between them, or in another order, still are."""
    s = afit_fdm.Study.from_toml(STUDY, runs=8)
    a, b = s.fly(0, 4), s.fly(2, 6)
    with pytest.raises(ValueError) as error:
        afit_fdm.RunTable.concat([s.fly(6, 8), a, b])
    assert str(error.value) == (
        "concat: run 2 is in more than one table (tables 1 and 2): the tables' runs must not overlap"
    )
    with pytest.raises(ValueError, match=r"^concat: run 0 is in more than one table \(tables 0 and 1\)"):
        afit_fdm.RunTable.concat([a, a])
    cols = a.to_columns()
    cols["run"] = np.array([0, 1, 2, 1], dtype=np.uint64)
    with pytest.raises(ValueError, match=r"^run: run 1 is in the table more than once$"):
        afit_fdm.RunTable(cols, seed=s.seed)
    apart = afit_fdm.RunTable.concat([s.fly(6, 8), s.fly(0, 2)])
    assert list(apart.run) == [6, 7, 0, 1]
    assert afit_fdm.RunTable.concat([a, s.fly(4, 8)]).identical(s.fly())
