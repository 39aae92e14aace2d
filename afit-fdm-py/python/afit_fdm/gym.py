"""Gymnasium environments over :class:`afit_fdm.Fleet`.

:class:`AircraftEnv` is one aircraft (a ``gymnasium.Env``);
:class:`AircraftVectorEnv` is ``num_envs`` aircraft stepped together by the
fleet kernels (a native ``gymnasium.vector.VectorEnv``, not a loop of single
environments). Both run the same task code, so a vector env and
``SyncVectorEnv`` over the single env give the same numbers, bit for bit, from
the same seeds (tested). An env step is one call into Rust
(``Fleet.task_step``, the GIL released, parallel over pieces of the fleet):
the action array validated and applied, the frames flown, and the
observations, rewards and flags below computed; the starts and targets are
drawn here in Python. Those numbers are the ones the NumPy code that computed
them before gave (``tests/test_task_kernel.py`` keeps it as the oracle),
except for two functions: the track's ``atan2`` and the horizontal speed's
``hypot`` are the project's deterministic ones (fdlibm's and musl's, pure Rust
in ``fdm_core::math``), so an observation is the same bits on every machine,
as the fleet's states are. NumPy's ``arctan2`` and ``hypot`` call the
platform's C library (and ``arctan2`` its own SIMD kernel on CPUs with
AVX-512): they differ from these in the last bit of some float64 values,
which moves a float32 observation by at most one unit in its last place.

Registered ids (``gymnasium.make`` / ``gymnasium.make_vec``)::

    afit_fdm/PalmerHeadingAltitude-v0   afit_fdm/PalmerClimb-v0
    afit_fdm/BourgHeadingAltitude-v0    afit_fdm/BourgClimb-v0

**Agent rate.** Each ``step`` flies ``frame_skip`` model frames at ``fps``
frames per second (defaults 30 and 1: a 30 Hz agent). ``fps`` is a whole
number from 1 to 10,000, ``frame_skip`` from 1 to an hour of frames (3,600 ×
``fps``: a step is one call that Ctrl-C cannot stop), ``num_envs`` and
``max_episode_steps`` at least 1; another type raises ``TypeError``, a number
out of range ``ValueError``, both naming the argument.

**Actions** (``Box(-1, 1)``, float32, scaled to the thesis's controls; any
array of ``num_envs`` times this many numbers is taken, float32 or float64 as
given, other dtypes converted to float64; values are clipped to -1..1, and a
NaN action raises ``ValueError`` naming the control it sets and the first
aircraft, with nothing changed; also where only a threshold reads the action,
whose comparisons would otherwise turn the NaN into a setting):

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

**Order**: ``step`` before ``reset`` raises Gymnasium's ``ResetNeeded`` (as
the ``OrderEnforcing`` wrapper of ``gymnasium.make`` does), and so does a
vector env's ``step`` while some aircraft were never reset (a first
``reset`` with a ``reset_mask`` that leaves some out): an aircraft has no
episode, no start and no target, before its first reset.

**Copies**: ``copy.deepcopy`` and ``pickle`` of either env (also as
``gymnasium.make`` wraps it) give an independent env at the same point:
the fleet (``Fleet``'s pickle, every aircraft's bits), each aircraft's
step count, target and generator, pending autoresets and the action space's
generator. Stepped with the same actions, it gives what the original gives,
bit for bit (``tests/test_gym.py``). ``copy.copy`` is shallow and shares
the fleet.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import gymnasium
from gymnasium import spaces
from gymnasium.error import ResetNeeded
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from . import MAX_FPS, Fleet, Status

FT_PER_M = 1.0 / 0.3048
KT_PER_MPS = 3600.0 / 1852.0
TASKS = ("heading-altitude", "climb")
OBS_LIMIT = 10.0
# The longest agent step, seconds of flight: ``frame_skip`` is at most this
# many seconds of frames. A step is one call into Rust that Ctrl-C cannot
# stop, so an absurd ``frame_skip`` is refused rather than flown for hours.
MAX_AGENT_STEP_S = 3600
_MAX_INT64 = 2**63 - 1


def _whole(name: str, value: Any, low: int, high: int) -> int:
    """``value`` if it is a whole number in ``low..=high`` (both ends
    included): ``TypeError`` for another type (``bool`` included),
    ``ValueError`` out of range, both naming the argument, in the words of
    the extension's own arguments (``fps: expected a whole number (int),
    got float``)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        kind = type(value)
        shown = kind.__name__ if kind.__module__ == "builtins" else f"{kind.__module__}.{kind.__name__}"
        raise TypeError(f"{name}: expected a whole number (int), got {shown}")
    if not low <= value <= high:
        raise ValueError(f"{name}: {value} is not a whole number in {low}..={high}")
    return int(value)
AIRBORNE = int(Status.AIRBORNE)


class _Task:
    """The task's numbers for ``n`` aircraft of ``model``: starts, actions,
    observations, rewards. Everything is vectorised over aircraft."""

    def __init__(self, model: str, task: str, n: int, fps: int, frame_skip: int, parallel: bool) -> None:
        if model not in ("palmer", "bourg"):
            raise ValueError(f"model: {model!r} is not 'palmer' or 'bourg'")
        if task not in TASKS:
            raise ValueError(f"task: {task!r} is not one of {TASKS}")
        fps = _whole("fps", fps, 1, MAX_FPS)
        frame_skip = _whole("frame_skip", frame_skip, 1, MAX_AGENT_STEP_S * fps)
        self.model, self.task, self.n, self.frame_skip = model, task, n, frame_skip
        self.fleet = Fleet(model, n, fps=fps, parallel=parallel, altitude_ft=2000.0, speed_kt=100.0, trim=True)
        self.fps = fps
        self.target_alt_ft = np.zeros(n)
        self.target_heading_deg = np.zeros(n)
        n_act = 4 if model == "palmer" else 5
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n_act,), dtype=np.float32)
        n_obs = 6 + (4 if model == "palmer" else 5)
        self.observation_space = spaces.Box(-OBS_LIMIT, OBS_LIMIT, shape=(n_obs,), dtype=np.float32)

    def draw(self, rngs: Sequence[Optional[np.random.Generator]], indices: np.ndarray) -> Dict[str, np.ndarray]:
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

    def reset(self, rngs: Sequence[Optional[np.random.Generator]], mask: np.ndarray) -> None:
        d = self.draw(rngs, np.flatnonzero(mask))
        self.fleet.reset(mask, altitude_ft=d["altitude_ft"], speed_kt=d["speed_kt"], heading_deg=d["heading_deg"], trim=True)
        self.target_alt_ft[mask] = d["t_alt"][mask]
        self.target_heading_deg[mask] = d["t_hdg"][mask]

    def _outputs(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """New observation, reward, terminated and truncated arrays (new each
        step, as a Gymnasium caller may keep the previous step's)."""
        n_obs = self.observation_space.shape[0]
        return (
            np.empty((self.n, n_obs), dtype=np.float32),
            np.empty(self.n),
            np.empty(self.n, dtype=bool),
            np.empty(self.n, dtype=bool),
        )

    def step(
        self, actions: Any, steps: np.ndarray, max_steps: int, observe: bool = True, views: bool = False
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """One agent step in one call into Rust (``Fleet.task_step``, the
        GIL released): the action array validated (a NaN action raises
        ``ValueError`` naming its control as ``Fleet.set_controls`` does;
        nothing changes then), clipped to -1..1 and scaled to the controls (see the
        module docstring), ``frame_skip`` frames flown, ``steps`` counted
        up, and with ``observe`` the observations, rewards (0 for an ended
        episode), terminated (not airborne) and truncated (``steps >=
        max_steps`` and not terminated) filled; with ``views`` the fleet's
        state views refreshed too (the statuses always are)."""
        out = self._outputs()
        # The environments read the outputs and the statuses only, never
        # the fleet's state views (the fleet is not theirs to hand out), so
        # by default the step skips refreshing those on every step.
        self.fleet.task_step(
            actions, self.frame_skip, self.task, self.target_alt_ft, self.target_heading_deg,
            steps, max_steps, *out, observe=observe, views=views,
        )
        return out

    def observe(self, steps: np.ndarray, max_steps: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Observations, rewards, terminated and truncated of the fleet as it
        is (after a reset): ``Fleet.task_observe``. (The fleet's state is
        always finite: a diverged aircraft keeps its last finite state.)"""
        out = self._outputs()
        self.fleet.task_observe(
            self.task, self.target_alt_ft, self.target_heading_deg, steps, max_steps, *out
        )
        return out


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
        max_episode_steps = _whole("max_episode_steps", max_episode_steps, 1, _MAX_INT64)
        self._task = _Task(model, task, 1, fps, frame_skip, parallel=False)
        self.action_space = self._task.action_space
        self.observation_space = self._task.observation_space
        self.max_episode_steps = max_episode_steps
        self.metadata = {"render_modes": [], "render_fps": fps / frame_skip}
        self._steps = np.zeros(1, dtype=np.int64)
        self._was_reset = False

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        super().reset(seed=seed)
        self._task.reset([self.np_random], np.ones(1, dtype=bool))
        self._steps[0] = 0
        self._was_reset = True
        obs = self._task.observe(self._steps, self.max_episode_steps)[0]
        return obs[0], {"status": int(_statuses(self._task.fleet)[0])}

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
        if not self._was_reset:
            # What Gymnasium's OrderEnforcing wrapper (which gymnasium.make
            # adds) raises; the aircraft has no episode (start, target) yet.
            raise ResetNeeded("Cannot call env.step() before calling env.reset()")
        obs, reward, ended, truncated = self._task.step(action, self._steps, self.max_episode_steps)
        return obs[0], float(reward[0]), bool(ended[0]), bool(truncated[0]), {"status": int(_statuses(self._task.fleet)[0])}


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
        num_envs = _whole("num_envs", num_envs, 1, _MAX_INT64)
        max_episode_steps = _whole("max_episode_steps", max_episode_steps, 1, _MAX_INT64)
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
        self._rngs: List[Optional[np.random.Generator]] = []
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._autoreset = np.zeros(num_envs, dtype=bool)
        # Aircraft not reset yet (no episode: start, target); cleared by
        # reset, and dropped once every aircraft has been reset.
        self._never_reset: Optional[np.ndarray] = np.ones(num_envs, dtype=bool)

    def _seed(self, seed: Optional[int], mask: np.ndarray) -> None:
        if not self._rngs:
            self._rngs = [None] * self.num_envs
        for i in np.flatnonzero(mask):
            if seed is None:
                if self._rngs[i] is None:
                    self._rngs[i] = seeding.np_random()[0]
            else:
                self._rngs[i] = seeding.np_random(seed + int(i))[0]

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
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
        if self._never_reset is not None:
            self._never_reset[mask] = False
        obs = self._task.observe(self._steps, self.max_episode_steps)[0]
        return obs, {"status": np.where(mask, _statuses(self._task.fleet), 0), "_status": mask.copy()}

    def step(self, actions: Any) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        if self._never_reset is not None:
            never = np.flatnonzero(self._never_reset)
            if never.size:
                shown = ", ".join(str(i) for i in never[:5]) + (", ..." if never.size > 5 else "")
                raise ResetNeeded(
                    f"Cannot call step() before every environment is reset (not reset: {shown}); "
                    "call reset() first"
                )
            self._never_reset = None
        task = self._task
        infos: Dict[str, Any] = {}
        if self.autoreset_mode == AutoresetMode.NEXT_STEP and self._autoreset.any():
            # The aircraft whose episode ended last step fly this step's
            # frames too (as every aircraft does), then restart: reward 0,
            # neither terminated nor truncated.
            was = self._autoreset
            task.step(actions, self._steps, self.max_episode_steps, observe=False)
            task.reset(self._rngs, was)
            self._steps[was] = 0
            obs, reward, ended, truncated = task.observe(self._steps, self.max_episode_steps)
            reward[was] = 0.0
            ended[was] = False
            truncated[was] = False
        else:
            obs, reward, ended, truncated = task.step(actions, self._steps, self.max_episode_steps)
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
            obs = task.observe(self._steps, self.max_episode_steps)[0]
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
