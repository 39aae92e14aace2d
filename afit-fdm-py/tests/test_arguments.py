"""Plain arguments (whole numbers, numbers, flags, text, origins) refused with
the argument's name in the message, as the controls' arrays are: ``str(error)``
starts with the name on every Python the wheel serves (PyO3's own errors named
it only in a note, which ``str`` leaves out and Python 3.9 and 3.10 lack), and a
whole number out of range is a ``ValueError`` saying the range, not PyO3's
``OverflowError: can't convert negative int to unsigned``."""

from __future__ import annotations

import pathlib
from typing import Any, Callable

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import afit_fdm
from afit_fdm import Fleet, Flight

U64_MAX = 2**64 - 1


def raises(kind: type, message: str, call: Callable[[], Any]) -> None:
    """``call()`` raises exactly ``kind`` with exactly ``message`` (PyO3 still
    adds its note ``while processing 'n'``, which pytest's ``match`` sees)."""
    with pytest.raises(kind) as caught:
        call()
    assert type(caught.value) is kind
    assert str(caught.value) == message


def test_flight_arguments_are_named() -> None:
    raises(ValueError, "fps: -1 is not a whole number in 1..=10000", lambda: Flight("palmer", fps=-1))
    raises(ValueError, "fps: 0 is not a whole number in 1..=10000", lambda: Flight("palmer", fps=0))
    raises(
        ValueError,
        f"fps: {2**40} is not a whole number in 1..=10000",
        lambda: Flight("palmer", fps=2**40),
    )
    raises(TypeError, "fps: expected a whole number (int), got float", lambda: Flight("palmer", fps=30.0))
    # The range's both ends are taken, one past either refused, by Flight and Fleet alike;
    # the top is the package's MAX_FPS (which the Gymnasium environments check against too).
    assert afit_fdm.MAX_FPS == 10000
    assert Flight("palmer", fps=1).fps == 1.0 and Flight("palmer", fps=10000).fps == 10000.0
    raises(ValueError, "fps: 10001 is not a whole number in 1..=10000", lambda: Flight("palmer", fps=10001))
    raises(ValueError, "fps: 10001 is not a whole number in 1..=10000", lambda: Fleet("palmer", 2, fps=10001))
    raises(ValueError, "fps: 0 is not a whole number in 1..=10000", lambda: Fleet("palmer", 2, fps=0))
    raises(TypeError, "model: expected a str, got int", lambda: Flight(5))  # type: ignore[arg-type]
    raises(
        TypeError,
        "altitude_ft: expected a number, got str",
        lambda: Flight("palmer", altitude_ft="high"),  # type: ignore[arg-type]
    )
    raises(TypeError, "trim: expected True or False, got int", lambda: Flight("palmer", trim=1))  # type: ignore[arg-type]
    raises(TypeError, "script: expected a str, got int", lambda: Flight("palmer", script=3))  # type: ignore[arg-type]


def test_flight_step_counts_are_named() -> None:
    flight = Flight("palmer")
    raises(ValueError, f"n: -1 is not a whole number in 0..={U64_MAX}", lambda: flight.step(-1))
    raises(ValueError, f"n: {2**64} is not a whole number in 0..={U64_MAX}", lambda: flight.step(2**64))
    raises(
        ValueError,
        f"n: -2 is not a whole number in 0..={U64_MAX}",
        lambda: flight.step(np.int64(-2)),  # type: ignore[arg-type]
    )
    raises(TypeError, "n: expected a whole number (int), got float", lambda: flight.step(1.0))  # type: ignore[arg-type]
    raises(
        TypeError,
        "n: expected a whole number (int), got numpy.float64",
        lambda: flight.step(np.float64(1.0)),  # type: ignore[arg-type]
    )
    raises(TypeError, "actions: expected a list of str, got str", lambda: flight.step(1, actions="up"))  # type: ignore[arg-type]
    raises(TypeError, "actions: expected a list of str, got list", lambda: flight.step(1, actions=[1]))  # type: ignore[list-item]
    assert flight.frame == 0, "a refused step flies nothing"
    # NumPy's whole numbers are whole numbers, its floats are numbers.
    flight.step(np.int64(3))  # type: ignore[arg-type]
    assert flight.frame == 3
    Flight("palmer", fps=np.uint16(60), altitude_ft=np.float32(1000.0))  # type: ignore[arg-type]


def test_output_arguments_are_named(tmp_path: pathlib.Path) -> None:
    flight = Flight("palmer")
    csv = tmp_path / "f.csv"
    raises(
        ValueError,
        "origin: expected three numbers (latitude_deg, longitude_deg, altitude_m), got 2 items",
        lambda: flight.csv_to(csv, origin=(1.0, 2.0)),  # type: ignore[arg-type]
    )
    raises(
        TypeError,
        "origin: expected three numbers (latitude_deg, longitude_deg, altitude_m), got str",
        lambda: flight.acmi_to(tmp_path / "f.acmi", origin="39,-84,0"),  # type: ignore[arg-type]
    )
    raises(
        TypeError,
        "origin: expected a number, got str",
        lambda: flight.record_to(tmp_path / "f.rec", origin=(39.0, "east", 0.0)),  # type: ignore[arg-type]
    )
    raises(TypeError, "title: expected a str, got int", lambda: flight.acmi_to(tmp_path / "f.acmi", title=1))  # type: ignore[arg-type]
    raises(TypeError, "target: expected a str, got int", lambda: flight.flightgear_to(5500))  # type: ignore[arg-type]
    assert flight.outputs == [], "no refused output is attached"
    assert not csv.exists()
    # An origin as a list or an array of three numbers is taken.
    flight.csv_to(csv, origin=np.array([39.0, -84.0, 250.0]))  # type: ignore[arg-type]


@pytest.mark.skipif(not hasattr(Flight, "dis_to"), reason="built without the dis feature")
def test_dis_arguments_are_named() -> None:
    flight = Flight("palmer")
    target = "127.0.0.1:3000"
    raises(ValueError, "entity: -1 is not a whole number in 0..=65535", lambda: flight.dis_to(target, entity=-1))
    raises(ValueError, "exercise: 256 is not a whole number in 0..=255", lambda: flight.dis_to(target, exercise=256))
    raises(
        TypeError,
        "heartbeat_s: expected a number, got str",
        lambda: flight.dis_to(target, heartbeat_s="5"),  # type: ignore[arg-type]
    )
    raises(
        TypeError,
        "every_frame: expected True or False, got int",
        lambda: flight.dis_to(target, every_frame=1),  # type: ignore[arg-type]
    )
    assert flight.outputs == []


def test_fleet_arguments_are_named(tmp_path: pathlib.Path) -> None:
    raises(
        ValueError,
        f"n: -5 is not a whole number in 0..={U64_MAX}",
        lambda: Fleet("palmer", -5),
    )
    raises(TypeError, "n: expected a whole number (int), got float", lambda: Fleet("palmer", 2.0))  # type: ignore[arg-type]
    raises(TypeError, "precision: expected a str, got int", lambda: Fleet("palmer", 2, precision=1))  # type: ignore[arg-type]
    raises(TypeError, "parallel: expected True or False, got str", lambda: Fleet("palmer", 2, parallel="no"))  # type: ignore[arg-type]
    fleet = Fleet("palmer", 2)
    raises(ValueError, f"frames: -1 is not a whole number in 0..={U64_MAX}", lambda: fleet.step(-1))
    raises(TypeError, "trim: expected True or False, got NoneType", lambda: fleet.reset(trim=None))  # type: ignore[arg-type]
    recording = tmp_path / "r.rec"
    flight = Flight("palmer")
    flight.record_to(recording)
    flight.step(2)
    flight.stop_recording()
    raises(
        TypeError,
        "trajectory: expected True or False, got int",
        lambda: afit_fdm.replay(recording, trajectory=1),  # type: ignore[arg-type]
    )


@given(st.one_of(st.integers(max_value=-1), st.integers(min_value=2**64)))
def test_any_count_out_of_range_is_a_value_error_naming_it(count: int) -> None:
    flight = Flight("palmer")
    raises(ValueError, f"n: {count} is not a whole number in 0..={U64_MAX}", lambda: flight.step(count))
    assert flight.frame == 0
