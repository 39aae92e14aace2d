"""A small training loop: a linear policy for ``afit_fdm/PalmerHeadingAltitude-v0``
learned by a cross-entropy method, every candidate flown at once by one
vector env (one aircraft per candidate). Runs in seconds::

    python examples/train_heading.py --iterations 20 --population 64
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import afit_fdm  # noqa: F401  (registers the ids)


def evaluate(env: gym.vector.VectorEnv, weights: np.ndarray, seed: int, steps: int) -> np.ndarray:
    """Return of each aircraft flying its own linear policy ``tanh(W obs + b)``."""
    obs, _ = env.reset(seed=seed)
    total = np.zeros(env.num_envs)
    alive = np.ones(env.num_envs, dtype=bool)
    for _ in range(steps):
        w, b = weights[:, :, :-1], weights[:, :, -1]
        actions = np.tanh(np.einsum("nao,no->na", w, obs) + b).astype(np.float32)
        obs, reward, terminated, truncated, _ = env.step(actions)
        total += np.where(alive, reward, 0.0)
        alive &= ~(terminated | truncated)
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--iterations", type=int, default=20)
    parser.add_argument("--population", type=int, default=64)
    parser.add_argument("--steps", type=int, default=60, help="agent steps per episode (frame_skip 15: 0.5 s each)")
    args = parser.parse_args()

    env = gym.make_vec(
        "afit_fdm/PalmerHeadingAltitude-v0",
        num_envs=args.population,
        vectorization_mode="vector_entry_point",
        frame_skip=15,
        max_episode_steps=args.steps,
    )
    # Both spaces are Boxes (the module docstring of afit_fdm.gym): their
    # shapes are known.
    act_space, obs_space = env.single_action_space, env.single_observation_space
    assert isinstance(act_space, gym.spaces.Box) and isinstance(obs_space, gym.spaces.Box)
    n_act, n_obs = act_space.shape[0], obs_space.shape[0]
    rng = np.random.default_rng(0)
    mean = np.zeros((n_act, n_obs + 1))
    std = np.full_like(mean, 0.5)
    elite = max(2, args.population // 8)
    for it in range(args.iterations):
        weights = mean + std * rng.standard_normal((args.population, *mean.shape))
        returns = evaluate(env, weights, seed=it, steps=args.steps)
        best = weights[np.argsort(returns)[-elite:]]
        mean, std = best.mean(axis=0), best.std(axis=0) + 0.02
        print(f"iteration {it}: mean return {returns.mean():.2f}, best {returns.max():.2f}")
    env.close()


if __name__ == "__main__":
    main()
