"""Every snippet of ``docs/rl-libraries.md`` runs, as written there, with the real libraries.

One test per section of the page: its code blocks run in order in one fresh folder (Python
blocks with this interpreter, shell blocks with bash, this venv's ``bin`` first on ``PATH``),
so a later block reads what an earlier one wrote. A section whose libraries are not installed
is skipped, unless ``RADIAL_IBVS_REQUIRE_CLIENTS`` asks for it: ``1`` for every section but
those that need Gymnasium 1.0 (d3rlpy), or a comma-separated list of sections. CI installs the
``clients`` extra and sets it, and runs the other sections, d3rlpy's among them, in its
Gymnasium-1.0 environment (TorchRL refuses 1.0 itself).
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "rl-libraries.md"

#: each section of the page and the modules its snippets import
NEEDS = {
    "stable-baselines3": ["stable_baselines3"],
    "rl-zoo3": ["rl_zoo3"],
    "TorchRL": ["torchrl"],
    "Tianshou": ["tianshou"],
    "CleanRL": ["tyro", "tensorboard"],
    "Minari": ["minari", "h5py"],
    "d3rlpy": ["d3rlpy", "minari", "h5py"],
    "rliable": ["rliable", "pandas"],
}
#: sections that need Gymnasium 1.0 (d3rlpy pins it): run in CI's second environment
FLOOR_ONLY = ("d3rlpy",)
#: sections whose library refuses Gymnasium 1.0 (TorchRL, by its own check)
NOT_AT_FLOOR = ("TorchRL",)


def page_sections() -> dict[str, list[tuple[str, str]]]:
    """The page's ``## `` sections and their code blocks, ``(language, code)`` in order."""
    sections: dict[str, list[tuple[str, str]]] = {}
    current = None
    for part in re.split(r"^## (.+)$", PAGE.read_text(), flags=re.MULTILINE)[1:]:
        if current is None:
            current = part.strip()
            continue
        blocks = re.findall(r"^```(python|bash)\n(.*?)^```", part, flags=re.MULTILINE | re.DOTALL)
        sections[current] = blocks
        current = None
    return sections


def _required(section: str) -> bool:
    wanted = os.environ.get("RADIAL_IBVS_REQUIRE_CLIENTS", "")
    if wanted == "1":
        return section not in FLOOR_ONLY
    return section in [w.strip() for w in wanted.split(",")]


def test_every_section_of_the_page_is_tested() -> None:
    sections = page_sections()
    assert list(sections) == list(NEEDS)
    assert all(sections.values()), [s for s, blocks in sections.items() if not blocks]


@pytest.mark.slow
@pytest.mark.parametrize("section", list(NEEDS))
def test_the_snippets_run_as_written(section: str, tmp_path: Path) -> None:
    import gymnasium

    if section in NOT_AT_FLOOR and gymnasium.__version__.startswith("1.0."):
        pytest.skip(f"{section} refuses Gymnasium {gymnasium.__version__} (it needs >= 1.1)")
    missing = [m for m in NEEDS[section] if importlib.util.find_spec(m) is None]
    if missing:
        if _required(section):
            pytest.fail(f"{section}: {missing} not installed (pip install -e '.[clients]')")
        pytest.skip(f"{section}: {missing} not installed (the clients extra)")
    for name in ("configs", "examples"):
        (tmp_path / name).symlink_to(ROOT / name)
    env = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
        "MPLBACKEND": "Agg",
        "MINARI_DATASETS_PATH": str(tmp_path / "minari"),
        "PYTHONPATH": str(ROOT),
    }
    for k, (language, code) in enumerate(page_sections()[section]):
        script = tmp_path / f"block_{k}.{'py' if language == 'python' else 'sh'}"
        script.write_text(code)
        command = [sys.executable, script.name] if language == "python" else ["bash", script.name]
        done = subprocess.run(
            command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900
        )
        assert done.returncode == 0, f"{section}, block {k}:\n{code}\n{done.stderr[-4000:]}"
