"""``radial-ibvs report``: tables and curves from benchmark rows, as Markdown."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def _pairs(items: list[str], option: str) -> dict[str, str]:
    """``["A=B", ...]`` as ``{"A": "B"}``; a bad item is an error naming the option."""
    bad = [item for item in items if "=" not in item or item.startswith("=")]
    if bad:
        raise ValueError(f"{option} takes NAME=VALUE, got {bad}")
    return dict(item.split("=", 1) for item in items)


def add_parser(sub: Any) -> None:
    """Add the ``report`` sub-command to the sub-parsers ``sub``."""
    parser = sub.add_parser(
        "report",
        help="tables and curves from benchmark rows (Markdown, ready to paste)",
        description=(
            "Read the rows of one or more `radial-ibvs benchmark` runs (their episodes.json) "
            "and print, as Markdown: the success table (policies as columns, the planner's "
            "limit first, 95 % Wilson intervals) and how the episodes ended; with --seeds, "
            "each group of training seeds' rates and their IQM with a stratified-bootstrap "
            "interval; with --curves, DAgger students' per-round success. With --out, writes "
            "OUT/report.md with its figures (the success heat map, the success curves, the "
            "DAgger curves) and OUT/success.csv (one row per suite variant and policy: what "
            "pandas reads)."
        ),
    )
    parser.add_argument("rows", type=Path, nargs="+", help="episodes.json of benchmark runs")
    parser.add_argument("--suites", nargs="+", help="suites, in this order (default: all)")
    parser.add_argument("--policies", nargs="+", help="policies, in this order (default: all)")
    parser.add_argument(
        "--rename", nargs="+", default=[], metavar="OLD=NEW", help="show policy OLD as NEW"
    )
    parser.add_argument(
        "--seeds",
        action="append",
        default=[],
        metavar="NAME=POLICY,POLICY,...",
        help="a config's training seeds (one policy per seed): IQM across them; repeatable",
    )
    parser.add_argument(
        "--tolerance",
        default="2cm/2deg",
        choices=("2cm/2deg", "10cm/5deg", "30cm/15deg"),
        help="for --seeds (default: %(default)s)",
    )
    parser.add_argument(
        "--curves",
        action="append",
        default=[],
        metavar="LABEL=DIR,DIR,...",
        help="DAgger runs (radial-ibvs distill directories) to plot per round; repeatable",
    )
    parser.add_argument("--out", type=Path, help="write report.md (and the curves) here")
    parser.add_argument(
        "--variants",
        nargs="+",
        metavar="'SUITE: VARIANT'",
        help="only these rows of the success table, in this order",
    )
    parser.add_argument(
        "--into",
        type=Path,
        metavar="FILE",
        help="write the success table into FILE between its <!-- results:start --> and "
        "<!-- results:end --> lines (the README, a results page), with the command that made it",
    )
    parser.add_argument(
        "--block",
        default="results",
        metavar="NAME",
        help="with --into: the block's name, <!-- NAME:start --> (default: %(default)s; a page "
        "with several generated tables names each)",
    )
    parser.add_argument(
        "--heatmap", type=Path, metavar="PNG", help="draw the success heat map of the rows here"
    )


def run(args: argparse.Namespace) -> int:
    """Run ``radial-ibvs report``; returns the exit code."""
    from radial_ibvs_agents.experiments.report import dagger_curves
    from radial_ibvs_agents.experiments.tables import results_table, seeds_table
    from radial_ibvs_agents.io import write_atomic
    from radial_ibvs_agents.rows import hold_steps, judging_rule, load_rows

    renames = _pairs(args.rename, "--rename")
    seeds = {k: v.split(",") for k, v in _pairs(args.seeds, "--seeds").items()}
    curves = {k: v.split(",") for k, v in _pairs(args.curves, "--curves").items()}
    if curves and args.out is None:
        raise ValueError("--curves draws a figure: give --out DIR for it")
    rows = load_rows(args.rows)
    if args.into is not None:
        _write_into(args, rows, renames)
    if args.heatmap is not None:
        from radial_ibvs_agents.experiments.benchmark_plots import plot_success
        from radial_ibvs_agents.rows import success_summaries

        renamed = [{**r, "policy": renames.get(str(r["policy"]), r["policy"])} for r in rows]
        kept = [r for r in renamed if not args.suites or r["suite"] in args.suites]
        print(f"saved {plot_success(success_summaries(kept, args.policies), args.heatmap)}")
    sources = ", ".join(str(p) for p in args.rows)
    rule = judging_rule(hold_steps(rows))
    parts = [
        "# Benchmark report",
        "",
        f"From {len(rows)} episodes ({sources}). Success: {rule}; in brackets, the 95 % "
        "Wilson interval (cells of 20 episodes or more).",
        "",
        results_table(rows, args.suites, args.policies, renames),
    ]
    if seeds:
        parts += ["## Across training seeds", "", seeds_table(rows, seeds, args.tolerance)]
    if curves:
        args.out.mkdir(parents=True, exist_ok=True)
        figure = args.out / "dagger-curves.png"
        parts += [
            "## DAgger rounds",
            "",
            "![success after each DAgger round](dagger-curves.png)",
            "",
            dagger_curves(curves, figure),
        ]
    if args.out is not None:
        parts += _figures(args, rows, renames)
    text = "\n".join(parts)
    print(text)
    if args.out is not None:
        write_atomic(args.out / "report.md", text.encode())
        print(f"saved {args.out / 'report.md'}")
    return 0


def _figures(args: argparse.Namespace, rows: list[dict[str, Any]], renames: dict) -> list[str]:
    """Write the heat map, the success curves and ``success.csv`` into ``--out``; their lines."""
    from radial_ibvs_agents.experiments.benchmark_plots import plot_success, plot_success_curves
    from radial_ibvs_agents.experiments.tables import success_csv
    from radial_ibvs_agents.io import write_atomic
    from radial_ibvs_agents.rows import success_summaries

    args.out.mkdir(parents=True, exist_ok=True)
    renamed = [{**r, "policy": renames.get(str(r["policy"]), r["policy"])} for r in rows]
    kept = [r for r in renamed if not args.suites or r["suite"] in args.suites]
    summaries = success_summaries(kept, args.policies)
    plot_success(summaries, args.out / "heatmap.png")
    write_atomic(args.out / "success.csv", success_csv(summaries).encode())
    lines = ["## Success per suite variant", "", "![success heat map](heatmap.png)", ""]
    shown = list(dict.fromkeys(str(s["policy"]) for s in summaries))
    with_errors = [r for r in kept if r["policy"] in shown and "final_position_error_m" in r]
    if with_errors:
        plot_success_curves(with_errors, args.out / "success-curves.png", shown)
        lines += [
            "## Success curves",
            "",
            "The share of episodes that end within a tolerance, as the tolerance grows (every "
            "suite above together; a collision is outside every tolerance).",
            "",
            "![success curves](success-curves.png)",
            "",
        ]
    return [
        *lines,
        "One row per suite variant and policy: [success.csv](success.csv) (`pandas.read_csv`).",
        "",
    ]


def _write_into(args: argparse.Namespace, rows: list[dict[str, Any]], renames: dict) -> None:
    """Regenerate the results block of ``--into`` from the rows (and say how)."""
    import shlex
    import sys

    from radial_ibvs_agents.experiments.report import replace_block
    from radial_ibvs_agents.experiments.tables import md_code, results_table
    from radial_ibvs_agents.io import write_through
    from radial_ibvs_agents.rows import hold_steps, judging_rule

    ends = args.variants is None  # a headline (chosen rows) without the second table
    table = results_table(rows, args.suites, args.policies, renames, args.variants, ends)
    command = shlex.join(["radial-ibvs", *getattr(args, "argv", sys.argv[1:])])
    n = len({(r["suite"], r["variant"], r["policy"], r["seed"]) for r in rows})
    rule = judging_rule(hold_steps(rows))
    text = (
        f"Success: {rule}.\n\n{table}\n<sub>Generated from {n} benchmark episodes by "
        f"{md_code(command)}.</sub>\n"
    )
    if not args.block.replace("-", "").replace("_", "").isalnum():
        raise ValueError(f"--block must be letters, digits, '-' or '_', got {args.block!r}")
    write_through(args.into, replace_block(args.into, args.block, text).encode())
    print(f"updated {args.into}")
