"""``radial-ibvs benchmark``: suites, rows, summaries, outputs, bad input."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments.benchmark import run_benchmark, summary_rows
from radial_ibvs_agents.experiments.suites import SUITES, suite_variants
from radial_ibvs_agents.rows import RUN_FIELDS, wilson_interval


def test_every_suite_of_the_issue_exists_with_its_variants() -> None:
    assert set(SUITES) == {
        "paper",
        "random",
        "noise",
        "calibration",
        "mirror-swap",
        "physics",
        "pixels",
        "held-out",
        "unseen-scenes",
        "paper-lab",
        "cross-camera",
        "obstacles",
        "imperfect",
    }
    imperfect = SUITES["imperfect"]
    assert [v.label for v in imperfect] == [
        "noise 1 px", "pp (2, -1) px, fy +1 %", "all together", "drawn per episode",
        "all together, goal over 30 frames",
    ]  # fmt: skip
    assert all(v.scenario == "random" and v.seed_offset == 100_000 for v in imperfect)
    assert "imperfection_ranges" in imperfect[3].overrides["camera"]
    assert imperfect[4].overrides["goal_image_frames"] == 30
    assert imperfect[4].overrides["camera"] == imperfect[2].overrides["camera"]
    unseen = SUITES["unseen-scenes"]
    assert all(v.scenario == "random-unseen" and v.seed_offset == 100_000 for v in unseen)
    assert [v.episodes for v in unseen] == [200, 200, 200]
    assert "camera" not in unseen[0].overrides
    assert unseen[1].overrides["camera"] == unseen[2].overrides["camera"]
    assert unseen[1].overrides["camera"] == imperfect[2].overrides["camera"]
    assert unseen[2].overrides["goal_image_frames"] == 30
    measured = {v.overrides.get("measurement", "ideal") for v in SUITES["pixels"]}
    assert measured == {"ideal", "detected"}
    assert [v.label for v in SUITES["noise"]] == ["0.0 px", "0.5 px", "1.0 px", "2.0 px"]
    assert SUITES["random"][0].episodes >= 200
    assert {v.overrides["physics"] for v in SUITES["physics"]} == {"kinematic", "pymunk"}


def test_benchmark_rows_follow_the_contract_and_summaries_count_them() -> None:
    results = run_benchmark(
        ["ibvs", "random"], ["paper", "mirror-swap"], episodes=4, progress=False
    )
    assert len(results) == 2 * (2 + 2)  # policies x variants
    rows = [row for result in results for row in result.rows]
    assert len(rows) == 2 * 4 * 4
    for row in rows:
        assert {
            "policy",
            "scenario",
            "suite",
            "variant",
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
            "control_effort",
            "smoothness",
        } <= set(row)
    ibvs = [r for r in rows if r["policy"] == "ibvs"]
    assert all(r["success"] for r in ibvs)  # the paper's tasks, exact and 1.3 d*, mirror swap
    assert sorted({r["task"] for r in ibvs}) == [0, 1, 2, 3]
    summaries = summary_rows(results)
    paper_ibvs = next(s for s in summaries if s["policy"] == "ibvs" and s["variant"] == "d*")
    assert paper_ibvs["episodes"] == 4 and paper_ibvs["success_rate"] == 1.0
    assert paper_ibvs["success_ci95"] == pytest.approx(wilson_interval(4, 4))
    random = next(s for s in summaries if s["policy"] == "random" and s["variant"] == "d*")
    assert random["success_rate"] == 0.0 and random["smoothness"] > 0.3


@pytest.mark.slow
def test_parallel_workers_give_the_same_rows_as_one_process() -> None:
    kwargs = {"episodes": 2, "progress": False}
    one = run_benchmark(["ibvs", "oracle"], ["physics"], workers=1, **kwargs)
    two = run_benchmark(["ibvs", "oracle"], ["physics"], workers=2, **kwargs)
    strip = RUN_FIELDS
    for a, b in zip(one, two, strict=True):
        assert [{k: v for k, v in r.items() if k not in strip} for r in a.rows] == [
            {k: v for k, v in r.items() if k not in strip} for r in b.rows
        ]


def test_cli_writes_the_table_csv_json_and_plots(tmp_path: Path) -> None:
    out, rows_path = tmp_path / "bench", tmp_path / "rows.json"
    argv = ["benchmark", "--suites", "paper", "random", "--policies", "ibvs", "oracle"]
    argv += ["--episodes", "4", "--workers", "1", "--out", str(out), "--json", str(rows_path)]
    assert main([*argv, "--no-progress"]) == 0
    rows = json.loads(rows_path.read_text())
    assert len(rows) == 2 * (2 + 1) * 4
    with (out / "episodes.csv").open() as handle:
        assert len(list(csv.DictReader(handle))) == len(rows)
    summary = (out / "summary.md").read_text()
    assert "| paper | 1.3 d* | kinematic | ibvs | 100% |" in summary
    for name in ("success_by_suite.png", "convergence_map.png", "trajectories.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG", name


def test_unknown_suites_and_policies_fail_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(ValueError, match="unknown suite"):
        suite_variants(["paper", "moon"])
    out = tmp_path / "nothing"
    assert main(["benchmark", "--policies", "ibvs", "ppo-moon", "--out", str(out)]) == 2
    assert "unknown policy 'ppo-moon'" in capsys.readouterr().err
    assert not out.exists()  # nothing written half-way
    assert main(["benchmark", "--suites", "moon", "--out", str(out)]) == 2
    assert not out.exists()


def test_wilson_interval_is_sound_at_the_extremes() -> None:
    lo, hi = wilson_interval(0, 10)
    assert lo == 0.0 and 0.25 < hi < 0.35
    lo, hi = wilson_interval(10, 10)
    assert 0.65 < lo < 0.75 and hi == 1.0
    lo, hi = wilson_interval(50, 100)
    assert lo == pytest.approx(0.404, abs=1e-3) and hi == pytest.approx(0.596, abs=1e-3)


def test_render_saves_an_animated_gif(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from PIL import Image

    out = tmp_path / "ibvs.gif"
    argv = ["render", "--policy", "ibvs", "--task", "1", "--out", str(out), "--max-steps", "5"]
    assert main(argv) == 0
    with Image.open(out) as gif:
        assert gif.n_frames >= 6 and gif.size == (640, 320)
    assert "saved" in capsys.readouterr().out


def test_render_rejects_bad_formats_before_running(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    assert main(["render", "--policy", "ibvs", "--out", str(tmp_path / "a.avi")]) == 2
    assert ".gif or .mp4" in capsys.readouterr().err
    monkeypatch.setattr("shutil.which", lambda name: None)
    assert main(["render", "--policy", "ibvs", "--out", str(tmp_path / "a.mp4")]) == 2
    assert "ffmpeg" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


@pytest.mark.slow
def test_long_variants_are_split_into_chunks_and_merged_back_in_seed_order(monkeypatch) -> None:
    from radial_ibvs_agents.experiments import benchmark

    monkeypatch.setattr(benchmark, "CHUNK", 3)
    results = run_benchmark(["random"], ["mirror-swap"], episodes=7, workers=2, progress=False)
    assert [(r.job.variant.label, r.job.episodes) for r in results] == [
        ("goal mirror A", 7),
        ("goal mirror B", 7),
    ]
    for result in results:
        assert [row["seed"] for row in result.rows] == list(range(7))
        assert [task for task, _ in result.paths] == [0, 1, 2, 3]


def test_the_costliest_jobs_start_first_and_the_results_keep_their_order() -> None:
    from radial_ibvs_agents.experiments.backends import LocalBackend
    from radial_ibvs_agents.experiments.benchmark import job_cost

    class Recording(LocalBackend):
        def imap_unordered(self, fn, items, initializer=None):
            self.started = [(item.variant.suite, item.variant.label) for item in items]
            yield from super().imap_unordered(fn, items, initializer)

    backend = Recording(1)
    results = run_benchmark(
        ["random"], ["paper", "pixels", "noise"], episodes=1, progress=False, backend=backend
    )
    assert backend.started[:2] == [
        ("pixels", "paper-sim detected"),
        ("pixels", "paper-lab detected"),
    ]
    assert {suite for suite, _ in backend.started[2:5]} == {"noise"}  # 3 imperfect cameras
    costs = [job_cost(r.job) for r in results]
    assert costs != sorted(costs, reverse=True)  # the results are in suite order, not run order
    assert [r.job.variant.suite for r in results][:2] == ["paper", "paper"]


def test_generalisation_suites_use_held_out_seeds_and_other_cameras() -> None:
    from radial_ibvs_agents.experiments.suites import HELD_OUT_SEED

    results = run_benchmark(["ibvs"], ["held-out", "cross-camera"], episodes=2, progress=False)
    for result in results:
        assert [row["seed"] for row in result.rows] == [HELD_OUT_SEED, HELD_OUT_SEED + 1]
    cameras = {r.job.variant.label: r.job.variant.overrides for r in results}
    assert cameras["random rooms, mirror B"]["camera"]["mirror"] == "B"
    assert cameras["random rooms, camera at 1.2 m"]["camera_height"] == 1.2


def test_rows_report_success_at_three_tolerances_and_why_they_ended() -> None:
    from radial_ibvs_agents.rows import TOLERANCES

    results = run_benchmark(
        ["ibvs", "random"], ["random"], episodes=6, progress=False
    )  # the random policy collides or times out; the IBVS mostly parks
    rows = [row for result in results for row in result.rows]
    ends = {row["end"] for row in rows}
    assert "success" in ends and ends <= {"success", "collision", "lost", "time-out"}
    for row in rows:
        tolerance = row["success_by_tolerance"]
        assert list(tolerance) == list(TOLERANCES)
        assert tolerance["2cm/2deg"] == row["success"] == (row["end"] == "success")
        assert tolerance["2cm/2deg"] <= tolerance["10cm/5deg"] <= tolerance["30cm/15deg"]
        assert row["collision"] == (row["end"] == "collision") or row["success"]
    summary = summary_rows(results)[0]
    assert summary["success_by_tolerance"]["2cm/2deg"]["rate"] == summary["success_rate"]
    assert sum(summary["ends"].values()) == summary["episodes"]


def test_by_the_older_rule_a_looser_tolerance_counts_a_close_time_out_not_a_crash() -> None:
    from radial_ibvs_agents.rollouts.log import EpisodeLog

    def log(position: float, heading: float, collision: bool, terminated: bool) -> EpisodeLog:
        info = {"position_error_m": position, "heading_error_deg": heading,
                "is_success": False, "collision": collision}  # fmt: skip
        empty = np.zeros((1, 0))
        return EpisodeLog("p", "s", "kinematic", 0, 0, 0.1, np.zeros((1, 3)), np.zeros((0, 2)),
                          empty, empty, empty, info, 0.0, terminated=terminated)  # fmt: skip

    timeout = log(0.05, 3.0, collision=False, terminated=False)
    assert timeout.end == "time-out"
    assert [timeout.success_at(*t) for t in ((0.02, 2), (0.1, 5), (0.3, 15))] == [0, 1, 1]
    crash = log(0.05, 3.0, collision=True, terminated=True)
    assert crash.end == "collision" and not crash.success_at(0.3, 15.0)
    lost = log(2.0, 90.0, collision=False, terminated=True)
    assert lost.end == "lost" and not lost.success_at(0.3, 15.0)


def test_by_the_park_rule_a_looser_tolerance_counts_a_pose_held_there_1_s() -> None:
    """The looser tolerances are judged by the same hold: a run of 10 steps within them."""
    from radial_ibvs_agents.rollouts.log import EpisodeLog

    def log(distances: list[float], collision: bool = False) -> EpisodeLog:
        poses = np.zeros((len(distances) + 1, 3))
        poses[1:, 0] = distances  # the goal at the origin, heading 0
        info = {
            "position_error_m": distances[-1],
            "heading_error_deg": 0.0,
            "is_success": False,
            "collision": collision,
            "goal_pose": [0.0, 0.0, 0.0],
        }
        empty = np.zeros((1, 0))
        return EpisodeLog("p", "s", "kinematic", 0, 0, 0.1, poses, np.zeros((len(distances), 2)),
                          empty, empty, empty, info, 0.0, success_hold_steps=10)  # fmt: skip

    held = log([1.0] + [0.05] * 10 + [1.0])  # 10 steps within 10 cm, then away: parked there
    assert held.longest_run_within(0.1, 5.0) == 10
    assert [held.success_at(*t) for t in ((0.02, 2), (0.1, 5), (0.3, 15))] == [0, 1, 1]
    passing = log([1.0] + [0.05] * 9 + [1.0])  # 9 steps: a pass
    assert not passing.success_at(0.1, 5.0)
    # a time-out that ends close, but not for 1 s, does not count (the older rule counted it)
    assert not log([1.0] * 5 + [0.05] * 3).success_at(0.1, 5.0)
    # held there 1 s before a crash: the env at that tolerance would have ended it parked
    assert log([0.05] * 10 + [0.5], collision=True).success_at(0.1, 5.0)


def test_each_suites_time_is_summed_from_its_jobs_and_resumed_chunks_are_counted_apart():
    from radial_ibvs_agents.experiments.benchmark import suite_timings
    from radial_ibvs_agents.experiments.jobs import Job, JobResult
    from radial_ibvs_agents.experiments.tables import timings_table

    paper, held = SUITES["paper"][0], SUITES["held-out"][0]
    results = [
        JobResult(Job("ibvs", paper, 2), [{}, {}], [], wall_s=3.0),
        JobResult(Job("pbvs", paper, 2), [{}, {}], [], wall_s=1.0),
        JobResult(Job("ibvs", held, 3), [{}, {}, {}], [], resumed=1),  # loaded, not run
    ]
    timings = {t["suite"]: t for t in suite_timings(results)}
    assert timings["paper"]["seconds"] == 4.0 and timings["paper"]["episodes"] == 4
    assert timings["held-out"]["resumed"] == 1 and timings["held-out"]["seconds"] == 0.0
    table = timings_table(suite_timings(results), workers=2)
    assert "| paper | 4 | 4 | 100% | 2 s |" in table and "held-out (1 chunks resumed)" in table
    # a job of two chunks, one loaded and one run now, keeps the run one's time
    from radial_ibvs_agents.experiments.benchmark import _merge

    chunks = [
        JobResult(Job("ibvs", held, 2, 0), [{}, {}], [], resumed=1),
        JobResult(Job("ibvs", held, 2, 2), [{}, {}], [], wall_s=5.0),
    ]
    (merged,) = _merge(chunks)
    assert (merged.wall_s, merged.resumed, len(merged.rows)) == (5.0, 1, 4)
    # a skipped job took time too, and resumed nothing
    (timing,) = suite_timings([JobResult(Job("x", held, 2), [], [], "no fit", wall_s=0.5)])
    assert (timing["resumed"], timing["seconds"]) == (0, 0.5)


def test_every_policy_is_judged_alike_whatever_its_training_env_asked(monkeypatch, tmp_path):
    """A model trained with ``success_hold_steps: 3`` is judged by the job's rule, not its own."""
    from held_model import model_trained_with_hold

    import radial_ibvs_agents.rollouts as rollouts
    from radial_ibvs_agents.experiments import jobs
    from radial_ibvs_agents.learned import load

    model = str(model_trained_with_hold(tmp_path, 3))
    assert load(model).env_kwargs.get("success_hold_steps") == 3  # what its training asked
    seen = {}
    real = rollouts.make_env

    def spy(policy, scenario, overrides, **kwargs):
        seen.update(rollouts.env_kwargs_for(policy, scenario, overrides))
        return real(policy, scenario, overrides, **kwargs)

    monkeypatch.setattr(rollouts, "make_env", spy)
    variant = next(v for v in SUITES["paper"] if v.label == "d*")
    result = jobs.run_job(jobs.Job(model, variant, 1))
    assert result.skipped is None
    # the park rule (the env's default: 1 s) and the task's tolerance, not the model's
    assert seen["success_hold_steps"] is None and seen["success_position_m"] == 0.02
    assert result.rows[0]["success_hold_steps"] == 10  # what the env judged by
    passing = replace(variant, overrides={**variant.overrides, "success_hold_steps": 1})
    result = jobs.run_job(jobs.Job(model, passing, 1))
    assert seen["success_hold_steps"] == 1 and result.rows[0]["success_hold_steps"] == 1


def test_success_hold_steps_judges_every_policy_by_a_held_pose():
    kwargs = {"episodes": 2, "progress": False}
    passed = run_benchmark(["ibvs-straight"], ["paper"], success_hold_steps=1, **kwargs)
    parked = run_benchmark(["ibvs-straight"], ["paper"], **kwargs)  # the default: held 1 s
    for a, b in zip(passed, parked, strict=True):
        assert a.job.variant.overrides["success_hold_steps"] == 1  # the rule is in the key
        assert b.job.variant.overrides["success_hold_steps"] == 10
        for row_a, row_b in zip(a.rows, b.rows, strict=True):
            assert row_a["success"] and row_b["success"]  # it stops at the goal: it stays
            assert row_b["steps"] == row_a["steps"] + 9
            assert row_a["reached"] and row_b["reached"]
            assert (row_a["success_hold_steps"], row_b["success_hold_steps"]) == (1, 10)
    for bad in (0, True, 601):
        with pytest.raises(ValueError, match="success_hold_steps"):
            run_benchmark(["ibvs"], ["paper"], success_hold_steps=bad, **kwargs)


def test_a_rerun_with_fewer_policies_keeps_the_other_rows(tmp_path: Path, capsys) -> None:
    out = tmp_path / "bench"
    argv = ["benchmark", "--suites", "paper-lab", "--episodes", "2", "--workers", "1"]
    argv += ["--out", str(out), "--no-progress"]
    assert main([*argv, "--policies", "ibvs", "oracle"]) == 0
    first = json.loads((out / "episodes.json").read_text())
    assert main([*argv, "--policies", "ibvs"]) == 0
    assert "kept" in capsys.readouterr().out
    second = json.loads((out / "episodes.json").read_text())
    key = lambda r: (r["policy"], r["suite"], r["variant"], r["seed"])  # noqa: E731
    assert sorted(map(key, second)) == sorted(map(key, first))  # oracle's rows kept
    assert {r["policy"] for r in second} == {"ibvs", "oracle"}


@pytest.mark.slow  # runs the benchmark command twice (8 s)
def test_the_benchmark_command_says_the_rule_it_judged_by(tmp_path: Path, capsys) -> None:
    base = ["benchmark", "--suites", "paper", "--policies", "ibvs", "--episodes", "1"]
    assert main([*base, "--no-progress", "--out", str(tmp_path / "park")]) == 0
    out = capsys.readouterr().out
    assert "success: a park: the pose within 2 cm and 2 deg of the goal, held 10 steps" in out
    assert (tmp_path / "park" / "summary.md").read_text().startswith("Success: a park")
    held = [*base, "--success-hold-steps", "1", "--no-progress", "--out", str(tmp_path / "pass")]
    assert main(held) == 0
    assert "success: a pass: the first step within 2 cm" in capsys.readouterr().out
