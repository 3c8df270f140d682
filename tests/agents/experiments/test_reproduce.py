"""``radial-ibvs reproduce``: the paper's Section 4.1 as files (table, CSV, JSON, figures)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments import CASES, ROBUSTNESS_CASES, reproduce
from radial_ibvs_agents.experiments.figures import servoing_signals
from radial_ibvs_agents.io import write_atomic

CONTRACT_KEYS = {
    "policy",
    "scenario",
    "suite",
    "task",
    "seed",
    "physics",
    "success",
    "final_position_error_m",
    "final_heading_error_deg",
    "steps",
    "time_s",
    "path_length_m",
    "collision",
    "compute_us_per_step",
}


def test_reproduce_writes_the_table_csv_json_and_figures(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, rows_path = tmp_path / "rep", tmp_path / "rows.json"
    argv = ["reproduce", "paper-sim", "--physics", "kinematic", "--tasks", "1", "--out", str(out)]
    assert main([*argv, "--json", str(rows_path), "--no-robustness"]) == 0
    assert "| kinematic | 90 | ibvs | yes |" in capsys.readouterr().out
    rows = json.loads(rows_path.read_text())
    assert [r["policy"] for r in rows] == ["ibvs", "oracle", "ibvs-d1.3"]
    for row in rows:
        assert CONTRACT_KEYS <= set(row)
        assert row["success"] and not row["collision"] and row["scenario"] == "paper-sim"
        assert row["final_position_error_m"] <= 0.01 and row["final_heading_error_deg"] <= 0.5
    assert json.loads((out / "results.json").read_text()) == rows
    with (out / "trajectories.csv").open() as handle:
        table = list(csv.DictReader(handle))
    assert list(table[0]) == ["policy", "task", "physics", "t", "x", "y", "yaw"]
    assert len(table) == sum(r["steps"] + 1 for r in rows)
    first = table[0]
    assert (first["policy"], first["task"], float(first["x"]), float(first["y"])) == (
        "ibvs",
        "1",
        3.0,
        3.0,
    )
    for name in ("fig3-paths-kinematic.png", "fig4-depth-scale-kinematic.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    assert (out / "fig6-8-servoing-task1.png").exists()
    assert not list(out.glob(".*.tmp"))  # atomic writes leave nothing behind
    assert (out / "table.md").stat().st_mode & 0o044  # readable by others, like any new file


def test_reproduce_rejects_a_bad_task_with_a_message(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["reproduce", "--tasks", "9", "--no-figures"]) == 2
    assert "task(s) [9] out of range" in capsys.readouterr().err


def test_goal_image_through_mirror_b_changes_nothing_the_radial_model_is_mirror_free() -> None:
    # x_n depends only on the bearing of each point (eq. 9), not on the mirror: the paper's
    # mirror-swap test, exact here although the goal pixels differ
    swap = [c for c in ROBUSTNESS_CASES if c.label == "ibvs-goal-mirror-B"]
    (swapped,) = reproduce(physics=("kinematic",), tasks=[1], cases=swap, progress=False)
    (reference,) = reproduce(physics=("kinematic",), tasks=[1], cases=CASES[:1], progress=False)
    np.testing.assert_allclose(swapped.poses, reference.poses, atol=1e-9)
    assert not np.allclose(swapped.extra["goal_pixels"], reference.extra["goal_pixels"])


def test_servoing_signals_vanish_at_the_end_of_a_parking() -> None:
    (log,) = reproduce(physics=("kinematic",), tasks=[2], cases=CASES[:1], progress=False)
    s = servoing_signals(log)
    assert np.abs(s["pixel_error"][-1]).max() < 1.0  # pixels
    assert np.abs(s["c_error"][-1]).max() < 0.01 * np.abs(s["c_error"][0]).max()
    assert abs(s["alpha_m_error"][-1]) < np.radians(0.5)
    assert np.abs(s["camera_velocity"][0]).max() > 0.1
    assert np.abs(s["camera_velocity"][-1]).max() < 0.01


def test_write_atomic_keeps_the_old_file_when_writing_fails(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = write_atomic(tmp_path / "a.txt", "old")

    def disk_full(*args: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr("os.replace", disk_full)
    with pytest.raises(OSError, match="disk full"):
        write_atomic(target, "new")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_the_default_output_folder_is_named_after_the_scenario(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    argv = ["reproduce", "paper-sim", "--physics", "kinematic", "--tasks", "1"]
    assert main([*argv, "--no-figures", "--no-robustness"]) == 0
    assert (tmp_path / "outputs" / "reproduce" / "paper-sim" / "table.md").is_file()
    assert not (tmp_path / "outputs" / "reproduce" / "table.md").exists()
