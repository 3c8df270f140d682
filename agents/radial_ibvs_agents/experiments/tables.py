"""Tables of rows and summaries: Markdown for pages and reports, the terminal's, and CSV.

The rows and their summaries come from :mod:`radial_ibvs_agents.rows`; this module only lays them
out:

- :func:`markdown_table` and :func:`rich_table`: the benchmark's summary per policy and
  variant (``summary.md``, and the terminal);
- :func:`results_table`: suite variants as rows, policies as columns (the README's headline,
  the results pages, ``radial-ibvs report``);
- :func:`seeds_table`: success across training seeds (IQM, stratified bootstrap);
- :func:`timings_table`: where a benchmark's worker-seconds went;
- :func:`success_csv` and :func:`write_rows_csv`: CSV that ``pandas.read_csv`` reads as is.
"""

from __future__ import annotations

import csv
import html
import io
import math
import re
from collections import Counter, defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.io import write_csv
from radial_ibvs_agents.rows import (
    CSV_COLUMNS,
    TOLERANCES,
    csv_row,
    ordered_policies,
    wilson_interval,
)

__all__ = [
    "markdown_table",
    "results_table",
    "rich_table",
    "seeds_table",
    "success_csv",
    "timings_table",
    "write_rows_csv",
]


#: the fewest episodes for which a cell shows its 95 % interval
MIN_EPISODES_FOR_INTERVAL = 20

#: names written as they are (in a code span, for policies); any other is escaped
_PLAIN = re.compile(r"[\w .,:;/()+=%*#~'\"@\[\]-]*")
#: a CSV cell that a spreadsheet would read as a formula starts with one of these
_FORMULA = ("=", "+", "-", "@", "\t", "\r")


def md_text(value: Any) -> str:
    """Return a name as Markdown text that renders as itself (rows are data).

    ``&``, ``<`` and ``>`` become entities (no HTML, no ``<!-- marker -->`` goes into a page
    as is), ``|`` and backquotes are escaped, so a name can neither break a table nor end a
    generated block.
    """
    text = str(value)
    if _PLAIN.fullmatch(text):
        return text
    return html.escape(text, quote=False).replace("|", "\\|").replace("`", "&#96;")


def md_code(value: Any) -> str:
    """Return a name in a code span, or escaped as :func:`md_text` where a span cannot hold it."""
    text = str(value)
    return f"`{text}`" if _PLAIN.fullmatch(text) else md_text(text)


def csv_text(value: Any) -> Any:
    """Return a CSV cell that no spreadsheet reads as a formula (text starting ``= + - @``)."""
    return "'" + value if isinstance(value, str) and value.startswith(_FORMULA) else value


def _ends(summary: dict[str, Any]) -> str:
    """How the failed episodes ended, e.g. ``collision 17, time-out 3``."""
    ends = {k: v for k, v in (summary.get("ends") or {}).items() if k != "success" and v}
    return ", ".join(f"{k} {v}" for k, v in ends.items()) or "-"


def _limit(summary: dict[str, Any], key: str = "limit") -> str:
    value = summary.get(key)
    return "-" if value is None else f"{value:.0%}"


def _compute(summary: dict[str, Any]) -> str:
    """Return the compute per step and robot, and how many robots one call served."""
    batch = int(summary.get("compute_batch", 1))
    us = _fmt(summary["compute_us_per_step"], digits=0)
    return us if batch <= 1 else f"{us} (x{batch})"


def _fmt(value: float, scale: float = 1.0, digits: int = 2) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{scale * value:.{digits}f}"


def markdown_table(summaries: Sequence[dict[str, Any]]) -> str:
    """Format the summaries as a Markdown table."""
    lines = [
        "| suite | variant | physics | policy | success | 95% CI | limit | image-goal limit "
        "| failures "
        "| 10 cm / 5 deg "
        "| 30 cm / 15 deg "
        "| pos. err. median / p95 [cm] "
        "| head. err. median / p95 [deg] | time [s] | path [m] | effort | smooth. "
        "| coll. | us/step (batch) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        lo, hi = s["success_ci95"]
        loose = s.get("success_by_tolerance", {})
        cells = [
            f"{loose[k]['rate']:.0%}" if k in loose else "-" for k in ("10cm/5deg", "30cm/15deg")
        ]
        lines.append(
            f"| {md_text(s['suite'])} | {md_text(s['variant'])} | {md_text(s['physics'])} "
            f"| {md_text(s['policy'])} "
            f"| {s['success_rate']:.0%} "
            f"| {lo:.0%}-{hi:.0%} | {_limit(s)} | {_limit(s, 'image_goal_limit')} "
            f"| {_ends(s)} | {cells[0]} | {cells[1]} "
            f"| {_fmt(s['position_error_m_median'], 100)} / {_fmt(s['position_error_m_p95'], 100)} "
            f"| {_fmt(s['heading_error_deg_median'])} / {_fmt(s['heading_error_deg_p95'])} "
            f"| {_fmt(s['time_s_median'], digits=1)} | {_fmt(s['path_m_median'])} "
            f"| {_fmt(s['control_effort'])} | {_fmt(s['smoothness'], digits=3)} "
            f"| {s['collisions']} | {_compute(s)} |"
        )
    return "\n".join(lines) + "\n"


def rich_table(summaries: Sequence[dict[str, Any]]) -> Any:
    """Build a compact ``rich`` table for the terminal (the full one is ``summary.md``)."""
    from rich.table import Table

    table = Table(title="benchmark (full table: summary.md)")
    for name in (
        "suite / variant",
        "policy",
        "success (95% CI)",
        "limit",
        "image-goal limit",
        "failures",
        "pos. err. [cm]",
        "head. err. [deg]",
        "time [s]",
        "coll.",
    ):
        table.add_column(name, justify="left" if name in ("suite / variant", "policy") else "right")
    for s in summaries:
        lo, hi = s["success_ci95"]
        table.add_row(
            f"{s['suite']} / {s['variant']} ({s['physics']})",
            s["policy"],
            f"{s['success_rate']:.0%} ({lo:.0%}-{hi:.0%})",
            _limit(s),
            _limit(s, "image_goal_limit"),
            _ends(s),
            _fmt(s["position_error_m_median"], 100),
            _fmt(s["heading_error_deg_median"]),
            _fmt(s["time_s_median"], digits=1),
            str(s["collisions"]),
        )
    return table


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
    shown = ordered_policies(kept, policies)
    if not order or not shown:
        return "(no rows for these suites and policies)\n"
    lines = [
        "| suite: variant | episodes | " + " | ".join(md_code(p) for p in shown) + " |",
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
        name = f"{md_text(key[0])}: {md_text(key[1])}"
        lines.append(f"| {name} | {n} | " + " | ".join(out) + " |")
    if not ends:
        return "\n".join(lines) + "\n"
    lines += [
        "",
        "| how episodes ended (collision / time-out / lost) | | "
        + " | ".join(md_text(p) for p in shown)
        + " |",
        "|---|---|" + "---|" * len(shown),
    ]
    for key in order:
        out = []
        for policy in shown:
            counts = Counter(str(r.get("end")) for r in cells[key].get(policy, []))
            out.append(f"{counts['collision']} / {counts['time-out']} / {counts['lost']}")
        lines.append(f"| {md_text(key[0])}: {md_text(key[1])} | | " + " | ".join(out) + " |")
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
    from radial_ibvs_agents.stats import iqm_interval

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
                name = f"{md_text(suite)} | {md_text(variant)}"
                out.append(f"| {name} | {cells} ({len(values)} seeds) | - | - |")
                continue
            tasks.append(values)
            point, low, high = iqm_interval([values])
            name = f"{md_text(suite)} | {md_text(variant)}"
            out.append(f"| {name} | {cells} | {point:.0%} | {low:.0%}-{high:.0%} |")
        if tasks:
            point, low, high = iqm_interval(tasks)
            out.append(
                f"| all | stratified over {len(tasks)} variants | | {point:.0%} | "
                f"{low:.0%}-{high:.0%} |"
            )
        out.append("")
    return "\n".join(out)


def success_csv(summaries: Sequence[Mapping[str, Any]]) -> str:
    """Return :func:`success_summaries` as CSV: one row per suite variant and policy.

    Columns: ``suite``, ``variant``, ``policy``, ``episodes``, ``successes``,
    ``success_rate``, ``ci95_low``, ``ci95_high`` (what ``pandas.read_csv`` reads as is).
    """
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
        names = [csv_text(s[k]) for k in ("suite", "variant", "policy")]
        writer.writerow([*names, s["episodes"], wins, s["success_rate"], lo, hi])
    return buffer.getvalue()


def timings_table(rows: Sequence[Mapping[str, Any]], workers: int) -> str:
    """Return the suites' timings as Markdown, with the wall clock they imply per suite.

    Parameters
    ----------
    rows
        :func:`radial_ibvs_agents.experiments.benchmark.suite_timings`: per suite, its ``seconds``
        (worker-seconds), ``episodes`` and ``resumed`` chunks.
    workers
        The workers that shared them.
    """
    total = sum(r["seconds"] for r in rows)
    lines = [
        f"| suite | episodes | worker-seconds | share | about, with {workers} workers |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        share = r["seconds"] / total if total else 0.0
        resumed = f" ({r['resumed']} chunks resumed)" if r["resumed"] else ""
        lines.append(
            f"| {md_text(r['suite'])}{resumed} | {r['episodes']} | {r['seconds']:.0f} "
            f"| {share:.0%} "
            f"| {r['seconds'] / max(workers, 1):.0f} s |"
        )
    lines.append(f"| all | {sum(r['episodes'] for r in rows)} | {total:.0f} | 100% "
                 f"| {total / max(workers, 1):.0f} s |")  # fmt: skip
    return "\n".join(lines) + "\n"


def write_rows_csv(path: Path | str, rows: Sequence[Mapping[str, Any]]) -> Path:
    """Write rows as ``episodes.csv``: the columns :data:`radial_ibvs_agents.rows.CSV_COLUMNS`."""
    cells = [{k: csv_text(v) for k, v in csv_row(row).items()} for row in rows]
    return write_csv(path, cells, CSV_COLUMNS)
