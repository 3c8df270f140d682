"""The project's import names: its own, one copy of each module, in the editable install too.

The wheel installs ``radial_ibvs_gym`` and ``radial_ibvs_agents`` (``tests/packaging/
test_wheel.py`` checks its top level). An editable install puts the repository root and
``agents/`` on the path: nothing under a generic name such as ``agents`` is ever imported.
"""

from __future__ import annotations

import json
import subprocess
import sys
from importlib import metadata
from pathlib import Path


def test_the_policies_import_under_their_own_name_once(tmp_path: Path) -> None:
    # every command's modules, imported outside the repository: none under another name
    code = (
        "import json, sys\n"
        "import radial_ibvs_agents, radial_ibvs_agents.cli\n"
        "from radial_ibvs_agents.experiments import benchmark, evaluate, reproduce\n"
        "from radial_ibvs_agents.learned.files import loading, model_files\n"
        "from radial_ibvs_agents.learned.training import train\n"
        "from radial_ibvs_agents.learned.dagger import distill\n"
        "print(json.dumps({m: getattr(v, '__file__', None) for m, v in sys.modules.items()}))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=tmp_path
    )
    loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert not [m for m in loaded if m == "agents" or m.startswith("agents.")]
    ours = {m: f for m, f in loaded.items() if m.split(".")[0] == "radial_ibvs_agents" and f}
    assert "radial_ibvs_agents.learned.dagger.distill" in ours
    assert len(set(ours.values())) == len(ours)  # one module per file: no second copy


def test_the_console_script_runs_the_projects_own_package() -> None:
    (script,) = [
        e for e in metadata.entry_points(group="console_scripts") if e.name == "radial-ibvs"
    ]
    assert script.value == "radial_ibvs_agents.cli:main"
    assert callable(script.load())
