"""``Flight`` against ``sim-cli``: every frame of the reference cases, bit for bit."""

from __future__ import annotations

import math
import subprocess
import pathlib
import struct
from typing import Dict, List, Optional

import pytest

import afit_fdm
from conftest import REPO, csv_rows, reference, run_csv

PALMER_COLUMNS = {
    "time_s": "time_s",
    "x": "x_m",
    "y": "y_m",
    "z": "z_m",
    "vx": "vx_mps",
    "vy": "vy_mps",
    "vz": "vz_mps",
}
BOURG_COLUMNS = {
    "time_s": "time_s",
    "x": "x_ft",
    "y": "y_ft",
    "z": "z_ft",
    "vx": "vx_ftps",
    "vy": "vy_ftps",
    "vz": "vz_ftps",
    "speed": "speed_ftps",
    "euler_x_deg": "euler_x_deg",
    "euler_y_deg": "euler_y_deg",
    "euler_z_deg": "euler_z_deg",
    "stalling": "stalling",
}


def bits(x: float) -> int:
    return struct.unpack("<q", struct.pack("<d", x))[0]


def same(a: float, b: float) -> bool:
    """Equal bits (``-0.0`` and ``0.0`` differ; ``sim-cli`` prints ``-0``)."""
    return bits(a) == bits(b)


def fly_rows(flight: afit_fdm.Flight, frames: int) -> List[Dict[str, float]]:
    rows = [row_of(flight)]
    for _ in range(frames):
        flight.step()
        rows.append(row_of(flight))
    return rows


def row_of(flight: afit_fdm.Flight) -> Dict[str, float]:
    row: Dict[str, float] = dict(flight.state)
    row.update(flight.controls)
    row["status"] = float(flight.status_code)
    row["airspeed_mps"] = float(flight.view["airspeed_mps"])
    return row


def compare(cli: List[Dict[str, float]], ours: List[Dict[str, float]], model: str) -> None:
    assert len(cli) == len(ours)
    columns = dict(PALMER_COLUMNS if model == "palmer" else BOURG_COLUMNS)
    if model == "palmer":
        columns.update(
            throttle="throttle",
            alpha_deg="alpha_deg",
            bank_deg="bank_deg",
            flaps_deg="flaps_deg",
            airspeed="airspeed_mps",
        )
    else:
        columns.update(thrust_lb="thrust_lb", flaps="landing_flaps", pitch_trim="pitch_trim")
    for frame, (a, b) in enumerate(zip(cli, ours)):
        for cli_name, our_name in columns.items():
            assert same(a[cli_name], b[our_name]), (
                f"frame {frame} {cli_name}: sim-cli {a[cli_name]!r}, Flight {b[our_name]!r}"
            )
        # The CSV's 6 is "airborne, stalling" (a report code, not a flight status).
        cli_status = 1.0 if a["status"] == 6.0 else a["status"]
        assert cli_status == b["status"], f"frame {frame} status"


PALMER_CASES = reference("palmer.json")["cases"]
BOURG_CASES = reference("bourg.json")["cases"]


@pytest.mark.parametrize("case", PALMER_CASES, ids=[c["name"] for c in PALMER_CASES])
def test_palmer_reference_cases_match_sim_cli(sim_cli: pathlib.Path, tmp_path: pathlib.Path, case: dict) -> None:
    c = case["controls"]
    args = [
        "palmer", "--fps", "10", "--frames", "600",
        "--throttle", repr(c["throttle"]), "--alpha", repr(c["alpha"]),
        "--bank", repr(c["bank"]), "--flaps", str(c["flaps"]),
    ]
    flight = afit_fdm.Flight(
        "palmer", fps=10, throttle=c["throttle"], alpha_deg=c["alpha"],
        bank_deg=c["bank"], flaps_deg=c["flaps"],
    )
    compare(run_csv(sim_cli, args, tmp_path), fly_rows(flight, 600), "palmer")
    # And the C program's final state (the reference file's own bar).
    want = case["final"]
    assert abs(flight.state["x_m"] - want["position"][0]) < 1e-9


@pytest.mark.parametrize("case", BOURG_CASES, ids=[c["name"] for c in BOURG_CASES])
def test_bourg_reference_cases_match_sim_cli(sim_cli: pathlib.Path, tmp_path: pathlib.Path, case: dict) -> None:
    script = "\n".join(case["script"]) + "\n"
    path = tmp_path / "script.txt"
    path.write_text(script, encoding="utf-8")
    args = ["bourg", "--fps", "30", "--frames", "900", "--script", str(path)]
    flight = afit_fdm.Flight("bourg", fps=30, script=script)
    compare(run_csv(sim_cli, args, tmp_path), fly_rows(flight, 900), "bourg")
    want = case["cpp_final_full_precision"]["position_ft"]
    got = [flight.state[k] for k in ("x_ft", "y_ft", "z_ft")]
    assert got == [struct.unpack("<f", struct.pack("<f", w))[0] for w in want]


STARTS = [
    ("palmer", ["--altitude-ft", "2000", "--speed-kt", "100", "--trim"], dict(altitude_ft=2000.0, speed_kt=100.0, trim=True), 900),
    ("palmer", ["--altitude-ft", "300", "--speed-kt", "80", "--heading-deg", "45", "--throttle", "0.2", "--alpha", "-6"], dict(altitude_ft=300.0, speed_kt=80.0, heading_deg=45.0, throttle=0.2, alpha_deg=-6.0), 900),
    ("bourg", ["--altitude-ft", "3000", "--speed-kt", "90", "--trim"], dict(altitude_ft=3000.0, speed_kt=90.0, trim=True), 600),
    ("bourg", ["--heading-deg", "270", "--thrust-lb", "1200"], dict(heading_deg=270.0, thrust_lb=1200.0), 600),
]


@pytest.mark.parametrize("model,args,kwargs,frames", STARTS)
def test_starts_and_trim_match_sim_cli(sim_cli, tmp_path, model, args, kwargs, frames) -> None:
    flight = afit_fdm.Flight(model, fps=30, **kwargs)
    cli = run_csv(sim_cli, [model, "--fps", "30", "--frames", str(frames), *args], tmp_path)
    compare(cli, fly_rows(flight, frames), model)


def test_palmer_takeoff_turn_landing_script_matches_sim_cli(sim_cli, tmp_path) -> None:
    # The example script, then throttle to idle and nose down: it lands or crashes.
    script = (REPO / "examples" / "scripts" / "palmer_climb_turn.txt").read_text(encoding="utf-8")
    script += "2401-2420 throttle-down\n2401-2430 alpha-down\n"
    path = tmp_path / "s.txt"
    path.write_text(script, encoding="utf-8")
    flight = afit_fdm.Flight("palmer", fps=30, script=script)
    cli = run_csv(sim_cli, ["palmer", "--fps", "30", "--frames", "4500", "--script", str(path)], tmp_path)
    rows = fly_rows(flight, 4500)
    compare(cli, rows, "palmer")
    assert flight.status in ("landed_safe", "landed_rough", "crashed")


def test_actions_given_to_step_are_key_presses(sim_cli, tmp_path) -> None:
    # step(actions=...) on frames 1..5 is the script "1-5 thrust-up".
    a = afit_fdm.Flight("bourg", fps=30)
    b = afit_fdm.Flight("bourg", fps=30, script="1-5 thrust-up\n")
    a.step(5, actions=["thrust-up"])
    b.step(5)
    a.step(100)
    b.step(100)
    assert a.state == b.state and a.controls == b.controls
    assert a.controls["thrust_lb"] == 1000.0


def test_reset_flies_the_same_bits_again() -> None:
    f = afit_fdm.Flight("palmer", fps=30, throttle=1.0, alpha_deg=5.0, script="100-110 bank-right\n")
    f.step(300)
    first = f.state
    f.reset()
    assert f.frame == 0 and f.state["x_m"] == 0.0 and f.status == "on_ground"
    f.step(300)
    assert f.state == first


def test_bad_arguments_raise_naming_them() -> None:
    with pytest.raises(ValueError, match="model"):
        afit_fdm.Flight("cessna")
    with pytest.raises(ValueError, match="fps"):
        afit_fdm.Flight("palmer", fps=0)
    with pytest.raises(ValueError, match="throttle"):
        afit_fdm.Flight("palmer", throttle=1.5)
    with pytest.raises(ValueError, match="alpha_deg"):
        afit_fdm.Flight("palmer", alpha_deg=math.nan)
    with pytest.raises(ValueError, match="flaps_deg"):
        afit_fdm.Flight("palmer", flaps_deg=10)
    with pytest.raises(TypeError, match="thrust_lb"):
        afit_fdm.Flight("palmer", thrust_lb=10)
    with pytest.raises(TypeError, match="throttle"):
        afit_fdm.Flight("palmer", throttle="full")
    with pytest.raises(ValueError, match="altitude_ft"):
        afit_fdm.Flight("palmer", altitude_ft=-1.0)
    with pytest.raises(ValueError, match="trim"):
        afit_fdm.Flight("palmer", altitude_ft=2000.0, speed_kt=20.0, trim=True)
    with pytest.raises(ValueError, match="trim"):
        afit_fdm.Flight("palmer", trim=True)
    with pytest.raises(ValueError, match="thrust_lb"):
        afit_fdm.Flight("bourg", altitude_ft=2000.0, trim=True, thrust_lb=100.0)
    with pytest.raises(ValueError, match="script"):
        afit_fdm.Flight("palmer", script="3-2 throttle-up\n")
    f = afit_fdm.Flight("palmer")
    with pytest.raises(ValueError, match="actions"):
        f.step(1, actions=["warp"])
    assert f.frame == 0
    with pytest.raises(ValueError, match="bank_deg"):
        f.set_controls(bank_deg=45.0)


def test_divergence_keeps_the_last_finite_state(sim_cli, tmp_path) -> None:
    # Bourg's explicit Euler at 1 frame per second with 3000 lb of thrust blows up.
    f = afit_fdm.Flight("bourg", fps=1, script="1-30 thrust-up\n")
    f.step(2000)
    assert f.status == "diverged" and f.status_code == afit_fdm.Status.DIVERGED
    assert all(math.isfinite(v) for v in f.state.values())
    frozen = f.state
    f.step(10)
    assert f.state == frozen and f.frame == 2010
    # sim-cli stops at the same frame: its rows are ours up to the divergence.
    path = tmp_path / "s.txt"
    path.write_text("1-30 thrust-up\n", encoding="utf-8")
    proc = subprocess.run(
        [str(sim_cli), "bourg", "--fps", "1", "--headless", "--frames", "2000",
         "--script", str(path), "--csv", str(tmp_path / "d.csv")],
        capture_output=True, text=True,
    )
    assert proc.returncode == 1 and "diverged" in proc.stderr
    rows = csv_rows((tmp_path / "d.csv").read_text(encoding="utf-8"), "bourg")
    g = afit_fdm.Flight("bourg", fps=1, script="1-30 thrust-up\n")
    g.step(len(rows) - 1)
    assert g.status != "diverged" and g.state["x_ft"] == float(rows[-1]["x"])
    g.step()
    assert g.status == "diverged"


def test_view_and_fields_have_units_in_their_names() -> None:
    f = afit_fdm.Flight("bourg")
    assert set(afit_fdm.MODELS) == {"palmer", "bourg"}
    assert list(f.state) == afit_fdm.MODELS["bourg"]["state_fields"]
    v = f.view
    assert v["z_m"] == pytest.approx(2000 * 0.3048, rel=1e-6)
    assert {"airspeed_mps", "alpha_deg", "heading_deg", "engine_rpm"} <= set(v)
    assert f.actions == afit_fdm.MODELS["bourg"]["actions"]
    assert afit_fdm.Status(f.status_code).name == "AIRBORNE"


def test_palmer_wheel_brakes_hold_and_are_checked() -> None:
    # The wheel brakes (docs/palmer-model.md): at rest on the runway they hold
    # the aircraft against full power, exactly (tolerance 0: the friction
    # cancels the thrust); released, the take-off roll starts.
    held = afit_fdm.Flight("palmer", throttle=1.0, brakes=1.0)
    assert held.controls["brakes"] == 1.0
    for _ in range(30):
        held.step()
    assert held.state["x_m"] == 0.0 and held.state["vx_mps"] == 0.0
    free = afit_fdm.Flight("palmer", throttle=1.0)
    assert free.controls["brakes"] == 0.0
    for _ in range(30):
        free.step()
    assert free.state["x_m"] > 1.0
    assert "brakes-on" in free.actions and "brakes-off" in free.actions
    with pytest.raises(ValueError, match="brakes"):
        afit_fdm.Flight("palmer", brakes=0.5)
