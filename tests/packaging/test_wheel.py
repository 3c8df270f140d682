"""The release: an sdist and a wheel that pass twine and check-wheel-contents, and a wheel that
runs the demo and a shipped model once installed in a fresh venv outside the source tree."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def dist(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("build")
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "build", "-q", "--outdir", str(out), str(ROOT)],
                   check=True, capture_output=True)  # fmt: skip
    return out


@pytest.mark.slow
def test_the_sdist_and_wheel_pass_the_release_checks(dist: Path) -> None:
    files = sorted(dist.iterdir())
    assert {p.suffix for p in files} == {".gz", ".whl"}
    subprocess.run([sys.executable, "-m", "twine", "check", "--strict", *map(str, files)],
                   check=True, capture_output=True)  # fmt: skip
    wheel = next(p for p in files if p.suffix == ".whl")
    checker = Path(sys.executable).with_name("check-wheel-contents")
    subprocess.run([str(checker), str(wheel)], check=True, capture_output=True, cwd=ROOT)
    names = zipfile.ZipFile(wheel).namelist()
    for expected in (
        "radial_ibvs_gym/_configs/scenarios/paper-sim.yaml",
        "radial_ibvs_agents/learned/models/dagger-student/policy.safetensors",
        "radial_ibvs_agents/learned/models/dagger-student/policy.json",
        "radial_ibvs_gym/py.typed",
        "radial_ibvs_agents/bags/foxglove_layout.json",
    ):
        assert expected in names, expected
    assert any(n.endswith("licenses/LICENSE") for n in names)
    # two import names, both the project's own: nothing generic at the top of site-packages
    tops = {n.split("/")[0] for n in names if ".dist-info/" not in n}
    assert tops == {"radial_ibvs_gym", "radial_ibvs_agents"}, tops


@pytest.mark.slow
def test_the_installed_wheel_runs_the_demo_and_a_shipped_model(dist: Path, tmp_path: Path) -> None:
    wheel = next(dist.glob("*.whl"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    pip = [str(venv / "bin" / "python"), "-m", "pip", "install", "-q"]
    subprocess.run([*pip, "torch==2.13.0", str(wheel)], check=True, capture_output=True)
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": ""}
    run = [str(venv / "bin" / "radial-ibvs")]
    work = tmp_path / "elsewhere"  # outside the source tree: nothing is read from it
    work.mkdir()
    subprocess.run([*run, "demo"], check=True, cwd=work, env=env, capture_output=True)
    assert (work / "outputs" / "demo.png").is_file()
    argv = [*run, "evaluate", "--policy", "dagger-student", "--scenario", "paper-lab"]
    out = subprocess.run(
        [*argv, "--episodes", "2"], check=True, cwd=work, env=env, capture_output=True, text=True
    )
    assert "dagger-student on paper-lab" in out.stdout and "2 episodes" in out.stdout


@pytest.mark.slow
def test_the_wheel_and_openai_agents_install_side_by_side(dist: Path, tmp_path: Path) -> None:
    # OpenAI's Agents SDK installs the import name `agents`: this project no longer does
    wheel = next(dist.glob("*.whl"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    pip = [str(venv / "bin" / "python"), "-m", "pip", "install", "-q"]
    subprocess.run(
        [*pip, "torch==2.13.0", str(wheel), "openai-agents"], check=True, capture_output=True
    )
    code = (
        "import agents, radial_ibvs_agents, radial_ibvs_gym\n"
        "assert hasattr(agents, 'Agent') and hasattr(agents, 'Runner'), agents.__file__\n"
        "assert radial_ibvs_agents.make_policy('ibvs').env_kwargs\n"
        "print(agents.__file__)\n"
    )
    env = {**os.environ, "PYTHONPATH": ""}
    out = subprocess.run(
        [str(venv / "bin" / "python"), "-c", code],
        check=True,
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
    )
    assert "site-packages/agents/__init__.py" in out.stdout
