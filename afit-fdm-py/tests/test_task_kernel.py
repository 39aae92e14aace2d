"""The Gymnasium tasks' step in Rust (``Fleet.task_step``) against the NumPy
code it replaced, kept here as the oracle (``OldTask``: ``afit_fdm.gym``'s
``_Task.act`` and ``_Task.observe`` as they were, verbatim but for the
``arctan2`` and ``hypot`` they call).

Bit for bit, on random actions (Hypothesis), both models and both tasks,
with the oracle's ``np.arctan2`` and ``np.hypot`` replaced by the
deterministic functions the Rust step uses: ``fdm_core::math``'s ``atan2``
(fdlibm's) and ``hypot`` (musl's), pure Rust, the same bits on every machine
(``_afit_fdm._math_atan2`` and ``_math_hypot`` compute them one pair at a
time; the Rust step computes eight aircraft at once with lane forms proven
bit for bit against them in ``fdm-core``, which these tests check again on
the fleets' own velocities). NumPy's two functions are not the same on every
machine: both call the platform's C library, and ``arctan2`` runs NumPy's own
SIMD kernel on CPUs with AVX-512 (it differs from the C library's in the
last bit on about 7 % of inputs on this project's machine). Every other
operation is NumPy's. A second test runs the oracle with NumPy's own
``arctan2`` and ``hypot`` and bounds the difference that remains (see
there).
"""

from __future__ import annotations

from typing import Callable, Tuple

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from afit_fdm import Fleet, Status, _afit_fdm
from afit_fdm.gym import FT_PER_M, KT_PER_MPS, OBS_LIMIT, _Task

AIRBORNE = int(Status.AIRBORNE)


def math_arctan2(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``fdm_core::math::atan2`` elementwise (the Rust step's track)."""
    return _afit_fdm._math_atan2(np.ascontiguousarray(y, dtype=np.float64), np.ascontiguousarray(x, dtype=np.float64))


def math_hypot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``fdm_core::math::hypot`` elementwise (the Rust step's horizontal speed)."""
    return _afit_fdm._math_hypot(np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(y, dtype=np.float64))


def _surface(a: np.ndarray) -> np.ndarray:
    return np.where(a > 1.0 / 3.0, 1.0, np.where(a < -1.0 / 3.0, -1.0, 0.0))


class OldTask:
    """``_Task`` as it computed actions, observations and rewards in NumPy
    before the step moved into Rust (commit 46ec60a), on a fleet of its own."""

    def __init__(
        self, model: str, task: str, n: int, arctan2: Callable = np.arctan2, hypot: Callable = np.hypot
    ) -> None:
        self.model, self.task, self.n = model, task, n
        self.arctan2, self.hypot = arctan2, hypot
        self.fleet = Fleet(model, n, fps=30, parallel=False, altitude_ft=2000.0, speed_kt=100.0, trim=True)
        self.target_alt_ft = np.zeros(n)
        self.target_heading_deg = np.zeros(n)
        self.n_obs = 6 + (4 if model == "palmer" else 5)

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
            ground_mps = self.hypot(vx, vy)
        else:
            alt_ft = np.array(f["z_ft"])
            vx, vy, vz_fps = f["vx_ftps"], f["vy_ftps"], np.array(f["vz_ftps"])
            ground_mps = self.hypot(vx, vy) * 0.3048
        track_deg = np.degrees(self.arctan2(-vy, vx)) % 360.0
        return alt_ft, vz_fps, ground_mps * KT_PER_MPS, track_deg, vx, vy, ground_mps

    def observe(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        alt_ft, vz_fps, ground_kt, track_deg, vx, vy, ground = self._kinematics()
        alt_err = self.target_alt_ft - alt_ft
        hdg_err = (self.target_heading_deg - track_deg + 180.0) % 360.0 - 180.0
        c = self.fleet.controls
        if self.model == "palmer":
            ctl = [c["throttle"], c["alpha_deg"] / 20.0, c["bank_deg"] / 20.0, c["flaps_deg"] / 40.0]
        else:
            ctl = [c["thrust_lb"] / 3000.0, c["elevator"], c["aileron"], c["rudder"], c["pitch_trim"]]
        moving = ground > 0.0
        safe = np.where(moving, self.hypot(vx, vy), 1.0)  # the velocity's own units
        obs = np.empty((self.n, self.n_obs), dtype=np.float32)
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


def pair(
    model: str,
    task: str,
    n: int,
    seed: int,
    parallel: bool,
    arctan2: Callable = math_arctan2,
    hypot: Callable = math_hypot,
):
    """The new task and the oracle, from the same starts and targets."""
    new = _Task(model, task, n, 30, 1, parallel)
    rngs = [np.random.default_rng(seed + i) for i in range(n)]
    new.reset(rngs, np.ones(n, dtype=bool))
    old = OldTask(model, task, n, arctan2, hypot)
    rngs = [np.random.default_rng(seed + i) for i in range(n)]
    d = new.draw(rngs, np.arange(n))
    old.fleet.reset(None, altitude_ft=d["altitude_ft"], speed_kt=d["speed_kt"], heading_deg=d["heading_deg"], trim=True)
    old.target_alt_ft[:] = d["t_alt"]
    old.target_heading_deg[:] = d["t_hdg"]
    assert np.array_equal(old.target_alt_ft, new.target_alt_ft)
    return new, old


def bits(a: np.ndarray) -> np.ndarray:
    return a.view(np.uint32 if a.dtype == np.float32 else np.uint64)


ACTION = st.one_of(
    st.floats(-3.0, 3.0, width=32),
    st.sampled_from([-1.0, 1.0, -1.0 / 3.0, 1.0 / 3.0, -0.0, 0.0, np.inf, -np.inf]),
)


@settings(max_examples=60, deadline=None)
@given(
    model=st.sampled_from(["palmer", "bourg"]),
    task=st.sampled_from(["heading-altitude", "climb"]),
    n=st.integers(1, 40),
    seed=st.integers(0, 2**32),
    parallel=st.booleans(),
    dtype=st.sampled_from([np.float32, np.float64]),
    data=st.data(),
)
def test_task_step_is_the_old_numpy_step_bit_for_bit(model, task, n, seed, parallel, dtype, data) -> None:
    """Observations (float32), rewards (float64), terminated and truncated,
    and the fleet's state and controls after each step: identical bits
    (tolerance 0), over 1 to 6 steps of random actions, in and out of -1..1,
    the flap and surface thresholds and infinities included. With
    ``views=False`` (the environments' step) the outputs and statuses are
    the same bits, the state views are left as they were at the reset, and
    ``task_observe`` at the end brings them to the oracle's."""
    new, old = pair(model, task, n, seed, parallel)
    k = 4 if model == "palmer" else 5
    steps = np.zeros(n, dtype=np.int64)
    old_steps = np.zeros(n, dtype=np.int64)
    max_steps = data.draw(st.integers(1, 6))
    views = data.draw(st.booleans())
    at_reset = new.fleet.columns.copy()
    for _ in range(data.draw(st.integers(1, 6))):
        actions = data.draw(hnp.arrays(dtype, (n, k), elements=ACTION))
        obs, reward, terminated, truncated = new.step(actions, steps, max_steps, views=views)
        old.act(actions)
        old.fleet.step(1)
        old_steps += 1
        old_obs, old_reward, old_ended = old.observe()
        old_truncated = (old_steps >= max_steps) & ~old_ended
        assert np.array_equal(steps, old_steps)
        assert np.array_equal(bits(obs), bits(old_obs))
        assert np.array_equal(bits(reward), bits(old_reward))
        assert np.array_equal(terminated, old_ended)
        assert np.array_equal(truncated, old_truncated)
        want = old.fleet.columns if views else at_reset
        assert np.array_equal(bits(new.fleet.columns), bits(want))
        assert np.array_equal(new.fleet.status, old.fleet.status)
        for name, values in old.fleet.controls.items():
            assert np.array_equal(bits(new.fleet.controls[name]), bits(values)), name
    new.observe(steps, max_steps)
    assert np.array_equal(bits(new.fleet.columns), bits(old.fleet.columns))


def test_a_large_fleet_in_parallel_pieces_is_the_old_step_bit_for_bit() -> None:
    """10,000 aircraft: the pass runs in several pieces on rayon's threads;
    every aircraft is still the oracle's."""
    n = 10_000
    for model in ("palmer", "bourg"):
        new, old = pair(model, "climb", n, 7, True)
        k = 4 if model == "palmer" else 5
        rng = np.random.default_rng(3)
        steps, old_steps = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
        for _ in range(3):
            actions = rng.uniform(-1.5, 1.5, size=(n, k)).astype(np.float32)
            obs, reward, terminated, truncated = new.step(actions, steps, 2)
            old.act(actions)
            old.fleet.step(1)
            old_steps += 1
            old_obs, old_reward, old_ended = old.observe()
            assert np.array_equal(bits(obs), bits(old_obs))
            assert np.array_equal(bits(reward), bits(old_reward))
            assert np.array_equal(terminated, old_ended)
            assert np.array_equal(truncated, (old_steps >= 2) & ~old_ended)


def test_against_numpys_own_arctan2_only_the_heading_error_differs_within_bounds() -> None:
    """The oracle with NumPy's own ``arctan2`` and ``hypot`` as they run here
    (the AVX-512 SIMD ``arctan2`` on such a CPU, the C library's ``hypot``):
    every observation column but the heading error (column 1) is identical
    bits (glibc's ``hypot`` and musl's differ in the last bit of about 13 %
    of velocities, which moves a float32 observation only where the two
    straddle a float32 rounding boundary: none of these 40,000 aircraft);
    the heading error within 1 float32 ulp (f64 track angles a few ulp
    apart move ``hdg_err / 180`` by about 1e-16, which changes the float32
    rounding only when it straddles a rounding boundary); rewards within
    1e-14 (``0.5 / 45`` times the heading error's difference, under 1e-13
    degrees)."""
    n = 20_000
    for model in ("palmer", "bourg"):
        new, old = pair(model, "heading-altitude", n, 11, True, arctan2=np.arctan2, hypot=np.hypot)
        k = 4 if model == "palmer" else 5
        rng = np.random.default_rng(5)
        steps = np.zeros(n, dtype=np.int64)
        actions = rng.uniform(-0.3, 0.3, size=(n, k)).astype(np.float32)
        obs, reward, terminated, _ = new.step(actions, steps, 10)
        old.act(actions)
        old.fleet.step(1)
        old_obs, old_reward, old_ended = old.observe()
        others = [c for c in range(obs.shape[1]) if c != 1]
        assert np.array_equal(bits(obs[:, others]), bits(old_obs[:, others]))
        assert np.all(np.abs(obs[:, 1] - old_obs[:, 1]) <= np.spacing(np.abs(old_obs[:, 1])))
        assert np.all(np.abs(reward - old_reward) <= 1e-14)
        assert np.array_equal(terminated, old_ended)


@pytest.mark.parametrize("model,column,name,bounds", [
    ("palmer", 0, "throttle", "0..1"),
    ("palmer", 2, "bank_deg", "-20..20"),
    ("bourg", 0, "thrust_lb", "0..3000"),
    ("bourg", 4, "pitch_trim", "-1..1"),
])
def test_nan_actions_raise_as_before_and_change_nothing(model, column, name, bounds) -> None:
    """A NaN that reaches a control: the old code's ``ValueError`` (the same
    message, naming the control and the first aircraft), and the fleet is
    untouched: not stepped, controls unchanged."""
    n = 6
    new, old = pair(model, "heading-altitude", n, 1, False)
    k = 4 if model == "palmer" else 5
    actions = np.zeros((n, k), dtype=np.float32)
    actions[3, column] = np.nan
    actions[5, column] = np.nan
    with pytest.raises(ValueError) as old_error:
        old.act(actions)
    before = new.fleet.columns.copy(), {c: v.copy() for c, v in new.fleet.controls.items()}
    steps = np.zeros(n, dtype=np.int64)
    with pytest.raises(ValueError) as new_error:
        new.step(actions, steps, 10)
    assert str(new_error.value) == str(old_error.value)
    assert str(new_error.value) == f"{name}[3]: NaN is not a finite number in {bounds}"
    assert np.array_equal(new.fleet.columns, before[0]) and not steps.any()
    assert all(np.array_equal(new.fleet.controls[c], v) for c, v in before[1].items())


@pytest.mark.parametrize("model,column,name,bounds", [
    ("palmer", 3, "flaps_deg", "0..40"),
    ("bourg", 1, "elevator", "-1..1"),
    ("bourg", 2, "aileron", "-1..1"),
    ("bourg", 3, "rudder", "-1..1"),
])
def test_nan_actions_read_by_a_threshold_raise_too(model, column, name, bounds) -> None:
    """A NaN where only a threshold reads it (Palmer's flaps, Bourg's
    surfaces): the old NumPy code made a setting of it without a word (all
    its comparisons are false: 40 degrees of flaps, a neutral surface); now
    it is refused as a NaN reaching a continuous control is, naming the
    control it sets and the first aircraft, and nothing changes. A NaN in an
    earlier action of a later aircraft is named first (control by control,
    then aircraft by aircraft, as ``Fleet.set_controls`` checks)."""
    n = 6
    new, old = pair(model, "heading-altitude", n, 1, False)
    k = 4 if model == "palmer" else 5
    actions = np.zeros((n, k), dtype=np.float32)
    actions[2:, column] = np.nan
    old.act(actions)  # The old code: silently a setting.
    before = new.fleet.columns.copy(), {c: v.copy() for c, v in new.fleet.controls.items()}
    steps = np.zeros(n, dtype=np.int64)
    for dtype in (np.float32, np.float64):
        with pytest.raises(ValueError) as error:
            new.step(actions.astype(dtype), steps, 10)
        assert str(error.value) == f"{name}[2]: NaN is not a finite number in {bounds}"
    assert np.array_equal(new.fleet.columns, before[0]) and not steps.any()
    assert all(np.array_equal(new.fleet.controls[c], v) for c, v in before[1].items())
    if column > 0:
        actions[4, 0] = np.nan
        with pytest.raises(ValueError) as error:
            new.step(actions, steps, 10)
        first = "throttle" if model == "palmer" else "thrust_lb"
        assert str(error.value).startswith(f"{first}[4]: NaN ")


def test_bad_action_arrays_are_refused_by_name() -> None:
    new, _ = pair("palmer", "climb", 3, 0, False)
    steps = np.zeros(3, dtype=np.int64)
    with pytest.raises(ValueError, match=r"actions: expected 3 × 4 values"):
        new.step(np.zeros((3, 5), dtype=np.float32), steps, 10)
    with pytest.raises(ValueError):
        new.step(np.array([["a"] * 4] * 3), steps, 10)
    # Lists and other dtypes convert as np.asarray(..., float64) did.
    obs, *_ = new.step([[0, 0, 0, 0]] * 3, steps, 10)
    assert obs.shape == (3, 10) and obs.dtype == np.float32
    with pytest.raises(TypeError, match="steps"):
        new.fleet.task_step(np.zeros((3, 4)), 1, "climb", new.target_alt_ft, new.target_heading_deg,
                            np.zeros(3, dtype=np.int32), 10, *new._outputs())
    with pytest.raises(ValueError, match="task"):
        new.fleet.task_step(np.zeros((3, 4)), 1, "loop", new.target_alt_ft, new.target_heading_deg,
                            steps, 10, *new._outputs())


@pytest.mark.parametrize("model", ["palmer", "bourg"])
@pytest.mark.parametrize("views", [True, False])
def test_a_long_task_step_flown_in_stretches_is_the_same_bits(model: str, views: bool) -> None:
    """A ``task_step`` of more frames than one look at Ctrl-C allows (2**21
    aircraft-frames: 2,097 frames for 1,000 aircraft) sets the actions with
    the first stretch, flies the rest in stretches and then observes (and a
    signal stops it: ``test_interrupt.py``). Its outputs, statuses and state
    are the bits of the same 3,000 frames flown by three task steps of 1,000
    frames (one stretch each) with the same actions, which set the same
    controls each time: the step counts end equal (2 + 1 against 0 + 3), so
    ``truncated`` (``max_steps`` 3) is compared too."""
    n = 1000
    tasks = []
    for _ in range(2):
        task = _Task(model, "climb", n, 30, 1, True)
        task.reset([np.random.default_rng(20 + i) for i in range(n)], np.ones(n, dtype=bool))
        tasks.append(task)
    long, cut = tasks
    actions = np.random.default_rng(3).uniform(-1.0, 1.0, size=(n, long.action_space.shape[0]))
    args = (long.target_alt_ft, long.target_heading_deg)
    assert np.array_equal(args[0], cut.target_alt_ft) and np.array_equal(args[1], cut.target_heading_deg)
    long_steps, cut_steps = np.full(n, 2, dtype=np.int64), np.zeros(n, dtype=np.int64)
    long_out = long._outputs()
    long.fleet.task_step(actions, 3000, "climb", *args, long_steps, 3, *long_out, views=views)
    for _ in range(3):
        cut_out = cut._outputs()
        cut.fleet.task_step(actions, 1000, "climb", *args, cut_steps, 3, *cut_out)
    assert np.array_equal(long_steps, cut_steps) and (cut_steps == 3).all()
    for a, b in zip(long_out, cut_out):
        assert np.array_equal(bits(a) if a.dtype != bool else a, bits(b) if b.dtype != bool else b)
    assert np.array_equal(long.fleet.status, cut.fleet.status)
    # Both flew: some aircraft still in the air (truncated), the clock at 100 s.
    assert cut_out[3].any()
    long.fleet.step(0)  # the views refreshed (with views=False they were not)
    assert np.array_equal(bits(long.fleet.columns), bits(cut.fleet.columns))
    assert float(cut.fleet["time_s"][0]) == pytest.approx(100.0)
