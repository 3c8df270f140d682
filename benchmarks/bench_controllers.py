"""Controller cost per step: the paper's IBVS vs classic IBVS (a pseudo-inverse every step).

Usage: ``python benchmarks/bench_controllers.py`` (or ``make bench``). The paper's choice, the
goal interaction matrix with its pseudo-inverse computed once per goal (Section 3.3), leaves
only the features and one matrix product per step; classic IBVS builds the interaction matrix
at the current pose and pseudo-inverts it every step. For 9 and 36 points, one scene (the
policies' ``twist``, what ``predict`` costs) and a batch of 1,000 scenes (the batched maths).
"""

from __future__ import annotations

import platform
import timeit

import numpy as np

from radial_ibvs_agents import IBVSPolicy
from radial_ibvs_gym.features import L_alpha_m, L_cij, alpha_m, c_ij, virtual_point_weights


def scenes(batch: int, n: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    """Goal and current images of ``n`` wall points around ``batch`` robots 0.3 m from goal."""
    rng = np.random.default_rng(seed)
    angles = np.sort(rng.uniform(-np.pi, np.pi, (batch, n)), axis=-1)
    dist = rng.uniform(2.0, 8.0, (batch, n))
    goal = np.stack([dist * np.cos(angles), dist * np.sin(angles)], axis=-1)  # (B, N, 2)
    shift = rng.normal(0.0, 0.3, (batch, 1, 2))
    now = goal - shift
    d_goal, d_now = np.linalg.norm(goal, axis=-1), np.linalg.norm(now, axis=-1)
    return goal / d_goal[..., None], d_goal, now / d_now[..., None], d_now


def per_call_us(fn, number: int) -> float:
    """Best of 5 repeats, microseconds per call."""
    return 1e6 * min(timeit.repeat(fn, number=number, repeat=5)) / number


def bench_single(n: int) -> tuple[float, float]:
    """One scene: the policies' ``twist`` (validation, masks, the cached goal model included)."""
    x_goal, d_goal, x_now, d_now = (a[0] for a in scenes(1, n))
    obs = {
        "points": x_now.reshape(-1),
        "goal_points": x_goal.reshape(-1),
        "visible": np.ones(n),
        "goal_depths": d_goal,
        "depths": d_now,
    }
    paper, classic = IBVSPolicy("paper"), IBVSPolicy("current")
    return per_call_us(lambda: paper.twist(obs), 300), per_call_us(lambda: classic.twist(obs), 300)


def bench_batch(n: int, batch: int) -> tuple[float, float]:
    """A batch of scenes: the per-step maths vectorised over them; microseconds per scene."""
    x_goal, d_goal, x_now, d_now = scenes(batch, n)
    z = np.zeros_like(d_goal)
    weights = virtual_point_weights(x_goal)
    L_goal_pinv = np.linalg.pinv(L_cij(x_goal, d_goal, z)[..., :2])  # once per goal: not timed
    c_goal = c_ij(x_goal)

    def paper_step() -> np.ndarray:
        v_star = np.einsum("bij,bj->bi", L_goal_pinv, c_ij(x_now) - c_goal)
        return np.concatenate([v_star, alpha_m(x_now, weights)[..., None]], axis=-1)

    def classic_step() -> np.ndarray:
        L = np.zeros((batch, c_goal.shape[-1] + 1, 3))
        L[:, :-1, :2] = L_cij(x_now, d_now, z)[..., :2]
        L[:, -1] = L_alpha_m(x_now, d_now, z, weights)[..., [0, 1, 5]]
        e = np.concatenate([c_ij(x_now) - c_goal, alpha_m(x_now, weights)[..., None]], -1)
        return np.einsum("bij,bj->bi", np.linalg.pinv(L), e)

    return per_call_us(paper_step, 5) / batch, per_call_us(classic_step, 5) / batch


def main() -> None:
    """Print the table."""
    print(f"# controller cost per step: {platform.machine()}, numpy {np.__version__}")
    print(f"{'points':>6}  {'scenes':>6}  {'paper [us]':>11}  {'classic [us]':>13}  {'ratio':>6}")
    for n in (9, 36):
        for batch in (1, 1000):
            paper, classic = bench_single(n) if batch == 1 else bench_batch(n, batch)
            note = "" if batch == 1 else "   (per scene)"
            print(
                f"{n:>6}  {batch:>6}  {paper:>11.2f}  {classic:>13.2f}  {classic / paper:>6.2f}"
                + note
            )


if __name__ == "__main__":
    main()
