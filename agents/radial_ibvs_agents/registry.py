"""Policies by name, as the CLI and the benchmark use them (README, "Command line").

Every policy has stable-baselines3's ``predict(observation, state=None, episode_start=None,
deterministic=True) -> (action, state)`` and an ``env_kwargs`` mapping: what ``gym.make`` must
add to the observation for it (the goal depths, the true poses).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from radial_ibvs_agents.analytic import ANALYTIC_POLICIES
from radial_ibvs_gym.config import did_you_mean

__all__ = ["POLICY_NAMES", "Policy", "RandomPolicy", "make_policy"]


class Policy(Protocol):
    """What every policy provides."""

    @property
    def env_kwargs(self) -> dict[str, bool]:  # noqa: D102
        ...

    def predict(  # noqa: D102
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]: ...


class RandomPolicy:
    """Uniform random actions in ``[-1, 1]^2`` (a floor for the benchmark).

    Each episode draws from its own generator: the next child of the policy's seed
    (:meth:`numpy.random.SeedSequence.spawn`), taken when the episode starts. So the ``k``-th
    episode a policy object starts gets the same actions whether the episodes run one at a
    time or batched (robots start in order), and whatever the lengths of the episodes before
    it. The state :meth:`predict` returns holds the episodes' generators.

    Parameters
    ----------
    seed
        Seed of the policy's generators (the same seed, the same actions).
    """

    env_kwargs: dict[str, bool] = {}  # noqa: RUF012
    #: one call serves a batch (:mod:`radial_ibvs_agents.rollouts`)
    batch_mode = "batch"

    def __init__(self, seed: int | None = 0) -> None:
        self._seeds = np.random.SeedSequence(seed)

    def __repr__(self) -> str:
        return "RandomPolicy()"

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: list[np.random.Generator] | None = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, list[np.random.Generator]]:
        """Random action(s), ``(2,)`` or ``(B, 2)`` float32, for one observation or a batch.

        Parameters
        ----------
        observation
            One observation, or a batch of ``B`` (its ``"points"`` entry tells which).
        state
            The generators of the episodes under way, as the last call returned them, or
            ``None``: new episodes.
        episode_start
            ``(B,)`` booleans: the episodes that start now (they get new generators); ``None``
            with a state: none starts.
        deterministic
            Ignored.

        Returns
        -------
        actions, state
            The actions and the episodes' generators.
        """
        points = np.asarray(observation["points"])
        batched = points.ndim == 2
        n = len(points) if batched else 1
        if state is not None and len(state) != n:
            raise ValueError(f"state holds {len(state)} episode(s) for a batch of {n}")
        if state is None:  # new episodes, whatever episode_start says
            generators = [np.random.default_rng(s) for s in self._seeds.spawn(n)]
        else:  # as SB3's recurrent policies: no episode_start, no episode starts
            generators = list(state)
            starts = np.zeros(n, dtype=bool) if episode_start is None else episode_start
            for i in np.flatnonzero(np.broadcast_to(np.asarray(starts, bool).ravel(), (n,))):
                generators[i] = np.random.default_rng(self._seeds.spawn(1)[0])
        actions = np.stack([g.uniform(-1.0, 1.0, 2) for g in generators]).astype(np.float32)
        return (actions if batched else actions[0]), generators

    def select_state(
        self, state: list[np.random.Generator], rows: np.ndarray
    ) -> list[np.random.Generator]:
        """Return the generators of the episodes at positions ``rows`` of the batch."""
        return [state[i] for i in np.asarray(rows).tolist()]


_FACTORIES: dict[str, Callable[..., Policy]] = {
    **ANALYTIC_POLICIES,
    "random": lambda **kw: RandomPolicy(**kw),
}
POLICY_NAMES = tuple(_FACTORIES)


#: policies renamed before 0.1: the old name gets an error that gives the new one
RENAMED = {"ppo-student": "dagger-student"}  # distilled from the planner by DAgger, not PPO


def make_policy(name: str, *, trust_pickle: bool = False, **kwargs: Any) -> Policy:
    """Build a policy by its name.

    Parameters
    ----------
    name
        One of :data:`POLICY_NAMES` (``ibvs``, ``ibvs-current``, ``ibvs-mean``,
        ``ibvs-no-frame-change``, ``oracle``, ``random``), a shipped model's name
        (:func:`radial_ibvs_agents.learned.shipped_models`, e.g. ``dagger-student``) or a model
        directory's path (``./my-model``: a bare name is never a folder, so none can shadow a
        shipped one).
    trust_pickle
        For a model directory that holds only a stable-baselines3 ``model.zip``: load it through its
        pickles (:func:`radial_ibvs_agents.learned.load`). Ignored by the other policies.
    **kwargs
        Passed to the policy (e.g. ``lam=0.5`` for the IBVS variants, ``seed`` for ``random``;
        none for a learned model).

    Raises
    ------
    ValueError
        If the name is unknown (the message lists the valid ones), or a model file is missing
        or corrupt.
    """
    if name in _FACTORIES:
        return _FACTORIES[name](**kwargs)
    from radial_ibvs_agents.learned import load, shipped_models
    from radial_ibvs_agents.learned.files.loading import is_bare_name

    if name in shipped_models() or not is_bare_name(name):
        if kwargs:
            raise ValueError(f"a learned model takes no arguments, got {sorted(kwargs)}")
        return load(name, trust_pickle=trust_pickle)
    if name in RENAMED:
        raise ValueError(f"the policy {name!r} is now called {RENAMED[name]!r}")
    valid = [*POLICY_NAMES, *shipped_models()]
    hint = f"; for the folder of that name, give its path: ./{name}" if Path(name).exists() else ""
    close = did_you_mean(name, valid)
    raise ValueError(
        f"unknown policy {name!r}{close}; valid: {valid} or a model directory's path{hint}"
    )
