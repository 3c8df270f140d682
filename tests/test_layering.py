"""The maths layers never import the simulation or RL stack (one-way imports)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "radial_ibvs_gym"
#: lower layers first; a layer may import only itself and the layers before it
LAYERS = ("config", "geometry", "camera", "features", "render", "physics", "scenarios")
#: layers that must stay free of the simulation/RL stack (those that exist yet)
MATHS_LAYERS = tuple(name for name in LAYERS[1:] if (PACKAGE / name).is_dir())
FORBIDDEN = ("gymnasium", "pymunk", "stable_baselines3", "torch", "matplotlib", "agents")
#: what each layer may import from the outside world beyond numpy and the standard library
EXTRA_ALLOWED = {"physics": {"pymunk"}, "render": {"cv2"}}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


@pytest.mark.parametrize("layer", MATHS_LAYERS)
def test_maths_layer_imports_only_numpy_and_lower_layers(layer: str) -> None:
    files = sorted((PACKAGE / layer).rglob("*.py"))
    assert files, f"no module found in {layer}"
    for path in files:
        for name in _imports(path):
            top = name.split(".")[0]
            allowed_outside = EXTRA_ALLOWED.get(layer, set())
            assert top not in set(FORBIDDEN) - allowed_outside, f"{path.name} imports {name}"
            if name.startswith("radial_ibvs_gym."):
                sub = name.split(".")[1]
                allowed = {"_validation", *LAYERS[: LAYERS.index(layer) + 1]}
                assert sub in allowed, f"{path.name} imports the higher layer {name}"


def test_only_the_top_layer_imports_the_experiments_and_agents_never_import_it() -> None:
    # envs -> agents -> experiments/CLI: nothing below the experiments imports them
    root = PACKAGE.parent
    below = [*sorted((PACKAGE / "envs").rglob("*.py")), *sorted((root / "agents").rglob("*.py"))]
    for layer in LAYERS:
        below.extend(sorted((PACKAGE / layer).rglob("*.py")))
    for path in below:
        for name in _imports(path):
            assert not name.startswith("radial_ibvs_gym.experiments"), f"{path} imports {name}"
            assert not name.startswith("radial_ibvs_gym.cli"), f"{path} imports {name}"
    for path in sorted((PACKAGE / "envs").rglob("*.py")):
        assert not any(n.split(".")[0] == "agents" for n in _imports(path)), path
