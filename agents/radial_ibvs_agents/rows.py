"""Episode rows: the one owner of their columns, the success rule they report, and summaries.

A row is one episode as a flat JSON object (the ``--json`` contract of ``radial-ibvs evaluate`` and
the ``episodes.json`` of ``radial-ibvs benchmark``). This module makes them from an
:class:`~radial_ibvs_agents.rollouts.log.EpisodeLog` (:func:`episode_row`), says which columns the
CSV holds (:data:`CSV_COLUMNS`), how every episode is judged (:data:`JUDGING`, :data:`TOLERANCES`),
which policies are the tables' limits (:data:`LIMITS`), and groups, summarises and loads rows. A new
column is added here (and, if it is a new measure of the episode, on the log).

About 460 lines, one owner of the rows: their columns, the rule that judges them, and their
checks on reading (rows are data a user hands over) belong together, so that a new column
cannot be written without being checked.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.rollouts.log import EpisodeLog
from radial_ibvs_agents.untrusted import read_json
from radial_ibvs_gym.envs.rules import SUCCESS_TOLERANCES, TASK_TOLERANCE

__all__ = [
    "CSV_COLUMNS",
    "IMAGE_GOAL_LIMIT",
    "JUDGING",
    "LIMIT",
    "LIMITS",
    "MAX_ROWS",
    "MAX_ROWS_BYTES",
    "MAX_ROW_ENTRIES",
    "MAX_ROW_TEXT",
    "ROW_SCHEMA",
    "RUN_FIELDS",
    "TASK_TOLERANCE",
    "TOLERANCES",
    "add_limits",
    "check_row",
    "csv_row",
    "episode_row",
    "group_rows",
    "hold_steps",
    "judging_rule",
    "judging_rules",
    "load_rows",
    "ordered_policies",
    "success_summaries",
    "summarise",
    "wilson_interval",
]

#: the success tolerances every row reports in ``success_by_tolerance`` (name -> position in
#: metres, heading in degrees): the task's own (:data:`TASK_TOLERANCE`, the ``success``
#: column) first, then two looser ones
TOLERANCES: Mapping[str, tuple[float, float]] = SUCCESS_TOLERANCES

#: how every episode is judged, whatever env a model was trained in (its metadata may ask
#: another hold or other tolerances): the task's tolerance, held 1 s (a park: the env's
#: default ``success_hold_steps``, ``None``)
JUDGING: dict[str, Any] = {
    "success_position_m": TOLERANCES[TASK_TOLERANCE][0],
    "success_heading_deg": TOLERANCES[TASK_TOLERANCE][1],
    "success_hold_steps": None,
}

#: the policy whose rate is every table's limit: a planner with the true poses and the map
LIMIT = "planner"
#: the limit the images allow: the same planner driving to the pose the goal image shows
IMAGE_GOAL_LIMIT = "planner-image-goal"
#: both limits, in the order the tables show them
LIMITS = (LIMIT, IMAGE_GOAL_LIMIT)

#: a row's fields that describe how it was run, not the episode: the policy's compute per step
#: (a timing) and how many robots one ``predict`` served (set by the chunking)
RUN_FIELDS = ("compute_us_per_step", "compute_batch")

#: the columns of ``episodes.csv``, in order (``success_by_tolerance`` flattened, the task's
#: own tolerance being ``success``)
CSV_COLUMNS = (
    "policy",
    "scenario",
    "suite",
    "variant",
    "task",
    "seed",
    "physics",
    "success",
    "reached",
    "final_position_error_m",
    "final_heading_error_deg",
    "steps",
    "time_s",
    "path_length_m",
    "collision",
    "end",
    *("success_" + name.replace("/", "_") for name in TOLERANCES if name != TASK_TOLERANCE),
    "compute_us_per_step",
    "compute_batch",
    "control_effort",
    "smoothness",
)

#: the keys a row must have to be reported (:func:`load_rows`)
REPORT_KEYS = ("policy", "suite", "variant", "success")


def episode_row(log: EpisodeLog, variant: Any = None) -> dict[str, Any]:
    """Return an episode as a row (README, "JSON rows"), plus the log's ``extra``.

    Parameters
    ----------
    log
        The episode.
    variant
        The benchmark's suite variant it ran in (anything with ``suite`` and ``label``), or
        ``None``. Given, the row also holds ``suite``, ``variant``, and the ``start_pose`` and
        ``goal_pose`` (x, y, yaw: metres, radians) of the episode.
    """
    steps = max(log.steps, 1)
    info = log.info
    row = {
        "policy": log.policy,
        "scenario": log.scenario,
        "suite": log.extra.get("suite"),
        "task": log.task,
        "seed": log.seed,
        "physics": log.physics,
        "success": log.success,
        "reached": log.longest_run_within(*TOLERANCES[TASK_TOLERANCE]) > 0,
        "final_position_error_m": float(info["position_error_m"]),
        "final_heading_error_deg": float(info["heading_error_deg"]),
        "steps": log.steps,
        "time_s": round(log.steps * log.control_dt, 9),
        "path_length_m": log.path_length_m,
        "collision": bool(info.get("collision", False)),
        "end": log.end,
        "success_hold_steps": log.success_hold_steps,
        "success_by_tolerance": {name: log.success_at(*tol) for name, tol in TOLERANCES.items()},
        "compute_us_per_step": 1e6 * log.compute_s / steps,
        "compute_batch": log.batch,
        "control_effort": log.control_effort,
        "smoothness": log.smoothness,
        **(
            {"camera_imperfections": info["camera_imperfections"]}
            if "camera_imperfections" in info
            else {}
        ),
        **{k: v for k, v in log.extra.items() if k != "suite"},
    }
    if variant is not None:
        row.update(
            suite=variant.suite,
            variant=variant.label,
            start_pose=[float(v) for v in log.poses[0]],
            goal_pose=[float(v) for v in info["goal_pose"]],
        )
    return row


def csv_row(row: Mapping[str, Any]) -> dict[str, Any]:
    """Return a row with ``success_by_tolerance`` flattened into ``success_<name>`` columns."""
    flat = {
        "success_" + name.replace("/", "_"): value
        for name, value in (row.get("success_by_tolerance") or {}).items()
    }
    return {**row, **flat}


def judging_rule(hold: int, control_dt: float = 0.1) -> str:
    """Say in words how rows judged with ``success_hold_steps=hold`` count a success.

    Parameters
    ----------
    hold
        The rows' ``success_hold_steps`` (:func:`hold_steps`).
    control_dt
        The control period, seconds (0.1, the envs' default).
    """
    position_m, heading_deg = TOLERANCES[TASK_TOLERANCE]
    window = f"{100 * position_m:g} cm and {heading_deg:g} deg of the goal"
    if hold > 1:
        return (
            f"a park: the pose within {window}, held {hold} steps in a row "
            f"({hold * control_dt:g} s)"
        )
    return f"a pass: the first step within {window} (the older rule; the pose need not stay)"


def judging_rules(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Return :func:`judging_rule` for each ``success_hold_steps`` among the rows, in order."""
    holds = sorted({int(row.get("success_hold_steps", 1)) for row in rows})
    return [judging_rule(hold) for hold in holds]


def wilson_interval(successes: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """95 % Wilson score interval of a success rate (sound for small ``n`` and 0 or 1 rates)."""
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    lo = 0.0 if successes == 0 else max(0.0, centre - half)  # exact at the extremes
    hi = 1.0 if successes == n else min(1.0, centre + half)
    return (lo, hi)


def group_rows(
    rows: Iterable[Mapping[str, Any]], keys: Sequence[str]
) -> dict[tuple[str, ...], list[Mapping[str, Any]]]:
    """Group rows by the values of ``keys`` (as strings), groups in the order first met."""
    groups: dict[tuple[str, ...], list[Mapping[str, Any]]] = defaultdict(list)
    for row in rows:
        groups[tuple(str(row[k]) for k in keys)].append(row)
    return dict(groups)


def summarise(rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Success rate with its 95 % interval, and medians / 95th percentiles of the errors.

    Also the success rate per tolerance (where rows have ``success_by_tolerance``) and how the
    episodes ended (where rows have ``end``).
    """
    n = len(rows)
    wins = sum(bool(r["success"]) for r in rows)
    lo, hi = wilson_interval(wins, n)
    pos = np.array([r["final_position_error_m"] for r in rows])
    head = np.array([r["final_heading_error_deg"] for r in rows])
    parked = [r for r in rows if r["success"]]
    return {
        "episodes": n,
        "success_rate": wins / n if n else math.nan,
        "success_ci95": (lo, hi),
        "position_error_m_median": float(np.median(pos)) if n else math.nan,
        "position_error_m_p95": float(np.percentile(pos, 95)) if n else math.nan,
        "heading_error_deg_median": float(np.median(head)) if n else math.nan,
        "heading_error_deg_p95": float(np.percentile(head, 95)) if n else math.nan,
        "time_s_median": float(np.median([r["time_s"] for r in parked])) if parked else math.nan,
        "path_m_median": (
            float(np.median([r["path_length_m"] for r in parked])) if parked else math.nan
        ),
        "collisions": sum(bool(r["collision"]) for r in rows),
        "compute_us_per_step": float(np.mean([r["compute_us_per_step"] for r in rows])),
        "compute_batch": max((int(r.get("compute_batch", 1)) for r in rows), default=1),
        **_tolerances_and_ends(rows),
    }


def _tolerances_and_ends(rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """Success rate (and Wilson interval) per tolerance, and how the episodes ended."""
    n = len(rows)
    out: dict[str, Any] = {}
    names = [k for k in (rows[0].get("success_by_tolerance") or {})] if rows else []
    if names:
        out["success_by_tolerance"] = {}
        for name in names:
            wins = sum(bool(r["success_by_tolerance"][name]) for r in rows)
            out["success_by_tolerance"][name] = {
                "rate": wins / n,
                "ci95": wilson_interval(wins, n),
            }
    if rows and "end" in rows[0]:
        ends = [str(r["end"]) for r in rows]
        out["ends"] = {e: ends.count(e) for e in ("success", "collision", "lost", "time-out")}
    return out


def add_limits(summaries: Sequence[dict[str, Any]]) -> None:
    """Set each summary's ``limit`` and ``image_goal_limit``: the two limits' success rates.

    Each summary has ``policy``, ``suite``, ``variant`` and ``success_rate``; a limit that did
    not run the variant is ``None``.
    """
    rates = {(s["policy"], s["suite"], s["variant"]): s["success_rate"] for s in summaries}
    for summary in summaries:
        key = (summary["suite"], summary["variant"])
        summary["limit"] = rates.get((LIMIT, *key))
        summary["image_goal_limit"] = rates.get((IMAGE_GOAL_LIMIT, *key))


def ordered_policies(rows: Sequence[Mapping[str, Any]], wanted: Sequence[str] | None) -> list[str]:
    """Return the policies to show: ``wanted`` (those with rows), else the two limits first."""
    present = list(dict.fromkeys(str(r["policy"]) for r in rows))
    if wanted:
        return [p for p in wanted if p in present]
    first = [p for p in LIMITS if p in present]
    return first + [p for p in present if p not in LIMITS]


def success_summaries(
    rows: Sequence[Mapping[str, Any]], policies: Sequence[str] | None = None
) -> list[dict[str, Any]]:
    """Per suite variant and policy: the success rate and its 95 % Wilson interval.

    Returns
    -------
    list of dict
        ``suite``, ``variant``, ``policy``, ``episodes``, ``success_rate``, ``success_ci95``,
        in the order of :func:`ordered_policies`, then as met (what the heat map draws).
    """
    shown = ordered_policies(rows, policies)
    out = []
    for (suite, variant, policy), group in group_rows(rows, ("suite", "variant", "policy")).items():
        if policy not in shown:
            continue
        wins = sum(bool(r["success"]) for r in group)
        out.append(
            {
                "suite": suite,
                "variant": variant,
                "policy": policy,
                "episodes": len(group),
                "success_rate": wins / len(group),
                "success_ci95": wilson_interval(wins, len(group)),
            }
        )
    out.sort(key=lambda s: shown.index(str(s["policy"])))
    return out


#: the most rows a report reads, and the bytes of one ``episodes.json``
MAX_ROWS = 5_000_000
MAX_ROWS_BYTES = 2 << 30
#: the longest text a row may hold (a name, an end), and the most entries of one of its maps
MAX_ROW_TEXT = 500
MAX_ROW_ENTRIES = 64

#: the row schema: each known key and the kinds of value it takes ("text", "int", "number",
#: "bool", "none", "pose": three numbers, "flags": names to booleans, "numbers": names to
#: numbers); the keys a row must have are :data:`REPORT_KEYS`
ROW_SCHEMA: dict[str, tuple[str, ...]] = {
    "policy": ("text",),
    "suite": ("text",),
    "variant": ("text",),
    "scenario": ("text", "none"),
    "physics": ("text", "none"),
    "end": ("text", "none"),
    "task": ("int", "none"),
    "seed": ("int", "none"),
    "steps": ("int",),
    "compute_batch": ("int",),
    "success_hold_steps": ("int",),
    "success": ("bool",),
    "reached": ("bool",),
    "collision": ("bool",),
    "final_position_error_m": ("number",),
    "final_heading_error_deg": ("number",),
    "time_s": ("number",),
    "path_length_m": ("number",),
    "compute_us_per_step": ("number",),
    "control_effort": ("number", "none"),
    "smoothness": ("number", "none"),
    "start_pose": ("pose",),
    "goal_pose": ("pose",),
    "success_by_tolerance": ("flags",),
    "camera_imperfections": ("numbers",),
}


def _is_kind(value: Any, kind: str) -> bool:
    """Whether ``value`` is of one kind of :data:`ROW_SCHEMA` (bounded, no nesting)."""
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if kind == "text":
        return isinstance(value, str) and len(value) <= MAX_ROW_TEXT and value.isprintable()
    if kind == "int":
        return isinstance(value, int) and not isinstance(value, bool)
    if kind == "number":
        return number and math.isfinite(value)
    if kind == "bool":
        return isinstance(value, bool)
    if kind == "none":
        return value is None
    if kind == "pose":
        return (
            isinstance(value, list)
            and len(value) == 3
            and all(_is_kind(v, "number") for v in value)
        )
    if kind in ("flags", "numbers"):
        inner = "bool" if kind == "flags" else "number"
        return (
            isinstance(value, dict)
            and len(value) <= MAX_ROW_ENTRIES
            and all(_is_kind(k, "text") and _is_kind(v, inner) for k, v in value.items())
        )
    return False


def check_row(row: Any, where: str) -> None:
    """Check one row read from a file against :data:`ROW_SCHEMA` (rows are data).

    A known key must hold a value of its kinds (``"success": "false"`` is refused, never read
    as true); any other key (a job's extra) a short text, a number, a boolean or ``None``. Text
    is printable and at most :data:`MAX_ROW_TEXT` characters; maps hold at most
    :data:`MAX_ROW_ENTRIES` entries.

    Raises
    ------
    ValueError
        Naming ``where`` (the file and row), the key and the value (shortened).
    """
    if not isinstance(row, dict):
        raise ValueError(f"{where}: expected an episode object, got {type(row).__name__}")
    if len(row) > 4 * MAX_ROW_ENTRIES:
        raise ValueError(f"{where}: more than {4 * MAX_ROW_ENTRIES} keys")
    for key, value in row.items():
        kinds = ROW_SCHEMA.get(key, ("text", "int", "number", "bool", "none"))
        if not (_is_kind(key, "text") and any(_is_kind(value, kind) for kind in kinds)):
            shown = repr(value)
            shown = shown if len(shown) <= 80 else shown[:77] + "..."
            raise ValueError(
                f"{where}: {str(key)[:80]!r} must be {' or '.join(kinds)}, got {shown}"
            )


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
        if not path.exists():
            raise ValueError(f"{path}: no such file (an episodes.json of radial-ibvs benchmark)")
        data = read_json(path, None, MAX_ROWS_BYTES, "MAX_ROWS_BYTES")  # a regular file, bounded
        if not isinstance(data, list):
            raise ValueError(f"{path}: expected a JSON list of episode objects")
        if len(rows) + len(data) > MAX_ROWS:
            raise ValueError(f"{path}: more than MAX_ROWS = {MAX_ROWS} rows in all")
        for k, row in enumerate(data):
            check_row(row, f"{path}: row {k}")
            missing = [key for key in REPORT_KEYS if key not in row]
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
