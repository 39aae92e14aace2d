"""Recordings from Python: ``Flight.record_to`` and ``afit_fdm.replay`` against
``sim-cli --record`` and ``sim-cli replay``, bit for bit (tolerance 0: the CLI
prints every float in its shortest round-trip form, so ``float`` of its text
is the exact value)."""

from __future__ import annotations

import gc
import json
import pathlib
import subprocess
from typing import Dict, List

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import afit_fdm
from conftest import REPO, csv_rows
from test_flight import compare, row_of, same

GOLDEN = REPO / "sim-cli" / "tests" / "golden"


def read_csv(path: pathlib.Path, model: str) -> List[Dict[str, float]]:
    """A flight CSV written by ``model`` (its first line says so), every
    number parsed with ``float``."""
    text = path.read_text(encoding="utf-8")
    return [{k: float(v) for k, v in row.items()} for row in csv_rows(text, model)]


def trajectory_rows(replay: afit_fdm.Replay) -> List[Dict[str, float]]:
    """The replay's trajectory as the rows ``test_flight.compare`` reads."""
    t = replay.trajectory
    assert t is not None
    n = len(t["frame"])
    rows = []
    for i in range(n):
        row = {k: float(v[i]) for k, v in t.items()}
        rows.append(row)
    return rows


def compare_csv(cli: List[Dict[str, float]], ours: List[Dict[str, float]], model: str) -> None:
    """Every row of a trajectory: frame number, state, controls and status,
    bit for bit (``test_flight.compare``)."""
    assert [r["frame"] for r in cli] == [r["frame"] for r in ours]
    if model == "palmer":
        # compare() also checks the CSV's airspeed against Flight.view's; a
        # trajectory holds the state and controls, not the view (the
        # airspeed follows from the state): leave that column out here.
        cli = [dict(r, airspeed=0.0) for r in cli]
        ours = [dict(r, airspeed_mps=0.0) for r in ours]
    compare(cli, ours, model)


@pytest.mark.parametrize("model", ["palmer", "bourg"])
@pytest.mark.parametrize("version", [1, 2, 3])
def test_golden_cli_recordings_replay_to_the_committed_csv_and_json(model: str, version: int) -> None:
    """sim-cli's committed recordings (sim-cli/tests/golden, made by
    ``sim-cli MODEL --record``; golden.rs keeps them current) replay from
    Python to the rows and report ``sim-cli replay`` printed for them."""
    stem = GOLDEN / f"{model}_v{version}"
    replay = afit_fdm.replay(stem.with_suffix(".rec"), trajectory=True)
    report = json.loads(stem.with_suffix(".replay.json").read_text(encoding="utf-8"))
    assert (replay.model, replay.fps, replay.frames) == (model, report["fps"], report["frames"])
    compare_csv(read_csv(stem.with_suffix(".replay.csv"), model), trajectory_rows(replay), model)
    final = replay.flight.state
    keys = ("x_m", "y_m", "z_m") if model == "palmer" else ("x_ft", "y_ft", "z_ft")
    assert all(same(final[k], v) for k, v in zip(keys, report["position"]))
    assert replay.flight.status == report["status"]
    # Versions 1 and 2 carry no fingerprint; version 3's matches.
    assert replay.same_final_state == (True if version == 3 else None)


def test_golden_bytes_and_path_agree_and_flight_flies_on() -> None:
    path = GOLDEN / "palmer_v3.rec"
    a = afit_fdm.replay(str(path))
    b = afit_fdm.replay(path.read_bytes())
    assert a.flight.state == b.flight.state
    assert a.origin == (37.6, -122.4, 4.0)
    frame = a.flight.frame
    a.flight.step(10)
    assert a.flight.frame == frame + 10
    a.flight.reset()
    assert a.flight.frame == 0
    # reset() goes back to the recording's start: the trajectory's row 0.
    t = afit_fdm.replay(path, trajectory=True).trajectory
    assert t is not None
    assert all(same(v, float(t[k][0])) for k, v in a.flight.state.items())


def fly_recorded(model: str, path: pathlib.Path) -> List[Dict[str, float]]:
    """A flight from Python with a trimmed start, a script, step actions and
    two resets, recorded to ``path``; returns its rows as ``sim-cli replay
    --csv`` writes them (frame 0, each frame, frame 0 after each reset)."""
    if model == "palmer":
        flight = afit_fdm.Flight(
            "palmer", fps=60, altitude_ft=2000.0, speed_kt=100.0, trim=True,
            flaps_deg=20.0, script="10-14 throttle-up\n30-45 bank-right\n",
        )
        keys = [["alpha-up"], ["bank-left", "throttle-down"], []]
    else:
        flight = afit_fdm.Flight(
            "bourg", fps=30, altitude_ft=3000.0, speed_kt=90.0, trim=True,
            script="1-5 thrust-up\n6-40 pitch-up\n",
        )
        keys = [["roll-right"], ["yaw-left", "thrust-down"], []]
    flight.record_to(path, origin=(47.5, 11.2, 700.0))
    assert flight.recording == str(path)
    rows = [dict(row_of(flight), frame=0.0)]

    def fly(n: int, actions: List[str]) -> None:
        for _ in range(n):
            flight.step(1, actions)
            rows.append(dict(row_of(flight), frame=float(flight.frame)))

    fly(40, [])
    fly(7, keys[0])
    flight.reset()
    rows.append(dict(row_of(flight), frame=0.0))
    fly(25, keys[1])
    flight.step(30, keys[2])  # several frames in one call
    rows.append(dict(row_of(flight), frame=float(flight.frame)))
    flight.reset()
    rows.append(dict(row_of(flight), frame=0.0))
    fly(20, [])
    assert flight.stop_recording() == 40 + 7 + 25 + 30 + 20
    assert flight.recording is None
    return rows


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_a_python_recording_replays_in_sim_cli_to_the_same_states(sim_cli, tmp_path, model) -> None:
    rec = tmp_path / f"{model}.rec"
    rows = fly_recorded(model, rec)
    out_csv = tmp_path / "replay.csv"
    proc = subprocess.run(
        [str(sim_cli), "replay", str(rec), "--json", "--csv", str(out_csv)],
        capture_output=True, text=True,
    )
    # Exit 0: sim-cli also compared its final state with the recording's
    # fingerprint (a different flight exits 4).
    assert proc.returncode == 0, proc.stderr
    assert "note" not in proc.stderr and "warning" not in proc.stderr, proc.stderr
    report = json.loads(proc.stdout)
    assert report["frames"] == 122
    cli = read_csv(out_csv, model)
    # Rows with a step of several frames in one call: only its last frame
    # was seen from Python; the CLI wrote them all.
    by_key = {}
    for r in cli:
        by_key.setdefault(r["frame"], []).append(r)
    picked = []
    seen: Dict[float, int] = {}
    for r in rows:
        k = r["frame"]
        i = seen.get(k, 0)
        seen[k] = i + 1
        picked.append(by_key[k][i])
    assert len(cli) == 1 + 40 + 7 + 1 + 25 + 30 + 1 + 20
    compare(picked, rows, model)
    # And Python's own replay: every row of the CLI's CSV.
    replay = afit_fdm.replay(rec, trajectory=True)
    assert replay.same_final_state is True and replay.same_maths is True
    assert (replay.frames, replay.resets, replay.origin) == (122, 2, (47.5, 11.2, 700.0))
    compare_csv(cli, trajectory_rows(replay), model)


def test_what_cannot_be_recorded_is_refused(tmp_path) -> None:
    f = afit_fdm.Flight("palmer", altitude_ft=1000.0, speed_kt=90.0, trim=True)
    f.step()
    with pytest.raises(ValueError, match="at frame 1; call reset"):
        f.record_to(tmp_path / "a.rec")
    f.reset()
    f.set_controls(throttle=0.3)
    with pytest.raises(ValueError, match="controls set by value"):
        f.record_to(tmp_path / "a.rec")
    f.reset()
    f.record_to(tmp_path / "a.rec")
    with pytest.raises(ValueError, match="already recording"):
        f.record_to(tmp_path / "b.rec")
    before = f.controls
    with pytest.raises(ValueError, match="cannot be recorded"):
        f.set_controls(throttle=0.3)
    assert f.controls == before
    f.step(3)
    assert f.stop_recording() == 3
    with pytest.raises(ValueError, match="not recording"):
        f.stop_recording()
    # After stopping, set_controls works again.
    f.set_controls(throttle=0.3)
    with pytest.raises(OSError):
        afit_fdm.Flight("palmer").record_to(tmp_path / "no" / "such" / "dir.rec")
    with pytest.raises(ValueError, match="origin"):
        afit_fdm.Flight("palmer").record_to(tmp_path / "c.rec", origin=(95.0, 0.0, 0.0))
    assert afit_fdm.replay(tmp_path / "a.rec").frames == 3


def test_a_flight_dropped_while_recording_seals_its_recording(tmp_path) -> None:
    f = afit_fdm.Flight("bourg", script="1-3 thrust-up\n")
    f.record_to(tmp_path / "d.rec")
    f.step(45)
    want = f.state
    del f
    gc.collect()
    r = afit_fdm.replay(tmp_path / "d.rec")
    assert r.frames == 45 and r.same_final_state is True
    assert r.flight.state == want


def test_damaged_recordings_raise_recording_error_naming_the_problem(tmp_path) -> None:
    good = (GOLDEN / "palmer_v3.rec").read_bytes()
    with pytest.raises(afit_fdm.RecordingError, match="not a sim-cli recording"):
        afit_fdm.replay(b"hello world")
    v9 = bytearray(good)
    v9[8] = 9
    with pytest.raises(afit_fdm.RecordingError, match="format version 9"):
        afit_fdm.replay(bytes(v9))
    with pytest.raises(afit_fdm.RecordingError, match="truncated"):
        afit_fdm.replay(good[:-5])
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x01
    with pytest.raises(afit_fdm.RecordingError):
        afit_fdm.replay(bytes(flipped))
    assert issubclass(afit_fdm.RecordingError, ValueError)
    with pytest.raises(FileNotFoundError):
        afit_fdm.replay(tmp_path / "missing.rec")
    with pytest.raises(TypeError):
        afit_fdm.replay(3)  # type: ignore[arg-type]


GOOD = {m: (GOLDEN / f"{m}_v3.rec").read_bytes() for m in ("palmer", "bourg")}


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.binary(max_size=2048))
def test_arbitrary_bytes_raise_recording_error_never_crash(data: bytes) -> None:
    with pytest.raises(afit_fdm.RecordingError):
        afit_fdm.replay(data)


@settings(max_examples=300, deadline=None)
@given(
    st.sampled_from(["palmer", "bourg"]),
    st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 255), st.integers(0, 2)), min_size=1, max_size=5),
    st.integers(0, 10**6),
)
def test_mangled_recordings_are_refused_or_are_the_original(model, edits, cut) -> None:
    """A recording with bytes overwritten, inserted or removed, and maybe
    cut: a RecordingError, or (an edit that changed nothing) the original
    flight."""
    original = GOOD[model]
    data = bytearray(original)
    for at, byte, kind in edits:
        i = at % len(data)
        if kind == 0:
            data[i] = byte
        elif kind == 1:
            data.insert(i, byte)
        elif len(data) > 1:
            del data[i]
    if cut % 3 == 0:
        data = data[: cut % (len(data) + 1)]
    try:
        r = afit_fdm.replay(bytes(data))
    except afit_fdm.RecordingError:
        return
    assert bytes(data) == original
    assert r.same_final_state is True


def test_a_cut_recording_is_refused_with_where_it_was_cut_or_salvaged(sim_cli, tmp_path) -> None:
    """A recording cut before its end marker (its recording run killed)
    raises RecordingCutError with sim-cli replay's words (where, how many
    frames are intact); ``salvage=True`` flies those frames, the rows
    ``sim-cli replay --csv`` writes for the same cut file (which exits 3)."""
    f = afit_fdm.Flight("palmer", fps=30, script="1-40 throttle-up\n10-30 alpha-up\n")
    full = tmp_path / "full.rec"
    f.record_to(full)
    for i in range(100):  # a new event every frame: blocks of 30 frames
        f.step(1, ["bank-right"] if i % 2 else ["bank-left"])
    f.reset()
    f.step(75)
    assert f.stop_recording() == 175
    data = full.read_bytes()
    cut_file = tmp_path / "cut.rec"
    cut_file.write_bytes(data[: len(data) - 100])
    with pytest.raises(afit_fdm.RecordingCutError) as info:
        afit_fdm.replay(cut_file)
    err = info.value
    assert isinstance(err, afit_fdm.RecordingError) and isinstance(err, ValueError)
    assert str(err).startswith(f"{cut_file}: cut at byte {err.at_byte} before its end marker")
    assert f"the {err.frames} frames before the cut are intact" in str(err)
    assert 0 < err.frames < 175 and 0 < err.at_byte < len(data)
    # sim-cli replay salvages the same frames and says the same.
    proc = subprocess.run([str(sim_cli), "replay", str(cut_file), "--csv", str(tmp_path / "cut.csv")],
                          capture_output=True, text=True)
    assert proc.returncode == 3, proc.stderr
    assert f"cut at byte {err.at_byte} before its end marker; the {err.frames} frames" in proc.stderr
    r = afit_fdm.replay(cut_file, trajectory=True, salvage=True)
    assert r.cut == (err.at_byte, err.frames) and r.frames == err.frames
    assert r.same_final_state is None
    compare_csv(read_csv(tmp_path / "cut.csv", "palmer"), trajectory_rows(r), "palmer")
    # Bytes name no file; a complete recording has no cut.
    with pytest.raises(afit_fdm.RecordingCutError, match="^the recording: cut at byte"):
        afit_fdm.replay(cut_file.read_bytes())
    assert afit_fdm.replay(full, salvage=True).cut is None


def test_a_replay_stops_at_the_diverged_frame_as_sim_cli_replay(sim_cli, tmp_path) -> None:
    """Bourg at 1 fps with full thrust diverges; a recording of that flight
    (Python's flight flies on, frozen, past the divergence) replays up to the
    diverged frame and stops there with ReplayDivergedError, as sim-cli
    replay stops (exit 1, the same frame in its message; its CSV the
    trajectory's rows)."""
    f = afit_fdm.Flight("bourg", fps=1, script="1-30 thrust-up\n")
    path = tmp_path / "d.rec"
    f.record_to(path)
    f.step(2000)
    assert f.status == "diverged"
    f.stop_recording()
    with pytest.raises(afit_fdm.ReplayDivergedError) as info:
        afit_fdm.replay(path, trajectory=True)
    err = info.value
    assert isinstance(err, ValueError)
    frame = err.frame
    assert 0 < frame < 2000
    assert str(err) == f"frame {frame}: the bourg model diverged (non-finite state) at dt = 1.0 s"
    replay = err.replay
    assert replay.flight.frame == frame and replay.flight.status == "diverged"
    assert replay.same_final_state is None
    proc = subprocess.run([str(sim_cli), "replay", str(path), "--csv", str(tmp_path / "d.csv")],
                          capture_output=True, text=True)
    assert proc.returncode == 1
    assert f"frame {frame}: the bourg model diverged" in proc.stderr
    rows = read_csv(tmp_path / "d.csv", "bourg")
    assert len(rows) == frame
    compare_csv(rows, trajectory_rows(replay), "bourg")
