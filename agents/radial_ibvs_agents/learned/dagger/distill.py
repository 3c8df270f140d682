"""Distil a privileged teacher into an image-only student by DAgger (Ross et al., 2011).

The teacher (the ``planner`` by default) sees the poses and the map; the student sees only what the
other learned models see (the features observation: landmark slots, ``c_ij`` errors, ``alpha_m``
error, goal depths; optionally a short history, :mod:`radial_ibvs_agents.learned.networks.history`).
Each round:

1. the vector env is stepped with, per robot and step, the teacher's action with probability
   ``beta`` and the student's otherwise (``beta`` is 1 in the first round and decays);
2. the teacher labels every state visited (the student's states included: that is DAgger);
3. the student, an SB3 ``MultiInputPolicy`` (the actor of a PPO model), is fitted to all the
   labels so far (mean squared error of its mean action), and evaluated on held-out seeds.

The ``imitation`` package's DAgger would be the library for this, but its releases pin gymnasium
0.29 and stable-baselines3 2.2 (this project needs gymnasium >= 1.0), so the loop is written here,
over SB3's policy and torch. Observations are normalised with statistics fixed after the first
round, stored as the model's ``normalization.npz``; the result is an SB3 PPO model directory that
:func:`radial_ibvs_agents.load` runs like the others, with no analytic policy in it. About 490
lines: the DAgger loop and the student's fitting, which share the round's state; the settings are in
:mod:`radial_ibvs_agents.learned.dagger.distill_config`, the provenance in
:mod:`radial_ibvs_agents.learned.files.provenance`.
"""

from __future__ import annotations

import csv
import json
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.io import write_json
from radial_ibvs_agents.learned.dagger.distill_config import (
    ACTIVATIONS,
    EXTRACTORS,
    PRIVILEGED,
    DaggerConfig,
    load_dagger_config,
)
from radial_ibvs_agents.learned.files.model_dir import replace_model_files
from radial_ibvs_agents.learned.networks import extractors
from radial_ibvs_agents.learned.networks.extractors import POSE_HISTORY_KEYS, error_key_of, raw_keys
from radial_ibvs_agents.learned.networks.history import HistoryConfig, HistoryStack, history_space
from radial_ibvs_gym.geometry import relative_pose

__all__ = [
    "DaggerConfig",
    "dagger",
    "dataset_labels",
    "goal_in_robot_frame",
    "load_dagger_config",
    "round_schedule",
]


class _Dataset:
    """Labelled states, at most ``size``; when full, new ones replace old ones at random."""

    def __init__(self, size: int, rng: np.random.Generator) -> None:
        self.size, self.rng = size, rng
        self.obs: dict[str, np.ndarray] = {}
        self.labels = np.zeros((0, 0), dtype=np.float32)
        self.count = 0  # rows filled
        self.seen = 0  # rows ever added

    def add(self, obs: dict[str, np.ndarray], labels: np.ndarray) -> None:
        n = len(labels)
        if not self.obs:
            self.obs = {k: np.zeros((self.size, *v.shape[1:]), np.float32) for k, v in obs.items()}
            self.labels = np.zeros((self.size, labels.shape[1]), dtype=np.float32)
        free = min(self.size - self.count, n)
        rows = np.arange(self.count, self.count + free)
        if free < n:  # reservoir-style: the rest replace random old rows
            rows = np.concatenate([rows, self.rng.integers(0, self.size, n - free)])
        for key, value in obs.items():
            self.obs[key][rows] = value
        self.labels[rows] = labels
        self.count += free
        self.seen += n

    def sample(self, batch: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
        rows = self.rng.integers(0, self.count, batch)
        return {k: v[rows] for k, v in self.obs.items()}, self.labels[rows]


def dagger(
    config: DaggerConfig,
    out_dir: Path | str,
    *,
    seed: int = 0,
    progress: bool = True,
    torch_threads: int = 1,
    command: str | None = None,
) -> Path:
    """Run DAgger and write the student's model directory (``radial_ibvs_agents.load`` runs it).

    Parameters
    ----------
    config
        The validated configuration (:func:`load_dagger_config`).
    out_dir
        Output directory (created): the model files, ``progress.csv`` (one row per round),
        ``learning_curve.png``, ``rounds/round_K/`` (the student after round ``K``).
    seed
        Seed of the envs, the mixing and the network.
    progress
        Show a progress bar over the rounds.
    torch_threads
        Threads for torch.
    command
        The command line, for the metadata.

    Returns
    -------
    pathlib.Path
        The model directory.
    """
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.running_mean_std import RunningMeanStd
    from tqdm.auto import tqdm

    from radial_ibvs_agents.learned.files.provenance import provenance
    from radial_ibvs_agents.learned.files.saving import save_model_dir
    from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env, spaces_env

    origin = provenance(command, config.source)  # at the start: the code that trains
    torch.set_num_threads(torch_threads)
    torch.manual_seed(seed)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    student_env = make_vec_env(config.env_id, 1, seed=seed, monitor=False, **config.env_kwargs)
    base_space: Any = student_env.observation_space
    base_keys = list(base_space.spaces)
    student_space = history_space(config.history, base_space)
    history = HistoryStack(config.history, config.n_envs)
    student_env.close()
    venv = make_vec_env(
        config.env_id, config.n_envs, seed=seed, monitor=False, **config.env_kwargs, **PRIVILEGED
    )
    teacher = make_analytic(config.teacher, **config.teacher_kwargs)
    landmark_set = config.extractor in ("landmark_set", "landmark_pose")
    model = PPO(
        "MultiInputPolicy",
        spaces_env(student_space, venv.action_space),
        seed=seed,
        device="cpu",
        policy_kwargs={
            "net_arch": list(config.net_arch),
            "activation_fn": getattr(torch.nn, ACTIVATIONS[config.activation]),
            "log_std_init": -1.0,
            **(
                {
                    "features_extractor_class": getattr(extractors, EXTRACTORS[config.extractor]),
                    "features_extractor_kwargs": {
                        "error_keys": list(config.error_keys),
                        "point_error": config.point_error,
                        **({"angle_keys": list(config.angle_keys)} if config.angle_keys else {}),
                        **({"pose_history": True} if config.pose_history else {}),
                    },
                }
                if config.error_keys or config.point_error or landmark_set
                else {}
            ),
        },
    )
    policy = model.policy
    actor = [
        *policy.features_extractor.parameters(),
        *policy.mlp_extractor.policy_net.parameters(),
        *policy.action_net.parameters(),
    ]
    # an auxiliary head, in training only: the goal's pose in the robot frame, from the
    # actor's last hidden layer (what the student must infer from the image to act)
    aux_head = torch.nn.Linear(policy.mlp_extractor.latent_dim_pi, 4)
    optimiser = torch.optim.Adam([*actor, *aux_head.parameters()], lr=config.learning_rate)
    raw = raw_keys(config.error_keys, config.point_error, landmark_set)  # read raw
    if config.pose_history:  # the past frames' points are solved for poses too
        raw = (*raw, *(k for k in student_space.spaces if k.split("@", 1)[0] in POSE_HISTORY_KEYS))
    rms = {
        k: RunningMeanStd(shape=tuple(student_space.spaces[k].shape or ()))
        for k in student_space.spaces
        if k not in raw and error_key_of(k, config.error_keys) is None
    }
    clip, eps = 10.0, 1e-8
    dataset = _Dataset(config.dataset_size, rng)

    def normalise(obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        out = {}
        for k in student_space.spaces:
            value = np.asarray(obs[k], dtype=np.float32)
            if k in rms:
                value = np.clip((value - rms[k].mean) / np.sqrt(rms[k].var + eps), -clip, clip)
            out[k] = value.astype(np.float32)
        return out

    def student_act(obs: dict[str, np.ndarray]) -> np.ndarray:
        with torch.no_grad():
            action, _ = policy.predict(normalise(obs), deterministic=True)
        return np.asarray(action, dtype=np.float32)

    if config.initial_dataset is not None:  # a teacher's recorded episodes (radial-ibvs collect)
        first_obs, first_labels = dataset_labels(config.initial_dataset, base_keys, config.history)
        for k, stats in rms.items():
            stats.update(first_obs[k])
        dataset.add(first_obs, first_labels)
    rows: list[dict[str, float]] = []
    obs: Any = venv.reset()
    starts = np.ones(config.n_envs, dtype=bool)
    teacher_state: Any = None
    student_obs = history.reset({k: obs[k] for k in base_keys})
    beta = config.beta
    start_time = time.perf_counter()
    bar = tqdm(range(config.rounds), desc="DAgger", disable=not progress)
    for round_index in bar:
        steps = max(config.steps_per_round // config.n_envs, 1)
        batch_obs: dict[str, list[np.ndarray]] = {k: [] for k in student_space.spaces}
        batch_labels: list[np.ndarray] = []
        teacher_share = 0.0
        for _ in range(steps):
            label, teacher_state = teacher.predict(obs, teacher_state, starts)
            label = np.clip(np.asarray(label, dtype=np.float32), -1.0, 1.0)
            for k in student_space.spaces:
                batch_obs[k].append(student_obs[k].astype(np.float32))
            batch_labels.append(np.concatenate([label, goal_in_robot_frame(obs)], axis=1))
            if round_index == 0:
                for k, stats in rms.items():
                    stats.update(student_obs[k])
            use_teacher = rng.random(config.n_envs) < beta
            teacher_share += float(use_teacher.mean())
            if beta < 1.0:
                own = student_act(student_obs)
                action = np.where(use_teacher[:, None], label, own)
            else:
                action = label
            obs, _rewards, dones, _infos = venv.step(action)
            starts = dones
            student_obs = history.step({k: obs[k] for k in base_keys}, dones)
        dataset.add(
            {k: np.concatenate(v) for k, v in batch_obs.items()}, np.concatenate(batch_labels)
        )
        loss = _fit(policy, aux_head, optimiser, dataset, normalise, config, torch)
        success = _evaluate(config, student_act, base_keys, seed)
        rows.append(
            {
                "round": round_index,
                "beta": round(beta, 4),
                "teacher_share": round(teacher_share / steps, 4),
                "labels": dataset.seen,
                "env_steps": (round_index + 1) * steps * config.n_envs,
                "loss": round(loss, 6),
                "success_rate": success,
                "wall_s": round(time.perf_counter() - start_time, 1),
            }
        )
        bar.set_postfix(success=f"{success:.2f}", loss=f"{loss:.4f}")
        _write_progress(out / "progress.csv", rows)
        vecnorm = _vec_normalize(student_space, venv.action_space, rms, clip, eps)
        meta = _metadata(config, seed, rows, origin)
        save_model_dir(
            model, out / "rounds" / f"round_{round_index}", env_id=config.env_id,
            env_kwargs=config.env_kwargs, normalization=vecnorm, metadata=meta,
        )  # fmt: skip
        beta *= config.beta_decay
    best = max(rows, key=lambda r: (r["success_rate"], r["round"]))
    final = out / "rounds" / f"round_{int(best['round'])}"
    meta = json.loads((final / "metadata.json").read_text())  # algo, env_id, env_kwargs...
    meta |= _metadata(config, seed, rows, origin) | {"best_round": int(best["round"])}
    with replace_model_files(out) as staging:  # the best round's files, all at once
        for name in ("policy.safetensors", "policy.json", "normalization.npz"):
            (staging / name).write_bytes((final / name).read_bytes())
        write_json(staging / "metadata.json", meta)
        _plot(rows, staging / "learning_curve.png")
    venv.close()
    return out


def dataset_labels(
    path: str | Path, keys: list[str], history: HistoryConfig | None
) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Return the student observations and the labels of a teacher's Minari dataset.

    Each episode's observations are stacked as in the rollouts (``history``); the labels are
    the recorded actions and the auxiliary targets (:func:`goal_in_robot_frame`, from the
    recorded ``robot_pose`` and ``goal_pose``).

    Raises
    ------
    ValueError
        If the dataset lacks a key the student or the auxiliary targets need (naming it).
    """
    from radial_ibvs_agents.learned.dagger.datasets import load_collected

    data = load_collected(path)
    parts: dict[str, list[np.ndarray]] = {}
    labels: list[np.ndarray] = []
    for episode in data.iterate_episodes():
        recorded = episode.observations
        missing = sorted({*keys, "robot_pose", "goal_pose"} - set(recorded))
        if missing:
            raise ValueError(f"{path}: the dataset's observations lack {missing}")
        steps = len(episode.actions)
        stack = HistoryStack(history, 1)
        for t in range(steps):
            row = {k: np.asarray(recorded[k][t : t + 1]) for k in keys}
            stacked = stack.reset(row) if t == 0 else stack.step(row, np.zeros(1, dtype=bool))
            for k, v in stacked.items():
                parts.setdefault(k, []).append(v.astype(np.float32))
        poses = {k: np.asarray(recorded[k][:steps]) for k in ("robot_pose", "goal_pose")}
        action = np.clip(np.asarray(episode.actions, dtype=np.float32), -1.0, 1.0)
        labels.append(np.concatenate([action, goal_in_robot_frame(poses)], axis=1))
    return {k: np.concatenate(v) for k, v in parts.items()}, np.concatenate(labels)


def goal_in_robot_frame(obs: Mapping[str, np.ndarray]) -> np.ndarray:
    """Return the auxiliary targets: the goal in the robot's frame, ``(B, 4)``.

    ``(x / 3 m, y / 3 m, cos e, sin e)``, with ``(x, y)`` the goal position in the robot's
    frame and ``e`` the heading error, from the privileged ``robot_pose`` and ``goal_pose``.
    """
    robot = np.asarray(obs["robot_pose"], dtype=np.float64).reshape(-1, 3)
    goal = np.asarray(obs["goal_pose"], dtype=np.float64).reshape(-1, 3)
    x, y = relative_pose(robot, goal)[:, :2].T  # the goal in the robot's frame
    error = goal[:, 2] - robot[:, 2]  # not wrapped: only its cosine and sine are used
    out = np.stack([x / 3.0, y / 3.0, np.cos(error), np.sin(error)], 1)
    return out.astype(np.float32)


def action_loss(actions: Any, labels: Any, weights: Any, relative_floor: float = 0.0) -> Any:
    """Return the student's loss: the mean weighted squared error of its actions (torch).

    Parameters
    ----------
    actions, labels
        ``(B, 2)`` tensors: the student's mean actions and the teacher's labels.
    weights
        ``(2,)`` weight of each action component.
    relative_floor
        ``0``: the squared error. ``> 0``: the squared relative error, each error divided by
        ``|label| + relative_floor`` (``DaggerConfig.relative_floor``).
    """
    error = actions - labels
    if relative_floor > 0:  # small labels fit as closely, relatively, as large ones
        error = error / (labels.abs() + relative_floor)
    return (error**2 * weights).mean()


def round_schedule(optimiser: Any, config: DaggerConfig) -> Any:
    """Return the step-size schedule of one round's fit, or ``None`` for a constant one.

    With ``config.final_learning_rate``, the optimiser's step size is reset to
    ``config.learning_rate`` and a ``CosineAnnealingLR`` brings it to ``final_learning_rate``
    over ``config.updates_per_round`` steps (call its ``step()`` after each optimiser step).
    """
    if config.final_learning_rate is None:
        return None
    import torch

    for group in optimiser.param_groups:  # each round starts from the full step size
        group["lr"] = config.learning_rate
    return torch.optim.lr_scheduler.CosineAnnealingLR(
        optimiser, T_max=config.updates_per_round, eta_min=config.final_learning_rate
    )


def _fit(
    policy: Any,
    aux_head: Any,
    optimiser: Any,
    dataset: _Dataset,
    normalise: Any,
    config: DaggerConfig,
    torch: Any,
) -> float:
    """Fit the actor's mean action to the labels; return the mean loss of the last 10 %."""
    policy.set_training_mode(True)
    losses = []
    weights = torch.ones(2)
    if config.balance_actions:  # each action component weighted by 1 / its label variance
        variance = np.maximum(dataset.labels[: dataset.count, :2].var(axis=0), 1e-6)
        weights = torch.as_tensor((1.0 / variance) / np.mean(1.0 / variance), dtype=torch.float32)
    schedule = round_schedule(optimiser, config)
    for _ in range(config.updates_per_round):
        obs, labels = dataset.sample(config.batch_size)
        tensors = {k: torch.as_tensor(v) for k, v in normalise(obs).items()}
        features = policy.extract_features(tensors, policy.pi_features_extractor)
        latent = policy.mlp_extractor.forward_actor(features)
        targets = torch.as_tensor(labels)
        loss = action_loss(
            policy.action_net(latent), targets[:, :2], weights, config.relative_floor
        )
        if config.aux_weight > 0:
            aux = torch.mean((aux_head(latent) - targets[:, 2:]) ** 2)
            loss = loss + config.aux_weight * aux
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        if schedule is not None:
            schedule.step()
        losses.append(loss.item())
    policy.set_training_mode(False)
    tail = losses[-max(len(losses) // 10, 1) :]
    return float(np.mean(tail))


def _evaluate(config: DaggerConfig, act: Any, base_keys: list[str], seed: int) -> float:
    """Success rate of ``act`` over the held-out episodes (each robot's first episode)."""
    from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

    n = config.eval_episodes
    venv = make_vec_env(config.env_id, n, seed=config.eval_seed, monitor=False, **config.env_kwargs)
    stack = HistoryStack(config.history, n)
    first: Any = venv.reset()
    obs = stack.reset({k: v for k, v in first.items() if k in base_keys})
    done = np.zeros(n, dtype=bool)
    success = np.zeros(n, dtype=bool)
    while not done.all():
        step_obs: Any
        step_obs, _r, dones, infos = venv.step(act(obs))
        for i in np.flatnonzero(dones & ~done):
            success[i] = bool(infos[i].get("is_success", False))
        done |= dones
        obs = stack.step({k: v for k, v in step_obs.items() if k in base_keys}, dones)
    venv.close()
    return float(success.mean())


def _vec_normalize(
    space: Any, action_space: Any, rms: dict[str, Any], clip: float, eps: float
) -> Any:
    """Return a ``VecNormalize`` holding the DAgger statistics (``save_normalization`` input)."""
    from stable_baselines3.common.vec_env import VecNormalize

    from radial_ibvs_agents.learned.training.sb3_vec_env import spaces_env

    venv = VecNormalize(
        spaces_env(space, action_space),
        norm_obs=True,
        norm_obs_keys=list(rms),
        norm_reward=False,
        clip_obs=clip,
        epsilon=eps,
    )
    venv.obs_rms = rms
    return venv


def _metadata(
    config: DaggerConfig, seed: int, rows: list[dict[str, float]], origin: dict[str, Any]
) -> dict[str, Any]:
    from radial_ibvs_agents.learned.files.provenance import jsonable

    return {
        "trained_by": "dagger",
        "teacher": config.teacher,
        "teacher_kwargs": jsonable(config.teacher_kwargs),
        **({"history": config.history.as_dict()} if config.history else {}),
        "seed": seed,
        "total_timesteps": int(rows[-1]["env_steps"]) if rows else 0,
        **origin,  # the command, config and revision as the run started
        "wall_clock_s": rows[-1]["wall_s"] if rows else 0.0,
        "learning_curve": [
            {"timesteps": r["env_steps"], "success_rate": r["success_rate"]} for r in rows
        ],
    }


def _write_progress(path: Path, rows: list[dict[str, float]]) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _plot(rows: list[dict[str, float]], path: Path) -> None:
    from radial_ibvs_agents.plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot([r["env_steps"] / 1e6 for r in rows], [r["success_rate"] for r in rows], marker="o")
    ax.set_xlabel("env steps (millions)")
    ax.set_ylabel("held-out success rate")
    ax.set_ylim(0, 1.02)
    ax.set_title("DAgger: the student after each round")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)
