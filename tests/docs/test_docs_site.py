"""The documentation site builds with warnings as errors and renders in headless Chromium."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: CI sets this, so a missing browser fails instead of skipping
REQUIRED = os.environ.get("RADIAL_IBVS_REQUIRE_BROWSER") == "1"
FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--enable-logging=stderr", "--log-level=0", "--window-size=1200,900",
]  # fmt: skip


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


#: a script appended to a copy of a page: once loaded, it lists the images that did not load
#: (zero natural size) in the DOM, where --dump-dom shows it
_CHECK_IMAGES = """<script>
window.addEventListener("load", () => {
  const images = Array.from(document.images);
  const broken = images.filter((im) => !(im.complete && im.naturalWidth > 0));
  const out = document.createElement("pre");
  out.id = "image-check";
  out.textContent = `images ${images.length} broken ${broken.map((im) => im.src).join(" ")}`;
  document.body.appendChild(out);
});
</script>"""


@pytest.mark.slow
@pytest.mark.parametrize(
    ("page", "expected", "min_images"),
    [
        ("index.html", "Park a wheeled robot", 1),
        ("envs/parking.html", "Action Space", 1),
        ("results.html", "Every policy on the same seeded episodes", 1),
        ("notebooks/04_ibvs_vs_ppo.html", "IBVS", 1),
    ],
)
def test_a_page_renders_with_its_images_and_without_console_errors(
    site: Path, tmp_path: Path, page: str, expected: str, min_images: int
) -> None:
    from PIL import Image

    checked = (site / page).with_name(f"_check_{(site / page).name}")
    checked.write_text((site / page).read_text().replace("</body>", f"{_CHECK_IMAGES}</body>"))
    dom = _chromium(checked, tmp_path, "--virtual-time-budget=10000", "--dump-dom")
    assert expected in dom.stdout
    report = dom.stdout.split('<pre id="image-check">')[1].split("</pre>")[0].split()
    assert int(report[1]) >= min_images, report
    assert report[2:] == ["broken"], f"images that did not load: {report[3:]}"
    assert ":CONSOLE" not in "".join(
        line for line in dom.stderr.splitlines() if "Uncaught" in line or "rror" in line
    ), dom.stderr[-2000:]
    shot = tmp_path / "shot.png"
    _chromium(site / page, tmp_path, f"--screenshot={shot}")
    pixels = np.asarray(Image.open(shot).convert("L"), dtype=np.float64)
    assert pixels.std() > 10.0  # text and figures, not a blank page


@pytest.mark.slow
def test_no_page_shows_raw_roles_or_raw_tables(site: Path) -> None:
    """MyST renders `{class}` roles and tables; a raw `:class:` or `|---|` is a bug (Sphinx
    writes `---` as an em dash, `|—|`; ``test_site_tables.py`` scans for whole pipe tables)."""
    import re

    bad = {}
    for page in site.rglob("*.html"):
        if page.name.startswith("_check_") or "_modules" in page.parts:
            continue
        text = re.sub(r"<(script|style|pre)[^>]*>.*?</\1>", "", page.read_text(), flags=re.S)
        text = re.sub(r"<[^>]+>", "", text)
        roles = r":(?:class|mod|func|meth|attr|data|exc):(?=\S)"
        found = re.findall(roles + r"|\|(?:---|\u2014|\u2013)\|", text)
        if found:
            bad[str(page.relative_to(site))] = found[:3]
    assert not bad, bad
