"""``radial-ibvs evaluate``: one policy, N seeded episodes, Wilson intervals, JSON rows."""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

from radial_ibvs_agents.cli._options import add_trust_model_option, policies_help, seed_value

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Add the ``evaluate`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "evaluate",
        help="run one policy for N seeded episodes; print a summary, write JSON rows",
        description=(
            "Run a policy (below) on a scenario for N episodes seeded S, S+1, ...; print the "
            "success rate (95% Wilson interval) and the errors; --json writes one row per "
            "episode. Every policy runs on the same physics, kinematic unless --env-kwarg "
            "physics=pymunk says otherwise (the output names it), and is judged as the benchmark "
            "judges (a park: 2 cm / 2 deg held 1 s, whatever a model was trained with; "
            "--env-kwarg success_hold_steps=N asks another hold, 1 the older rule where a pass "
            "counts), so that two calls, or one call with several policies, compare policies "
            "only."
        ),
        epilog=policies_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--policy",
        required=True,
        nargs="+",
        help="one or more policy names or model directories (listed below), run on the same "
        "physics and seeds",
    )
    parser.add_argument("--scenario", default="paper-sim", help="default: %(default)s")
    parser.add_argument("--task", type=int, help="task index (default: drawn per episode)")
    parser.add_argument("--episodes", type=int, default=10, help="default: %(default)s")
    parser.add_argument(
        "--seed", type=seed_value, default=0, help="first seed (default: %(default)s)"
    )
    parser.add_argument(
        "--env-kwarg",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="gym.make argument (YAML value), e.g. physics=kinematic or depth_scale=1.3",
    )
    parser.add_argument("--json", type=Path, help="write the per-episode rows here")
    add_trust_model_option(parser)


#: the physics every evaluated policy runs on unless --env-kwarg physics=... says otherwise
DEFAULT_PHYSICS = "kinematic"


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs evaluate``; returns the exit code."""
    from radial_ibvs_agents.experiments import write_json
    from radial_ibvs_agents.experiments.evaluate import evaluate, parse_env_kwargs
    from radial_ibvs_agents.rows import JUDGING

    # judged as the benchmark judges, whatever a model's training env asked (e.g. a hold)
    env_kwargs = {"physics": DEFAULT_PHYSICS, **JUDGING, **parse_env_kwargs(args.env_kwarg)}
    # the policies' networks are small: one torch thread is fastest (3x here); read by torch
    # when a learned policy imports it (numpy, imported already, keeps its threads)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    every = []
    for name in args.policy:  # one physics for all: a comparison compares policies only
        logs = evaluate(
            name,
            args.scenario,
            task=args.task,
            episodes=args.episodes,
            seed=args.seed,
            env_kwargs=env_kwargs,
            trust_model=args.trust_model,
        )
        _print_summary(name, args.scenario, logs)
        every += logs
    if args.json is not None:
        print(f"saved {write_json(every, args.json)}")
    return 0


def _print_summary(name: str, scenario: str, logs: list[Any]) -> None:
    from radial_ibvs_agents.rows import episode_row, summarise

    rows = [episode_row(log) for log in logs]
    summary = summarise(rows)
    lo, hi = summary["success_ci95"]
    physics = ", ".join(sorted({str(row["physics"]) for row in rows}))
    hold = max(int(row.get("success_hold_steps", 1)) for row in rows)
    judged = f", success held {hold} steps" if hold > 1 else ""
    print(f"{name} on {scenario}, {physics} physics{judged}: {summary['episodes']} episodes")
    print(
        f"  success {summary['success_rate']:.0%} (95% CI {lo:.0%}-{hi:.0%}), "
        f"collisions {summary['collisions']}"
    )
    pos, head = summary["position_error_m_median"], summary["heading_error_deg_median"]
    print(
        f"  final position error median {100 * pos:.2f} cm "
        f"(p95 {100 * summary['position_error_m_p95']:.2f}), heading error median "
        f"{head:.2f} deg (p95 {summary['heading_error_deg_p95']:.2f})"
    )
    by_tolerance = summary.get("success_by_tolerance", {})
    if by_tolerance:
        print(
            "  success by tolerance: "
            + ", ".join(
                f"{name} {s['rate']:.0%} ({s['ci95'][0]:.0%}-{s['ci95'][1]:.0%})"
                for name, s in by_tolerance.items()
            )
        )
    if "ends" in summary:
        print("  ends: " + ", ".join(f"{k} {v}" for k, v in summary["ends"].items()))
    batch = int(summary.get("compute_batch", 1))
    print(
        f"  compute {summary['compute_us_per_step']:.0f} us/step"
        + (f" per robot ({batch} robots per call)" if batch > 1 else " (one robot per call)")
    )
