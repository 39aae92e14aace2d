"""The Gymnasium environments: Gymnasium's checker, the vector env against
``SyncVectorEnv`` over the single env (Gymnasium's documented autoreset
semantics) in all three modes, bit for bit, and seeding."""

from __future__ import annotations

import copy
import pathlib
import pickle
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.vector import AutoresetMode, SyncVectorEnv
from hypothesis import given, settings
from hypothesis import strategies as st

import afit_fdm  # noqa: F401  (registers the ids)
from afit_fdm.gym import AircraftEnv, AircraftVectorEnv

IDS = [
    "afit_fdm/PalmerHeadingAltitude-v0",
    "afit_fdm/PalmerClimb-v0",
    "afit_fdm/BourgHeadingAltitude-v0",
    "afit_fdm/BourgClimb-v0",
]


@pytest.mark.parametrize("env_id", IDS)
def test_registered_envs_pass_gymnasiums_checker(env_id: str) -> None:
    env = gym.make(env_id)  # with Gymnasium's passive checker
    check_env(env.unwrapped)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    for _ in range(50):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert env.observation_space.contains(obs) and 0.0 <= reward <= 1.0
    vec = gym.make_vec(env_id, num_envs=3, vectorization_mode="vector_entry_point")
    assert isinstance(vec.unwrapped, AircraftVectorEnv)
    assert vec.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    obs, info = vec.reset(seed=0)
    assert vec.observation_space.contains(obs)


def actions_for(space: gym.Space, num_envs: int, steps: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    shape = space.shape
    a = rng.uniform(-1.0, 1.0, size=(steps, num_envs, shape[0])).astype(np.float32)
    a[:, 0, :] = -1.0  # aircraft 0: idle, nose down hard: it comes down (termination)
    if shape[0] == 4:
        a[:, 0, 1] = -1.0
    return a


def same(x, y) -> bool:
    if isinstance(x, dict):
        return x.keys() == y.keys() and all(same(x[k], y[k]) for k in x)
    if isinstance(x, tuple):
        return isinstance(y, tuple) and len(x) == len(y) and all(same(a, b) for a, b in zip(x, y))
    if x is None or y is None:
        return x is y
    x, y = np.asarray(x), np.asarray(y)
    if x.dtype == object:
        return y.dtype == object and x.shape == y.shape and all(same(a, b) for a, b in zip(x, y))
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP, AutoresetMode.DISABLED])
@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_vector_env_is_sync_vector_env_bit_for_bit(mode: AutoresetMode, model: str) -> None:
    n, steps = 5, 150
    kw = dict(model=model, task="heading-altitude", fps=30, frame_skip=30, max_episode_steps=25)
    ours = AircraftVectorEnv(num_envs=n, autoreset_mode=mode, parallel=False, **kw)
    sync = SyncVectorEnv([lambda: AircraftEnv(**kw) for _ in range(n)], autoreset_mode=mode)
    assert ours.metadata["autoreset_mode"] == sync.metadata["autoreset_mode"] == mode
    o1, i1 = ours.reset(seed=42)
    o2, i2 = sync.reset(seed=42)
    assert same(o1, o2) and same(i1, i2)
    ended_by_status = truncated_seen = 0
    for a in actions_for(ours.single_action_space, n, steps, seed=7):
        r1 = ours.step(a)
        r2 = sync.step(a)
        for x, y in zip(r1, r2):
            assert same(x, y)
        ended_by_status += int(r1[2].sum())
        truncated_seen += int(r1[3].sum())
        if mode == AutoresetMode.DISABLED:
            done = r1[2] | r1[3]
            if done.any():
                o1, i1 = ours.reset(options={"reset_mask": done.copy()})
                o2, i2 = sync.reset(options={"reset_mask": done.copy()})
                assert same(o1, o2) and same(i1, i2)
    assert ended_by_status > 0 and truncated_seen > 0  # both kinds of ending happened


def copied(env, how):
    """``env`` deep-copied, or pickled with protocol ``how`` and unpickled."""
    return copy.deepcopy(env) if how == "deepcopy" else pickle.loads(pickle.dumps(env, protocol=how))


@settings(max_examples=40, deadline=None)
@given(
    model=st.sampled_from(["palmer", "bourg"]),
    task=st.sampled_from(["heading-altitude", "climb"]),
    mode=st.sampled_from([AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP, AutoresetMode.DISABLED]),
    n=st.integers(1, 6),
    before=st.integers(0, 40),
    after=st.integers(1, 40),
    max_steps=st.integers(1, 30),
    seed=st.integers(0, 2**32 - 1),
    how=st.sampled_from(["deepcopy", 2, 3, 4, 5]),
)
def test_a_pickled_or_deepcopied_vector_env_steps_on_to_the_bits_of_the_env_it_came_from(
    model, task, mode, n, before, after, max_steps, seed, how
) -> None:
    """A vector env copied mid-rollout (``copy.deepcopy``, or ``pickle`` as
    Ray, ``multiprocessing`` and the vector wrappers send an env) is the env:
    its fleet (``Fleet``'s pickle), episode counters, pending autoresets,
    per-aircraft generators (the starts and targets of the next episodes)
    and its action space's generator come along. Stepped with the same
    actions it gives what the original gives, bit for bit (observations,
    rewards, flags and infos, resets included), and the original still gives
    what a twin that was never copied gives. No tolerance: the same
    operations on the same bits."""
    kw = dict(model=model, task=task, num_envs=n, frame_skip=30, max_episode_steps=max_steps,
              autoreset_mode=mode, parallel=False)
    env, twin = AircraftVectorEnv(**kw), AircraftVectorEnv(**kw)
    assert same(env.reset(seed=seed), twin.reset(seed=seed))
    env.action_space.seed(seed)
    actions = actions_for(env.single_action_space, n, before + after, seed % 1000)

    def advance(e, a):
        out = e.step(a)
        if mode == AutoresetMode.DISABLED:
            done = out[2] | out[3]
            if done.any():
                out = out + e.reset(options={"reset_mask": done.copy()})
        return out

    for a in actions[:before]:
        assert same(advance(env, a), advance(twin, a))
    other = copied(env, how)
    assert other.metadata == env.metadata and other.num_envs == n
    from_copy = [advance(other, a) for a in actions[before:]]
    for a, theirs in zip(actions[before:], from_copy):
        ours = advance(env, a)
        assert same(ours, advance(twin, a))
        assert same(ours, theirs)
    assert same(other.action_space.sample(), env.action_space.sample())


@pytest.mark.parametrize("how", ["deepcopy", 2, 5])
@pytest.mark.parametrize("model", ["palmer", "bourg"])
@pytest.mark.parametrize("task", ["heading-altitude", "climb"])
def test_a_pickled_or_deepcopied_single_env_steps_on_to_the_same_bits(model: str, task: str, how) -> None:
    """The single env, unwrapped and as ``gymnasium.make`` wraps it, copied
    mid-episode: it steps on to the original's bits, through the end of its
    episode and the next reset without a seed (its generator came along)."""
    env_id = f"afit_fdm/{model.capitalize()}{'Climb' if task == 'climb' else 'HeadingAltitude'}-v0"
    kw = dict(frame_skip=30, max_episode_steps=20)
    for env in (AircraftEnv(model, task, **kw), gym.make(env_id, **kw)):
        env.reset(seed=11)
        env.action_space.seed(11)
        for _ in range(7):
            env.step(env.action_space.sample())
        other = copied(env, how)
        resets = 0
        for _ in range(30):
            a = env.action_space.sample()
            assert same(other.action_space.sample(), a)
            ours = env.step(a)
            assert same(ours, other.step(a))
            if ours[2] or ours[3]:
                assert same(env.reset(), other.reset())
                resets += 1
        assert resets > 0


def test_seeding_repeats_rollouts_bit_for_bit() -> None:
    def rollout(seed: int) -> bytes:
        env = AircraftVectorEnv("palmer", "climb", num_envs=8)
        obs, _ = env.reset(seed=seed)
        env.action_space.seed(seed)
        out = [obs.tobytes()]
        for _ in range(100):
            obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
            out += [obs.tobytes(), reward.tobytes(), terminated.tobytes(), truncated.tobytes()]
        return b"".join(out)

    assert rollout(3) == rollout(3)
    assert rollout(3) != rollout(4)


@pytest.mark.parametrize("model", ["palmer", "bourg"])
def test_track_sine_and_cosine_are_a_unit_vector(model: str) -> None:
    # Documented: observations 4 and 5 are the sine and cosine of the track.
    # (Bourg's once divided its ft/s velocity by the speed in m/s: a vector
    # of length 1/0.3048.) float32 observations: within 1e-6 of length 1.
    env = AircraftVectorEnv(model, "heading-altitude", num_envs=64)
    obs, _ = env.reset(seed=5)
    env.action_space.seed(5)
    for _ in range(20):
        sin_t, cos_t = obs[:, 4].astype(np.float64), obs[:, 5].astype(np.float64)
        assert np.all(np.abs(np.hypot(sin_t, cos_t) - 1.0) < 1e-6), (sin_t, cos_t)
        obs, *_ = env.step(env.action_space.sample())


def test_crashed_aircraft_terminate_cleanly() -> None:
    env = AircraftEnv("palmer", "heading-altitude", frame_skip=30)
    env.reset(seed=1)
    for _ in range(200):
        obs, reward, terminated, truncated, info = env.step(np.array([-1, -1, 0, -1], dtype=np.float32))
        assert np.isfinite(obs).all()
        if terminated:
            break
    assert terminated and reward == 0.0
    assert afit_fdm.Status(info["status"]) in (
        afit_fdm.Status.CRASHED, afit_fdm.Status.LANDED_ROUGH, afit_fdm.Status.LANDED_SAFE,
    )


def test_bad_reset_masks_are_refused() -> None:
    env = AircraftVectorEnv("palmer", num_envs=3, autoreset_mode=AutoresetMode.DISABLED)
    env.reset(seed=0)
    with pytest.raises(TypeError):
        env.reset(options={"reset_mask": np.array([1, 0, 0])})
    with pytest.raises(ValueError):
        env.reset(options={"reset_mask": np.array([True, False])})
    with pytest.raises(ValueError):
        env.reset(options={"reset_mask": np.zeros(3, dtype=bool)})


def test_step_before_reset_raises_reset_needed() -> None:
    """An aircraft has no episode (start, target) before its first reset:
    ``step`` raises Gymnasium's ``ResetNeeded``, as ``gymnasium.make``'s
    ``OrderEnforcing`` wrapper does, instead of flying the fleet's initial
    aircraft toward a target of 0 ft (what it used to do). A vector env
    refuses while any aircraft was never reset (a first reset with a
    ``reset_mask``), naming them; nothing is flown."""
    single = AircraftEnv("bourg", "climb")
    with pytest.raises(gym.error.ResetNeeded, match=r"before calling env\.reset\(\)"):
        single.step(np.zeros(5, dtype=np.float32))
    single.reset(seed=4)
    single.step(np.zeros(5, dtype=np.float32))
    made = gym.make("afit_fdm/PalmerClimb-v0")
    with pytest.raises(gym.error.ResetNeeded):
        made.step(np.zeros(4, dtype=np.float32))

    vec = AircraftVectorEnv("palmer", "climb", num_envs=8, autoreset_mode=AutoresetMode.DISABLED)
    with pytest.raises(gym.error.ResetNeeded, match=r"not reset: 0, 1, 2, 3, 4, \.\.\.\)"):
        vec.step(np.zeros((8, 4), dtype=np.float32))
    mask = np.zeros(8, dtype=bool)
    mask[[1, 5]] = True
    vec.reset(seed=0, options={"reset_mask": mask})
    before = vec._task.fleet.columns.copy()
    with pytest.raises(gym.error.ResetNeeded, match=r"\(not reset: 0, 2, 3, 4, 6, \.\.\.\)"):
        vec.step(np.zeros((8, 4), dtype=np.float32))
    assert np.array_equal(vec._task.fleet.columns, before)
    vec.reset(seed=0, options={"reset_mask": ~mask})
    obs, reward, *_ = vec.step(np.zeros((8, 4), dtype=np.float32))
    assert obs.shape == (8, 10) and np.isfinite(reward).all()


@pytest.mark.parametrize("make", [AircraftEnv, AircraftVectorEnv])
def test_bad_constructor_arguments_are_refused_by_name(make) -> None:
    """Whole-number arguments of another type raise ``TypeError`` and out of
    their range ``ValueError``, naming the argument, when the environment is
    made (not at its first step, and never taken as given: a fractional or
    negative ``max_episode_steps`` used to truncate every step, a fractional
    ``frame_skip`` to fail only in ``step``)."""
    for kw, error, words in [
        (dict(frame_skip=1.5), TypeError, "frame_skip: expected a whole number (int), got float"),
        (dict(frame_skip=True), TypeError, "frame_skip: expected a whole number (int), got bool"),
        (dict(frame_skip=0), ValueError, "frame_skip: 0 is not a whole number in 1..=108000"),
        (dict(frame_skip=108_001), ValueError, "frame_skip: 108001 is not a whole number in 1..=108000"),
        (dict(fps=10, frame_skip=36_001), ValueError, "frame_skip: 36001 is not a whole number in 1..=36000"),
        (dict(fps=29.97), TypeError, "fps: expected a whole number (int), got float"),
        (dict(fps=0), ValueError, "fps: 0 is not a whole number in 1..=10000"),
        (dict(max_episode_steps=0), ValueError, "max_episode_steps: 0 is not a whole number in 1..="),
        (dict(max_episode_steps=-5), ValueError, "max_episode_steps: -5 is not"),
        (dict(max_episode_steps=2.5), TypeError, "max_episode_steps: expected a whole number (int), got float"),
    ]:
        with pytest.raises(error) as raised:
            make("palmer", "climb", **kw)
        assert str(raised.value).startswith(words), (kw, str(raised.value))
    # The ends of the ranges are taken, NumPy integers too.
    make("palmer", "climb", fps=np.int64(10), frame_skip=36_000, max_episode_steps=np.int32(1))
    if make is AircraftVectorEnv:
        for n, error in [(0, ValueError), (2.0, TypeError), (True, TypeError)]:
            with pytest.raises(error, match="num_envs"):
                make("palmer", "climb", n)


def test_example_training_loop_runs_and_improves() -> None:
    example = pathlib.Path(__file__).resolve().parents[1] / "examples" / "train_heading.py"
    out = subprocess.run(
        [sys.executable, "-W", "error", str(example), "--iterations", "8", "--population", "32"],
        check=True, capture_output=True, text=True, timeout=300,
    )
    lines = [l for l in out.stdout.splitlines() if l.startswith("iteration")]
    assert len(lines) == 8
