"""Reports from benchmark rows: the results table, success across training seeds, DAgger curves.

``radial-ibvs report`` (:mod:`agents.cli.report`) prints these as Markdown and, with ``--out``,
writes them into a folder (``report.md`` and the figures), ready to paste into a paper or a
pull request. The rows are what ``radial-ibvs benchmark`` writes (``episodes.json``): one object
per episode with at least ``policy``, ``suite``, ``variant``, ``success`` and ``end``, and
``success_by_tolerance`` for the tables across seeds.
"""

from __future__ import annotations

import csv
import json
from collections import Counter, defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from agents.experiments.evaluate import wilson_interval
from radial_ibvs_gym.envs.rules import SUCCESS_TOLERANCES

__all__ = [
    "TOLERANCES",
    "dagger_curves",
    "hold_steps",
    "load_rows",
    "read_rounds",
    "replace_block",
    "results_table",
    "seeds_table",
    "success_csv",
    "success_summaries",
]

#: the tolerances of ``success_by_tolerance`` (position / heading)
TOLERANCES = tuple(SUCCESS_TOLERANCES)

#: the fewest episodes for which a cell shows its 95 % interval
MIN_EPISODES_FOR_INTERVAL = 20


def load_rows(paths: Sequence[Path | str]) -> list[dict[str, Any]]:
    """Read and join the rows of several ``episodes.json`` files.

    Raises
    ------
    ValueError
        For a missing file, one that is not a JSON list of objects, a row without the keys a
        report needs (the message names the file), or rows judged differently (a
        ``success_hold_steps`` that differs: such rows are reported apart).
    """
    rows: list[dict[str, Any]] = []
    holds: dict[int, Path] = {}
    for path in map(Path, paths):
        if not path.is_file():
            raise ValueError(f"{path}: no such file (an episodes.json of radial-ibvs benchmark)")
        try:
            data = json.loads(path.read_text())
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
            raise ValueError(f"{path}: not a JSON file of benchmark rows: {error}") from None
        if not isinstance(data, list) or not all(isinstance(r, dict) for r in data):
            raise ValueError(f"{path}: expected a JSON list of episode objects")
        for k, row in enumerate(data):
            missing = [key for key in ("policy", "suite", "variant", "success") if key not in row]
            if missing:
                raise ValueError(f"{path}: row {k} has no {missing}")
            hold = row.get("success_hold_steps", 1)
            if hold not in holds:
                holds[hold] = path
            if len(holds) > 1:
                (a, first), (b, second) = list(holds.items())[:2]
                raise ValueError(
                    f"rows judged differently: success_hold_steps {a} in {first}, {b} in "
                    f"{second} (row {k}); report each judging on its own"
                )
        rows.extend(data)
    return rows


def hold_steps(rows: Sequence[Mapping[str, Any]]) -> int:
    """Return the rows' ``success_hold_steps`` (1 where rows predate the key)."""
    return max((int(r.get("success_hold_steps", 1)) for r in rows), default=1)


def _policies(rows: Sequence[Mapping[str, Any]], wanted: Sequence[str] | None) -> list[str]:
    """Return the policies to show: ``wanted`` (those with rows), else the two limits first."""
    present = list(dict.fromkeys(str(r["policy"]) for r in rows))
    if wanted:
        return [p for p in wanted if p in present]
    limits = ("planner", "planner-image-goal")
    first = [p for p in limits if p in present]
    return first + [p for p in present if p not in limits]


def results_table(
    rows: Sequence[Mapping[str, Any]],
    suites: Sequence[str] | None = None,
    policies: Sequence[str] | None = None,
    renames: Mapping[str, str] | None = None,
    variants: Sequence[str] | None = None,
    ends: bool = True,
) -> str:
    """Return the success table (Markdown): suite variants as rows, policies as columns.

    Each cell is the success rate (percent, at the benchmark's tolerance: 2 cm / 2 deg) with
    its 95 % Wilson interval where a cell has at least 20 episodes; a second table says how the
    episodes ended (collision / time-out / lost) per policy.

    Parameters
    ----------
    rows
        Benchmark rows (:func:`load_rows`).
    suites
        The suites to show, in this order (default: every suite, as met).
    policies
        The policies to show, in this order (default: every policy, the planner first).
    renames
        ``{old: new}``: show policy ``old`` as ``new`` (e.g. a model directory under the name
        it ships as).
    variants
        Only these rows, as ``"suite: variant"``, in this order (default: every variant of
        ``suites``).
    ends
        Add the second table (how the episodes ended).
    """
    renames = dict(renames or {})
    cells: dict[tuple[str, str], dict[str, list[Mapping[str, Any]]]] = defaultdict(
        lambda: defaultdict(list)
    )
    order: list[tuple[str, str]] = []
    kept = []
    for row in rows:
        if suites and row["suite"] not in suites:
            continue
        if variants and f"{row['suite']}: {row['variant']}" not in variants:
            continue
        row = {**row, "policy": renames.get(str(row["policy"]), str(row["policy"]))}
        kept.append(row)
        key = (str(row["suite"]), str(row["variant"]))
        if key not in cells:
            order.append(key)
        cells[key][row["policy"]].append(row)
    if variants:
        order.sort(key=lambda k: list(variants).index(f"{k[0]}: {k[1]}"))
    elif suites:
        order.sort(key=lambda k: list(suites).index(k[0]))
    shown = _policies(kept, policies)
    if not order or not shown:
        return "(no rows for these suites and policies)\n"
    lines = [
        "| suite: variant | episodes | " + " | ".join(f"`{p}`" for p in shown) + " |",
        "|---|---|" + "---|" * len(shown),
    ]
    for key in order:
        n = max(len(v) for v in cells[key].values())
        out = []
        for policy in shown:
            episodes = cells[key].get(policy, [])
            if not episodes:
                out.append("-")
                continue
            wins = sum(bool(r["success"]) for r in episodes)
            rate = f"{100 * wins / len(episodes):.0f}"
            if len(episodes) >= MIN_EPISODES_FOR_INTERVAL:
                lo, hi = wilson_interval(wins, len(episodes))
                rate += f" ({100 * lo:.0f}-{100 * hi:.0f})"
            out.append(rate)
        lines.append(f"| {key[0]}: {key[1]} | {n} | " + " | ".join(out) + " |")
    if not ends:
        return "\n".join(lines) + "\n"
    lines += [
        "",
        "| how episodes ended (collision / time-out / lost) | | " + " | ".join(shown) + " |",
        "|---|---|" + "---|" * len(shown),
    ]
    for key in order:
        out = []
        for policy in shown:
            counts = Counter(str(r.get("end")) for r in cells[key].get(policy, []))
            out.append(f"{counts['collision']} / {counts['time-out']} / {counts['lost']}")
        lines.append(f"| {key[0]}: {key[1]} | | " + " | ".join(out) + " |")
    return "\n".join(lines) + "\n"


def seeds_table(
    rows: Sequence[Mapping[str, Any]],
    groups: Mapping[str, Sequence[str]],
    tolerance: str = "2cm/2deg",
) -> str:
    """Return, per group of seeds, each seed's success and their IQM with a 95 % interval.

    A group is one config trained with several seeds (one policy name per seed). For every
    suite variant the table gives each seed's rate and their interquartile mean with a
    bootstrap interval; the last line, the IQM over all variants and seeds with a stratified
    bootstrap (seeds resampled within each variant), as rliable does (Agarwal et al., NeurIPS
    2021). A variant that not every seed ran is listed without an interval and left out of the
    last line.

    Parameters
    ----------
    rows
        Benchmark rows with ``success_by_tolerance``.
    groups
        ``{name: [policy of seed 0, policy of seed 1, ...]}``.
    tolerance
        One of :data:`TOLERANCES`.

    Raises
    ------
    ValueError
        For an unknown tolerance, or a group whose policies have no rows.
    """
    from agents.stats import iqm_interval

    if tolerance not in TOLERANCES:
        raise ValueError(f"unknown tolerance {tolerance!r}; valid: {list(TOLERANCES)}")
    out: list[str] = []
    for name, policies in groups.items():
        rates: dict[tuple[str, str], dict[str, float]] = defaultdict(dict)
        for policy in policies:
            by_variant: dict[tuple[str, str], list[bool]] = defaultdict(list)
            for row in rows:
                if row["policy"] == policy:
                    by_tolerance = row.get("success_by_tolerance") or {}
                    by_variant[row["suite"], row["variant"]].append(bool(by_tolerance[tolerance]))
            if not by_variant:
                raise ValueError(f"group {name!r}: no rows for policy {policy!r}")
            for key, outcomes in by_variant.items():
                rates[key][policy] = float(np.mean(outcomes))
        out += [
            f"{name}: {len(policies)} seeds, success at {tolerance}",
            "",
            "| suite | variant | per seed | IQM | 95 % CI |",
            "|---|---|---|---|---|",
        ]
        tasks = []
        for (suite, variant), per in rates.items():
            values = [per[p] for p in policies if p in per]
            cells = " ".join(f"{v:.0%}" for v in values)
            if len(values) < len(policies):
                out.append(f"| {suite} | {variant} | {cells} ({len(values)} seeds) | - | - |")
                continue
            tasks.append(values)
            point, low, high = iqm_interval([values])
            out.append(f"| {suite} | {variant} | {cells} | {point:.0%} | {low:.0%}-{high:.0%} |")
        if tasks:
            point, low, high = iqm_interval(tasks)
            out.append(
                f"| all | stratified over {len(tasks)} variants | | {point:.0%} | "
                f"{low:.0%}-{high:.0%} |"
            )
        out.append("")
    return "\n".join(out)


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
    from agents.plotting import pyplot, save_figure

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


def success_summaries(
    rows: Sequence[Mapping[str, Any]], policies: Sequence[str] | None = None
) -> list[dict[str, Any]]:
    """Per suite variant and policy: the success rate and its 95 % Wilson interval.

    Returns
    -------
    list of dict
        ``suite``, ``variant``, ``policy``, ``episodes``, ``success_rate``, ``success_ci95``,
        in the order met (what the benchmark's heat map draws).
    """
    groups: dict[tuple[str, str, str], list[bool]] = defaultdict(list)
    for row in rows:
        groups[(str(row["suite"]), str(row["variant"]), str(row["policy"]))].append(
            bool(row["success"])
        )
    shown = _policies(rows, policies)
    out = []
    for (suite, variant, policy), wins in groups.items():
        if policy not in shown:
            continue
        out.append(
            {
                "suite": suite,
                "variant": variant,
                "policy": policy,
                "episodes": len(wins),
                "success_rate": sum(wins) / len(wins),
                "success_ci95": wilson_interval(sum(wins), len(wins)),
            }
        )
    out.sort(key=lambda s: shown.index(str(s["policy"])))
    return out


def success_csv(summaries: Sequence[Mapping[str, Any]]) -> str:
    """Return :func:`success_summaries` as CSV: one row per suite variant and policy.

    Columns: ``suite``, ``variant``, ``policy``, ``episodes``, ``successes``,
    ``success_rate``, ``ci95_low``, ``ci95_high`` (what ``pandas.read_csv`` reads as is).
    """
    import io

    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(
        [
            "suite",
            "variant",
            "policy",
            "episodes",
            "successes",
            "success_rate",
            "ci95_low",
            "ci95_high",
        ]
    )
    for s in summaries:
        lo, hi = s["success_ci95"]
        wins = round(s["success_rate"] * s["episodes"])
        writer.writerow(
            [s["suite"], s["variant"], s["policy"], s["episodes"], wins, s["success_rate"], lo, hi]
        )
    return buffer.getvalue()


def replace_block(path: Path | str, name: str, text: str) -> str:
    """Return the file's text with the block between its ``name`` markers replaced by ``text``.

    The markers are ``<!-- name:start -->`` and ``<!-- name:end -->`` (HTML comments, invisible
    in Markdown); what lies between them is generated, the rest of the file is kept.

    Raises
    ------
    ValueError
        If the file lacks the markers (naming it and them).
    """
    start, end = f"<!-- {name}:start -->", f"<!-- {name}:end -->"
    content = Path(path).read_text()
    if (
        content.count(start) != 1
        or content.count(end) != 1
        or content.index(start) > content.index(end)
    ):
        raise ValueError(f"{path}: needs one {start} line and, after it, one {end} line")
    before, rest = content.split(start)
    _, after = rest.split(end)
    return f"{before}{start}\n{text.strip()}\n{end}{after}"
