"""Reports from benchmark rows: DAgger curves, and generated blocks of Markdown pages.

``radial-ibvs report`` (:mod:`radial_ibvs_agents.cli.report`) reads rows
(:func:`radial_ibvs_agents.rows.load_rows`), lays them out as tables
(:mod:`radial_ibvs_agents.experiments.tables`) and, with ``--out``, writes them into a folder
(``report.md`` and the figures), ready to paste into a paper or a pull request; with ``--into``, it
regenerates a page's results block (:func:`replace_block`). This module holds what only reports
draw: the DAgger students' curves (:func:`dagger_curves`).
"""

from __future__ import annotations

import csv
import json
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from radial_ibvs_agents.untrusted import read_bytes

__all__ = ["MAX_PAGE_BYTES", "dagger_curves", "read_rounds", "replace_block"]

#: the largest page ``report --into`` regenerates a block of
MAX_PAGE_BYTES = 16 << 20


def read_rounds(directory: Path | str) -> tuple[np.ndarray, np.ndarray, int | None]:
    """Return ``(env_steps, success_rate, kept round)`` of one DAgger run's directory.

    Raises
    ------
    ValueError
        For a directory without a ``progress.csv`` of rounds.
    """
    directory = Path(directory)
    progress = directory / "progress.csv"
    if not progress.is_file():
        raise ValueError(f"{progress}: no such file (a radial-ibvs distill run's directory?)")
    with progress.open() as file:
        rows = list(csv.DictReader(file))
    if not rows or not {"env_steps", "success_rate"} <= set(rows[0]):
        raise ValueError(f"{progress} has no rounds (env_steps, success_rate)")
    steps = np.array([float(r["env_steps"]) for r in rows])
    success = np.array([float(r["success_rate"]) for r in rows])
    meta = directory / "metadata.json"
    kept = json.loads(meta.read_text()).get("best_round") if meta.is_file() else None
    return steps, success, kept if isinstance(kept, int) else None


def dagger_curves(groups: Mapping[str, Sequence[Path | str]], out: Path | str) -> str:
    """Plot the per-round success of DAgger students, one curve per group, seeds as a band.

    A group of one seed is drawn as its line; a group of several as the mean across seeds with
    the band from the lowest to the highest seed, each seed's kept round starred.

    Parameters
    ----------
    groups
        ``{label: [run directory, ...]}``: what ``radial-ibvs distill`` writes.
    out
        The figure (``.png``).

    Returns
    -------
    str
        Each group's per-round rates, one line per group.
    """
    from radial_ibvs_agents.plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    lines = []
    for k, (label, members) in enumerate(groups.items()):
        runs = [read_rounds(d) for d in members]
        n = min(len(r[1]) for r in runs)
        steps = runs[0][0][:n] / 1e6
        table = np.stack([r[1][:n] for r in runs])
        color = f"C{k}"
        name = f"{label} ({len(runs)} seed{'s' if len(runs) > 1 else ''})"
        ax.plot(steps, table.mean(axis=0), "o-", color=color, label=name)
        if len(runs) > 1:
            ax.fill_between(steps, table.min(axis=0), table.max(axis=0), color=color, alpha=0.2)
        for _, success, kept in runs:
            if kept is not None and kept < n:
                ax.plot(steps[kept], success[kept], "*", color=color, ms=12, mec="k", mew=0.5)
        cells = "; ".join(" ".join(f"{v:.0%}" for v in row) for row in table)
        lines.append(f"{label}: {cells}")
    ax.set_xlabel("env steps (millions): one point per DAgger round")
    ax.set_ylabel("success, validation rooms")
    ax.set_ylim(0.0, 1.0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("DAgger students: success after each round (band: lowest to highest seed)")
    fig.tight_layout()
    save_figure(fig, out)
    return "\n".join(lines) + "\n"


def replace_block(path: Path | str, name: str, text: str) -> str:
    """Return the file's text with the block between its ``name`` markers replaced by ``text``.

    The markers are ``<!-- name:start -->`` and ``<!-- name:end -->`` (HTML comments, invisible
    in Markdown); what lies between them is generated, the rest of the file is kept.

    The file is read as data: a regular file (a FIFO or a device is refused, never opened), of
    at most ``MAX_PAGE_BYTES``.

    Raises
    ------
    ValueError
        If the file lacks the markers (naming it and them), is not a regular file, or is too
        large.
    """
    start, end = f"<!-- {name}:start -->", f"<!-- {name}:end -->"
    try:
        content = read_bytes(path, None, MAX_PAGE_BYTES, "MAX_PAGE_BYTES").decode()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not UTF-8 text") from None
    if (
        content.count(start) != 1
        or content.count(end) != 1
        or content.index(start) > content.index(end)
    ):
        raise ValueError(f"{path}: needs one {start} line and, after it, one {end} line")
    before, rest = content.split(start)
    _, after = rest.split(end)
    return f"{before}{start}\n{text.strip()}\n{end}{after}"
