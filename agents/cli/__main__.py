"""``python -m agents.cli``: the same as the ``radial-ibvs`` command."""

import sys

from agents.cli import main

sys.exit(main())
