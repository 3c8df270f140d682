"""Validation success at 2 cm, 10 cm and 30 cm along training, for runs side by side.

Usage::

    python research/diagnostics/tolerance_curves.py --out docs/img/reward-alone-curves.png \\
        "PPO, pose layer=outputs/reward_pose/ppo_seed0,outputs/reward_pose/ppo_seed1" \\
        "TQC + HER, pose layer=outputs/reward_pose/tqc_seed0,outputs/reward_pose/tqc_seed1"

Each argument is ``TITLE=DIR[,DIR...]``: one panel per title, one line style per seed
(``DIR/eval/tolerances.npz``, written by ``radial-ibvs train``), one colour per tolerance.
Prints each run's last evaluation.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from radial_ibvs_agents.learned.training.tolerance_eval import read_tolerance_curve
from radial_ibvs_agents.plotting import pyplot, save_figure
from radial_ibvs_gym.envs.rules import SUCCESS_TOLERANCES

COLOURS = {"2cm/2deg": "C3", "10cm/5deg": "C1", "30cm/15deg": "C2"}
STYLES = ("-", "--", ":", "-.")


def _panel(spec: str) -> tuple[str, list[Path]]:
    title, sep, dirs = spec.partition("=")
    if not sep or not dirs:
        raise SystemExit(f"expected TITLE=DIR[,DIR...], got {spec!r}")
    return title, [Path(d) for d in dirs.split(",")]


def main() -> None:
    """Draw the panels and print the last evaluations."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("panels", nargs="+", help="TITLE=DIR[,DIR...]")
    parser.add_argument("--out", required=True, help="figure path (.png)")
    args = parser.parse_args()
    panels = [_panel(spec) for spec in args.panels]
    plt = pyplot()
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 3.6), squeeze=False)
    for ax, (title, dirs) in zip(axes[0], panels, strict=True):
        for seed, run in enumerate(dirs):
            curve = read_tolerance_curve(run / "eval" / "tolerances.npz")
            if not curve:
                raise SystemExit(f"{run}: no eval/tolerances.npz (train with radial-ibvs train)")
            steps = sorted(curve)
            for name in SUCCESS_TOLERANCES:
                ax.plot(
                    [s / 1e6 for s in steps],
                    [100 * curve[s][name] for s in steps],
                    STYLES[seed % len(STYLES)],
                    color=COLOURS[name],
                    label=f"{name}, {run.name}",
                )
            last = curve[steps[-1]]
            rates = ", ".join(f"{name} {100 * last[name]:.1f} %" for name in SUCCESS_TOLERANCES)
            print(f"{title} / {run}: {steps[-1]:,} steps: {rates}")
        ax.set(title=title, xlabel="training steps (millions)", ylabel="validation success (%)")
        ax.set_ylim(-3, 103)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    print(f"saved {save_figure(fig, args.out)}")


if __name__ == "__main__":
    main()
