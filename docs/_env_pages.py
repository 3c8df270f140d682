"""One documentation page per env id, generated from the env's docstring (as Farama does)."""

from __future__ import annotations

import inspect
import shutil
from pathlib import Path

#: env id -> (page name, class path); a GIF ``docs/img/<page>.gif`` is shown if present
ENVS = {
    "RadialIBVS/Parking-v0": ("parking", "radial_ibvs_gym.envs.parking.ParkingEnv"),
    "RadialIBVS/ParkingGoal-v1": (
        "parking-goal",
        "radial_ibvs_gym.envs.parking_goal.ParkingGoalEnv",
    ),
    "RadialIBVS/ParkingImage-v0": (
        "parking-image",
        "radial_ibvs_gym.envs.parking_image.ParkingImageEnv",
    ),
}


#: what each page's GIF shows (made with ``radial-ibvs render``)
CAPTIONS = {
    "parking": "The paper's IBVS parking in the paper's room, task 1: `radial-ibvs render "
    "--policy ibvs --scenario paper-sim --task 1 --env-kwarg physics=kinematic`.",
    "parking-goal": "The planner (the limit) around obstacles in a held-out room: `radial-ibvs "
    "render --policy planner --scenario random-obstacles --seed 100003`.",
    "parking-image": "The turn-first IBVS in the lab: `radial-ibvs render --policy "
    "ibvs-straight --scenario paper-lab --seed 2`.",
}


def _load(path: str) -> type:
    module, _, name = path.rpartition(".")
    return getattr(__import__(module, fromlist=[name]), name)


def write_env_pages(folder: Path) -> None:
    """Write ``folder/<page>.md`` for every env id from its class docstring."""
    folder.mkdir(parents=True, exist_ok=True)
    for env_id, (page, path) in ENVS.items():
        doc = inspect.cleandoc(_load(path).__doc__ or "")
        picture = Path(__file__).resolve().parent / "img" / f"{page}.gif"
        lines = [f"# `{env_id}`", ""]
        if picture.is_file():
            lines += [f"![{env_id}](../img/{page}.gif)", "", f"*{CAPTIONS[page]}*", ""]
        lines += [f"`{path}`", "", _demote(doc), ""]
        text = "\n".join(lines)
        target = folder / f"{page}.md"
        if not target.is_file() or target.read_text() != text:
            target.write_text(text)


def _demote(doc: str) -> str:
    """Return the docstring with its ``## Heading`` lines one level below the page title."""
    out = []
    for line in doc.splitlines():
        out.append("#" + line if line.startswith("## ") else line)
    return "\n".join(out)


def copy_notebooks(source: Path, folder: Path) -> None:
    """Copy the teaching notebooks into the docs tree (rendered from their stored outputs)."""
    folder.mkdir(parents=True, exist_ok=True)
    for notebook in sorted(source.glob("*.ipynb")):
        target = folder / notebook.name
        if not target.is_file() or target.read_bytes() != notebook.read_bytes():
            shutil.copyfile(notebook, target)
