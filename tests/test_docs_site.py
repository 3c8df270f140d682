"""The documentation site builds with warnings as errors and renders in headless Chromium."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: CI sets this, so a missing browser fails instead of skipping
REQUIRED = os.environ.get("RADIAL_IBVS_REQUIRE_BROWSER") == "1"
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--enable-logging=stderr", "--log-level=0", "--window-size=1200,900",
]  # fmt: skip


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("sphinx")
    out = tmp_path_factory.mktemp("site")
    build = [sys.executable, "-m", "sphinx", "-E", "-W", "--keep-going", "-q", "-b", "html"]
    subprocess.run([*build, str(ROOT / "docs"), str(out)], check=True, cwd=ROOT)
    return out


def _chromium(page: Path, tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    if CHROMIUM is None:
        if REQUIRED:
            pytest.fail("chromium is not installed (.ci/run installs Debian's chromium)")
        pytest.skip("chromium is not installed")
    profile = tmp_path / f"profile-{len(list(tmp_path.iterdir()))}"
    return subprocess.run(
        [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", *args, page.as_uri()],
        capture_output=True, text=True, timeout=120, check=True,
    )  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize(
    ("page", "expected"),
    [("index.html", "Visual servoing of mobile robots"), ("envs/parking.html", "Action Space")],
)
def test_a_page_renders_not_blank_and_without_console_errors(
    site: Path, tmp_path: Path, page: str, expected: str
) -> None:
    from PIL import Image

    dom = _chromium(site / page, tmp_path, "--dump-dom")
    assert expected in dom.stdout
    consoles = [line for line in dom.stderr.splitlines() if ":CONSOLE" in line]
    errors = [line for line in consoles if "Uncaught" in line or "rror" in line]
    assert not errors, errors
    shot = tmp_path / "shot.png"
    _chromium(site / page, tmp_path, f"--screenshot={shot}")
    pixels = np.asarray(Image.open(shot).convert("L"), dtype=np.float64)
    assert pixels.std() > 10.0  # text and figures, not a blank page
