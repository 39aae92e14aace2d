"""Where a vector-env step's CPU time goes, on one thread (BENCHMARKS.md,
"Run P13"): a benchmark, not a test. Run as::

    RAYON_NUM_THREADS=1 python afit-fdm-py/bench/env_split.py 100000 30 5 palmer bourg

Arguments: aircraft, steps per round, rounds, models. For each model, CPU ns
per aircraft-step (``time.process_time``; medians of the rounds, the five
parts interleaved in each round) of:

* ``kernel``: the fleet alone, ``Fleet.step(steps)`` (the issue's figure (a));
* ``step(1)``: ``Fleet.step(1)`` once per step (the views refreshed every frame);
* ``act+fly``: ``Fleet.task_step(..., observe=False)``: the actions set as the
  controls and one frame flown;
* ``act+fly+obs``: ``Fleet.task_step(..., views=False)``, as the env steps;
* ``env.step``: ``AircraftVectorEnv.step``, the task step and the Python
  around it.

Random actions in -0.3..0.3 (as ``bench_env.py``); fleet and env serial.
"""

import statistics
import sys
import time
from typing import Callable, Dict, List

import numpy as np

import afit_fdm
from afit_fdm.gym import AircraftVectorEnv

n, steps, rounds = (int(a) for a in sys.argv[1:4])
for model in sys.argv[4:]:
    env = AircraftVectorEnv(model, "heading-altitude", num_envs=n, max_episode_steps=10**9, parallel=False)
    env.reset(seed=0)
    task = env._task
    rng = np.random.default_rng(0)
    actions = rng.uniform(-0.3, 0.3, size=(8, n, env.single_action_space.shape[0])).astype(np.float32)
    fleet = afit_fdm.Fleet(model, n, altitude_ft=2000.0, speed_kt=100.0, trim=True, parallel=False)
    out = task._outputs()
    counts = env._steps

    def task_steps(observe: bool) -> None:
        for k in range(steps):
            task.fleet.task_step(
                actions[k % 8], 1, task.task, task.target_alt_ft, task.target_heading_deg,
                counts, 10**9, *out, observe=observe, views=False,
            )

    def frames() -> None:
        for _ in range(steps):
            fleet.step(1)

    def env_steps() -> None:
        for k in range(steps):
            env.step(actions[k % 8])

    parts: Dict[str, Callable[[], None]] = {
        "kernel": lambda: fleet.step(steps),
        "step(1)": frames,
        "act+fly": lambda: task_steps(False),
        "act+fly+obs": lambda: task_steps(True),
        "env.step": env_steps,
    }
    cpu: Dict[str, List[float]] = {name: [] for name in parts}
    for part in parts.values():
        part()
    for _ in range(rounds):
        for name, part in parts.items():
            start = time.process_time()
            part()
            cpu[name].append(time.process_time() - start)
    print(model, " ".join(f"{name} {statistics.median(v) / n / steps * 1e9:.1f}" for name, v in cpu.items()), flush=True)
