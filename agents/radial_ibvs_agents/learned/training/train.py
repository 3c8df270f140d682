"""``radial-ibvs train``: stable-baselines3 training from an rl-zoo3-style config.

Vectorised envs, observation normalisation (``VecNormalize``), evaluation on held-out seeds
with best-model checkpointing, periodic checkpoints, CSV (and TensorBoard, when installed) logs,
a progress bar, resuming from a checkpoint; the result is a model directory that
:func:`radial_ibvs_agents.learned.load` reads without unpickling anything (``policy.safetensors``,
``policy.json``, ``normalization.npz``, ``metadata.json``), with ``learning_curve.png``, the
best model in ``best/``, and SB3's own ``model.zip`` for SB3 users and for resuming.

About 600 lines: :func:`train` and the callbacks, checks, resuming and export it needs, which
share the run's state; the model files are in :mod:`radial_ibvs_agents.learned.files.model_files`
(written all at once by :mod:`~radial_ibvs_agents.learned.files.model_dir`), the provenance in
:mod:`radial_ibvs_agents.learned.files.provenance`.
"""

from __future__ import annotations

import importlib.util
import json
import re
import shutil
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback, CheckpointCallback
from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
from stable_baselines3.common.logger import configure
from stable_baselines3.common.vec_env import VecNormalize

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.io import write_json
from radial_ibvs_agents.learned.files.model_dir import BEST_FILES, replace_model_files
from radial_ibvs_agents.learned.files.model_files import (
    DESCRIPTION,
    WEIGHTS,
    algorithms,
    has_policy_files,
    load_policy,
    read_normalization,
    save_normalization,
    save_policy,
)
from radial_ibvs_agents.learned.files.provenance import jsonable, provenance, versions
from radial_ibvs_agents.learned.networks.history import HistoryConfig, history_vec_env
from radial_ibvs_agents.learned.networks.residual import ResidualVecEnv
from radial_ibvs_agents.learned.training.curriculum import StartReachCurriculum
from radial_ibvs_agents.learned.training.fine_tune import CriticWarmup
from radial_ibvs_agents.learned.training.tolerance_eval import (
    ToleranceEvalCallback,
    read_tolerance_curve,
)
from radial_ibvs_agents.learned.training.zoo_config import TRAIN_EXTRACTORS, TrainConfig
from radial_ibvs_agents.plotting import save_figure
from radial_ibvs_agents.untrusted import check_archive, read_json
from radial_ibvs_gym.config import did_you_mean

__all__ = ["ALGOS", "export_model", "save_normalization", "train"]

#: the algorithms by name (one table:
#: :func:`radial_ibvs_agents.learned.files.model_files.algorithms`)
ALGOS: dict[str, Any] = algorithms()


class _SaveBestFiles(BaseCallback):
    """With ``EvalCallback``'s ``callback_on_new_best``: the best model's files, no pickles.

    Writes ``policy.safetensors`` and ``policy.json`` (and the observation statistics of that
    moment) into ``directory``, beside the ``best_model.zip`` that ``EvalCallback`` saves.
    """

    def __init__(self, venv: VecNormalize | None, directory: Path, algo: str) -> None:
        super().__init__()
        self.venv, self.directory, self.algo = venv, directory, algo

    def _on_step(self) -> bool:
        with replace_model_files(self.directory, BEST_FILES) as staging:
            save_policy(self.model, staging, self.algo)
            if self.venv is not None:
                save_normalization(self.venv, staging / "normalization.npz")
        return True


class _Checkpoints(CheckpointCallback):
    """SB3's periodic checkpoints, each with its observation statistics as plain arrays.

    ``checkpoints/rl_model_N_steps.zip`` gets ``rl_model_normalization_N_steps.npz`` beside
    it (no pickled ``VecNormalize``): what :func:`train` needs to resume from it.
    """

    def _on_step(self) -> bool:
        result = super()._on_step()
        venv = self.model.get_vec_normalize_env()
        if venv is not None and self.n_calls % self.save_freq == 0:
            save_normalization(venv, self._checkpoint_path("normalization_", extension="npz"))
        return result


_CHECKPOINT = re.compile(r"^(?P<prefix>.+)_(?P<steps>\d+)_steps\.zip$")


def _resume(model: Any, venv: Any, path: Path) -> None:
    """Continue ``model`` from a model directory or a checkpoint ``.zip``; no pickle is read.

    The weights and the optimizer's state come from the zip's ``policy.pth`` and
    ``policy.optimizer.pth`` (tensors, read by ``torch.load(weights_only=True)``); its pickled
    ``data`` entry is never deserialised: the step count is read from it as plain JSON. The
    observation statistics come from ``normalization.npz`` (or, beside a checkpoint,
    ``rl_model_normalization_N_steps.npz``), never from a pickled ``VecNormalize``.

    Raises
    ------
    ValueError
        If a file is missing, corrupt, or does not fit the config's model.
    """
    import pickle

    zipped = path.suffix == ".zip"
    zip_path = path if zipped else path / "model.zip"
    if not zip_path.is_file():
        raise ValueError(f"cannot resume: {zip_path} not found")
    try:
        check_archive(zip_path, zip_path.parent)  # no member inflates beyond the limits
        with zipfile.ZipFile(zip_path) as archive:
            data = json.loads(archive.read("data"))  # plain JSON: ":serialized:" stays text
        steps = data["num_timesteps"]
        if isinstance(steps, bool) or not isinstance(steps, int) or steps < 0:
            raise ValueError(f"num_timesteps is {str(steps)[:40]}")
        model.set_parameters(str(zip_path), exact_match=True, device="cpu")
    except (
        zipfile.BadZipFile,
        ValueError,
        KeyError,
        TypeError,
        RuntimeError,
        EOFError,
        pickle.UnpicklingError,
        RecursionError,
    ) as error:
        raise ValueError(f"cannot resume from {zip_path}: {str(error)[:300]}") from None
    model.num_timesteps = steps
    if not isinstance(venv, VecNormalize):
        return
    match = _CHECKPOINT.match(zip_path.name) if zipped else None
    stats = (
        zip_path.with_name(f"{match['prefix']}_normalization_{match['steps']}_steps.npz")
        if match
        else zip_path.parent / "normalization.npz"
    )
    if not stats.is_file():
        raise ValueError(f"cannot resume: the observation statistics {stats} are missing")
    _restore_normalization(venv, stats, default_count=max(steps, 1))


@dataclass
class _FineTune:
    """What fine-tuning takes from a model directory (``train(..., init_from=DIR)``)."""

    directory: Path
    policy: Any
    policy_kwargs: dict[str, Any]
    history: HistoryConfig | None
    normalised_keys: list[str]

    @classmethod
    def read(cls, directory: Path, algo: str) -> _FineTune:
        """Read the policy, its history and its statistics (no pickle); errors name the file."""
        if algo != "ppo":
            raise ValueError(f"init_from fine-tunes a PPO policy; got algo {algo!r}")
        policy, description = load_policy(directory)
        if description["algo"] != "ppo":
            raise ValueError(f"init_from: {directory} holds a {description['algo']} policy")
        meta = read_json(directory / "metadata.json", directory)
        if not isinstance(meta, dict):
            raise ValueError(f"init_from: {directory}/metadata.json is not a JSON object")
        history = (
            HistoryConfig.from_mapping(meta["history"], f"{directory}/metadata.json: history")
            if meta.get("history")
            else None
        )
        kwargs = _policy_kwargs(policy)
        stats = directory / "normalization.npz"
        keys = sorted(read_normalization(stats)["stats"]) if stats.is_file() else []
        return cls(directory, policy, kwargs, history, keys)

    def apply(self, model: Any, venv: Any) -> None:
        """Load the weights into ``model`` and the statistics into ``venv``."""
        try:
            model.policy.load_state_dict(self.policy.state_dict())
        except RuntimeError as error:
            raise ValueError(f"init_from: {self.directory}: {str(error)[:300]}") from None
        stats = self.directory / "normalization.npz"
        if isinstance(venv, VecNormalize) and stats.is_file():
            _restore_normalization(venv, stats, default_count=1e6)


def _policy_kwargs(policy: Any) -> dict[str, Any]:
    """Return the keyword arguments that rebuild ``policy`` (its spaces and schedule aside)."""
    params = policy._get_constructor_parameters()
    skip = ("observation_space", "action_space", "lr_schedule", "use_sde")
    return {k: v for k, v in params.items() if k not in skip}


def _restore_normalization(venv: VecNormalize, path: Path, default_count: float) -> None:
    """Set a ``VecNormalize``'s statistics from :func:`save_normalization`'s ``.npz``."""
    try:
        saved = read_normalization(path)
    except ValueError as error:
        raise ValueError(f"cannot resume: {error}") from None
    rms = venv.obs_rms
    for key, stats in rms.items() if isinstance(rms, dict) else [("obs", rms)]:
        if key not in saved["stats"]:
            raise ValueError(f"cannot resume: {path} has no statistics for {key!r}")
        mean, var = saved["stats"][key]
        if mean.shape != stats.mean.shape or var.shape != stats.var.shape:
            raise ValueError(
                f"cannot resume: {path}: {key}: shape {mean.shape}, the env's is {stats.mean.shape}"
            )
        stats.mean, stats.var = mean.astype(np.float64), var.astype(np.float64)
        stats.count = saved["counts"].get(key, default_count)
    if venv.norm_reward and saved["ret"] is not None:
        mean, var, count = saved["ret"]
        venv.ret_rms.mean, venv.ret_rms.var = mean.astype(np.float64), var.astype(np.float64)
        venv.ret_rms.count = count


def _with_extractor(config: TrainConfig, space: Any) -> tuple[dict[str, Any], list[str] | None]:
    """Return the policy's keyword arguments and the keys to normalise (``None``: all).

    With ``config.extractor`` (a student's extractor by name), the policy gets that class with
    the student's settings (the error keys as direction and log-size, the image error), and the
    keys the extractor reads raw are left out of ``VecNormalize``, as the student's are.
    """
    if config.extractor is None:
        return dict(config.policy_kwargs), None
    from radial_ibvs_agents.learned.networks import extractors

    if config.extractor == "goal_pose":  # every key read raw
        extractor = {"features_extractor_class": extractors.GoalPoseExtractor}
        return {**config.policy_kwargs, **extractor}, []
    landmark_set = config.extractor in ("landmark_set", "landmark_pose")
    error_keys = tuple(k for k in extractors.ERROR_KEYS if k in space.spaces)
    raw = extractors.raw_keys(error_keys, True, landmark_set)
    missing = sorted(set(raw) - set(space.spaces))
    if missing:
        where = config.source.get("file", "the config")
        raise ValueError(
            f"{where}: extractor {config.extractor!r} needs the observation keys {missing} "
            "(env_kwargs obs_mode: features, goal_depths: true)"
        )
    kwargs = {
        **config.policy_kwargs,
        "features_extractor_class": getattr(extractors, TRAIN_EXTRACTORS[config.extractor]),
        "features_extractor_kwargs": {"error_keys": list(error_keys), "point_error": True},
    }
    normalised = [
        k for k in space.spaces if k not in raw and extractors.error_key_of(k, error_keys) is None
    ]
    return kwargs, normalised


#: the algorithm's arguments that train() sets itself (a config may not)
_SET_BY_TRAIN = ("policy", "env", "seed", "policy_kwargs", "device", "verbose", "_init_setup_model")


def _check_algo_kwargs(config: TrainConfig, algo: str) -> None:
    """Refuse a config keyword the algorithm does not take, or one ``train`` sets itself.

    Raises
    ------
    ValueError
        Naming the config file, the key and the keywords the algorithm takes.
    """
    import inspect

    accepted = set(inspect.signature(ALGOS[algo].__init__).parameters) - {"self", "kwargs"}
    where = config.source.get("file", "the config")
    for key in config.algo_kwargs:
        if key in _SET_BY_TRAIN:
            what = "--seed" if key == "seed" else "train itself"
            raise ValueError(f"{where}: {key!r} is set by {what}, not by the config")
        if key not in accepted:
            valid = sorted(accepted - set(_SET_BY_TRAIN))
            raise ValueError(
                f"{where}: {algo} takes no keyword {key!r}{did_you_mean(key, valid)}; "
                f"valid: {valid}"
            )


def _make_venv(env_id: str, n_envs: int, seed: int, env_kwargs: dict[str, Any]) -> Any:
    """Make the native batched ``VecEnv`` where the id has one, else SB3's ``DummyVecEnv``."""
    from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env
    from radial_ibvs_gym.registration import VECTOR_ENTRY_POINTS

    native = env_id in VECTOR_ENTRY_POINTS and env_kwargs.get("measurement") != "detected"
    if native:
        return make_vec_env(env_id, n_envs, seed=seed, **env_kwargs)
    return sb3_make_vec_env(env_id, n_envs=n_envs, seed=seed, env_kwargs=env_kwargs)


def train(
    config: TrainConfig,
    out_dir: Path | str,
    *,
    algo: str = "ppo",
    seed: int = 0,
    total_timesteps: int | None = None,
    resume: Path | str | None = None,
    progress: bool = True,
    command: str | None = None,
    torch_threads: int = 1,
    init_from: Path | str | None = None,
) -> Path:
    """Train a model and write its directory.

    Parameters
    ----------
    config
        The validated configuration
        (:func:`radial_ibvs_agents.learned.training.zoo_config.load_train_config`).
    out_dir
        Output directory (created).
    algo
        ``"ppo"`` (or ``"sac"``, for a ``Box`` action space as here).
    seed
        Seed of the training envs and the algorithm.
    total_timesteps
        Overrides the config's ``n_timesteps``. SB3 collects whole rollouts, so a run takes at
        least ``n_envs * n_steps`` steps (4,096 with the shipped configs) however small this is.
    resume
        A model directory (or ``model.zip``) to continue from; its normalisation statistics
        are restored too.
    progress
        Show a progress bar.
    command
        The command line, for the metadata (default: ``sys.argv``).
    init_from
        A model directory to fine-tune (e.g. a DAgger student, ``radial-ibvs distill``): its
        policy's architecture and weights, its observation history and its normalisation
        statistics (only the keys it normalised) replace the config's; ``algo`` must be PPO.
    torch_threads
        Threads for torch. One is fastest for these small networks: the envs dominate, and
        more threads than free cores make torch's busy-waiting threads slow everything down
        (measured: 300 instead of 1,600 steps/s with two trainings on two cores).

    Returns
    -------
    pathlib.Path
        The model directory.
    """
    if algo not in ALGOS:
        raise ValueError(f"unknown algo {algo!r}; valid: {sorted(ALGOS)}")
    steps = config.n_timesteps if total_timesteps is None else int(total_timesteps)
    if steps <= 0:
        raise ValueError(f"total_timesteps must be positive, got {steps!r}")
    _check_algo_kwargs(config, algo)  # before anything is built or written
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    import torch

    torch.set_num_threads(torch_threads)
    venv, eval_env = (
        _make_venv(config.env_id, n, s, config.env_kwargs)
        for n, s in ((config.n_envs, seed), (1, config.eval_seed))
    )
    if config.residual is not None:
        venv, eval_env = (ResidualVecEnv(v, config.residual) for v in (venv, eval_env))
    if config.fine_tune is not None and init_from is None:
        raise ValueError(
            f"{config.source.get('file', 'the config')}: fine_tune starts from a student; "
            "give init_from (--init-from DIR)"
        )
    init = _FineTune.read(Path(init_from), algo) if init_from is not None else None
    if init is not None and init.history is not None:
        venv, eval_env = (history_vec_env(v, init.history) for v in (venv, eval_env))
    policy_kwargs, normalised = _with_extractor(config, venv.observation_space)
    if config.normalize is not None:
        keys: dict[str, Any] = {} if normalised is None else {"norm_obs_keys": normalised}
        if init is not None:
            keys = {"norm_obs_keys": init.normalised_keys}
        venv = VecNormalize(venv, **config.normalize, **keys)
        eval_env = VecNormalize(eval_env, training=False, norm_reward=False, **keys)
    model = ALGOS[algo](
        config.policy,
        venv,
        seed=seed,
        policy_kwargs=policy_kwargs if init is None else init.policy_kwargs,
        device="cpu",
        verbose=0,
        **config.algo_kwargs,
    )
    if init is not None:
        init.apply(model, venv)
        if config.fine_tune is not None:
            config.fine_tune.apply(model.policy)
    if resume is not None:
        _resume(model, venv, Path(resume))
    formats = ["csv"] + (["tensorboard"] if importlib.util.find_spec("tensorboard") else [])
    model.set_logger(configure(str(out / "logs"), formats))
    best_dir = out / "best"
    evaluation = ToleranceEvalCallback(
        eval_env,
        n_eval_episodes=config.eval_episodes,
        eval_freq=max(config.eval_freq // config.n_envs, 1),
        best_model_save_path=str(best_dir),
        log_path=str(out / "eval"),
        deterministic=True,
        verbose=0,
        callback_on_new_best=_SaveBestFiles(
            venv if isinstance(venv, VecNormalize) else None, best_dir, algo
        ),
    )
    checkpoints = _Checkpoints(
        save_freq=max(10 * config.eval_freq // config.n_envs, 1),
        save_path=str(out / "checkpoints"),
    )
    callbacks: list[BaseCallback] = [evaluation, checkpoints]
    if init is not None and config.fine_tune is not None and config.fine_tune.critic_warmup:
        callbacks.append(CriticWarmup(config.fine_tune.critic_warmup))
    if config.curriculum is not None:
        total = steps + (model.num_timesteps if resume is not None else 0)
        callbacks.append(StartReachCurriculum(config.curriculum, total))
    origin = provenance(command, config.source)  # at the start: the code that trains
    start = time.perf_counter()
    model.learn(
        steps,
        callback=callbacks,
        progress_bar=progress,
        reset_num_timesteps=resume is None,
    )
    if not evaluation.evaluations_timesteps:  # shorter than eval_freq: evaluate once, at the end
        evaluation.eval_freq = 1
        evaluation.on_step()  # writes eval/evaluations.npz, best/ and best_model.zip
    wall = time.perf_counter() - start
    model.logger.close()  # flush and close logs/progress.csv
    curve = _learning_curve(out / "eval" / "evaluations.npz")
    metadata = {
        "algo": algo,
        "env_id": config.env_id,
        "env_kwargs": jsonable(config.env_kwargs),
        "seed": seed,
        **({"residual": config.residual.as_dict()} if config.residual else {}),
        **({"curriculum": config.curriculum.as_dict()} if config.curriculum else {}),
        **({"history": init.history.as_dict()} if init and init.history else {}),
        **({"init_from": str(init_from)} if init_from is not None else {}),
        **({"fine_tune": config.fine_tune.as_dict()} if init and config.fine_tune else {}),
        **({"extractor": config.extractor} if config.extractor and init is None else {}),
        "total_timesteps": int(model.num_timesteps),
        **origin,
        "versions": versions(),
        "wall_clock_s": round(wall, 1),
        "env_steps_per_s": round(steps / wall, 1),
        "learning_curve": curve,
    }
    with replace_model_files(out) as staging:  # the model's files, all at once
        save_policy(model, staging, algo)  # what radial_ibvs_agents.load reads: no pickles
        model.save(staging / "model.zip")  # for SB3 users and --resume (read without pickles)
        if isinstance(venv, VecNormalize):
            save_normalization(venv, staging / "normalization.npz")
        write_json(staging / "metadata.json", metadata)
        if (best_dir / "best_model.zip").is_file():
            shutil.copy(best_dir / "best_model.zip", staging / "best_model.zip")
        if curve:
            title = f"{algo} on {config.env_id}"
            _plot_learning_curve(curve, staging / "learning_curve.png", title)
    return out


def _write_sb3_zip(folder: Path, path: Path) -> None:
    """Write a stable-baselines3 PPO ``model.zip`` holding the policy of ``folder``."""
    from radial_ibvs_agents.learned.training.sb3_vec_env import spaces_env

    policy, _ = load_policy(folder)
    env = spaces_env(policy.observation_space, policy.action_space)
    model = ALGOS["ppo"](
        type(policy), env, policy_kwargs=_policy_kwargs(policy), device="cpu", verbose=0
    )
    model.policy.load_state_dict(policy.state_dict())
    model.save(path)


def _learning_curve(path: Path) -> list[dict[str, float]]:
    """Read the evaluations over training: timesteps, mean return, success rate.

    With ``tolerances.npz`` beside ``path`` (:class:`ToleranceEvalCallback`), each row also
    has ``success_10cm/5deg`` and ``success_30cm/15deg``.
    """
    if not path.is_file():
        return []
    with np.load(path, allow_pickle=False) as data:
        steps, results = data["timesteps"], data["results"]
        successes = data["successes"] if "successes" in data.files else None
    looser = read_tolerance_curve(path.parent / "tolerances.npz")
    curve = []
    for k, t in enumerate(steps):
        row = {"timesteps": int(t), "mean_return": float(np.mean(results[k]))}
        if successes is not None and len(successes[k]):
            row["success_rate"] = float(np.mean(successes[k]))
        for name, rate in looser.get(int(t), {}).items():
            if name != "2cm/2deg":  # the env's own: success_rate
                row[f"success_{name}"] = rate
        curve.append(row)
    return curve


def _plot_learning_curve(curve: list[dict[str, float]], path: Path, title: str) -> None:
    import matplotlib.pyplot as plt  # no backend forced: Agg when headless, inline in Jupyter

    fig, ax = plt.subplots(figsize=(6, 3.5))
    t = [row["timesteps"] for row in curve]
    ax.plot(t, [row["mean_return"] for row in curve], "o-", color="C0", label="mean return")
    ax.set_xlabel("env steps")
    ax.set_ylabel("mean return (held-out seeds)")
    if "success_rate" in curve[0]:
        twin = ax.twinx()
        keys = [("success_rate", "2 cm / 2 deg", "s-")] + [
            (f"success_{name}", name.replace("cm/", " cm / ").replace("deg", " deg"), style)
            for name, style in (("10cm/5deg", "^--"), ("30cm/15deg", "v:"))
            if f"success_{name}" in curve[0]
        ]
        for (key, label, style), color in zip(keys, ("C3", "C1", "C2"), strict=False):
            twin.plot(t, [row.get(key, np.nan) for row in curve], style, color=color, label=label)
        twin.set_ylabel("success rate (held-out seeds)")
        twin.set_ylim(-0.05, 1.05)
        twin.legend(loc="lower right", fontsize=8, title="success within", title_fontsize=8)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)


def export_model(
    train_dir: Path | str,
    dest: Path | str,
    *,
    best: bool = True,
    residual_gate: float | None = None,
    note: str | None = None,
) -> Path:
    """Copy what a user needs from a training directory into a small model directory.

    Parameters
    ----------
    train_dir
        What :func:`train` wrote.
    dest
        The model directory to write (e.g.
        ``agents/radial_ibvs_agents/learned/models/dagger-student``).
    best
        Ship the best model of the validation evaluations (with its normalisation statistics)
        rather than the last one.
    residual_gate
        For a residual model: the ``gate`` to deploy it with
        (:class:`radial_ibvs_agents.learned.networks.residual.ResidualConfig`), when it differs from
        training's; the
        metadata keeps the training value as ``residual_trained``.
    note
        A line for the metadata (``export_note``): how the export was chosen.

    Returns
    -------
    pathlib.Path
        ``dest``, holding ``policy.safetensors``, ``policy.json``, ``normalization.npz``,
        ``metadata.json`` (noting which model it is), ``progress.csv``, ``learning_curve.png`` and
        the stable-baselines3 ``model.zip`` (for SB3 users: :func:`radial_ibvs_agents.load` never
        reads it).
    """
    src, out = Path(train_dir), Path(dest)
    use_best = best and has_policy_files(src / "best")
    folder = src / "best" if use_best else src
    if not has_policy_files(folder):
        raise ValueError(f"{folder} has no policy.safetensors and policy.json to export")
    zip_path = src / "best" / "best_model.zip" if use_best else src / "model.zip"
    metadata = json.loads((src / "metadata.json").read_text())
    metadata["shipped"] = "best model of the validation evaluations" if use_best else "last model"
    if metadata.get("trained_by") == "dagger":
        metadata["shipped"] = (
            f"round {metadata['best_round']}: the best of the per-round evaluations"
        )
    if use_best and metadata.get("learning_curve"):
        top = max(metadata["learning_curve"], key=lambda r: r["mean_return"])
        metadata["shipped_at_timesteps"] = top["timesteps"]
    if residual_gate is not None:
        from radial_ibvs_agents.learned.networks.residual import ResidualConfig

        if not metadata.get("residual"):
            raise ValueError(f"{src} is not a residual model: residual_gate does not apply")
        trained = ResidualConfig.from_mapping(metadata["residual"], f"{src}: residual")
        deployed = {**trained.as_dict(), "gate": residual_gate}
        ResidualConfig.from_mapping(deployed, "residual_gate")  # validate
        metadata["residual_trained"], metadata["residual"] = trained.as_dict(), deployed
    if note:
        metadata["export_note"] = note
    with replace_model_files(out) as staging:  # all at once: no stale file of an older export
        for name in (WEIGHTS, DESCRIPTION, "normalization.npz"):
            if (folder / name).is_file():
                shutil.copy(folder / name, staging / name)
        if zip_path.is_file():  # for SB3 users; radial_ibvs_agents.load never reads it
            shutil.copy(zip_path, staging / "model.zip")
        elif metadata.get("algo") == "ppo":  # e.g. a DAgger student: built from its weights
            _write_sb3_zip(folder, staging / "model.zip")
        write_json(staging / "metadata.json", metadata)
        for name in ("logs/progress.csv", "learning_curve.png"):
            if (src / name).is_file():
                shutil.copy(src / name, staging / Path(name).name)
    return out
