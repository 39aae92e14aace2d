"""Monte Carlo studies from Python: the study file of ``sim-cli study``, its
runs flown on SIMD fleets, their per-run table as NumPy columns, and the
summary of ``summary.json``.

The per-run results are the same bits as ``sim-cli study``'s ``runs.csv``
(and as ``sim-cli study --run I``): run *i*'s random values come from its own
counter-based stream keyed by (seed, *i*), so it does not depend on which
runs are flown with it, on the threads, or on the machine. That is what lets
:func:`afit_fdm.ray_study` split a study into shards and merge them.

A measure that does not apply to a run (no touchdown, a target height never
reached, a refused start) has no value: :meth:`RunTable.applies` is ``False``
there, :meth:`RunTable.measure` masks it, and :meth:`RunTable.values` holds
``0.0`` there. No cell is ever NaN unless a caller asks pandas for it
(:meth:`RunTable.to_dict` gives masked arrays, which pandas reads as missing).

Each row also carries the values the run drew, one ``input.KEY`` column per
dispersion (:meth:`RunTable.input`, ``runs.csv``'s columns after the
measures), and the fingerprint of the run's final state
(:attr:`RunTable.fingerprint`, the 64-bit hash a recording of the run
carries; ``runs.csv`` writes it as ``0x`` and 16 hex digits).
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._afit_fdm import STATUS_CODES, _Study, summarize_columns

__all__ = ["STATUS_CODES", "RunTable", "Study", "study"]

Columns = Dict[str, Any]
"""A table as plain data (what :meth:`RunTable.to_columns` returns)."""


def _first_repeated(runs: npt.NDArray[np.uint64]) -> Optional[int]:
    """The smallest run number that appears more than once in ``runs``."""
    if runs.size < 2:
        return None
    ordered = np.sort(runs)
    same = np.flatnonzero(ordered[1:] == ordered[:-1])
    return int(ordered[same[0]]) if same.size else None


class RunTable:
    """Per-run results of some runs of a study, in run order.

    Columns: :attr:`run` (uint64), :attr:`status_code` (uint8, an index into
    :data:`STATUS_CODES`; :attr:`status` gives the words), :attr:`frames`
    (uint64, frames each run flew), one float64 column per measure
    (:attr:`measure_names`), each with its ``applies`` flags, one float64
    column per drawn input (:attr:`input_names`, ``input.`` and the
    dispersion's key: the value the run flew with), and :attr:`fingerprint`
    (uint64, the hash of the run's final state) with :attr:`has_fingerprint`
    (``False`` for a refused start). The arrays are read-only.
    """

    __slots__ = ("run", "status_code", "frames", "seed", "_measures", "_inputs", "fingerprint", "has_fingerprint")

    run: npt.NDArray[np.uint64]
    status_code: npt.NDArray[np.uint8]
    frames: npt.NDArray[np.uint64]
    seed: int
    _measures: Dict[str, Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]]
    _inputs: Dict[str, npt.NDArray[np.float64]]
    fingerprint: npt.NDArray[np.uint64]
    has_fingerprint: npt.NDArray[np.bool_]

    def __init__(self, columns: Columns, *, seed: int) -> None:
        """A table from plain columns: a dict with ``run``, ``status_code``,
        ``frames`` and ``measures`` (a list of ``(name, values, applies)``),
        and optionally ``inputs`` (a list of ``(name, values)``; none if
        left out) and ``fingerprint`` with ``has_fingerprint`` (no
        fingerprint if left out), as :meth:`Study.fly` and :meth:`to_columns`
        give. The arrays are checked (dtype, one dimension, equal lengths,
        known status codes, each run at most once: a run is one row of its
        study, and a summary would count a repeated one twice) and copied."""
        n = _column(columns, "run", np.uint64, None).shape[0]
        self.run = _column(columns, "run", np.uint64, n)
        repeated = _first_repeated(self.run)
        if repeated is not None:
            raise ValueError(f"run: run {repeated} is in the table more than once")
        self.status_code = _column(columns, "status_code", np.uint8, n)
        if self.status_code.size and int(self.status_code.max()) >= len(STATUS_CODES):
            raise ValueError(
                f"status_code: {int(self.status_code.max())} is not a status code "
                f"(0 to {len(STATUS_CODES) - 1})"
            )
        self.frames = _column(columns, "frames", np.uint64, n)
        self.seed = int(seed)
        measures = columns.get("measures")
        if not isinstance(measures, (list, tuple)):
            raise TypeError("measures: expected a list of (name, values, applies)")
        self._measures = {}
        for item in measures:
            name, values, applies = item
            if not isinstance(name, str) or name in self._measures:
                raise ValueError(f"measures: {name!r} is not a new measure name")
            self._measures[name] = (
                _array(values, np.float64, n, name),
                _array(applies, np.bool_, n, name + " applies"),
            )
        inputs = columns.get("inputs", [])
        if not isinstance(inputs, (list, tuple)):
            raise TypeError("inputs: expected a list of (name, values)")
        self._inputs = {}
        for item in inputs:
            name, values = item
            if not isinstance(name, str) or name in self._inputs or name in self._measures:
                raise ValueError(f"inputs: {name!r} is not a new column name")
            self._inputs[name] = _array(values, np.float64, n, name)
        if "fingerprint" in columns:
            self.fingerprint = _column(columns, "fingerprint", np.uint64, n)
            self.has_fingerprint = _column(columns, "has_fingerprint", np.bool_, n)
        else:
            self.fingerprint = _array(np.zeros(n, dtype=np.uint64), np.uint64, n, "fingerprint")
            self.has_fingerprint = _array(np.zeros(n, dtype=np.bool_), np.bool_, n, "has_fingerprint")

    def __len__(self) -> int:
        return int(self.run.shape[0])

    def __repr__(self) -> str:
        return (
            f"RunTable({len(self)} runs, measures {list(self.measure_names)}, "
            f"inputs {list(self.input_names)})"
        )

    @property
    def measure_names(self) -> Tuple[str, ...]:
        """The measures, in the study's order."""
        return tuple(self._measures)

    @property
    def input_names(self) -> Tuple[str, ...]:
        """The drawn inputs' columns (``input.`` and each dispersion's key),
        in the study file's order."""
        return tuple(self._inputs)

    def input(self, name: str) -> npt.NDArray[np.float64]:
        """The values input ``name`` (e.g. ``"input.aircraft.mass_kg"``)
        drew, one per run: the very values the runs flew with."""
        try:
            return self._inputs[name]
        except KeyError:
            raise KeyError(
                f"{name!r} is not an input of this table (inputs: {', '.join(self._inputs)})"
            ) from None

    @property
    def fingerprint_text(self) -> npt.NDArray[np.object_]:
        """The fingerprints as ``runs.csv`` writes them (``0x`` and 16 hex
        digits), ``None`` where there is none."""
        return np.array(
            [f"{int(f):#018x}" if h else None for f, h in zip(self.fingerprint, self.has_fingerprint)],
            dtype=object,
        )

    @property
    def status(self) -> npt.NDArray[np.str_]:
        """How each run ended, as words (:data:`STATUS_CODES`)."""
        return np.asarray(STATUS_CODES, dtype=np.str_)[self.status_code]

    def values(self, name: str) -> npt.NDArray[np.float64]:
        """Measure ``name``'s values; ``0.0`` where it does not apply (see
        :meth:`applies`)."""
        return self._get(name)[0]

    def applies(self, name: str) -> npt.NDArray[np.bool_]:
        """Where measure ``name`` applies (has a value)."""
        return self._get(name)[1]

    def measure(self, name: str) -> "np.ma.MaskedArray[Any, np.dtype[np.float64]]":
        """Measure ``name`` as a masked array: masked where it does not apply."""
        values, applies = self._get(name)
        return np.ma.MaskedArray(values, mask=~applies)

    def _get(self, name: str) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        try:
            return self._measures[name]
        except KeyError:
            raise KeyError(
                f"{name!r} is not a measure of this table (measures: {', '.join(self._measures)})"
            ) from None

    def to_dict(self) -> Dict[str, Any]:
        """The table for ``pandas.DataFrame(table.to_dict())``: ``run``,
        ``status`` (words), ``frames``, then one masked array per measure
        (pandas turns the masked cells, where the measure does not apply,
        into its missing value), one array per drawn input, and
        ``fingerprint`` as text (:attr:`fingerprint_text`): the columns of
        ``runs.csv`` with ``frames`` after ``status``."""
        out: Dict[str, Any] = {"run": self.run, "status": self.status, "frames": self.frames}
        for name in self._measures:
            out[name] = self.measure(name)
        for name, values in self._inputs.items():
            out[name] = values
        out["fingerprint"] = self.fingerprint_text
        return out

    def to_columns(self) -> Columns:
        """The table as plain data (NumPy arrays, a list, strings): what a
        Ray task returns and :class:`RunTable` is built from."""
        return {
            "run": self.run,
            "status_code": self.status_code,
            "frames": self.frames,
            "measures": [(name, v, a) for name, (v, a) in self._measures.items()],
            "inputs": list(self._inputs.items()),
            "fingerprint": self.fingerprint,
            "has_fingerprint": self.has_fingerprint,
        }

    def summarize(self) -> Dict[str, Any]:
        """The summary of these runs, as ``sim-cli study``'s ``summary.json``
        (the same numbers: it is computed by the same Rust code): ``runs``,
        ``seed``, ``statuses`` (every status with its count) and
        ``measures`` (per measure: count, mean, sd, ci95, min, p1, p5, p50,
        p95, p99, max; ``None`` where there are too few values)."""
        text = summarize_columns(
            self.run,
            self.status_code,
            self.frames,
            [(name, v, a) for name, (v, a) in self._measures.items()],
            seed=self.seed,
        )
        result: Dict[str, Any] = json.loads(text)
        return result

    def identical(self, other: "RunTable") -> bool:
        """Whether ``other`` has the same columns with the same bits."""
        if (
            self.measure_names != other.measure_names
            or self.input_names != other.input_names
            or self.seed != other.seed
        ):
            return False
        if not (
            np.array_equal(self.run, other.run)
            and np.array_equal(self.status_code, other.status_code)
            and np.array_equal(self.frames, other.frames)
            and np.array_equal(self.fingerprint, other.fingerprint)
            and np.array_equal(self.has_fingerprint, other.has_fingerprint)
        ):
            return False
        for name, values in self._inputs.items():
            if not np.array_equal(values.view(np.uint64), other._inputs[name].view(np.uint64)):
                return False
        for name in self._measures:
            v, a = self._measures[name]
            ov, oa = other._measures[name]
            if not (np.array_equal(a, oa) and np.array_equal(v.view(np.uint64), ov.view(np.uint64))):
                return False
        return True

    @staticmethod
    def concat(tables: Sequence["RunTable"]) -> "RunTable":
        """The tables' rows one after the other (the caller's order). They
        must have the same measures, inputs and seed, and no run in two of
        them (tables of overlapping ranges would hold those runs twice)."""
        if not tables:
            raise ValueError("concat: no tables")
        first = tables[0]
        for t in tables[1:]:
            if t.measure_names != first.measure_names:
                raise ValueError(
                    f"concat: the tables' measures differ: {list(first.measure_names)} "
                    f"and {list(t.measure_names)}"
                )
            if t.input_names != first.input_names:
                raise ValueError(
                    f"concat: the tables' inputs differ: {list(first.input_names)} "
                    f"and {list(t.input_names)}"
                )
            if t.seed != first.seed:
                raise ValueError(f"concat: the tables' seeds differ: {first.seed} and {t.seed}")
        repeated = _first_repeated(np.concatenate([t.run for t in tables]))
        if repeated is not None:
            holders = [k for k, t in enumerate(tables) if repeated in t.run]
            raise ValueError(
                f"concat: run {repeated} is in more than one table (tables {holders[0]} and "
                f"{holders[1]}): the tables' runs must not overlap"
            )
        return RunTable(
            {
                "run": np.concatenate([t.run for t in tables]),
                "status_code": np.concatenate([t.status_code for t in tables]),
                "frames": np.concatenate([t.frames for t in tables]),
                "measures": [
                    (
                        name,
                        np.concatenate([t.values(name) for t in tables]),
                        np.concatenate([t.applies(name) for t in tables]),
                    )
                    for name in first.measure_names
                ],
                "inputs": [
                    (name, np.concatenate([t.input(name) for t in tables])) for name in first.input_names
                ],
                "fingerprint": np.concatenate([t.fingerprint for t in tables]),
                "has_fingerprint": np.concatenate([t.has_fingerprint for t in tables]),
            },
            seed=first.seed,
        )


def _array(value: Any, dtype: Any, n: Optional[int], name: str) -> Any:
    array = np.asarray(value)
    if array.dtype != np.dtype(dtype):
        raise TypeError(f"{name}: expected {np.dtype(dtype).name} values, got {array.dtype.name}")
    if array.ndim != 1:
        raise ValueError(f"{name}: expected one dimension, got {array.ndim}")
    if n is not None and array.shape[0] != n:
        raise ValueError(f"{name}: {array.shape[0]} values for {n} runs")
    array = np.array(array, copy=True)
    array.setflags(write=False)
    return array


def _column(columns: Columns, name: str, dtype: Any, n: Optional[int]) -> Any:
    if not isinstance(columns, dict) or name not in columns:
        raise TypeError(f"columns: expected a dict with {name!r}")
    return _array(columns[name], dtype, n, name)


PathOrText = Union[str, "os.PathLike[str]"]


class Study:
    """A parsed, validated study file (the format of ``sim-cli study``,
    docs/studies.md).

    ``Study(path)`` reads a file; :meth:`Study.from_toml` parses text.
    ``runs`` and ``seed`` override the file's (as ``sim-cli study --runs
    --seed``). A bad file raises ``ValueError`` naming the line and key (or
    the 16 MiB limit, as ``sim-cli``'s), an unreadable one ``OSError`` (also
    a device such as ``/dev/zero`` or a directory, refused unread).

    A study pickles as its text and overrides, so it can be sent to other
    processes (Ray tasks).
    """

    __slots__ = ("_inner",)

    _inner: _Study

    def __init__(
        self,
        path: "Union[str, os.PathLike[str]]",
        *,
        runs: Optional[int] = None,
        seed: Optional[int] = None,
    ) -> None:
        _check_overrides(runs, seed)
        self._inner = _Study.from_path(os.fspath(path), runs=runs, seed=seed)

    @classmethod
    def from_toml(cls, text: str, *, runs: Optional[int] = None, seed: Optional[int] = None) -> "Study":
        """A study from the text of a study file."""
        if not isinstance(text, str):
            raise TypeError(f"text: expected str, got {type(text).__name__}")
        _check_overrides(runs, seed)
        study = cls.__new__(cls)
        study._inner = _Study.from_toml(text, runs=runs, seed=seed)
        return study

    def __reduce__(self) -> Tuple[Any, Tuple[str, int, int]]:
        return (_from_state, (self.text, self.runs, self.seed))

    def __repr__(self) -> str:
        return f"Study(model={self.model!r}, runs={self.runs}, seed={self.seed})"

    @property
    def text(self) -> str:
        """The study file's text (the overrides are :attr:`runs`, :attr:`seed`)."""
        return self._inner.text

    @property
    def runs(self) -> int:
        """Number of runs."""
        return self._inner.runs

    @property
    def seed(self) -> int:
        """The master seed."""
        return self._inner.seed

    @property
    def model(self) -> str:
        """The model's name."""
        return self._inner.model

    @property
    def measure_names(self) -> Tuple[str, ...]:
        """The measures, in the file's order."""
        return tuple(self._inner.measure_names)

    @property
    def input_names(self) -> Tuple[str, ...]:
        """The drawn inputs' columns of the study's tables: ``input.`` and
        each dispersion's key, in the file's order."""
        return tuple(self._inner.input_names)

    def fly(
        self,
        first: int = 0,
        end: Optional[int] = None,
        *,
        threads: Optional[int] = None,
        precision: str = "exact",
    ) -> RunTable:
        """Flies runs ``first`` to ``end`` (excluded; default: all) on SIMD
        fleets, on ``threads`` threads (default: one per core), with the
        GIL released. Run *i*'s row is the same bits whatever the range and
        the threads. ``precision`` is ``"exact"`` (the bits of ``sim-cli
        study``) or ``"fast"`` (Palmer only). A range whose table would not
        fit in the memory this process can still allocate raises
        ``MemoryError`` before anything flies: fly it a range at a time, or
        stream it with ``sim-cli study``.

        Ctrl-C (SIGINT) stops it: called from the main thread, the fly
        looks at Python's pending signals every 20 ms, and a signal whose
        handler raises (``KeyboardInterrupt`` by default) stops the threads
        within a block of runs and is raised from here; the runs flown so
        far are dropped. Off the main thread Python delivers no signals, and
        the fly runs to its end."""
        if end is None:
            end = self.runs
        for name, value in (("first", first), ("end", end)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                raise ValueError(f"{name}: {value!r} is not a run index")
        if end > self.runs or first > end:
            raise ValueError(f"runs {first}..{end} are not within the study's {self.runs} runs")
        columns = self._inner.fly_columns(int(first), int(end), threads=threads, precision=precision)
        return RunTable(columns, seed=self.seed)


def _check_overrides(runs: Optional[int], seed: Optional[int]) -> None:
    for name, value in (("runs", runs), ("seed", seed)):
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value < 2**64:
            raise ValueError(f"{name}: {value!r} is not a whole number from 0 to 2**64 - 1")


def _from_state(text: str, runs: int, seed: int) -> Study:
    return Study.from_toml(text, runs=runs, seed=seed)


def load(source: Union[Study, PathOrText], *, runs: Optional[int] = None, seed: Optional[int] = None) -> Study:
    """A :class:`Study` from a study, a path, or a study file's text (a
    ``str`` with a line break is text; any other ``str`` is a path)."""
    if isinstance(source, Study):
        if runs is None and seed is None:
            return source
        return Study.from_toml(
            source.text,
            runs=source.runs if runs is None else runs,
            seed=source.seed if seed is None else seed,
        )
    if isinstance(source, str) and "\n" in source:
        return Study.from_toml(source, runs=runs, seed=seed)
    if isinstance(source, (str, os.PathLike)):
        return Study(source, runs=runs, seed=seed)
    raise TypeError(f"expected a Study, a path or a study file's text, got {type(source).__name__}")


def study(
    source: Union[Study, PathOrText],
    *,
    runs: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    precision: str = "exact",
) -> RunTable:
    """Flies every run of a study (a :class:`Study`, a path, or a study
    file's text) on this machine: the table of ``sim-cli study``'s
    ``runs.csv``, with ``table.summarize()`` its ``summary.json``. Ctrl-C
    raises ``KeyboardInterrupt`` within a fraction of a second (see
    :meth:`Study.fly`)."""
    return load(source, runs=runs, seed=seed).fly(threads=threads, precision=precision)


def shard_ranges(runs: int, shards: int) -> List[Tuple[int, int]]:
    """``runs`` split into ``shards`` contiguous ranges ``(first, end)`` in
    run order, their sizes differing by at most one."""
    if isinstance(shards, bool) or not isinstance(shards, (int, np.integer)) or not 1 <= shards <= runs:
        raise ValueError(f"shards: {shards!r} is not a whole number from 1 to the study's {runs} runs")
    base, extra = divmod(runs, int(shards))
    out = []
    first = 0
    for k in range(int(shards)):
        end = first + base + (1 if k < extra else 0)
        out.append((first, end))
        first = end
    return out

