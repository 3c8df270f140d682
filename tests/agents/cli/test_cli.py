from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments.demo import invariance_error
from radial_ibvs_gym import paper
from radial_ibvs_gym.camera import paper_camera
from radial_ibvs_gym.geometry import world_to_camera


def test_help_lists_demo(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert "demo" in capsys.readouterr().out


def test_demo_saves_a_png_and_reports_the_invariance(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sub" / "demo.png"
    assert main(["demo", "--out", str(out), "--task", "2"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    episode = out.with_name("demo-episode.png")
    assert episode.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = capsys.readouterr().out
    assert "the paper's IBVS, paper-sim task 2: parked" in text
    assert "mirror A" in text and "mirror B" in text
    assert "8/8 points visible" in text


def test_demo_rejects_an_unknown_task() -> None:
    with pytest.raises(SystemExit) as exc:
        main(["demo", "--task", "7"])
    assert exc.value.code == 2


@pytest.mark.parametrize("mirror", ["A", "B"])
@pytest.mark.parametrize("task", [0, 1, 2, 3])
def test_eq39_points_visible_and_radial_at_start_and_goals(mirror: str, task: int) -> None:
    camera = paper_camera(mirror, non_central_offset=0.01)
    for pose in (paper.START_POSE, paper.goal_pose(task)):
        p_cam = world_to_camera(paper.EQ39_POINTS, pose, paper.CAMERA_HEIGHT_M)
        assert np.all(camera.visible(p_cam))
        assert invariance_error(camera, p_cam) < 1e-9


def test_help_texts_print_percent_signs_once_and_the_version_is_there(capsys) -> None:
    from radial_ibvs_agents.cli import COMMANDS
    from radial_ibvs_gym import __version__

    for command in COMMANDS:
        with pytest.raises(SystemExit):
            main([command, "--help"])
        out = capsys.readouterr().out
        assert "%%" not in out, command
    with pytest.raises(SystemExit):
        main(["--version"])
    assert capsys.readouterr().out.strip() == f"radial-ibvs {__version__}"


@pytest.mark.parametrize("command", ["evaluate", "benchmark", "render", "collect"])
def test_help_lists_every_policy_and_the_extra_each_needs(
    command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from radial_ibvs_agents.analytic.registry import DESCRIPTIONS, EXTRAS
    from radial_ibvs_agents.experiments.suites import SUITES
    from radial_ibvs_agents.learned import shipped_models
    from radial_ibvs_agents.registry import POLICY_NAMES

    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = capsys.readouterr().out
    listed = [line.split()[0] for line in text.splitlines() if line.startswith("  ")]
    for name in [*POLICY_NAMES, *shipped_models()]:
        assert name in listed, name
    assert set(DESCRIPTIONS) <= set(POLICY_NAMES)  # every description names a policy
    for name, extra in EXTRAS.items():
        assert any(
            line.split()[0] == name and f"[extra: {extra}]" in line
            for line in text.splitlines()
            if line.startswith("  ")
        ), name
    if command == "benchmark":
        assert all(suite in listed for suite in SUITES)


def test_evaluate_judges_as_the_benchmark_whatever_hold_a_model_trained_with(
    tmp_path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``evaluate`` judges by the park rule (1 s) unless told, whatever a model trained with."""
    import json

    from held_model import model_trained_with_hold

    from radial_ibvs_agents.cli import main
    from radial_ibvs_agents.learned import load

    model = model_trained_with_hold(tmp_path, 3)
    assert load(model).env_kwargs["success_hold_steps"] == 3  # what its training asked
    rows = tmp_path / "rows.json"
    base = ["evaluate", "--policy", str(model), "--scenario", "random", "--episodes", "2"]
    assert main([*base, "--json", str(rows)]) == 0
    assert {r["success_hold_steps"] for r in json.loads(rows.read_text())} == {10}
    assert "success held 10 steps" in capsys.readouterr().out
    assert main([*base, "--json", str(rows), "--env-kwarg", "success_hold_steps=1"]) == 0
    assert {r["success_hold_steps"] for r in json.loads(rows.read_text())} == {1}
    assert "held" not in capsys.readouterr().out
