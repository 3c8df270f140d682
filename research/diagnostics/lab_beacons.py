"""A learned policy in the paper's lab with all 9 beacons, and with each one removed.

Usage::

    python research/diagnostics/lab_beacons.py POLICY [POLICY ...] [--episodes 8]

Every shipped learned model has 16 landmark slots (``max_landmarks=16``) and trained in random
rooms of 8 landmarks. With the fixed slot order landmark ``n`` fills slot ``n``, so slots 9-16
were never filled in training; the ``paper-lab`` scene has 9 beacons, and its 9th fills slot 9.
This script runs each policy on the ``paper-lab`` suite's episodes (seeds 0, 1, ...; kinematic)
with the 9 beacons, then with each beacon removed in turn (8 beacons: slots 1-8), and prints
the successes (2 cm / 2 deg). A policy that parks with 8 beacons and not with 9 fails on the
slot, not on the lab. ``slot_order="random"`` (``Parking-v0``) trains every slot.
"""

from __future__ import annotations

import argparse

from radial_ibvs_agents.experiments.evaluate import evaluate
from radial_ibvs_gym.scenarios import load_scenario


def lab_successes(policy: str, episodes: int) -> dict[str, int]:
    """Successes of ``policy`` in the lab, all beacons (``"all 9"``) and each one removed."""
    beacons = [list(map(float, b)) for b in load_scenario("paper-lab").config.landmarks]
    scenes: dict[str, dict] = {f"all {len(beacons)}": {}}
    for k in range(len(beacons)):
        scenes[f"without {k + 1}"] = {"landmarks": beacons[:k] + beacons[k + 1 :]}
    out = {}
    for label, overrides in scenes.items():
        logs = evaluate(
            policy,
            "paper-lab",
            episodes=episodes,
            seed=0,
            env_kwargs={"physics": "kinematic", **overrides},
            progress=False,
        )
        out[label] = sum(bool(log.info["is_success"]) for log in logs)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("policies", nargs="+", help="model directories or policy names")
    parser.add_argument("--episodes", type=int, default=8, help="episodes per scene")
    args = parser.parse_args()
    rows = {policy: lab_successes(policy, args.episodes) for policy in args.policies}
    labels = list(next(iter(rows.values())))
    print(f"successes of {args.episodes} lab episodes (2 cm / 2 deg)")
    print("| policy | " + " | ".join(labels) + " |")
    print("|---" * (len(labels) + 1) + "|")
    for policy, row in rows.items():
        print(f"| {policy} | " + " | ".join(str(row[k]) for k in labels) + " |")


if __name__ == "__main__":
    main()
