"""Imports flow one way: maths -> simulation -> envs, and ``agents`` -> ``radial_ibvs_gym``.

Inside ``agents`` too: utilities -> rollouts and rows -> analytic -> learned -> the registry ->
experiments -> CLI.

Checked twice: on the source (every ``import`` statement, lazy ones inside functions included,
but not those under ``TYPE_CHECKING``) and in a fresh interpreter (what importing a layer
really loads, transitively).
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "radial_ibvs_gym"
#: lower layers first; a layer may import only itself, the layers before it and the base modules
LAYERS = ("config", "geometry", "camera", "features", "vision", "physics", "scenarios", "envs")
#: single modules every layer may use: validation helpers, the paper's numbers, the env ids
BASE = {"_validation", "limits", "paper", "registration"}
#: what each layer may import from outside the standard library, numpy and yaml
EXTRA_ALLOWED = {
    "vision": {"cv2"},
    "physics": {"pymunk"},
    "envs": {"gymnasium", "pymunk", "cv2", "matplotlib"},
}
HEAVY = ("gymnasium", "pymunk", "cv2", "torch", "matplotlib", "stable_baselines3", "numba")
#: single modules allowed a library of their own: the optional compiled root-find, imported
#: at the first root-find only (camera.meridian_jit)
MODULE_ALLOWED = {"radial_ibvs_gym/camera/_meridian_numba.py": {"numba"}}
#: the maths: importing any of these loads numpy and nothing heavier
MATHS = ("radial_ibvs_gym", "radial_ibvs_gym.config", "radial_ibvs_gym.geometry",
         "radial_ibvs_gym.camera", "radial_ibvs_gym.features")  # fmt: skip


#: the policies' import name, and its folder (the repository's agents/)
AGENTS = "radial_ibvs_agents"
AGENTS_DIR = ROOT / "agents" / AGENTS


def _modules(package: str, base: Path = ROOT) -> dict[str, Path]:
    out = {}
    for path in sorted((base / package).rglob("*.py")):
        parts = list(path.relative_to(base).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = {**_modules("radial_ibvs_gym"), **_modules(AGENTS, ROOT / "agents")}


def _imports(path: Path, *, typing: bool = False) -> set[str]:
    """Every module named by an import in ``path`` (under ``if TYPE_CHECKING:``: if ``typing``)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    typing_only = (
        set()
        if typing
        else {
            id(inner)
            for node in ast.walk(tree)
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
            for inner in ast.walk(node)
        }
    )
    names: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            submodules = {f"{node.module}.{alias.name}" for alias in node.names}
            if submodules <= MODULES.keys():  # "from package import submodule": the submodule
                names.update(submodules)
            else:
                names.add(node.module)
    return names


@pytest.mark.parametrize("layer", LAYERS)
def test_each_layer_imports_only_lower_layers_and_its_allowed_libraries(layer: str) -> None:
    files = sorted((PACKAGE / layer).rglob("*.py"))
    assert files, f"no module found in {layer}"
    allowed_layers = {*BASE, *LAYERS[: LAYERS.index(layer) + 1]}
    forbidden = set(HEAVY) - EXTRA_ALLOWED.get(layer, set())
    for path in files:
        own = MODULE_ALLOWED.get(path.relative_to(ROOT).as_posix(), set())
        for name in _imports(path):
            top = name.split(".")[0]
            assert top not in forbidden - own, f"{path.relative_to(ROOT)} imports {name}"
            assert top != AGENTS, f"{path.relative_to(ROOT)} imports {name}"
            if name.startswith("radial_ibvs_gym."):
                sub = name.split(".")[1]
                assert sub in allowed_layers, f"{path.relative_to(ROOT)} imports {name}"


def test_no_module_of_the_env_package_imports_agents() -> None:
    for module, path in MODULES.items():
        if module.startswith("radial_ibvs_gym"):
            bad = [n for n in _imports(path) if n.split(".")[0] == AGENTS]
            assert not bad, f"{module} imports {bad}"


def test_the_import_graph_has_no_cycle() -> None:
    """No circle, not even through the imports made for type checking only."""
    graph = {m: {n for n in _imports(p, typing=True) if n in MODULES} for m, p in MODULES.items()}
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for target in sorted(graph[module]):
            if state.get(target) == 1:
                cycle = [*path[path.index(target) :], target]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if target not in state:
                visit(target, [*path, target])
        state[module] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])


#: the env package's modules by job, lower first: a module may import only lower ones (and
#: ``missed``, the missed-detection draws, ``viewer``, the renderer, ``autoreset``, the enum of
#: Gymnasium >= 1.1, ``slots``, the landmark slots, and ``noise_blocks``, the noise drawn ahead,
#: below them all)
ENV_JOBS = (
    ("missed", "viewer", "autoreset", "slots", "noise_blocks"),
    ("rules", "observation", "vector_info", "feature_errors", "camera_rows"),
    ("config",),
    ("episodes", "detectors"),
    ("episode_batch",),
    ("parking", "parking_vector"),
    ("parking_goal", "parking_image"),
)


def test_the_env_modules_import_by_job_one_way() -> None:
    rank = {name: k for k, names in enumerate(ENV_JOBS) for name in names}
    found = {m.rsplit(".", 1)[1] for m in MODULES if m.startswith("radial_ibvs_gym.envs.")}
    assert found == set(rank), f"place the env modules {sorted(found ^ set(rank))} in ENV_JOBS"
    for name, k in rank.items():
        for target in _imports(MODULES[f"radial_ibvs_gym.envs.{name}"]):
            if target.startswith("radial_ibvs_gym.envs."):
                other = target.rsplit(".", 1)[1]
                assert rank[other] < k, f"envs.{name} imports envs.{other}"
    # the rules and what is seen load plain numpy: no gymnasium, no simulator at import
    for name in ("rules", "observation"):
        tree = ast.parse(MODULES[f"radial_ibvs_gym.envs.{name}"].read_text())
        top = {
            (alias.name if isinstance(node, ast.Import) else str(node.module)).split(".")[0]
            for node in tree.body
            if isinstance(node, ast.Import | ast.ImportFrom)
            for alias in node.names
        }
        assert not top & {"gymnasium", "pymunk", "cv2"}, (name, top)


#: the rooms of ``agents``, lower first: a module may import only its own room and lower ones
AGENT_ROOMS = (
    "utilities", "rollouts", "analytic", "learned", "policies", "experiments", "bags", "cli",
)  # fmt: skip
#: the loose modules of ``agents``: the shared utilities, the rows of the rollouts (beside
#: them), and on top of both kinds of policy, the registry of every policy by name
AGENT_LOOSE = {
    "radial_ibvs_agents.io": "utilities",
    "radial_ibvs_agents.plotting": "utilities",
    "radial_ibvs_agents.stats": "utilities",
    "radial_ibvs_agents.untrusted": "utilities",
    AGENTS: "policies",
    "radial_ibvs_agents.registry": "policies",
    "radial_ibvs_agents.rows": "rollouts",
}
#: at most this many loose modules in ``agents/`` besides ``__init__.py``
MAX_LOOSE = 6


def _room(module: str) -> str:
    parts = module.split(".")
    if len(parts) > 1 and parts[1] in (
        "rollouts",
        "analytic",
        "learned",
        "experiments",
        "bags",
        "cli",
    ):
        return parts[1]
    if module not in AGENT_LOOSE:
        raise AssertionError(f"{module} is in no room: add it to a room or to AGENT_LOOSE")
    return AGENT_LOOSE[module]


def test_agents_has_few_loose_modules_and_every_module_has_a_room() -> None:
    loose = sorted(p.stem for p in AGENTS_DIR.glob("*.py") if p.stem != "__init__")
    assert len(loose) <= MAX_LOOSE, loose
    for module in MODULES:
        if module.split(".")[0] == AGENTS:
            _room(module)


@pytest.mark.parametrize("room", AGENT_ROOMS)
def test_each_room_of_agents_imports_only_itself_and_lower_rooms(room: str) -> None:
    allowed = set(AGENT_ROOMS[: AGENT_ROOMS.index(room) + 1])
    modules = [m for m in MODULES if m.split(".")[0] == AGENTS and _room(m) == room]
    assert modules, f"no module found in room {room}"
    for module in modules:
        for name in _imports(MODULES[module]):
            if name.split(".")[0] != AGENTS:
                continue
            target = name if name in MODULES else name.rsplit(".", 1)[0]
            assert _room(target) in allowed, f"{module} ({room}) imports {name} ({_room(target)})"


#: the groups of ``radial_ibvs_agents.learned``, lower first: a group imports only itself and lower
#: ones
LEARNED_GROUPS = ("networks", "files", "training", "dagger")


def test_the_groups_of_agents_learned_import_one_way() -> None:
    found = {m.split(".")[2] for m in MODULES if m.startswith("radial_ibvs_agents.learned.")}
    assert found == set(LEARNED_GROUPS), f"group {sorted(found ^ set(LEARNED_GROUPS))}"
    for module, path in MODULES.items():
        if not module.startswith("radial_ibvs_agents.learned."):
            continue
        rank = LEARNED_GROUPS.index(module.split(".")[2])
        for name in _imports(path):
            if name.startswith("radial_ibvs_agents.learned."):
                target = LEARNED_GROUPS.index(name.split(".")[2])
                assert target <= rank, f"{module} imports {name}"


def test_the_analytic_policies_import_no_learning_stack() -> None:
    for module, path in MODULES.items():
        if module.startswith("radial_ibvs_agents.analytic"):
            bad = [n for n in _imports(path) if n.split(".")[0] in ("torch", "stable_baselines3")]
            assert not bad, f"{module} imports {bad}"


def _loaded_after(statement: str) -> list[str]:
    code = (
        f"import json, sys; {statement}; "
        f"print(json.dumps(sorted(m for m in {list(HEAVY)!r} if m in sys.modules)))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT
    )
    return list(json.loads(out.stdout.strip().splitlines()[-1]))


@pytest.mark.parametrize("module", MATHS)
def test_importing_the_maths_loads_nothing_heavier_than_numpy(module: str) -> None:
    assert _loaded_after(f"import {module}") == []


@pytest.mark.parametrize("module", [AGENTS, f"{AGENTS}.analytic", f"{AGENTS}.learned"])
def test_importing_the_policies_loads_no_torch(module: str) -> None:
    loaded = _loaded_after(f"import {module}")
    assert "torch" not in loaded and "stable_baselines3" not in loaded, loaded


def test_importing_the_vision_and_the_physics_loads_no_rl_stack() -> None:
    assert _loaded_after("import radial_ibvs_gym.vision") == ["cv2"]
    assert _loaded_after("import radial_ibvs_gym.physics") == ["pymunk"]


@pytest.mark.parametrize(
    "statement",
    [
        "import radial_ibvs_gym; import gymnasium as gym",
        "import gymnasium as gym; import radial_ibvs_gym",
        "import radial_ibvs_gym.camera; import gymnasium as gym",
        # TorchRL asks whether Gymnasium is installed before it imports it
        "import radial_ibvs_gym, importlib.util; importlib.util.find_spec('gymnasium'); "
        "import gymnasium as gym",
    ],
)
def test_the_envs_are_registered_whichever_is_imported_first(statement: str) -> None:
    code = (
        f"{statement}; from radial_ibvs_gym.registration import ENV_IDS; "
        "assert all(i in gym.registry for i in ENV_IDS); "
        "env = gym.make('RadialIBVS/Parking-v0', physics='kinematic'); env.reset(seed=0); "
        "import importlib.resources; importlib.resources.files('gymnasium'); print('ok')"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT
    )
    assert out.stdout.strip().endswith("ok")


#: the tests' folders: one per package of ``radial_ibvs_gym`` and ``agents``, and the project's
#: own (the docs, the notebooks' helpers, the wheel, the RL clients, the files-are-data tests)
TEST_FOLDERS = {
    *LAYERS,
    *(f"agents/{room}" for room in ("analytic", "learned", "experiments", "cli")),
    "docs",
    "notebooks",
    "packaging",
    "clients",
    "security",
}


def test_the_tests_mirror_the_packages() -> None:
    tests = ROOT / "tests"
    loose = sorted(p.name for p in tests.glob("test_*.py") if p.name != Path(__file__).name)
    assert not loose, f"tests at the top of tests/: {loose}; put each in its package's folder"
    for path in tests.rglob("test_*.py"):
        folder = path.parent.relative_to(tests).as_posix()
        if folder != ".":
            mirrored = folder in TEST_FOLDERS or (
                folder.startswith("agents/")
                and (AGENTS_DIR / folder.removeprefix("agents/") / "__init__.py").is_file()
            )  # a subpackage of agents (tests/agents/learned/training: the tests that train)
            assert mirrored, f"{path.relative_to(ROOT)}: {folder} mirrors no package"
