"""pytest set-up shared by the tests and the notebooks (executed by nbmake).

The notebooks read ``RADIAL_IBVS_FAST``: under pytest they run in their fast mode (fewer
episodes, shorter training) unless the caller sets ``RADIAL_IBVS_FAST=0``. Opened in Jupyter,
they run in full.
"""

import os

os.environ.setdefault("RADIAL_IBVS_FAST", "1")
os.environ.setdefault("MPLBACKEND", "Agg")
