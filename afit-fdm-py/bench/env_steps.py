"""CPU time per aircraft-step of serial vector-env steps alone (BENCHMARKS.md,
"Run P10"): a benchmark and a target for ``perf record``, not a test.

Run as::

    RAYON_NUM_THREADS=1 python afit-fdm-py/bench/env_steps.py 100000 150
    MODEL=bourg RAYON_NUM_THREADS=1 python afit-fdm-py/bench/env_steps.py 100000 150

``AircraftVectorEnv(MODEL, "heading-altitude", num_envs=N, parallel=False)``
reset with seed 0, 20 warm-up steps, then ``STEPS`` timed calls of ``step``
with random actions in -0.3..0.3 (eight action arrays in turn, as
``cpu_share.py``); prints ``time.process_time`` per aircraft-step. With
``STEPS`` 0 nothing is timed: the same setup alone, to subtract from a
profile of a run with steps.
"""

import os
import sys
import time

import numpy as np

from afit_fdm.gym import AircraftVectorEnv

model = os.environ.get("MODEL", "palmer")
n = int(sys.argv[1])
steps = int(sys.argv[2])
env = AircraftVectorEnv(model, "heading-altitude", num_envs=n, max_episode_steps=10**9, parallel=False)
env.reset(seed=0)
rng = np.random.default_rng(0)
acts = rng.uniform(-0.3, 0.3, size=(8, n, env.single_action_space.shape[0])).astype(np.float32)
for k in range(20):
    env.step(acts[k % 8])
t = time.process_time()
for k in range(steps):
    env.step(acts[k % 8])
dt = time.process_time() - t
if steps:
    print(f"{model} n={n} steps={steps}: {dt / n / steps * 1e9:.1f} ns CPU per aircraft-step", flush=True)
