"""``Fleet``: the SIMD kernels from NumPy, against ``Flight`` aircraft by aircraft."""

from __future__ import annotations

import gc
import threading
import time

import numpy as np
import pytest

import afit_fdm
import afit_fdm.gym
from afit_fdm import Status


def test_exact_palmer_fleet_is_flight_bit_for_bit() -> None:
    n = 37  # not a multiple of the 8 lanes
    throttle = np.linspace(0.3, 1.0, n)
    alpha = np.linspace(-2.0, 8.0, n)
    bank = np.linspace(-20.0, 20.0, n)
    altitude = np.linspace(500.0, 5000.0, n)
    heading = np.linspace(-180.0, 180.0, n)
    fleet = afit_fdm.Fleet(
        "palmer", n, fps=30, altitude_ft=altitude, speed_kt=90.0, heading_deg=heading,
        throttle=throttle, alpha_deg=alpha, bank_deg=bank, flaps_deg=20.0,
    )
    fleet.step(300)
    for i in range(n):
        f = afit_fdm.Flight(
            "palmer", fps=30, altitude_ft=altitude[i], speed_kt=90.0, heading_deg=heading[i],
            throttle=throttle[i], alpha_deg=alpha[i], bank_deg=bank[i], flaps_deg=20,
        )
        f.step(300)
        for name, value in f.state.items():
            assert fleet[name][i] == value, (i, name)
        assert fleet.status[i] == f.status_code


def test_exact_bourg_fleet_is_flight_bit_for_bit() -> None:
    n = 21
    thrust = np.linspace(0.0, 3000.0, n)
    fleet = afit_fdm.Fleet("bourg", n, fps=30, altitude_ft=3000.0, speed_kt=90.0, trim=True)
    fleet.set_controls(thrust_lb=thrust, landing_flaps=1.0)
    fleet.step(120)
    for i in range(n):
        f = afit_fdm.Flight("bourg", fps=30, altitude_ft=3000.0, speed_kt=90.0, trim=True)
        f.set_controls(thrust_lb=thrust[i], landing_flaps=1)
        f.step(120)
        for name, value in f.state.items():
            assert fleet[name][i] == value, (i, name)


def test_views_are_read_only_zero_copy_and_refreshed_in_place() -> None:
    fleet = afit_fdm.Fleet("palmer", 10, throttle=1.0, alpha_deg=4.0)
    x = fleet["x_m"]
    assert x.shape == (10,) and x.dtype == np.float64
    assert not x.flags.writeable
    with pytest.raises(ValueError):
        x[0] = 1.0
    assert fleet.columns.shape == (len(fleet.fields), 10)
    assert np.shares_memory(x, fleet.columns)  # a view, not a copy
    assert np.shares_memory(fleet.state["x_m"], x)
    before = np.array(x)
    fleet.step(10)
    assert (x > before).all()  # the same view shows the new state
    assert fleet.status.dtype == np.uint8 and not fleet.status.flags.writeable
    del fleet
    gc.collect()
    assert x.sum() > 0  # the view keeps its buffer alive after the fleet


def test_statuses_are_codes_with_names() -> None:
    # From 300 ft at 80 kt, nose down and idle: every aircraft comes down;
    # the steepest crash, the gentlest land.
    alpha = np.array([-16.0, -10.0, 0.0, 2.0])
    fleet = afit_fdm.Fleet("palmer", 4, altitude_ft=300.0, speed_kt=80.0, alpha_deg=alpha)
    assert (fleet.status == Status.AIRBORNE).all()
    fleet.step(30 * 120)
    codes = [Status(c) for c in fleet.status]
    assert codes[0] == Status.CRASHED
    assert all(c in (Status.CRASHED, Status.LANDED_SAFE, Status.LANDED_ROUGH) for c in codes)
    crashed = fleet.status == Status.CRASHED
    assert (fleet["vx_mps"][crashed] == 0).all() and (fleet["z_m"] >= 0).all()


def test_reset_with_a_mask_restarts_only_those() -> None:
    fleet = afit_fdm.Fleet("palmer", 6, altitude_ft=1000.0, speed_kt=90.0, throttle=0.7, alpha_deg=3.0)
    fleet.step(60)
    x = np.array(fleet["x_m"])
    mask = np.array([True, False, True, False, False, False])
    fleet.reset(mask, altitude_ft=np.full(6, 2000.0), speed_kt=100.0, trim=True)
    assert (fleet["x_m"][mask] == 0).all() and (fleet["x_m"][~mask] == x[~mask]).all()
    assert fleet["z_m"][0] == pytest.approx(2000 * 0.3048)
    assert fleet.controls["throttle"][0] != 0.7 and fleet.controls["throttle"][1] == 0.7


def test_numpy_numbers_are_taken_as_the_numbers_they_are() -> None:
    """A NumPy number sets a control or a start as a Python number does:
    float32 (what Gymnasium's action arrays hold, e.g. ``action[0]``) and
    float16 widen to float64 exactly, integers, unsigned ones and bools too;
    a Flight takes them the same way. A longdouble or complex number, whose
    conversion would drop digits or a part, is refused naming the argument,
    and arrays must still be float64 (the test below)."""
    fleet = afit_fdm.Fleet("palmer", 3)
    flight = afit_fdm.Flight("palmer")
    for value in [np.float32(0.1), np.float16(0.25), np.float64(0.3), np.uint8(1), np.int32(0), np.bool_(True)]:
        fleet.set_controls(throttle=value)
        flight.set_controls(throttle=value)
        assert (fleet.controls["throttle"] == float(value)).all(), value
        assert flight.controls["throttle"] == float(value), value
    assert fleet.controls["throttle"][0] == 1.0 and float(np.float32(0.1)) != 0.1
    fleet.set_controls(throttle=np.float32(0.1))
    assert fleet.controls["throttle"][0] == float(np.float32(0.1))
    fleet.reset(altitude_ft=np.float32(1500.5), speed_kt=np.float32(90.0), trim=True)
    same = afit_fdm.Fleet("palmer", 3, altitude_ft=1500.5, speed_kt=90.0, trim=True)
    assert np.array_equal(fleet.columns.view(np.uint64), same.columns.view(np.uint64))
    refused = [np.complex64(0.5)]
    if np.dtype(np.longdouble) != np.dtype(np.float64):  # wider than f64 here
        refused.append(np.longdouble(0.5))
    for bad in refused:
        kind = np.dtype(type(bad)).name
        with pytest.raises(TypeError, match=rf"^throttle: expected a number or a float64 array, got a {kind} scalar$"):
            fleet.set_controls(throttle=bad)


def test_bad_controls_raise_naming_the_argument_and_change_nothing() -> None:
    fleet = afit_fdm.Fleet("palmer", 4, throttle=0.5)
    with pytest.raises(TypeError, match="throttle.*float64.*int64"):
        fleet.set_controls(throttle=np.array([1, 0, 1, 0]))
    with pytest.raises(TypeError, match="throttle.*float32"):
        fleet.set_controls(throttle=np.zeros(4, dtype=np.float32))
    with pytest.raises(ValueError, match=r"throttle: expected shape \(4,\)"):
        fleet.set_controls(throttle=np.zeros(5))
    with pytest.raises(ValueError, match=r"throttle: expected shape \(4,\)"):
        fleet.set_controls(throttle=np.zeros((4, 1)))
    with pytest.raises(ValueError, match=r"alpha_deg\[2\]: NaN"):
        fleet.set_controls(throttle=1.0, alpha_deg=np.array([0.0, 1.0, np.nan, 2.0]))
    with pytest.raises(ValueError, match=r"bank_deg\[1\]: 21"):
        fleet.set_controls(bank_deg=np.array([0.0, 21.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match=r"flaps_deg\[0\]: 10 is not 0, 20 or 40"):
        fleet.set_controls(flaps_deg=10.0)
    with pytest.raises(TypeError, match="thrust_lb: not a control of palmer"):
        fleet.set_controls(thrust_lb=1.0)
    with pytest.raises(TypeError, match="throttle: expected a number"):
        fleet.set_controls(throttle="full")
    with pytest.raises(TypeError, match="mask"):
        fleet.set_controls(np.array([1, 0, 1, 0]), throttle=1.0)
    with pytest.raises(ValueError, match="altitude_ft"):
        fleet.reset(altitude_ft=np.array([0.0, 1.0, np.inf, 0.0]))
    assert (fleet.controls["throttle"] == 0.5).all()
    assert (fleet.controls["alpha_deg"] == 0.0).all()
    with pytest.raises(ValueError, match="precision"):
        afit_fdm.Fleet("bourg", 2, precision="fast")
    with pytest.raises(ValueError, match="precision"):
        afit_fdm.Fleet("palmer", 2, precision="sloppy")
    with pytest.raises(ValueError, match="elevator"):
        afit_fdm.Fleet("bourg", 2, elevator=0.5)
    with pytest.raises(KeyError, match="x_ft"):
        fleet["x_ft"]


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_a_fleet_too_big_for_the_memory_is_refused_at_once(model: str) -> None:
    """A fleet this process cannot hold is a ``MemoryError`` before anything
    is allocated, saying what it needs, as ``sim-cli fleet`` refuses it: not
    a fleet that grows aircraft by aircraft until the machine runs out of
    memory (2^50 aircraft of a few hundred bytes each are exabytes). The
    Gymnasium vector env of that size is refused the same way (its NumPy
    arrays, never touched, cost nothing first)."""
    n = 2**50
    started = time.monotonic()
    with pytest.raises(MemoryError, match=rf"^a fleet of {n} {model} aircraft needs about \d+ MiB \(\d+ bytes each"):
        afit_fdm.Fleet(model, n)
    with pytest.raises(MemoryError, match=rf"a fleet of {n} {model} aircraft"):
        afit_fdm.gym.AircraftVectorEnv(model, "climb", num_envs=n)
    assert time.monotonic() - started < 10.0
    # A fleet that fits is still made.
    assert len(afit_fdm.Fleet(model, 1000)) == 1000


def test_a_long_step_in_chunks_is_the_same_bits_however_it_is_cut() -> None:
    """``Fleet.step`` and ``Flight.step`` fly a long step in chunks (looking
    at Ctrl-C between them): 3,000 frames of 1,000 aircraft in one call
    (two chunks of 2,097 frames and the rest) are the bits of the same
    frames flown in uneven calls, and so is a Flight's 200,000 frames (four
    chunks) against calls of 255 frames and less (never chunked)."""
    one = afit_fdm.Fleet("palmer", 1000, altitude_ft=3000.0, speed_kt=90.0, trim=True, parallel=False)
    cut = afit_fdm.Fleet("palmer", 1000, altitude_ft=3000.0, speed_kt=90.0, trim=True, parallel=True)
    one.step(3000)
    for frames in (1, 2096, 2, 901):
        cut.step(frames)
    assert np.array_equal(one.columns.view(np.uint64), cut.columns.view(np.uint64))
    assert np.array_equal(one.status, cut.status)
    a = afit_fdm.Flight("bourg", altitude_ft=3000.0, speed_kt=90.0, trim=True)
    b = afit_fdm.Flight("bourg", altitude_ft=3000.0, speed_kt=90.0, trim=True)
    a.step(200_000)
    left = 200_000
    while left:
        frames = min(left, 255)
        b.step(frames)
        left -= frames
    assert a.state == b.state and a.status == b.status
    assert a.state["time_s"] > 0


def test_fast_precision_stays_close_to_exact() -> None:
    kw = dict(altitude_ft=2000.0, speed_kt=100.0, trim=True)
    exact = afit_fdm.Fleet("palmer", 16, precision="exact", **kw)
    fast = afit_fdm.Fleet("palmer", 16, precision="fast", **kw)
    exact.step(1800)
    fast.step(1800)
    assert np.abs(exact.columns - fast.columns).max() < 1e-9


def test_two_threads_step_two_fleets_in_parallel() -> None:
    """``step`` releases the GIL: two Python threads stepping two fleets on
    one core each overlap in time, measured inside Rust (each step's
    ``last_step_interval``), not by wall-clock ratios."""
    fleets = [afit_fdm.Fleet("palmer", 4096, parallel=False, throttle=1.0, alpha_deg=4.0) for _ in range(2)]
    fleets[0].step(5)  # warm up (page in the buffers)
    fleets[1].step(5)
    barrier = threading.Barrier(2)

    def work(fleet: afit_fdm.Fleet) -> None:
        barrier.wait()
        fleet.step(600)  # about 0.1 to 1 s on one core

    threads = [threading.Thread(target=work, args=(f,)) for f in fleets]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    (a0, a1), (b0, b1) = (f.last_step_interval for f in fleets)
    overlap = min(a1, b1) - max(a0, b0)
    shorter = min(a1 - a0, b1 - b0)
    # Holding the GIL would serialise them (overlap <= 0). Released, they
    # overlap for most of the shorter one (both threads start at the barrier).
    assert overlap > 0.5 * shorter, ((a0, a1), (b0, b1))


def test_a_fleet_stepped_by_another_thread_is_busy_not_corrupted() -> None:
    fleet = afit_fdm.Fleet("palmer", 2048, parallel=False, throttle=1.0, alpha_deg=4.0)
    errors = []
    started = threading.Event()

    def work() -> None:
        started.set()
        fleet.step(2000)

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    try:
        for _ in range(1000):
            fleet.step(1)
    except RuntimeError as e:  # "Already borrowed": PyO3's own guard
        errors.append(e)
    t.join()
    assert errors or fleet.status is not None


def test_bytes_that_are_not_a_pickled_fleet_are_refused() -> None:
    """Damaged, cut, foreign or impossible bytes raise ``ValueError`` saying
    why, never a fleet with a NaN state, a crash, or an allocation the
    bytes cannot back."""
    import struct

    altitude = np.array([1000.0, 2000.0, 3000.0])
    fleet = afit_fdm.Fleet("palmer", 3, altitude_ft=altitude, speed_kt=100.0, throttle=0.625)
    restore, (good,) = fleet.__reduce__()
    assert restore(good).columns.tobytes() == fleet.columns.tobytes()

    def refused(data: bytes, words: str) -> None:
        with pytest.raises(ValueError, match="cannot restore a pickled fleet: " + words):
            restore(data)

    def once(old: bytes, new: bytes) -> bytes:
        assert good.count(old) == 1, old
        return good.replace(old, new)

    refused(b"", "not a pickled fleet")
    refused(good[:-3], "aircraft 2: damaged")
    refused(good + b"\0", "1 byte after the fleet")
    refused(b"\x02" + good[1:], "it has format 2, this package reads format 1")
    refused(once(b"palmer", b"pumper"), "`pumper` is not a model")
    refused(once(b"exact", b"exakt"), "precision")
    refused(once(struct.pack("<d", 30.0), struct.pack("<d", 0.0)), "fps 0 is not a whole number")
    refused(once(struct.pack("<d", 30.0), struct.pack("<d", 29.97)), "fps 29.97 is not a whole number")
    # The count of aircraft (bincode's variable-length integer: 0xfd, then
    # eight bytes) made a trillion: refused before anything is allocated.
    refused(once(b"exact\x01\x03", b"exact\x01\xfd" + struct.pack("<Q", 10**12)), "1000000000000 aircraft in")
    # Aircraft 1's height made NaN, its throttle (all three's) out of range.
    height = struct.pack("<d", fleet["z_m"][1])
    refused(once(height, struct.pack("<d", float("nan"))), "aircraft 1: the state is not finite")
    throttle = struct.pack("<d", 0.625)
    assert good.count(throttle) == 3
    refused(good.replace(throttle, struct.pack("<d", 1.5)), "aircraft 0: the controls: throttle")
