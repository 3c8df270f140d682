"""``radial-ibvs benchmark``: every policy on the same suites and seeds (tables, rows, plots)."""

from __future__ import annotations

import argparse
import importlib.util
import os
import shutil
import sys
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import (
    add_backend_options,
    add_trust_model_option,
    policies_help,
    suites_help,
)
from radial_ibvs_agents.rows import LIMITS, judging_rules

__all__ = ["BASELINES", "add_parser", "policies_to_run", "run"]

#: what ``--baselines`` adds: both limits, the classical image-based policies, the student
BASELINES = (
    *LIMITS,
    "ibvs",
    "ibvs-straight",
    "pbvs",
    "pbvs-ekf",
    "dagger-student",
)


def add_parser(sub: Any) -> None:
    """Add the ``benchmark`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "benchmark",
        help="run every policy on the same suites and seeds; table, CSV, JSON rows, plots",
        description=(
            "Run the policies on the suites (paper: the four tasks with d* and 1.3 d*; random: "
            "200 random rooms and start/goal pairs, the domain of convergence; noise: 0, 0.5, "
            "1, 2 px; calibration: principal-point and focal-ratio errors; mirror-swap: the "
            "goal image through mirror B; physics: pymunk vs kinematic; pixels: ideal points vs "
            "points detected in rendered images, paper-sim and paper-lab; generalisation, on "
            "seeds from 100,000 that no training draws: held-out: 200 random rooms; unseen-scenes: "
            "200 scenes per variant from a family no training draws (larger rooms, more "
            "landmarks, a lower camera), ideal and through a real camera; paper-lab: "
            "the lab zero-shot; cross-camera: mirror B and a camera at 1.2 m; obstacles: 200 "
            "random rooms with obstacles; imperfect: 100 held-out random rooms per variant "
            "through a real camera: 1 px noise, principal point (2, -1) px with focal ratio "
            "+1 %, both, and imperfections drawn per episode). Every table gives the planner's "
            "rate (a privileged policy with a map: the limit) beside each policy's. Prints a "
            "table and writes episodes.csv, episodes.json, summary.md and plots into --out."
        ),
        epilog=f"{policies_help()}\n\n{suites_help()}",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--suites", nargs="+", help="default: all")
    parser.add_argument(
        "--policies", nargs="+", help="default: the analytic policies and every shipped model"
    )
    parser.add_argument(
        "--baselines",
        action="store_true",
        help="add the baselines to --policies: both limits, the classical image-based "
        f"policies and the shipped student ({', '.join(BASELINES)})",
    )
    parser.add_argument("--episodes", type=int, help="per suite variant (default: 200 random, 8)")
    parser.add_argument(
        "--success-hold-steps",
        type=int,
        default=None,
        metavar="N",
        help="a success needs the pose within the tolerances N steps in a row, for every "
        "policy (default: a park, held 1 s: 10 steps of 0.1 s, so a policy passing through the "
        "goal does not count; 1: the older rule, the first step within them)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=2,
        help="local processes, or the CPUs of a private Ray instance (default: %(default)s)",
    )
    add_backend_options(parser, "100-episode chunk")
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("outputs/benchmark"),
        help="folder; each finished chunk is saved in OUT/chunks, and a rerun with the same "
        "--out skips the chunks done (default: %(default)s)",
    )
    parser.add_argument("--fresh", action="store_true", help="discard OUT/chunks, run everything")
    parser.add_argument("--json", type=Path, help="also write the per-episode rows here")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_trust_model_option(parser)


def policies_to_run(
    given: list[str] | None, baselines: bool, default: list[str], ompl: bool
) -> list[str]:
    """Return the policies a benchmark runs: ``given``, plus :data:`BASELINES` if asked.

    Without ``given`` and ``baselines``: ``default`` (every policy and shipped model). The
    planners need OMPL: where it is missing they are left out of the defaults and the
    baselines (a policy named in ``given`` stays, and fails with its install hint).
    """
    policies = list(given or ([] if baselines else default))
    added = [p for p in BASELINES if p not in policies] if baselines else []
    if not ompl:
        added = [p for p in added if p not in LIMITS]
        if not given:
            policies = [p for p in policies if p not in LIMITS]
    return [*policies, *added]


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs benchmark``; returns the exit code."""
    # the workers, spawned from here, share the cores: one BLAS thread each (read when they
    # load numpy and torch; numpy here keeps its threads)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    from rich.console import Console

    from radial_ibvs_agents import POLICY_NAMES
    from radial_ibvs_agents.analytic.planner import PLANNING_EXTRA
    from radial_ibvs_agents.experiments.benchmark import (
        run_benchmark,
        suite_timings,
        summary_rows,
        write_outputs,
    )
    from radial_ibvs_agents.experiments.suites import SUITES
    from radial_ibvs_agents.experiments.tables import rich_table, timings_table
    from radial_ibvs_agents.io import write_atomic, write_json
    from radial_ibvs_agents.learned import shipped_models

    default = [*POLICY_NAMES, *shipped_models()]
    ompl = importlib.util.find_spec("ompl") is not None
    policies = policies_to_run(args.policies, args.baselines, default, ompl)
    if not ompl and (not args.policies or args.baselines):
        print(f"without OMPL the planners' limit rows are left out: {PLANNING_EXTRA}")
    chunks = Path(args.out) / "chunks"
    if args.fresh and chunks.is_dir():
        shutil.rmtree(chunks)
    results = run_benchmark(
        policies,
        args.suites or list(SUITES),
        episodes=args.episodes,
        workers=args.workers,
        progress=not args.no_progress,
        backend=args.backend,
        address=args.address,
        store=chunks,
        notify=print,
        trust_model=args.trust_model,
        success_hold_steps=args.success_hold_steps,
    )
    console = Console()
    if not console.is_terminal:  # piped or redirected: every column, however wide
        console = Console(width=10_000)
    console.print(rich_table(summary_rows(results)))
    for rule in judging_rules([row for result in results for row in result.rows]):
        print(f"success: {rule}")
    for result in results:
        if result.skipped:
            print(f"skipped {result.job.policy} on {result.job.variant.suite}: {result.skipped}")
    written = write_outputs(results, args.out)
    timings = timings_table(suite_timings(results), args.workers)
    print(f"time per suite (each job timed in its worker):\n{timings}")
    written.append(write_atomic(Path(args.out) / "timings.md", timings.encode()))
    if args.json is not None:
        rows = [row for result in results for row in result.rows]
        written.append(write_json(args.json, rows))
    for path in written:
        print(f"saved {path}")
    ran = {r.job.policy for r in results if not r.skipped}
    never = sorted({r.job.policy for r in results} - ran)
    if never:  # a variant a policy cannot take is a designed skip; no variant at all is not
        print(
            f"radial-ibvs benchmark: error: {', '.join(never)} ran in no variant of "
            f"{', '.join(args.suites or ['the default suites'])} (the reasons are above)",
            file=sys.stderr,
        )
        return 1
    return 0
