"""radial-ibvs report: the tables and curves it writes from benchmark rows."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments.tables import results_table, seeds_table
from radial_ibvs_agents.rows import load_rows
from radial_ibvs_agents.stats import iqm_interval


def _row(policy: str, suite: str, variant: str, success: bool, end: str, seed: int) -> dict:
    tolerances = {"2cm/2deg": success, "10cm/5deg": True, "30cm/15deg": True}
    return {
        "final_position_error_m": 0.01 if success else 0.05 + 0.01 * seed,
        "final_heading_error_deg": 1.0 if success else 3.0,
        "collision": end == "collision",
        "policy": policy,
        "suite": suite,
        "variant": variant,
        "success": success,
        "end": "success" if success else end,
        "seed": seed,
        "success_by_tolerance": tolerances,
    }


def _rows() -> list[dict]:
    rows = []
    for seed in range(20):
        rows.append(_row("ibvs", "held-out", "random", seed < 15, "time-out", seed))
        rows.append(_row("planner", "held-out", "random", True, "success", seed))
        rows.append(_row("a-s0", "held-out", "random", seed < 10, "collision", seed))
        rows.append(_row("a-s1", "held-out", "random", seed < 12, "lost", seed))
    for seed in range(4):
        rows.append(_row("ibvs", "paper", "task 0", seed != 2, "time-out", seed))
        rows.append(_row("a-s0", "paper", "task 0", True, "success", seed))
        rows.append(_row("a-s1", "paper", "task 0", seed < 2, "lost", seed))
    return rows


def test_the_table_counts_successes_and_ends_per_policy():
    table = results_table(_rows(), suites=["held-out", "paper"])
    lines = table.splitlines()
    assert lines[0].startswith("| suite: variant | episodes | `planner` | `ibvs` |")  # limit 1st
    held_out = next(line for line in lines if line.startswith("| held-out: random | 20 |"))
    cells = [c.strip() for c in held_out.split("|")[3:-1]]
    assert cells[0].startswith("100 (") and cells[1].startswith("75 (")  # Wilson intervals
    paper = next(line for line in lines if line.startswith("| paper: task 0 | 4 |"))
    assert [c.strip() for c in paper.split("|")[3:-1]][:2] == ["-", "75"]  # 4 episodes: no CI
    ends = next(line for line in lines if line.startswith("| held-out: random | |"))
    assert "0 / 5 / 0" in ends and "10 / 0 / 0" in ends  # ibvs's time-outs, a-s0's collisions


def test_the_table_takes_an_order_and_renames():
    table = results_table(_rows(), policies=["mine", "ibvs"], renames={"a-s0": "mine"})
    assert table.splitlines()[0] == "| suite: variant | episodes | `mine` | `ibvs` |"


def test_the_seeds_table_is_rliables_iqm():
    text = seeds_table(_rows(), {"a": ["a-s0", "a-s1"]})
    point, low, high = iqm_interval([[0.5, 0.6], [1.0, 0.5]])
    last = text.splitlines()[-1]
    assert last == f"| all | stratified over 2 variants | | {point:.0%} | {low:.0%}-{high:.0%} |"
    with pytest.raises(ValueError, match="no rows for policy 'nope'"):
        seeds_table(_rows(), {"b": ["nope"]})
    with pytest.raises(ValueError, match="unknown tolerance"):
        seeds_table(_rows(), {"a": ["a-s0"]}, tolerance="1cm")


def test_bad_rows_are_named(tmp_path: Path):
    bad = tmp_path / "rows.json"
    bad.write_text('{"policy": 1}')
    with pytest.raises(ValueError, match=r"rows\.json: expected a JSON list"):
        load_rows([bad])
    bad.write_text('[{"policy": "x"}]')
    with pytest.raises(ValueError, match=r"rows.json: row 0 has no \['suite'"):
        load_rows([bad])
    with pytest.raises(ValueError, match="no such file"):
        load_rows([tmp_path / "missing.json"])


def test_rows_judged_differently_are_not_merged(tmp_path: Path, capsys):
    plain, held = tmp_path / "plain.json", tmp_path / "held.json"
    plain.write_text(json.dumps(_rows()))  # rows without the key were judged at 1 step
    held.write_text(json.dumps([{**r, "success_hold_steps": 10} for r in _rows()]))
    with pytest.raises(ValueError, match=r"success_hold_steps 1 in .*plain\.json, 10 in .*held"):
        load_rows([plain, held])
    assert len(load_rows([held, held])) == 2 * len(_rows())
    assert main(["report", str(held)]) == 0
    assert "a park: the pose within 2 cm and 2 deg of the goal, held 10 steps in a row (1 s)" in (
        capsys.readouterr().out
    )
    assert main(["report", str(plain)]) == 0
    assert "a pass: the first step within 2 cm and 2 deg" in capsys.readouterr().out


def test_the_command_writes_the_report_and_curves(tmp_path: Path, capsys):
    rows = tmp_path / "episodes.json"
    rows.write_text(json.dumps(_rows()))
    run = tmp_path / "run"
    run.mkdir()
    (run / "progress.csv").write_text("round,env_steps,success_rate\n0,100,0.4\n1,200,0.8\n")
    (run / "metadata.json").write_text('{"best_round": 1}')
    out = tmp_path / "report"
    code = main(
        [
            "report", str(rows), "--seeds", "a=a-s0,a-s1", "--curves", f"one={run}",
            "--out", str(out),
        ]
    )  # fmt: skip
    assert code == 0
    text = (out / "report.md").read_text()
    assert "| held-out: random | 20 |" in text and "## Across training seeds" in text
    assert "one: 40% 80%" in text
    assert (out / "dagger-curves.png").stat().st_size > 1000
    for figure in ("heatmap.png", "success-curves.png"):
        assert (out / figure).stat().st_size > 1000 and f"]({figure})" in text
    pandas = pytest.importorskip("pandas")
    table = pandas.read_csv(out / "success.csv")
    ibvs = table[(table.policy == "ibvs") & (table.variant == "random")].iloc[0]
    assert (ibvs.episodes, ibvs.successes, ibvs.success_rate) == (20, 15, 0.75)
    assert len(table) == 7  # 4 policies on held-out, 3 on the paper's task
    assert main(["report", str(rows), "--seeds", "oops"]) == 2
    assert "--seeds takes NAME=VALUE" in capsys.readouterr().err


def test_into_regenerates_the_marked_block_and_keeps_the_rest(tmp_path: Path) -> None:
    rows = tmp_path / "episodes.json"
    rows.write_text(json.dumps(_rows()))
    page = tmp_path / "README.md"
    page.write_text("# Title\n\n<!-- results:start -->\nSTALE\n<!-- results:end -->\n\nafter\n")
    argv = ["report", str(rows), "--policies", "planner", "ibvs", "--into", str(page)]
    argv += [
        "--variants",
        "paper: task 0",
        "held-out: random",
        "--heatmap",
        str(tmp_path / "h.png"),
    ]
    assert main(argv) == 0
    text = page.read_text()
    assert text.startswith("# Title\n\n<!-- results:start -->\n") and text.endswith("after\n")
    assert "STALE" not in text and "| held-out: random | 20 | 100 (84-100) | 75 (53-89) |" in text
    assert text.index("paper: task 0") < text.index("held-out: random")  # the order given
    assert "how episodes ended" not in text
    assert f"by `radial-ibvs report {rows}" in text  # the command that regenerates it
    assert (tmp_path / "h.png").stat().st_size > 0
    page.write_text("no markers\n")
    assert main(["report", str(rows), "--into", str(page)]) == 2
    page.write_text("a\n<!-- held:start -->\n<!-- held:end -->\nb\n")
    assert main(["report", str(rows), "--into", str(page), "--block", "held"]) == 0
    assert "| held-out: random | 20 |" in page.read_text()
    assert main(["report", str(rows), "--into", str(page), "--block", "a b"]) == 2


def test_success_curves_count_the_episodes_within_each_tolerance():
    from radial_ibvs_agents.experiments.benchmark_plots import success_curve

    rows = [
        {"final_position_error_m": 0.01, "collision": False},
        {"final_position_error_m": 0.03, "collision": False},
        {"final_position_error_m": 0.001, "collision": True},  # hit something: never parked
        {"final_position_error_m": 0.5, "collision": False},
    ]
    curve = success_curve(rows, "final_position_error_m", np.array([0.005, 0.02, 0.1, 1.0]))
    np.testing.assert_array_equal(curve, [0.0, 0.25, 0.5, 0.75])
    assert np.isnan(success_curve([], "final_position_error_m", np.array([0.1]))).all()


def test_baselines_add_both_limits_the_classical_policies_and_the_student():
    from radial_ibvs_agents.cli.benchmark import BASELINES, policies_to_run

    default = ["ibvs", "planner", "planner-image-goal", "random"]
    assert policies_to_run(["./mine"], True, default, True) == ["./mine", *BASELINES]
    assert policies_to_run(["./mine", "ibvs"], True, default, True).count("ibvs") == 1
    assert policies_to_run(None, False, default, True) == default
    without = policies_to_run(["./mine"], True, default, False)
    assert "planner" not in without and "pbvs-ekf" in without
    assert policies_to_run(None, False, default, False) == ["ibvs", "random"]
    assert policies_to_run(["planner"], False, default, False) == ["planner"]  # named: kept
