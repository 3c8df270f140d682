"""The ``radial-ibvs`` command line.

Sub-commands land with the issues that build them; ``demo`` is the main job of the quick start.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``radial-ibvs`` (one sub-parser per command)."""
    parser = argparse.ArgumentParser(
        prog="radial-ibvs",
        description=(
            "Visual servoing of mobile robots with (non-)central catadioptric cameras "
            "(Aliakbarpour, Tahri, Araujo, RAS 2014)."
        ),
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    demo = sub.add_parser(
        "demo",
        help="project the paper's scene through mirrors A and B, drive the robot; save figures",
        description=(
            "Project the 8 points of the paper's eq. (39) through its two hyperbolic mirrors "
            "(A and B) from the start pose and a goal pose of a parking task, check the radial "
            "invariance (eq. 7 on the exact pixels equals eq. 9), and save a figure; then drive "
            "the robot of RadialIBVS/Parking-v0 (paper-sim) to the goal with the paper's IBVS "
            "(from the image points only) and save a "
            "rendered frame next to it (<out>-episode.png)."
        ),
    )
    demo.add_argument(
        "--out",
        type=Path,
        default=Path("outputs/demo.png"),
        help="where to save the figure (PNG, PDF or SVG; default: %(default)s)",
    )
    demo.add_argument(
        "--task",
        type=int,
        choices=(0, 1, 2, 3),
        default=1,
        help="parking task whose goal pose is shown (goal yaw 0/90/180/270 deg; "
        "default: %(default)s)",
    )
    demo.add_argument(
        "--non-central-offset",
        type=float,
        default=0.01,
        metavar="METRES",
        help="on-axis shift of the pinhole from the mirror focus, metres (0 = central; "
        "default: %(default)s)",
    )
    reproduce = sub.add_parser(
        "reproduce",
        help="reproduce the paper's Section 4.1: table, trajectories.csv, figures",
        description=(
            "Run the four parking tasks of a scenario with (a) the paper's IBVS, (b) the pose "
            "oracle (the same smooth control law fed the true poses) and (c) the IBVS with goal "
            "depths scaled by 1.3, on each physics backend, plus the robustness cases (goal "
            "image through mirror B, 0.5 px pixel noise, a 3 px principal-point error). "
            "Success is the paper's accuracy, 1 cm and 0.5 deg. Writes into --out: table.md, "
            "trajectories.csv (policy, task, physics, t, x, y, yaw), fig3-paths-<physics>.png "
            "(IBVS vs oracle), fig4-depth-scale-<physics>.png (d* vs 1.3 d*), "
            "fig6-8-servoing-task<k>.png (image, feature and alpha_m errors, velocities) and "
            "results.json (one row per episode)."
        ),
    )
    reproduce.add_argument("scenario", nargs="?", default="paper-sim", help="default: %(default)s")
    reproduce.add_argument(
        "--physics",
        nargs="+",
        choices=("kinematic", "pymunk"),
        default=["kinematic", "pymunk"],
        help="backends to run (default: both)",
    )
    reproduce.add_argument(
        "--out", type=Path, default=Path("outputs/reproduce"), help="output folder"
    )
    reproduce.add_argument("--json", type=Path, help="also write the per-episode rows here")
    reproduce.add_argument("--tasks", type=int, nargs="+", help="task indices (default: all)")
    reproduce.add_argument(
        "--lam", type=float, default=0.5, help="IBVS gain lambda, 1/s (default: %(default)s)"
    )
    reproduce.add_argument(
        "--control-dt", type=float, default=0.1, help="control period, s (default: %(default)s)"
    )
    reproduce.add_argument(
        "--max-steps", type=int, default=1000, help="step budget per episode (default: %(default)s)"
    )
    reproduce.add_argument("--no-robustness", action="store_true", help="skip the robustness cases")
    reproduce.add_argument(
        "--no-figures", action="store_true", help="write the table and data only"
    )
    evaluate = sub.add_parser(
        "evaluate",
        help="run one policy for N seeded episodes; print a summary, write JSON rows",
        description=(
            "Run a policy (ibvs, ibvs-current, ibvs-mean, ibvs-no-frame-change, oracle, random, "
            "a shipped model such as ppo-paper-sim, or a model directory) on a scenario for N "
            "episodes seeded S, S+1, ...; print the success rate (95%% Wilson interval) and the "
            "errors; --json writes one row per episode."
        ),
    )
    evaluate.add_argument("--policy", required=True, help="policy name or model directory")
    evaluate.add_argument("--scenario", default="paper-sim", help="default: %(default)s")
    evaluate.add_argument("--task", type=int, help="task index (default: drawn per episode)")
    evaluate.add_argument("--episodes", type=int, default=10, help="default: %(default)s")
    evaluate.add_argument("--seed", type=int, default=0, help="first seed (default: %(default)s)")
    evaluate.add_argument(
        "--env-kwarg",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="gym.make argument (YAML value), e.g. physics=kinematic or depth_scale=1.3",
    )
    evaluate.add_argument("--json", type=Path, help="write the per-episode rows here")

    train = sub.add_parser(
        "train",
        help="train a stable-baselines3 agent from an rl-zoo3-style config",
        description=(
            "Train PPO (or SAC) with the hyper-parameters of an rl-zoo3-format YAML file "
            "(configs/agents/ppo_parking.yaml): vectorised envs, observation normalisation, "
            "evaluation on held-out seeds with best-model checkpointing, checkpoints, CSV "
            "(and TensorBoard) logs, a progress bar. Writes a model directory that "
            "`radial-ibvs evaluate --policy DIR` and agents.load(DIR) read."
        ),
    )
    train.add_argument("--algo", choices=("ppo", "sac"), default="ppo")
    train.add_argument("--config", type=Path, required=True, help="rl-zoo3-format YAML file")
    train.add_argument("--env-id", help="config section (default: the file's only one)")
    train.add_argument("--seed", type=int, default=0, help="default: %(default)s")
    train.add_argument("--total-timesteps", type=int, help="default: the config's n_timesteps")
    train.add_argument("--out", type=Path, default=Path("outputs/train"), help="model directory")
    train.add_argument("--resume", type=Path, help="model directory to continue training from")
    train.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="override"
    )
    train.add_argument("--no-progress", action="store_true", help="no progress bar")
    bench = sub.add_parser(
        "benchmark",
        help="run every policy on the same suites and seeds; table, CSV, JSON rows, plots",
        description=(
            "Run the policies on the suites (paper: the four tasks with d* and 1.3 d*; random: "
            "200 random rooms and start/goal pairs, the domain of convergence; noise: 0, 0.5, "
            "1, 2 px; calibration: principal-point and focal-ratio errors; mirror-swap: the "
            "goal image through mirror B; physics: pymunk vs kinematic; pixels: ideal points vs "
            "points detected in rendered images, paper-sim and paper-lab). Prints a table and "
            "writes episodes.csv, episodes.json, summary.md and plots into --out."
        ),
    )
    bench.add_argument("--suites", nargs="+", help="default: all")
    bench.add_argument(
        "--policies", nargs="+", help="default: the analytic policies and every shipped model"
    )
    bench.add_argument("--episodes", type=int, help="per suite variant (default: 200 random, 8)")
    bench.add_argument("--workers", type=int, default=2, help="processes (default: %(default)s)")
    bench.add_argument("--out", type=Path, default=Path("outputs/benchmark"), help="folder")
    bench.add_argument("--json", type=Path, help="also write the per-episode rows here")
    bench.add_argument("--no-progress", action="store_true", help="no progress bar")
    render = sub.add_parser(
        "render",
        help="save a video (GIF, or MP4 with ffmpeg) of a policy parking",
        description="Run one episode of a policy with rgb_array rendering and save it.",
    )
    render.add_argument("--policy", required=True, help="policy name or model directory")
    render.add_argument("--scenario", default="paper-sim", help="default: %(default)s")
    render.add_argument("--task", type=int, help="task index (default: drawn)")
    render.add_argument("--seed", type=int, default=0, help="default: %(default)s")
    render.add_argument("--out", type=Path, required=True, help="FILE.gif or FILE.mp4")
    render.add_argument("--fps", type=int, default=10, help="default: %(default)s")
    render.add_argument("--max-steps", type=int, default=600, help="default: %(default)s")
    render.add_argument(
        "--env-kwarg", action="append", default=[], metavar="KEY=VALUE", help="gym.make argument"
    )
    image = sub.add_parser(
        "image",
        help="render an omnidirectional image and draw its measurement (border, beacons)",
        description=(
            "Render what the camera sees from an episode's start pose (clean, and with noise, "
            "blur and under-exposure), fit the mirror border, detect the beacons, and save the "
            "images with the fitted border, the detected centres and the true projections drawn."
        ),
    )
    image.add_argument("--scenario", default="paper-lab", help="default: %(default)s")
    image.add_argument("--seed", type=int, default=0, help="episode seed (default: %(default)s)")
    image.add_argument(
        "--out", type=Path, default=Path("outputs/pixels.png"), help="default: %(default)s"
    )
    return parser


def _image(args: argparse.Namespace) -> int:
    from radial_ibvs_gym.experiments.pixels import plot_measured

    print(f"saved {plot_measured(args.out, args.scenario, args.seed)}")
    return 0


def _render(args: argparse.Namespace) -> int:
    from radial_ibvs_gym.experiments.evaluate import parse_env_kwargs
    from radial_ibvs_gym.experiments.render import render_episode

    path, info = render_episode(
        args.policy,
        args.out,
        args.scenario,
        task=args.task,
        seed=args.seed,
        env_kwargs=parse_env_kwargs(args.env_kwarg),
        fps=args.fps,
        max_steps=args.max_steps,
    )
    outcome = "parked" if info.get("is_success") else "did not park"
    print(
        f"{args.policy} {outcome}: position error {100 * info['position_error_m']:.1f} cm, "
        f"heading error {info['heading_error_deg']:.1f} deg"
    )
    print(f"saved {path}")
    return 0


def _benchmark(args: argparse.Namespace) -> int:
    import json

    from rich.console import Console

    from agents import POLICY_NAMES
    from agents.learned import shipped_models
    from radial_ibvs_gym.experiments import write_atomic
    from radial_ibvs_gym.experiments.benchmark import (
        rich_table,
        run_benchmark,
        summary_rows,
        write_outputs,
    )
    from radial_ibvs_gym.experiments.suites import SUITES

    policies = args.policies or [*POLICY_NAMES, *shipped_models()]
    results = run_benchmark(
        policies,
        args.suites or list(SUITES),
        episodes=args.episodes,
        workers=args.workers,
        progress=not args.no_progress,
    )
    Console().print(rich_table(summary_rows(results)))
    for result in results:
        if result.skipped:
            print(f"skipped {result.job.policy} on {result.job.variant.suite}: {result.skipped}")
    written = write_outputs(results, args.out)
    if args.json is not None:
        rows = [row for result in results for row in result.rows]
        written.append(write_atomic(args.json, json.dumps(rows, indent=1) + "\n"))
    for path in written:
        print(f"saved {path}")
    return 0


def _evaluate(args: argparse.Namespace) -> int:
    from radial_ibvs_gym.experiments import write_json
    from radial_ibvs_gym.experiments.evaluate import evaluate, parse_env_kwargs, summarise

    logs = evaluate(
        args.policy,
        args.scenario,
        task=args.task,
        episodes=args.episodes,
        seed=args.seed,
        env_kwargs=parse_env_kwargs(args.env_kwarg),
    )
    rows = [log.row() for log in logs]
    summary = summarise(rows)
    lo, hi = summary["success_ci95"]
    print(f"{args.policy} on {args.scenario}: {summary['episodes']} episodes")
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
    print(f"  compute {summary['compute_us_per_step']:.0f} us/step")
    if args.json is not None:
        print(f"saved {write_json(logs, args.json)}")
    return 0


def _train(args: argparse.Namespace) -> int:
    import dataclasses

    from agents.training import train
    from agents.zoo import load_train_config
    from radial_ibvs_gym.experiments.evaluate import parse_env_kwargs

    config = load_train_config(args.config, args.env_id)
    overrides = parse_env_kwargs(args.env_kwarg)
    if overrides:
        config = dataclasses.replace(config, env_kwargs={**config.env_kwargs, **overrides})
    out = train(
        config,
        args.out,
        algo=args.algo,
        seed=args.seed,
        total_timesteps=args.total_timesteps,
        resume=args.resume,
        progress=not args.no_progress,
        command="radial-ibvs " + " ".join(args.argv),
    )
    print(f"saved {out}")
    return 0


def _reproduce(args: argparse.Namespace) -> int:
    from radial_ibvs_gym.experiments import (
        CASES,
        ROBUSTNESS_CASES,
        reproduce,
        summary_table,
        write_atomic,
        write_json,
        write_trajectories_csv,
    )

    cases = CASES if args.no_robustness else CASES + ROBUSTNESS_CASES
    logs = reproduce(
        args.scenario,
        physics=args.physics,
        tasks=args.tasks,
        cases=cases,
        control_dt=args.control_dt,
        lam=args.lam,
        max_steps=args.max_steps,
    )
    table = summary_table(logs)
    print(table)
    out: Path = args.out
    written = [
        write_atomic(out / "table.md", table),
        write_trajectories_csv(logs, out / "trajectories.csv"),
        write_json(logs, out / "results.json"),
    ]
    if args.json is not None:
        written.append(write_json(logs, args.json))
    if not args.no_figures:
        from radial_ibvs_gym.experiments.figures import plot_paths, plot_servoing

        for backend in args.physics:
            mine = [log for log in logs if log.physics == backend]
            written.append(
                plot_paths(
                    mine,
                    ("ibvs", "oracle"),
                    out / f"fig3-paths-{backend}.png",
                    f"IBVS vs the pose oracle (real 3D parameters), {backend}",
                )
            )
            written.append(
                plot_paths(
                    mine,
                    ("ibvs", "ibvs-d1.3"),
                    out / f"fig4-depth-scale-{backend}.png",
                    f"IBVS with d* and with 1.3 d*, {backend}",
                )
            )
        first = args.physics[0]
        for log in logs:
            if log.physics == first and log.policy in ("ibvs", "ibvs-noise-0.5px"):
                suffix = "" if log.policy == "ibvs" else f"-{log.policy}"
                name = f"fig6-8-servoing-task{log.task}{suffix}.png"
                written.append(plot_servoing(log, out / name, lam=args.lam))
    for path in written:
        print(f"saved {path}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``radial-ibvs``; returns the process exit code."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(argv)
    args.argv = argv  # the command line, for the metadata of what it writes
    if args.command == "demo":
        from radial_ibvs_gym.demo import run_demo, run_episode_demo

        path = run_demo(out=args.out, task=args.task, non_central_offset=args.non_central_offset)
        print(f"saved {path}")
        episode = args.out.with_name(f"{args.out.stem}-episode.png")
        print(f"saved {run_episode_demo(out=episode, task=args.task)}")
        return 0
    commands = {
        "reproduce": _reproduce,
        "evaluate": _evaluate,
        "train": _train,
        "benchmark": _benchmark,
        "render": _render,
        "image": _image,
    }
    if args.command in commands:
        try:
            return commands[args.command](args)
        except (ValueError, KeyError) as error:  # bad name, file or value: a message
            message = error.args[0] if error.args else error
            print(f"radial-ibvs {args.command}: error: {message}", file=sys.stderr)
            return 2
    raise AssertionError(f"unhandled command {args.command!r}")  # argparse rejects unknown ones


if __name__ == "__main__":
    sys.exit(main())
