"""One documentation page per env id, generated from the env's docstring (as Farama does)."""

from __future__ import annotations

import inspect
import re
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
    """Return the docstring as the page's MyST Markdown.

    ``## Heading`` lines go one level below the page title; Sphinx roles (``:class:`X```)
    become MyST's (``{class}`X```); the numpy-style ``Parameters`` section becomes a table.
    """
    doc = re.sub(r":(class|mod|func|meth|attr|data|exc):`", r"{\1}`", doc)
    out: list[str] = []
    lines = doc.splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.strip() == "Parameters" and k + 1 < len(lines) and set(lines[k + 1]) == {"-"}:
            table, k = _parameters(lines, k + 2)
            out += ["### Parameters", "", *table]
            continue
        out.append("#" + line if line.startswith("## ") else line)
        k += 1
    return "\n".join(out)


def _parameters(lines: list[str], k: int) -> tuple[list[str], int]:
    """Return the numpy-style entries from ``lines[k]`` as a table, and the index after them."""
    entries: list[tuple[str, list[str]]] = []
    while k < len(lines) and (
        lines[k].strip() == ""
        or lines[k].startswith((" ", "*"))
        or (
            lines[k]
            and not lines[k].startswith("#")
            and k + 1 < len(lines)
            and lines[k + 1].startswith("    ")
        )
    ):
        line = lines[k]
        if line.strip() and not line.startswith(" "):
            entries.append((line.strip(), []))
        elif line.strip() and entries:
            entries[-1][1].append(line.strip())
        k += 1
    table = ["| argument | meaning |", "|---|---|"]
    for name, text in entries:
        names = ", ".join(f"`{n.strip()}`" for n in name.split(","))
        table.append(f"| {names} | {' '.join(text).replace('|', '&#124;')} |")
    return [*table, ""], k


def copy_notebooks(source: Path, folder: Path) -> None:
    """Copy the teaching notebooks into the docs tree (rendered from their stored outputs)."""
    folder.mkdir(parents=True, exist_ok=True)
    for notebook in sorted(source.glob("*.ipynb")):
        target = folder / notebook.name
        if not target.is_file() or target.read_bytes() != notebook.read_bytes():
            shutil.copyfile(notebook, target)
