"""The Makefile's targets work from a fresh clone: each installs the tools it runs first."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(shutil.which("make") is None, reason="needs make")
@pytest.mark.parametrize(
    ("target", "tool", "extra"),
    [
        ("docs", "sphinx-build", "docs"),
        ("lint", "ruff", "dev"),
        ("type", "mypy", "dev"),
        ("test-fast", "pytest", "dev"),
    ],
)
def test_a_target_installs_its_tool_in_a_fresh_clone(
    tmp_path: Path, target: str, tool: str, extra: str
) -> None:
    shutil.copy(ROOT / "Makefile", tmp_path / "Makefile")  # no .venv here: a fresh clone
    plan = subprocess.run(
        ["make", "-n", target], cwd=tmp_path, capture_output=True, text=True, check=True
    ).stdout.splitlines()
    assert plan[0] == "python3 -m venv .venv"
    assert plan[1] == f'.venv/bin/pip install -q torch==2.13.0 -e ".[{extra}]"'
    assert any(line.startswith((f".venv/bin/{tool}", ".venv/bin/python -m")) for line in plan[2:])
