"""``radial-ibvs sweep``: one training run per seed, locally or on Ray, and a summary across seeds.

Each seed trains as ``radial-ibvs train`` does (as ``radial-ibvs distill`` does for a DAgger
config, one with a ``dagger:`` section), into ``<out>/seed-<s>/`` (the same model directory and
metadata). A seed whose directory holds ``metadata.json`` is done: a rerun
with the same ``--out`` skips it and says so; a seed stopped half-way is trained again (a
stop loses at most the seeds in flight). The runs happen in a scratch directory and come back
as one archive, so Ray workers on other machines need no shared file system.

The summary (``summary.json``, ``summary.md``, ``learning_curves.png``) gives the final success rate
of every seed in the evaluations during training (seeds from the config's ``eval_seed``, which
training does not draw), their IQM with a 95 % stratified-bootstrap interval
(:mod:`radial_ibvs_agents.stats`), and the learning curves: the IQM across seeds at each evaluation
with its bootstrap band, and each seed's own curve.
"""

from __future__ import annotations

import io
import json
import math
import os
import shutil
import tempfile
import zipfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.experiments.backends import make_backend
from radial_ibvs_agents.io import write_atomic, write_json
from radial_ibvs_agents.stats import iqm_interval

__all__ = ["SeedRun", "run_sweep", "summarise_sweep"]


@dataclass(frozen=True)
class SeedRun:
    """One training seed: what a worker needs (the config travels as text)."""

    config_text: str
    config_file: str  # the config's path as given: what the model's metadata names
    env_id: str | None
    algo: str
    seed: int
    total_timesteps: int | None
    command: str
    progress: bool = False


def is_dagger_config(path: Path) -> bool:
    """Whether the YAML file at ``path`` is a DAgger config (it has a ``dagger:`` section)."""
    from radial_ibvs_gym.config import read_yaml_with_base

    data = read_yaml_with_base(path)
    return isinstance(data, dict) and "dagger" in data


def _config_text(path: Path) -> str:
    """Return the config's text for a worker: a ``base:`` overlay resolved into one file."""
    import yaml

    from radial_ibvs_gym.config import read_yaml, read_yaml_with_base

    data = read_yaml(path)
    if isinstance(data, dict) and "base" in data:
        return str(yaml.safe_dump(read_yaml_with_base(path), sort_keys=False))
    return path.read_text()


#: the name of a worker's scratch folder in the temporary directory: prefix, worker pid, random
SCRATCH_PREFIX = "radial-ibvs-sweep-"


def remove_stale_scratch() -> list[Path]:
    """Remove the scratch folders of sweep workers that are gone (killed before cleaning up).

    A worker killed with its sweep (SIGKILL runs no clean-up) leaves its scratch training
    folder in the temporary directory; the next seed trained on this machine removes it.

    Returns
    -------
    list of pathlib.Path
        The folders removed.
    """
    removed = []
    for folder in Path(tempfile.gettempdir()).glob(f"{SCRATCH_PREFIX}*-*"):
        pid = folder.name[len(SCRATCH_PREFIX) :].split("-", 1)[0]
        if not pid.isdigit() or _running(int(pid)):
            continue
        shutil.rmtree(folder, ignore_errors=True)
        removed.append(folder)
    return removed


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def _train_seed(run: SeedRun) -> bytes:
    """Train one seed in a scratch directory; return the model directory as a zip archive."""
    import torch

    from radial_ibvs_agents.learned.dagger.distill import dagger
    from radial_ibvs_agents.learned.dagger.distill_config import load_dagger_config
    from radial_ibvs_agents.learned.training.train import train
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    torch.set_num_threads(1)
    remove_stale_scratch()
    with tempfile.TemporaryDirectory(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-") as scratch:
        config_path = Path(scratch) / Path(run.config_file).name
        config_path.write_text(run.config_text)
        model_dir = Path(scratch) / "model"
        source = {"file": run.config_file}  # not the scratch copy's path
        if is_dagger_config(config_path):
            config = load_dagger_config(config_path)
            config = replace(config, source={**config.source, **source})
            dagger(config, model_dir, seed=run.seed, progress=run.progress, command=run.command)
        else:
            train_config = load_train_config(config_path, run.env_id)
            train(
                replace(train_config, source={**train_config.source, **source}),
                model_dir,
                algo=run.algo,
                seed=run.seed,
                total_timesteps=run.total_timesteps,
                progress=run.progress,
                command=run.command,
            )
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            for path in sorted(model_dir.rglob("*")):
                if path.is_file():
                    archive.write(path, path.relative_to(model_dir).as_posix())
        return buffer.getvalue()


def _unpack(archive: bytes, dest: Path) -> None:
    """Extract a seed's archive into ``dest`` (whole or not at all: via a sibling, renamed)."""
    partial = dest.with_name(dest.name + ".partial")
    shutil.rmtree(partial, ignore_errors=True)
    with zipfile.ZipFile(io.BytesIO(archive)) as zf:
        zf.extractall(partial)
    shutil.rmtree(dest, ignore_errors=True)
    partial.rename(dest)


def run_sweep(
    config: Path | str,
    seeds: Sequence[int],
    out: Path | str,
    *,
    algo: str = "ppo",
    env_id: str | None = None,
    total_timesteps: int | None = None,
    backend: str = "local",
    address: str | None = None,
    workers: int = 1,
    command: str = "",
    progress: bool = True,
    notify: Callable[[str], None] = print,
) -> dict[str, Any]:
    """Train one model per seed, then write the summary across seeds.

    Parameters
    ----------
    config
        The training config
        (:func:`radial_ibvs_agents.learned.training.zoo_config.load_train_config`), or a DAgger
        config (:func:`radial_ibvs_agents.learned.dagger.distill_config.load_dagger_config`; its
        students train as ``radial-ibvs distill`` does, and ``algo``, ``env_id`` and
        ``total_timesteps`` must be left at their defaults); validated here first.
    seeds
        Training seeds (distinct).
    out
        Output folder: ``seed-<s>/`` per seed, and the summary.
    algo, env_id, total_timesteps
        As for ``radial-ibvs train``.
    backend, address
        ``"local"`` (``workers`` processes) or ``"ray"`` (one task of one CPU per seed).
    workers
        Seeds trained at once on the local backend (each uses about one core); the CPUs of a
        private Ray instance.
    command
        The command line, for each model's metadata.
    progress
        Show each seed's progress bar (when seeds train one at a time in this process).
    notify
        Called with a line of text about skipped seeds.

    Returns
    -------
    dict
        The summary (:func:`summarise_sweep`).

    Raises
    ------
    ValueError
        For a bad config, repeated seeds, an unknown backend or algo, or Ray missing.
    """
    from radial_ibvs_agents.learned.dagger.distill_config import load_dagger_config
    from radial_ibvs_agents.learned.training.train import ALGOS
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    config_path = Path(config)
    if not config_path.is_file():
        raise ValueError(f"config file {str(config_path)!r} not found")
    if is_dagger_config(config_path):
        load_dagger_config(config_path)  # fail early, naming the bad value
        given = {"algo": algo != "ppo", "env_id": env_id, "total_timesteps": total_timesteps}
        if any(v for v in given.values()):
            wrong = [k for k, v in given.items() if v]
            raise ValueError(f"{config_path.name} is a DAgger config: it takes no {wrong}")
    else:
        load_train_config(config_path, env_id)  # fail early, naming the bad value
    if algo not in ALGOS:
        raise ValueError(f"unknown algo {algo!r}; valid: {sorted(ALGOS)}")
    if not seeds:
        raise ValueError("give at least one seed")
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"repeated seeds in {list(seeds)}")
    out_dir = Path(out)
    out_dir.mkdir(parents=True, exist_ok=True)
    done = [s for s in seeds if (out_dir / f"seed-{s}" / "metadata.json").is_file()]
    if done:
        notify(f"seeds {done} already done in {out_dir}, skipping them")
    todo = [s for s in seeds if s not in done]
    here = backend == "local" and workers == 1  # one seed at a time, in this process
    runs = [
        SeedRun(_config_text(config_path), str(config_path), env_id, algo, s, total_timesteps,
                f"{command} (seed {s})".strip(), progress=here and progress)
        for s in todo
    ]  # fmt: skip
    if runs:
        notify(f"training seeds {todo} ({backend}, {workers} at a time)")
        runner = make_backend(backend, workers, address)
        try:
            for k, archive in runner.imap_unordered(_train_seed, runs):
                _unpack(archive, out_dir / f"seed-{runs[k].seed}")
                notify(f"seed {runs[k].seed} done")
        finally:
            runner.close()
    return summarise_sweep(out_dir, seeds)


def _final_success(metadata: dict[str, Any]) -> float:
    """Return the last evaluation's success (a DAgger student's: that of its kept round)."""
    curve = metadata.get("learning_curve") or []
    rates = [row["success_rate"] for row in curve if "success_rate" in row]
    kept = metadata.get("best_round")
    if isinstance(kept, int) and 0 <= kept < len(rates):
        return float(rates[kept])
    return float(rates[-1]) if rates else math.nan


def summarise_sweep(out: Path | str, seeds: Sequence[int] | None = None) -> dict[str, Any]:
    """Summarise the seeds' runs in ``out``: final success, IQM and interval, curves.

    Parameters
    ----------
    out
        A sweep's output folder.
    seeds
        The seeds to include (default: every ``seed-<s>`` folder with metadata).

    Returns
    -------
    dict
        ``seeds``, ``final_success`` (per seed, the last held-out evaluation; a DAgger
        student's: that of the round kept),
        ``success_iqm``, ``success_ci95`` (stratified bootstrap), ``mean_success``,
        ``total_timesteps``, ``wall_clock_s``; also written as ``summary.json`` and
        ``summary.md``, with ``learning_curves.png``.
    """
    out_dir = Path(out)
    if seeds is None:
        seeds = sorted(
            int(p.name[len("seed-") :])
            for p in out_dir.glob("seed-*")
            if p.name[len("seed-") :].lstrip("-").isdigit() and (p / "metadata.json").is_file()
        )
    metas = {s: json.loads((out_dir / f"seed-{s}" / "metadata.json").read_text()) for s in seeds}
    final = {s: _final_success(m) for s, m in metas.items()}
    scores = np.array([v for v in final.values() if math.isfinite(v)])
    point, low, high = iqm_interval([scores]) if scores.size else (math.nan,) * 3
    summary: dict[str, Any] = {
        "seeds": list(seeds),
        "final_success": {str(s): v for s, v in final.items()},
        "success_iqm": point,
        "success_ci95": [low, high],
        "mean_success": float(scores.mean()) if scores.size else math.nan,
        "total_timesteps": {str(s): m.get("total_timesteps") for s, m in metas.items()},
        "wall_clock_s": {str(s): m.get("wall_clock_s") for s, m in metas.items()},
        "command": next((m.get("command") for m in metas.values()), None),
    }
    write_json(out_dir / "summary.json", summary)
    write_atomic(out_dir / "summary.md", _markdown(summary))
    curves = {s: m.get("learning_curve") or [] for s, m in metas.items()}
    if any(curves.values()):
        plot_seed_curves(curves, out_dir / "learning_curves.png")
    return summary


def _markdown(summary: dict[str, Any]) -> str:
    def pct(v: float) -> str:
        return "-" if not math.isfinite(v) else f"{v:.0%}"

    low, high = summary["success_ci95"]
    lines = [
        f"Success at the last evaluation during training (episodes on the config's eval_seed "
        f"and up, which training does not draw), {len(summary['seeds'])} seeds: IQM "
        f"{pct(summary['success_iqm'])} (95 % stratified-bootstrap CI {pct(low)}-{pct(high)}), "
        f"mean {pct(summary['mean_success'])}.",
        "",
        "| seed | final success | env steps | wall clock [min] |",
        "|---|---|---|---|",
    ]
    for s in summary["seeds"]:
        wall = summary["wall_clock_s"][str(s)]
        lines.append(
            f"| {s} | {pct(summary['final_success'][str(s)])} "
            f"| {summary['total_timesteps'][str(s)]:,} "
            f"| {'-' if wall is None else f'{wall / 60:.1f}'} |"
        )
    return "\n".join(lines) + "\n"


def plot_seed_curves(curves: dict[int, list[dict[str, float]]], path: Path) -> Path:
    """Plot the evaluation success over training: IQM across seeds with its band, and each seed.

    Parameters
    ----------
    curves
        Per seed, the ``learning_curve`` of its metadata (``timesteps``, ``success_rate``).
    path
        The PNG to write.
    """
    import matplotlib.pyplot as plt

    from radial_ibvs_agents.plotting import save_figure

    fig, ax = plt.subplots(figsize=(6.5, 3.8))
    for curve in curves.values():
        t = [r["timesteps"] for r in curve if "success_rate" in r]
        ax.plot(t, [r["success_rate"] for r in curve if "success_rate" in r],
                color="0.6", lw=0.8, alpha=0.7)  # fmt: skip
    steps = sorted({r["timesteps"] for c in curves.values() for r in c if "success_rate" in r})
    table = {s: {r["timesteps"]: r["success_rate"] for r in c if "success_rate" in r}
             for s, c in curves.items()}  # fmt: skip
    xs: list[float] = []
    mid: list[float] = []
    lo: list[float] = []
    hi: list[float] = []
    for step in steps:
        values = [table[s][step] for s in table if step in table[s]]
        if len(values) < len(curves):
            continue  # a point only some seeds reached
        point, low, high = iqm_interval([values])
        xs.append(step)
        mid.append(point)
        lo.append(low if math.isfinite(low) else point)
        hi.append(high if math.isfinite(high) else point)
    if xs:
        ax.plot(xs, mid, color="C3", lw=2, label=f"IQM over {len(curves)} seeds")
        ax.fill_between(xs, lo, hi, color="C3", alpha=0.2, label="95 % bootstrap CI")
    ax.plot([], [], color="0.6", lw=0.8, label="one seed")
    ax.set_xlabel("env steps")
    ax.set_ylabel("success rate (evaluation seeds)")
    ax.set_ylim(-0.03, 1.03)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)
