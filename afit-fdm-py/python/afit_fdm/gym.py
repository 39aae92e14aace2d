"""Gymnasium environments over :class:`afit_fdm.Fleet`.

:class:`AircraftEnv` is one aircraft (a ``gymnasium.Env``);
:class:`AircraftVectorEnv` is ``num_envs`` aircraft stepped together by the
fleet kernels (a native ``gymnasium.vector.VectorEnv``, not a loop of single
environments). Both run the same task code on NumPy columns, so a vector env
and ``SyncVectorEnv`` over the single env give the same numbers, bit for bit,
from the same seeds (tested).

Registered ids (``gymnasium.make`` / ``gymnasium.make_vec``)::

    afit_fdm/PalmerHeadingAltitude-v0   afit_fdm/PalmerClimb-v0
    afit_fdm/BourgHeadingAltitude-v0    afit_fdm/BourgClimb-v0

**Agent rate.** Each ``step`` flies ``frame_skip`` model frames at ``fps``
frames per second (defaults 30 and 1: a 30 Hz agent).

**Actions** (``Box(-1, 1)``, float32, scaled to the thesis's controls):

* Palmer, 4 values: throttle ``(a0 + 1) / 2`` (0..1); angle of attack
  ``2 + 18 a1`` degrees (-16..20); bank ``20 a2`` degrees (-20..20, positive
  right); flaps 0, 20 or 40 degrees for ``a3`` below -1/3, up to 1/3, above.
* Bourg, 5 values: thrust ``1500 (a0 + 1)`` lb (0..3000); elevator, aileron,
  rudder from ``a1, a2, a3``: -1 below -1/3, +1 above 1/3, else 0 (Bourg's
  surfaces are all-or-nothing; +1 is pitch up, roll right, yaw right); pitch
  trim ``a4`` (-1..1). Landing flaps stay up.

**Observations** (``Box(-10, 10)``, float32, clipped), both models:
altitude error (target minus altitude) / 1000 ft, heading error (target minus
track, wrapped to -180..180) / 180 degrees, climb rate / 20 ft/s, ground speed
/ 200 kt, sine and cosine of the track (0 and 1 when not moving), then the controls as set (Palmer:
throttle, alpha / 20, bank / 20, flaps / 40; Bourg: thrust / 3000, elevator,
aileron, rudder, pitch trim). Track and speeds come from the velocity (no
wind).

**Tasks**:

* ``heading-altitude``: start level at 1,500 to 2,500 ft, 90 to 110 kt, any
  heading, trimmed; hold a target altitude within 300 ft and a heading within
  30 degrees of the start. Reward each step: ``1 - 0.5 min(|alt err| / 500
  ft, 1) - 0.5 min(|heading err| / 45 deg, 1)``, in 0..1.
* ``climb``: start level at 1,000 to 1,500 ft, 90 to 100 kt, trimmed; climb to
  and level off at a target 1,000 to 2,000 ft higher. Reward: ``1 - 0.7
  min(|alt err| / 1000 ft, 1) - 0.3 min(|climb rate| / 10 ft/s, 1)`` once
  within 200 ft of the target, else ``0.3 (1 - min(|alt err| / 2000 ft, 1))``.

**Termination**: the aircraft touches the ground (landed, crashed) or its
model diverged (reward 0 that step; ``info["status"]`` says which).
**Truncation**: ``max_episode_steps`` steps (default 1,800: 60 s at 30 Hz).

**Seeding**: ``reset(seed=s)`` draws the start and target of aircraft ``i``
from ``numpy.random.Generator(PCG64(s + i))`` (Gymnasium's
``seeding.np_random``), as ``SyncVectorEnv`` seeds its sub-environments, and
later resets continue each aircraft's generator: rollouts repeat bit for bit.

**Autoreset** (vector env; ``metadata["autoreset_mode"]``, chosen with
``autoreset_mode=``): ``NEXT_STEP`` (default; the step after an episode
ends resets those aircraft, ignoring their actions, reward 0), ``SAME_STEP``
(reset at once; ``info["final_obs"]``, ``info["final_info"]`` and their
``_final_obs`` masks hold the last observation), ``DISABLED`` (the caller
resets with ``reset(options={"reset_mask": mask})``).
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np
import gymnasium
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from . import Fleet, Status

FT_PER_M = 1.0 / 0.3048
KT_PER_MPS = 3600.0 / 1852.0
TASKS = ("heading-altitude", "climb")
OBS_LIMIT = 10.0
AIRBORNE = int(Status.AIRBORNE)


def _surface(a: np.ndarray) -> np.ndarray:
    return np.where(a > 1.0 / 3.0, 1.0, np.where(a < -1.0 / 3.0, -1.0, 0.0))


class _Task:
    """The task's numbers for ``n`` aircraft of ``model``: starts, actions,
    observations, rewards. Everything is vectorised over aircraft."""

    def __init__(self, model: str, task: str, n: int, fps: int, frame_skip: int, parallel: bool) -> None:
        if model not in ("palmer", "bourg"):
            raise ValueError(f"model: {model!r} is not 'palmer' or 'bourg'")
        if task not in TASKS:
            raise ValueError(f"task: {task!r} is not one of {TASKS}")
        if frame_skip < 1:
            raise ValueError(f"frame_skip: {frame_skip} is not a whole number >= 1")
        self.model, self.task, self.n, self.frame_skip = model, task, n, frame_skip
        self.fleet = Fleet(model, n, fps=fps, parallel=parallel, altitude_ft=2000.0, speed_kt=100.0, trim=True)
        self.target_alt_ft = np.zeros(n)
        self.target_heading_deg = np.zeros(n)
        n_act = 4 if model == "palmer" else 5
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n_act,), dtype=np.float32)
        n_obs = 6 + (4 if model == "palmer" else 5)
        self.observation_space = spaces.Box(-OBS_LIMIT, OBS_LIMIT, shape=(n_obs,), dtype=np.float32)

    def draw(self, rngs: list, indices: np.ndarray) -> Dict[str, np.ndarray]:
        """Starts and targets for aircraft ``indices``, each from its own generator."""
        alt, spd, hdg, t_alt, t_hdg = (np.zeros(self.n) for _ in range(5))
        for i in indices:
            r = rngs[i]
            if self.task == "heading-altitude":
                alt[i] = r.uniform(1500.0, 2500.0)
                spd[i] = r.uniform(90.0, 110.0)
                hdg[i] = r.uniform(0.0, 360.0)
                t_alt[i] = alt[i] + r.uniform(-300.0, 300.0)
                t_hdg[i] = (hdg[i] + r.uniform(-30.0, 30.0)) % 360.0
            else:
                alt[i] = r.uniform(1000.0, 1500.0)
                spd[i] = r.uniform(90.0, 100.0)
                hdg[i] = r.uniform(0.0, 360.0)
                t_alt[i] = alt[i] + r.uniform(1000.0, 2000.0)
                t_hdg[i] = hdg[i]
        return {"altitude_ft": alt, "speed_kt": spd, "heading_deg": hdg, "t_alt": t_alt, "t_hdg": t_hdg}

    def reset(self, rngs: list, mask: np.ndarray) -> None:
        d = self.draw(rngs, np.flatnonzero(mask))
        self.fleet.reset(mask, altitude_ft=d["altitude_ft"], speed_kt=d["speed_kt"], heading_deg=d["heading_deg"], trim=True)
        self.target_alt_ft[mask] = d["t_alt"][mask]
        self.target_heading_deg[mask] = d["t_hdg"][mask]

    def act(self, actions: np.ndarray) -> None:
        a = np.clip(np.asarray(actions, dtype=np.float64).reshape(self.n, -1), -1.0, 1.0)
        if self.model == "palmer":
            flaps = np.where(a[:, 3] < -1.0 / 3.0, 0.0, np.where(a[:, 3] <= 1.0 / 3.0, 20.0, 40.0))
            self.fleet.set_controls(
                throttle=(a[:, 0] + 1.0) * 0.5,
                alpha_deg=2.0 + 18.0 * a[:, 1],
                bank_deg=20.0 * a[:, 2],
                flaps_deg=flaps,
            )
        else:
            self.fleet.set_controls(
                thrust_lb=1500.0 * (a[:, 0] + 1.0),
                elevator=_surface(a[:, 1]),
                aileron=_surface(a[:, 2]),
                rudder=_surface(a[:, 3]),
                pitch_trim=np.ascontiguousarray(a[:, 4]),
            )

    def _kinematics(self) -> Tuple[np.ndarray, ...]:
        f = self.fleet
        if self.model == "palmer":
            alt_ft = f["z_m"] * FT_PER_M
            vx, vy, vz_fps = f["vx_mps"], f["vy_mps"], f["vz_mps"] * FT_PER_M
            ground_mps = np.hypot(vx, vy)
        else:
            alt_ft = np.array(f["z_ft"])
            vx, vy, vz_fps = f["vx_ftps"], f["vy_ftps"], np.array(f["vz_ftps"])
            ground_mps = np.hypot(vx, vy) * 0.3048
        # y points west: the track is clockwise from north toward east (-y).
        track_deg = np.degrees(np.arctan2(-vy, vx)) % 360.0
        return alt_ft, vz_fps, ground_mps * KT_PER_MPS, track_deg, vx, vy, ground_mps

    def observe(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Observations, rewards and the ended-by-status mask. (The fleet's
        state is always finite: a diverged aircraft keeps its last finite state.)"""
        alt_ft, vz_fps, ground_kt, track_deg, vx, vy, ground = self._kinematics()
        alt_err = self.target_alt_ft - alt_ft
        hdg_err = (self.target_heading_deg - track_deg + 180.0) % 360.0 - 180.0
        c = self.fleet.controls
        if self.model == "palmer":
            ctl = [c["throttle"], c["alpha_deg"] / 20.0, c["bank_deg"] / 20.0, c["flaps_deg"] / 40.0]
        else:
            ctl = [c["thrust_lb"] / 3000.0, c["elevator"], c["aileron"], c["rudder"], c["pitch_trim"]]
        moving = ground > 0.0
        safe = np.where(moving, ground, 1.0)
        obs = np.empty((self.n, self.observation_space.shape[0]), dtype=np.float32)
        columns = [alt_err / 1000.0, hdg_err / 180.0, vz_fps / 20.0, ground_kt / 200.0,
                   np.where(moving, -vy / safe, 0.0), np.where(moving, vx / safe, 1.0), *ctl]
        for k, column in enumerate(columns):
            obs[:, k] = column
        np.clip(obs, -OBS_LIMIT, OBS_LIMIT, out=obs)
        a_err, h_err = np.abs(alt_err), np.abs(hdg_err)
        if self.task == "heading-altitude":
            reward = 1.0 - 0.5 * np.minimum(a_err / 500.0, 1.0) - 0.5 * np.minimum(h_err / 45.0, 1.0)
        else:
            reward = np.where(
                a_err <= 200.0,
                1.0 - 0.7 * np.minimum(a_err / 1000.0, 1.0) - 0.3 * np.minimum(np.abs(vz_fps) / 10.0, 1.0),
                0.3 * (1.0 - np.minimum(a_err / 2000.0, 1.0)),
            )
        ended = self.fleet.status != AIRBORNE
        reward[ended] = 0.0
        return obs, reward, ended


def _statuses(fleet: Fleet) -> np.ndarray:
    return np.array(fleet.status, dtype=np.int64)


class AircraftEnv(gymnasium.Env):
    """One aircraft of ``model`` flying ``task`` (see the module docstring)."""

    metadata = {"render_modes": [], "render_fps": 30}

    def __init__(
        self,
        model: str = "palmer",
        task: str = "heading-altitude",
        *,
        fps: int = 30,
        frame_skip: int = 1,
        max_episode_steps: int = 1800,
        render_mode: Optional[str] = None,
    ) -> None:
        if render_mode is not None:
            raise ValueError(f"render_mode: {render_mode!r}: these environments do not render")
        self._task = _Task(model, task, 1, fps, frame_skip, parallel=False)
        self.action_space = self._task.action_space
        self.observation_space = self._task.observation_space
        self.max_episode_steps = max_episode_steps
        self.metadata = {"render_modes": [], "render_fps": fps / frame_skip}
        self._steps = 0

    def reset(self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None):
        super().reset(seed=seed)
        self._task.reset([self.np_random], np.ones(1, dtype=bool))
        self._steps = 0
        obs, _, _ = self._task.observe()
        return obs[0], {"status": int(_statuses(self._task.fleet)[0])}

    def step(self, action):
        self._task.act(np.asarray(action).reshape(1, -1))
        self._task.fleet.step(self._task.frame_skip)
        self._steps += 1
        obs, reward, ended = self._task.observe()
        truncated = self._steps >= self.max_episode_steps and not ended[0]
        return obs[0], float(reward[0]), bool(ended[0]), bool(truncated), {"status": int(_statuses(self._task.fleet)[0])}


class AircraftVectorEnv(VectorEnv):
    """``num_envs`` aircraft of ``model`` flying ``task`` in one fleet."""

    def __init__(
        self,
        model: str = "palmer",
        task: str = "heading-altitude",
        num_envs: int = 1,
        *,
        fps: int = 30,
        frame_skip: int = 1,
        max_episode_steps: int = 1800,
        autoreset_mode: Any = AutoresetMode.NEXT_STEP,
        parallel: bool = True,
        render_mode: Optional[str] = None,
    ) -> None:
        if render_mode is not None:
            raise ValueError(f"render_mode: {render_mode!r}: these environments do not render")
        if num_envs < 1:
            raise ValueError(f"num_envs: {num_envs} is not >= 1")
        self.num_envs = num_envs
        self.autoreset_mode = autoreset_mode if isinstance(autoreset_mode, AutoresetMode) else AutoresetMode(autoreset_mode)
        self._task = _Task(model, task, num_envs, fps, frame_skip, parallel)
        self.single_action_space = self._task.action_space
        self.single_observation_space = self._task.observation_space
        self.action_space = gymnasium.vector.utils.batch_space(self.single_action_space, num_envs)
        self.observation_space = gymnasium.vector.utils.batch_space(self.single_observation_space, num_envs)
        self.metadata = {"render_modes": [], "render_fps": fps / frame_skip, "autoreset_mode": self.autoreset_mode}
        self.render_mode = None
        self.max_episode_steps = max_episode_steps
        self._rngs: list = []
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._autoreset = np.zeros(num_envs, dtype=bool)

    def _seed(self, seed: Optional[int], mask: np.ndarray) -> None:
        if not self._rngs:
            self._rngs = [None] * self.num_envs
        for i in np.flatnonzero(mask):
            if seed is None:
                if self._rngs[i] is None:
                    self._rngs[i] = seeding.np_random()[0]
            else:
                self._rngs[i] = seeding.np_random(seed + int(i))[0]

    def reset(self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None):
        mask = np.ones(self.num_envs, dtype=bool)
        if options is not None and "reset_mask" in options:
            mask = options["reset_mask"]
            if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_:
                raise TypeError("options['reset_mask']: expected a bool NumPy array")
            if mask.shape != (self.num_envs,):
                raise ValueError(f"options['reset_mask']: expected shape ({self.num_envs},), got {mask.shape}")
            if not mask.any():
                raise ValueError("options['reset_mask']: no aircraft selected")
        if seed is not None:
            self._np_random, self._np_random_seed = seeding.np_random(seed)
        self._seed(seed, mask)
        self._task.reset(self._rngs, mask)
        self._steps[mask] = 0
        self._autoreset[mask] = False
        obs, _, _ = self._task.observe()
        return obs, {"status": np.where(mask, _statuses(self._task.fleet), 0), "_status": mask.copy()}

    def step(self, actions):
        task = self._task
        task.act(actions)
        task.fleet.step(task.frame_skip)
        self._steps += 1
        infos: Dict[str, Any] = {}
        if self.autoreset_mode == AutoresetMode.NEXT_STEP and self._autoreset.any():
            task.reset(self._rngs, self._autoreset)
            self._steps[self._autoreset] = 0
        obs, reward, ended = task.observe()
        truncated = (self._steps >= self.max_episode_steps) & ~ended
        if self.autoreset_mode == AutoresetMode.NEXT_STEP:
            was = self._autoreset
            reward[was] = 0.0
            ended[was] = False
            truncated[was] = False
        done = ended | truncated
        status = _statuses(task.fleet)
        if self.autoreset_mode == AutoresetMode.SAME_STEP and done.any():
            # The layout SyncVectorEnv gives (VectorEnv._add_info): final_obs
            # an object array (None or the aircraft's last observation), the
            # rest arrays over all aircraft, each with a mask.
            final_obs = np.full(self.num_envs, None, dtype=object)
            for i in np.flatnonzero(done):
                final_obs[i] = obs[i].copy()
            infos.update(
                final_obs=final_obs,
                _final_obs=done.copy(),
                final_info={"status": np.where(done, status, 0), "_status": done.copy()},
                _final_info=done.copy(),
            )
            task.reset(self._rngs, done)
            self._steps[done] = 0
            obs, _, _ = task.observe()
            status = _statuses(task.fleet)
        self._autoreset = done if self.autoreset_mode == AutoresetMode.NEXT_STEP else np.zeros(self.num_envs, dtype=bool)
        infos["status"] = status
        infos["_status"] = np.ones(self.num_envs, dtype=bool)
        return obs, reward, ended, truncated, infos


def register_envs() -> None:
    """Registers the four ids (called on ``import afit_fdm``)."""
    for model in ("palmer", "bourg"):
        for task, name in (("heading-altitude", "HeadingAltitude"), ("climb", "Climb")):
            env_id = f"afit_fdm/{model.capitalize()}{name}-v0"
            if env_id in gymnasium.registry:
                continue
            gymnasium.register(
                id=env_id,
                entry_point="afit_fdm.gym:AircraftEnv",
                vector_entry_point="afit_fdm.gym:AircraftVectorEnv",
                kwargs={"model": model, "task": task},
            )
