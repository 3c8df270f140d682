"""``radial-ibvs collect``: a policy's episodes as a Minari dataset (Farama's offline-RL format).

The dataset is written locally (``DIR/<dataset_id>``, Minari's HDF5 layout); nothing goes to a hub.
Its observations are the env's whole ``Dict`` observation: by default the features observation of
the learned models (``obs_mode="features"``, goal depths, 16 landmark slots) plus whatever the
policy needs (the planner's poses and map), so a student can be distilled from a teacher's dataset
(the ``initial_dataset`` of :mod:`radial_ibvs_agents.learned.dagger.distill`). Each episode keeps
its ``info`` (``is_success``, the errors, the reward terms...) as Minari's ``infos``: one row for
the reset and one per step.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.learned.dagger.datasets import datasets_path, minari_module
from radial_ibvs_agents.registry import make_policy
from radial_ibvs_agents.rollouts import make_env

__all__ = ["DEFAULT_LAYOUT", "collect", "dataset_id_for", "stack_infos"]

#: the observation the learned models see, the default layout of a dataset
DEFAULT_LAYOUT: dict[str, Any] = {
    "obs_mode": "features",
    "goal_depths": True,
    "max_landmarks": 16,
    "physics": "kinematic",
}


def stack_infos(infos: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Stack an episode's ``info`` dicts (reset's, then each step's) as Minari stores them.

    Parameters
    ----------
    infos
        ``T + 1`` dicts with the same keys (the envs give the same keys at reset and step).

    Returns
    -------
    dict
        Per key a ``(T + 1, ...)`` array; nested dicts stacked alike; text values (a pixel
        detector's ``status``) left out, as HDF5 stores numbers.
    """
    out: dict[str, Any] = {}
    for key, first in infos[0].items():
        if isinstance(first, Mapping):
            out[key] = stack_infos([i[key] for i in infos])
        elif not isinstance(first, str):
            out[key] = np.stack([np.asarray(i[key]) for i in infos])
    return out


#: Minari's dataset ids, kept to plain names: ``namespace/name-vN`` or ``name-vN``
_DATASET_ID = re.compile(r"(?:[A-Za-z0-9_-]+/)?[A-Za-z0-9_][A-Za-z0-9_.-]*-v[0-9]+")


def dataset_id_for(policy: str, scenario: str) -> str:
    """Return the dataset id of a policy's episodes in a scenario: ``radial-ibvs/P-S-v0``."""
    clean = "".join(c if c.isalnum() else "_" for c in f"{Path(policy).name}-{Path(scenario).stem}")
    return f"radial-ibvs/{clean.replace('-', '_')}-v0"


def collect(
    policy_name: str,
    scenario: str,
    episodes: int,
    out_dir: Path | str,
    *,
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    dataset_id: str | None = None,
    trust_model: bool = False,
    progress: bool = True,
) -> Path:
    """Run ``episodes`` seeded episodes of a policy and write them as a Minari dataset.

    Parameters
    ----------
    policy_name
        A policy name (``planner``, ``ibvs``...) or a model directory.
    scenario
        Scenario name or YAML path.
    episodes
        Episodes, seeded ``seed, seed + 1, ...`` (>= 1).
    out_dir
        The datasets directory; the dataset is ``out_dir/<dataset_id>``.
    seed
        First seed.
    env_kwargs
        ``gym.make`` arguments over :data:`DEFAULT_LAYOUT` and the policy's own.
    dataset_id
        Minari id (``namespace/name-vN``); default :func:`dataset_id_for`.
    trust_model, progress
        As for ``evaluate``; a progress bar over the episodes.

    Returns
    -------
    pathlib.Path
        The dataset's directory.

    Raises
    ------
    ValueError
        For a bad argument, a dataset id already in ``out_dir``, or Minari missing.
    """
    minari = minari_module()
    from tqdm.auto import tqdm

    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise ValueError(f"episodes must be an integer >= 1, got {episodes!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    dataset_id = dataset_id or dataset_id_for(policy_name, scenario)
    if not _DATASET_ID.fullmatch(dataset_id):  # before any episode runs: no folder outside out
        raise ValueError(
            f"dataset id {dataset_id[:80]!r} must be NAMESPACE/NAME-vN or NAME-vN (letters, "
            "digits, '-', '_' and '.'; no '..' and no leading '/')"
        )
    if (out / dataset_id).exists():
        raise ValueError(f"{out / dataset_id} exists: remove it or give another --out")
    policy = make_policy(policy_name, trust_pickle=trust_model)
    overrides = {
        **DEFAULT_LAYOUT,
        **dict(getattr(policy, "env_kwargs", {})),
        **dict(env_kwargs or {}),
    }
    env = make_env(policy, scenario, overrides)
    from minari.data_collector import EpisodeBuffer  # filled whole: no jax needed

    buffers, successes = [], 0
    for episode in tqdm(range(episodes), desc=f"collect {policy_name}", disable=not progress):
        obs, info = env.reset(seed=seed + episode)
        observations, actions, rewards, terminations, truncations = [obs], [], [], [], []
        infos = [info]
        state, start, done = None, True, False
        while not done:
            action, state = policy.predict(obs, state, np.array([start]))
            action = np.asarray(action, dtype=np.float32)
            obs, reward, terminated, truncated, info = env.step(action)
            observations.append(obs)
            infos.append(info)
            actions.append(action)
            rewards.append(float(reward))
            terminations.append(bool(terminated))
            truncations.append(bool(truncated))
            start, done = False, bool(terminated or truncated)
        successes += bool(info.get("is_success", False))
        buffers.append(
            EpisodeBuffer(
                id=episode,
                seed=seed + episode,
                observations={k: np.stack([o[k] for o in observations]) for k in observations[0]},
                actions=np.stack(actions),
                rewards=rewards,
                terminations=terminations,
                truncations=truncations,
                infos=stack_infos(infos),
            )
        )
    with datasets_path(out), warnings.catch_warnings():
        # no public code URL or contact e-mail is known to this package: Minari's reminders
        warnings.filterwarnings("ignore", ".*(code_permalink|author_email)", UserWarning)
        minari.create_dataset_from_buffers(
            dataset_id=dataset_id,
            buffer=buffers,
            env=env.spec,
            eval_env=env.spec,
            algorithm_name=f"radial_ibvs_gym {policy_name}",
            author="radial_ibvs_gym",
            description=(
                f"{episodes} episodes of {policy_name} in {scenario}, seeds {seed}.."
                f"{seed + episodes - 1}; success rate {successes / episodes:.3f}; gym.make "
                f"arguments {overrides}"
            ),
            data_format="hdf5",
            jpeg_encoding=False,  # lossless, and images of any channel count (JPEG: 1 or 3)
        )
    env.close()
    return out / dataset_id
