"""``python -m radial_ibvs_agents.cli``: the same as the ``radial-ibvs`` command."""

import sys

from radial_ibvs_agents.cli import main

sys.exit(main())
