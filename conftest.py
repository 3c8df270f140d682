"""pytest set-up shared by the tests and the notebooks (executed by nbmake).

The notebooks read ``RADIAL_IBVS_FAST``: under pytest they run in their fast mode (fewer
episodes, shorter training) unless the caller sets ``RADIAL_IBVS_FAST=0``. Opened in Jupyter,
they run in full.
"""

import os
import sys
from pathlib import Path

os.environ.setdefault("RADIAL_IBVS_FAST", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

# the notebooks' helpers (notebooks/_helpers) are imported as ``_helpers``, as the notebooks do
sys.path.insert(0, str(Path(__file__).resolve().parent / "notebooks"))
