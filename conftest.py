"""pytest set-up shared by the tests and the notebooks (executed by nbmake).

The notebooks read ``RADIAL_IBVS_FAST``: under pytest they run in their fast mode (fewer
episodes, shorter training) unless the caller sets ``RADIAL_IBVS_FAST=0``. Opened in Jupyter,
they run in full.

Hypothesis runs derandomised by default (profile ``ci``): every run, here and in CI, draws the
same examples, so a fresh clone never fails on a draw nobody has seen. ``make test-random`` (the
profile ``random``, ``HYPOTHESIS_PROFILE=random``) draws new examples, many more of them, to hunt
for failures; a failing draw it finds is pinned with ``@example`` before it is fixed.
"""

import os
import sys
from pathlib import Path

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("random", derandomize=False, max_examples=1000, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

os.environ.setdefault("RADIAL_IBVS_FAST", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

# the notebooks' helpers (notebooks/_helpers) are imported as ``_helpers``, as the notebooks do
sys.path.insert(0, str(Path(__file__).resolve().parent / "notebooks"))
# the tests' shared helpers (tests/_support, e.g. ``bearing_scenes``), last on the path
sys.path.append(str(Path(__file__).resolve().parent / "tests" / "_support"))


def pytest_configure(config):
    """Execute the notebooks (nbmake's ``--nbmake``) wherever nbmake is installed.

    The light test install (the ``test`` extra) has no Jupyter: the notebooks, slow tests, are
    then not collected. ``RADIAL_IBVS_REQUIRE_NOTEBOOKS=1`` (CI) makes that an error instead.
    """
    import pytest

    if config.pluginmanager.hasplugin("nbmake"):
        config.option.nbmake = True
    elif os.environ.get("RADIAL_IBVS_REQUIRE_NOTEBOOKS") == "1":
        raise pytest.UsageError(
            "RADIAL_IBVS_REQUIRE_NOTEBOOKS=1 but nbmake is not installed: pip install -e '.[dev]'"
        )


def pytest_collection_modifyitems(config, items):
    """Mark every notebook ``slow``: each executes from top to bottom (seconds to a minute)."""
    import pytest

    for item in items:
        if str(item.path).endswith(".ipynb"):
            item.add_marker(pytest.mark.slow)
