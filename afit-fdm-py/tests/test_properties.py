"""Hypothesis: random scenarios flown from Python and by ``sim-cli`` (Rust)
agree bit for bit; random fleets agree with single flights."""

from __future__ import annotations

import pathlib

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import afit_fdm
from test_flight import compare, fly_rows
from conftest import run_csv

PALMER_ACTIONS = afit_fdm.MODELS["palmer"]["actions"]
BOURG_ACTIONS = afit_fdm.MODELS["bourg"]["actions"]


def scripts(actions):
    rule = st.tuples(st.integers(1, 120), st.integers(0, 60), st.sampled_from(actions)).map(
        lambda r: f"{r[0]}-{r[0] + r[1]} {r[2]}"
    )
    return st.lists(rule, max_size=6).map(lambda rules: "".join(r + "\n" for r in rules))


starts = st.fixed_dictionaries(
    {},
    optional={
        "altitude_ft": st.floats(0, 8000),
        "speed_kt": st.floats(0, 160),
        "heading_deg": st.floats(-360, 360),
    },
)
slow = settings(
    max_examples=20,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)


def cli_start_args(start: dict) -> list:
    args = []
    for k, flag in (("altitude_ft", "--altitude-ft"), ("speed_kt", "--speed-kt"), ("heading_deg", "--heading-deg")):
        if k in start:
            args += [flag, repr(start[k])]
    return args


@slow
@given(
    start=starts,
    throttle=st.floats(0, 1),
    alpha=st.floats(-16, 20),
    bank=st.floats(-20, 20),
    flaps=st.sampled_from([0, 20, 40]),
    fps=st.integers(5, 120),
    frames=st.integers(0, 200),
    script=scripts(PALMER_ACTIONS),
)
def test_random_palmer_flights_match_sim_cli(sim_cli: pathlib.Path, tmp_path_factory, start, throttle, alpha, bank, flaps, fps, frames, script) -> None:
    tmp = tmp_path_factory.mktemp("p")
    (tmp / "s.txt").write_text(script, encoding="utf-8")
    args = ["palmer", "--fps", str(fps), "--frames", str(frames), "--script", str(tmp / "s.txt"),
            "--throttle", repr(throttle), "--alpha", repr(alpha), "--bank", repr(bank),
            "--flaps", str(flaps), *cli_start_args(start)]
    flight = afit_fdm.Flight("palmer", fps=fps, script=script, throttle=throttle,
                             alpha_deg=alpha, bank_deg=bank, flaps_deg=flaps, **start)
    compare(run_csv(sim_cli, args, tmp), fly_rows(flight, frames), "palmer")


@slow
@given(
    start=starts,
    thrust=st.floats(0, 3000),
    fps=st.integers(10, 120),
    frames=st.integers(0, 200),
    script=scripts(BOURG_ACTIONS),
)
def test_random_bourg_flights_match_sim_cli(sim_cli: pathlib.Path, tmp_path_factory, start, thrust, fps, frames, script) -> None:
    tmp = tmp_path_factory.mktemp("b")
    (tmp / "s.txt").write_text(script, encoding="utf-8")
    args = ["bourg", "--fps", str(fps), "--frames", str(frames), "--script", str(tmp / "s.txt"),
            "--thrust-lb", repr(thrust), *cli_start_args(start)]
    flight = afit_fdm.Flight("bourg", fps=fps, script=script, thrust_lb=thrust, **start)
    compare(run_csv(sim_cli, args, tmp), fly_rows(flight, frames), "bourg")


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(1, 20),
    seed=st.integers(0, 2**32 - 1),
    frames=st.integers(1, 400),
    model=st.sampled_from(["palmer", "bourg"]),
)
def test_random_exact_fleets_match_flights(n, seed, frames, model) -> None:
    rng = np.random.default_rng(seed)
    start = dict(
        altitude_ft=rng.uniform(0.0, 6000.0, n),
        speed_kt=rng.uniform(0.0, 150.0, n),
        heading_deg=rng.uniform(-360.0, 360.0, n),
    )
    if model == "palmer":
        controls = dict(
            throttle=rng.uniform(0, 1, n), alpha_deg=rng.uniform(-16, 20, n),
            bank_deg=rng.uniform(-20, 20, n), flaps_deg=rng.choice([0.0, 20.0, 40.0], n),
        )
    else:
        controls = dict(
            thrust_lb=rng.uniform(0, 3000, n), landing_flaps=rng.choice([0.0, 1.0], n),
            pitch_trim=rng.uniform(-1, 1, n),
        )
    fleet = afit_fdm.Fleet(model, n, parallel=bool(seed % 2), **start, **controls)
    fleet.step(frames)
    for i in range(n):
        f = afit_fdm.Flight(model, **{k: float(v[i]) for k, v in {**start, **controls}.items()})
        f.step(frames)
        for name, value in f.state.items():
            assert fleet[name][i] == value or (value != value and fleet[name][i] != fleet[name][i]), (i, name)
        assert fleet.status[i] == f.status_code


def _bits(flight: afit_fdm.Flight) -> tuple:
    """Everything a flight shows, numbers as their exact hex form (so that
    -0.0 and 0.0 differ and nothing is compared within a tolerance)."""
    numbers = lambda d: tuple((k, float(v).hex()) for k, v in sorted(d.items()))
    return (flight.frame, flight.status, numbers(flight.state), numbers(flight.controls), numbers(flight.view))


def _branch(flight: afit_fdm.Flight, how: object) -> afit_fdm.Flight:
    """``flight.copy()``, or a ``pickle`` round trip with protocol ``how``."""
    import pickle

    if how == "copy":
        return flight.copy()
    thawed = pickle.loads(pickle.dumps(flight, protocol=how))
    assert isinstance(thawed, afit_fdm.Flight)
    return thawed


@settings(max_examples=150, deadline=None)
@given(
    model=st.sampled_from(["palmer", "bourg"]),
    start=starts,
    fps=st.integers(5, 120),
    before=st.integers(0, 150),
    after=st.integers(0, 150),
    how=st.sampled_from(["copy", 2, 3, 4, 5]),
    data=st.data(),
)
def test_a_copy_or_a_pickled_flight_flies_on_to_the_bits_of_the_flight_it_came_from(
    model, start, fps, before, after, how, data
) -> None:
    """A copy (``Flight.copy``, or a ``pickle`` round trip with every
    protocol from 2) taken after ``before`` frames, stepped ``after`` more
    with the same key presses, is where one flight stepped ``before +
    after`` frames is, bit for bit, every frame (the script too: its text
    goes through the pickle); the flight it came from is not moved by
    stepping the copy, and a reset of the copy goes back to the same start.
    The tolerance is none: the copy is the same numbers, and a step of the
    same numbers is the same step."""
    actions = afit_fdm.MODELS[model]["actions"]
    script = data.draw(scripts(actions))
    presses = data.draw(st.lists(st.sampled_from(actions), max_size=3))
    make = lambda: afit_fdm.Flight(model, fps=fps, script=script, **start)
    alone, branched = make(), make()
    for flight in (alone, branched):
        flight.step(before)
    copied = _branch(branched, how)
    assert _bits(copied) == _bits(branched)
    for _ in range(after):
        alone.step(1, presses)
        copied.step(1, presses)
        assert _bits(copied) == _bits(alone)
    assert _bits(branched)[0] == before, "stepping the copy moved the flight it came from"
    copied.reset()
    fresh = make()
    assert _bits(copied) == _bits(fresh)


def test_copy_copy_and_deepcopy_are_copies_without_the_outputs(tmp_path: pathlib.Path) -> None:
    """``copy.copy`` and ``copy.deepcopy`` make the same independent copy; the
    copy writes none of the flight's files (their bytes are the flight's
    alone), and its ``record_to`` refuses a flight past its start as the
    flight's own does."""
    import copy

    import pytest

    flight = afit_fdm.Flight("bourg", altitude_ft=3000.0, speed_kt=120.0, trim=True)
    flight.csv_to(tmp_path / "f.csv")
    flight.step(10)
    for made in (flight.copy(), copy.copy(flight), copy.deepcopy(flight)):
        assert made is not flight and _bits(made) == _bits(flight)
        assert made.outputs == [] and made.recording is None
        made.step(30)
        assert made.frame == 40 and flight.frame == 10
        with pytest.raises(ValueError, match="call reset"):
            made.record_to(tmp_path / "r.rec")
    flight.close_outputs()
    rows = (tmp_path / "f.csv").read_text(encoding="utf-8").splitlines()
    # The model line, the header, frame 0 and the flight's ten frames: none of the copies'.
    assert len(rows) == 2 + 1 + 10, rows[-1]


def test_bytes_that_are_not_a_pickled_flight_are_refused() -> None:
    """Damaged, cut, foreign or impossible bytes raise ``ValueError`` saying
    why, never a flight with a NaN state or a crash."""
    import struct

    import pytest

    flight = afit_fdm.Flight("palmer", altitude_ft=2000.0, speed_kt=100.0, trim=True)
    start_height = flight.state["z_m"]
    flight.step(5)
    restore, (good,) = flight.__reduce__()
    assert _bits(restore(good)) == _bits(flight)

    def refused(data: bytes, words: str) -> None:
        with pytest.raises(ValueError, match="cannot restore a pickled flight: " + words):
            restore(data)

    refused(b"", "not a pickled flight")
    refused(good[:-3], "damaged")
    refused(good + b"\0", "1 byte after the flight")
    refused(b"\x02" + good[1:], "it has format 2, this package reads format 1")
    refused(good.replace(b"palmer", b"pumper"), "`pumper` is not a model")
    # The start's height, as its 8 bytes, made NaN.
    height = struct.pack("<d", start_height)
    assert good.count(height) >= 1
    refused(good.replace(height, struct.pack("<d", float("nan"))), r"the state \(start\) is not finite")
    # A throttle of 2 (the range is 0..1), in the start's controls and now.
    throttled = afit_fdm.Flight("palmer", throttle=0.637)
    _, (data,) = throttled.__reduce__()
    throttle = struct.pack("<d", 0.637)
    assert data.count(throttle) == 2
    refused(data.replace(throttle, struct.pack("<d", 2.0)), r"the controls \(start\): throttle: 2 is not in 0")
    with pytest.raises(TypeError):
        restore("not bytes")


def _fleet_bits(fleet: afit_fdm.Fleet) -> tuple:
    """What a fleet shows, as bytes: every state column, status and control
    of every aircraft, bit for bit (-0.0 and 0.0 differ, NaNs by payload)."""
    return (
        fleet.model,
        len(fleet),
        fleet.fps,
        fleet.precision,
        fleet.columns.tobytes(),
        fleet.status.tobytes(),
        tuple((name, column.tobytes()) for name, column in sorted(fleet.controls.items())),
    )


def _branch_fleet(fleet: afit_fdm.Fleet, how: object) -> afit_fdm.Fleet:
    """``fleet.copy()``, ``copy.copy``, ``copy.deepcopy``, or a ``pickle``
    round trip with protocol ``how``."""
    import copy
    import pickle

    if how == "copy":
        made = fleet.copy()
    elif how == "copy.copy":
        made = copy.copy(fleet)
    elif how == "deepcopy":
        made = copy.deepcopy(fleet)
    else:
        made = pickle.loads(pickle.dumps(fleet, protocol=how))
    assert isinstance(made, afit_fdm.Fleet) and made is not fleet
    return made


def _random_controls(model: str, rng: np.random.Generator, n: int) -> dict:
    if model == "palmer":
        return dict(
            throttle=rng.uniform(0, 1, n), alpha_deg=rng.uniform(-16, 20, n),
            bank_deg=rng.uniform(-20, 20, n), flaps_deg=rng.choice([0.0, 20.0, 40.0], n),
            brakes=rng.choice([0.0, 1.0], n),
        )
    return dict(
        thrust_lb=rng.uniform(0, 3000, n), elevator=rng.choice([-1.0, 0.0, 1.0], n),
        aileron=rng.choice([-1.0, 0.0, 1.0], n), rudder=rng.choice([-1.0, 0.0, 1.0], n),
        landing_flaps=rng.choice([0.0, 1.0], n), pitch_trim=rng.uniform(-1, 1, n),
    )


@settings(max_examples=60, deadline=None)
@given(
    model=st.sampled_from(["palmer", "bourg"]),
    n=st.integers(0, 40),
    seed=st.integers(0, 2**32 - 1),
    fps=st.integers(5, 120),
    fast=st.booleans(),
    before=st.integers(0, 300),
    after=st.integers(1, 300),
    how=st.sampled_from(["copy", "copy.copy", "deepcopy", 2, 3, 4, 5]),
    views=st.booleans(),
)
def test_a_copied_or_pickled_fleet_flies_on_to_the_bits_of_the_fleet_it_came_from(
    model, n, seed, fps, fast, before, after, how, views
) -> None:
    """A copy of a fleet (``Fleet.copy``, ``copy.copy``, ``copy.deepcopy``,
    or a ``pickle`` round trip with every protocol from 2), taken after
    ``before`` frames and a change of some aircraft's controls, shows the
    same state, statuses and controls, bit for bit; stepped ``after`` more
    frames, it is where a fleet stepped ``before + after`` frames is; and
    stepping it does not move the fleet it came from. Random starts from the
    ground up (so some aircraft land or crash: statuses other than airborne
    go through the copy too), both precisions, both threadings, and a fleet
    whose state views were left stale by ``task_step(..., views=False)``.
    The tolerance is none: the copy holds the same numbers, and a step of
    the same numbers is the same step."""
    rng = np.random.default_rng(seed)
    precision = "fast" if fast and model == "palmer" else "exact"
    start = dict(
        altitude_ft=rng.uniform(0.0, 3000.0, n),
        speed_kt=rng.uniform(0.0, 150.0, n),
        heading_deg=rng.uniform(-360.0, 360.0, n),
    )
    controls = _random_controls(model, rng, n)
    later = _random_controls(model, rng, n)
    mask = rng.random(n) < 0.5
    make = lambda: afit_fdm.Fleet(
        model, n, fps=fps, precision=precision, parallel=bool(seed % 2), **start, **controls
    )
    alone, branched = make(), make()
    for fleet in (alone, branched):
        fleet.step(before)
        fleet.set_controls(mask, **later)
    if not views and n > 0:
        # A task step that leaves the state views as they were: the copy's
        # views show the aircraft's state all the same.
        task = dict(
            task="climb", target_alt_ft=np.full(n, 3000.0), target_heading_deg=np.zeros(n),
            max_steps=10**6,
        )
        outputs = lambda: dict(
            steps=np.zeros(n, np.int64), obs=np.zeros((n, 10 if model == "palmer" else 11), np.float32),
            reward=np.zeros(n), terminated=np.zeros(n, bool), truncated=np.zeros(n, bool),
        )
        actions = rng.uniform(-1.0, 1.0, (n, 4 if model == "palmer" else 5))
        for fleet in (alone, branched):
            fleet.task_step(actions, 1, **task, **outputs(), views=False)
        alone.step(0)
    copied = _branch_fleet(branched, how)
    if views or n == 0:
        assert _fleet_bits(copied) == _fleet_bits(branched)
    else:
        assert _fleet_bits(copied) == _fleet_bits(alone)
    kept = _fleet_bits(copied)
    assert copied.last_step_interval == (0.0, 0.0)
    alone.step(after)
    copied.step(after)
    assert _fleet_bits(copied) == _fleet_bits(alone)
    branched.step(0)
    assert _fleet_bits(branched) == kept, "stepping the copy moved the fleet it came from"
