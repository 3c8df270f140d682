"""The documentation site, built once for every test of tests/docs that reads it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Build the site (warnings as errors) into a temporary folder; return the folder."""
    pytest.importorskip("sphinx")
    out = tmp_path_factory.mktemp("site")
    build = [sys.executable, "-m", "sphinx", "-E", "-W", "--keep-going", "-q", "-b", "html"]
    subprocess.run([*build, str(ROOT / "docs"), str(out)], check=True, cwd=ROOT)
    return out
