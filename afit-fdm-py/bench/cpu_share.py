"""CPU time per aircraft-step of the vector env against the Rust fleet alone,
on one thread (BENCHMARKS.md, "Run P3"): a benchmark, not a test.

On a shared machine the wall-clock rates of ``bench_env.py`` move with the
other load; the CPU time of one thread moves much less. Run as::

    PAR=0 RAYON_NUM_THREADS=1 python afit-fdm-py/bench/cpu_share.py 100000 3

``PAR=0`` makes the fleet and the env serial (``parallel=False``). For each
model: ``Fleet.step(steps)`` and ``steps`` calls of ``AircraftVectorEnv.step``
with random actions in -0.3..0.3 (the steps as ``bench_env.py`` chooses them),
interleaved, ``repeats`` times; medians of ``time.process_time`` (every
thread of the process) per aircraft-step, and of the wall clock.
"""

import os
import statistics
import sys
import time

import numpy as np

import afit_fdm
from afit_fdm.gym import AircraftVectorEnv

PAR = bool(int(os.environ.get("PAR", "1")))
n = int(sys.argv[1])
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 5
for model in ["palmer", "bourg"]:
    steps = max(20, min(3000, 3_000_000 // n // 10))
    env = AircraftVectorEnv(model, "heading-altitude", num_envs=n, max_episode_steps=10**9, parallel=PAR)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    acts = rng.uniform(-0.3, 0.3, size=(8, n, env.single_action_space.shape[0])).astype(np.float32)
    fleet = afit_fdm.Fleet(model, n, altitude_ft=2000.0, speed_kt=100.0, trim=True, parallel=PAR)

    def envrun() -> None:
        for k in range(steps):
            env.step(acts[k % 8])

    def fleetrun() -> None:
        fleet.step(steps)

    envrun()
    fleetrun()
    fe, ee, fw, ew = [], [], [], []
    for _ in range(reps):
        for f, c, w in ((fleetrun, fe, fw), (envrun, ee, ew)):
            t = time.process_time()
            t2 = time.perf_counter()
            f()
            c.append(time.process_time() - t)
            w.append(time.perf_counter() - t2)
    m = statistics.median
    print(
        f"{model} n={n}: CPU ns/aircraft-step fleet {m(fe) / n / steps * 1e9:.1f} env {m(ee) / n / steps * 1e9:.1f} "
        f"cpu-share {m(fe) / m(ee):.2f} | wall M/s fleet {n * steps / m(fw) / 1e6:.2f} env {n * steps / m(ew) / 1e6:.2f} "
        f"wall-share {m(fw) / m(ew):.2f}",
        flush=True,
    )
