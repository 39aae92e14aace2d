"""Env-steps per second: afit_fdm's vector env against the Rust fleet alone,
JSBSim's Python module, a JSBSim Gymnasium environment from PyPI, and
Gymnasium's SyncVectorEnv over afit_fdm's single env (BENCHMARKS.md, "Python").

A benchmark, not a test: run it by hand on a quiet machine::

    pip install ./afit-fdm-py gymnasium==1.4.0 -r afit-fdm-py/bench/requirements.txt
    python afit-fdm-py/bench/bench_env.py --json results.json

Every figure is the median of ``--repeats`` timed runs (after one warm-up), as
env-steps (aircraft-steps at the agent rate) per second. The agent rate is
30 Hz everywhere: afit_fdm steps one 30 fps frame per env step; JSBSim's c172p
runs at 120 Hz, four model steps per env step; jsbgym's HeadingControlTask
integrates at 60 Hz, two JSBSim steps per env step.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from typing import Callable, Dict, List, Optional

import numpy as np


def median_rate(run: Callable[[], int], repeats: int) -> float:
    run()  # warm-up
    rates = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        steps = run()
        rates.append(steps / (time.perf_counter() - t0))
    return statistics.median(rates)


def bench_fleet(model: str, n: int, steps: int, repeats: int) -> float:
    import afit_fdm

    fleet = afit_fdm.Fleet(model, n, altitude_ft=2000.0, speed_kt=100.0, trim=True)

    def run() -> int:
        fleet.step(steps)
        return n * steps

    return median_rate(run, repeats)


def bench_vector(model: str, n: int, steps: int, repeats: int) -> float:
    from afit_fdm.gym import AircraftVectorEnv

    env = AircraftVectorEnv(model, "heading-altitude", num_envs=n, max_episode_steps=10**9)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-0.3, 0.3, size=(8, n, env.single_action_space.shape[0])).astype(np.float32)

    def run() -> int:
        for k in range(steps):
            env.step(actions[k % 8])
        return n * steps

    return median_rate(run, repeats)


def bench_sync(model: str, n: int, steps: int, repeats: int) -> float:
    from gymnasium.vector import SyncVectorEnv

    from afit_fdm.gym import AircraftEnv

    env = SyncVectorEnv([lambda: AircraftEnv(model, "heading-altitude", max_episode_steps=10**9) for _ in range(n)])
    env.reset(seed=0)
    env.action_space.seed(0)

    def run() -> int:
        for _ in range(steps):
            env.step(env.action_space.sample())
        return n * steps

    return median_rate(run, repeats)


def bench_flight_step(repeats: int) -> float:
    """Seconds per ``Flight.step()`` call from Python (one frame)."""
    import afit_fdm

    f = afit_fdm.Flight("palmer", altitude_ft=2000.0, speed_kt=100.0, trim=True)
    calls = 200_000

    def run() -> int:
        step = f.step
        for _ in range(calls):
            step()
        return calls

    return 1.0 / median_rate(run, repeats)


def bench_jsbsim(steps: int, repeats: int) -> Optional[float]:
    try:
        import jsbsim
    except ImportError:
        return None
    fdm = jsbsim.FGFDMExec(None)  # the aircraft shipped in the wheel
    fdm.set_debug_level(0)
    fdm.load_model("c172p")
    fdm.set_dt(1.0 / 120.0)
    fdm["ic/h-sl-ft"] = 2000.0
    fdm["ic/vc-kts"] = 100.0
    fdm["ic/psi-true-deg"] = 0.0
    fdm.run_ic()
    fdm["propulsion/set-running"] = -1
    rng = np.random.default_rng(0)

    def run() -> int:
        for _ in range(steps):
            fdm["fcs/aileron-cmd-norm"] = rng.uniform(-0.3, 0.3)
            fdm["fcs/elevator-cmd-norm"] = rng.uniform(-0.3, 0.3)
            fdm["fcs/throttle-cmd-norm"] = 0.7
            for _ in range(4):
                fdm.run()
        return steps

    return median_rate(run, repeats)


def bench_jsbgym(steps: int, repeats: int) -> Optional[float]:
    try:
        import gymnasium as gym
        import jsbgym  # noqa: F401  (registers its ids)
    except Exception:  # noqa: BLE001: missing or incompatible: "not measured"
        return None
    env_id = "C172-HeadingControlTask-Shaping.STANDARD-NoFG-v0"
    if env_id not in gym.registry:
        return None
    # jsbgym integrates at 60 Hz; a 30 Hz agent is 2 JSBSim steps per env step.
    env = gym.make(env_id, agent_interaction_freq=30)
    env.reset(seed=0)
    env.action_space.seed(0)

    def run() -> int:
        for _ in range(steps):
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                env.reset()
        return steps

    return median_rate(run, repeats)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 1000, 100_000])
    parser.add_argument("--sync-max", type=int, default=1000, help="largest SyncVectorEnv measured")
    parser.add_argument("--json", help="write the results here too")
    args = parser.parse_args()

    results: Dict[str, object] = {
        "machine": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
        "python": sys.version.split()[0],
        "load_before": os.getloadavg(),
    }
    rows: List[Dict[str, object]] = []
    for model in ("palmer", "bourg"):
        for n in args.sizes:
            steps = max(20, min(3000, 3_000_000 // n // 10))
            row: Dict[str, object] = {"model": model, "n": n}
            row["fleet"] = bench_fleet(model, n, steps, args.repeats)
            row["vector_env"] = bench_vector(model, n, steps, args.repeats)
            row["sync_vector_env"] = bench_sync(model, n, max(5, steps // 10), args.repeats) if n <= args.sync_max else None
            rows.append(row)
            print(json.dumps(row), flush=True)
    results["rows"] = rows
    results["flight_step_s"] = bench_flight_step(args.repeats)
    results["jsbsim_c172p"] = bench_jsbsim(2000, args.repeats)
    results["jsbgym"] = bench_jsbgym(2000, args.repeats)
    results["load_after"] = os.getloadavg()
    print(json.dumps({k: v for k, v in results.items() if k != "rows"}), flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
