"""Batched evaluation gives the rows of one episode at a time: same seed, same episode.

The benchmark steps a job's episodes together in the native vector env and calls each policy once
per step for the batch (:mod:`radial_ibvs_agents.rollouts.vector`). For every analytic policy the
rows equal the scalar runner's bit for bit (timing aside); for the networks, the same success and
end in every episode here (the actions differ in the last bits of a matrix product).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.analytic.registry import ANALYTIC_POLICIES
from radial_ibvs_agents.experiments import jobs
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rollouts import batch_mode, make_env, run_episode, run_episodes
from radial_ibvs_agents.rollouts.vector import batchable, run_batch
from radial_ibvs_agents.rows import RUN_FIELDS

TIMING = RUN_FIELDS


def _variant(suite: str, label: str) -> Any:
    return next(v for v in SUITES[suite] if v.label == label)


#: variants that exercise the task cycle, random rooms, noise and drawn imperfections
VARIANTS = [
    ("paper", "d*", 4),
    ("held-out", "random rooms", 3),
    ("imperfect", "all together", 2),
    ("imperfect", "drawn per episode", 2),
]


def _rows(job: jobs.Job, batched: bool, monkeypatch: pytest.MonkeyPatch) -> list[dict]:
    if not batched:  # the rollouts read batch_mode when they run: None sends it one by one
        import radial_ibvs_agents.rollouts as rollouts_module

        monkeypatch.setattr(rollouts_module, "batch_mode", lambda policy: None)
    result = jobs.run_job(job)
    monkeypatch.undo()
    assert result.skipped is None, result.skipped
    return [{k: v for k, v in row.items() if k not in TIMING} for row in result.rows]


@pytest.mark.parametrize("name", [*sorted(ANALYTIC_POLICIES), "random"])
def test_every_analytic_policy_gives_the_same_rows_batched_bit_for_bit(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert batch_mode(make_policy(name)) is not None
    for suite, label, episodes in VARIANTS:
        job = jobs.Job(name, _variant(suite, label), episodes, first=1)
        assert _rows(job, True, monkeypatch) == _rows(job, False, monkeypatch), (suite, label)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(ANALYTIC_POLICIES))
def test_every_analytic_policy_gives_the_same_rows_batched_in_a_long_chunk(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    for suite, label in (("obstacles", "random rooms with obstacles"), ("noise", "2.0 px")):
        job = jobs.Job(name, _variant(suite, label), 20)
        assert _rows(job, True, monkeypatch) == _rows(job, False, monkeypatch), (suite, label)


@pytest.mark.parametrize("name", ["ibvs", "pbvs-ekf"])
def test_detected_points_give_the_same_rows_batched_bit_for_bit(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each robot's frames rendered and detected in the vector env: the scalar env's rows."""
    job = jobs.Job(name, _variant("pixels", "paper-lab detected"), 2, first=3)
    assert _rows(job, True, monkeypatch) == _rows(job, False, monkeypatch)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(ANALYTIC_POLICIES))
def test_every_analytic_policy_gives_the_same_rows_batched_on_detected_points(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    job = jobs.Job(name, _variant("pixels", "paper-sim detected"), 2, first=5)
    assert _rows(job, True, monkeypatch) == _rows(job, False, monkeypatch)


@pytest.mark.parametrize("name", ["dagger-student"])
def test_learned_policies_end_the_same_episodes_batched(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    job = jobs.Job(name, _variant("held-out", "random rooms"), 12)
    batched, alone = _rows(job, True, monkeypatch), _rows(job, False, monkeypatch)
    for a, b in zip(batched, alone, strict=True):
        assert (a["seed"], a["success"], a["end"]) == (b["seed"], b["success"], b["end"])
        # a batched matmul differs in the last bits; over the 1 s a park holds, the final poses
        # drift apart by a fraction of a millimetre (a 20th of the 2 cm tolerance at most)
        assert abs(a["final_position_error_m"] - b["final_position_error_m"]) < 1e-3


def test_a_log_is_the_scalar_runners_trajectory() -> None:
    policy = make_policy("ibvs-straight")
    kwargs = {"physics": "kinematic", "task": None}
    seeds = [7, 3, 11]
    logs = run_episodes(policy, seeds, "random", kwargs, policy_name="ibvs-straight")
    assert {log.batch for log in logs} == {3}  # stepped together
    env = make_env(policy, "random", kwargs)
    for seed, log in zip(seeds, logs, strict=True):
        alone = run_episode(policy, env, seed=seed, policy_name="ibvs-straight")
        for field in ("poses", "actions", "points", "visible", "goal_points"):
            np.testing.assert_array_equal(getattr(log, field), getattr(alone, field), field)
        assert (log.seed, log.task, log.end, log.terminated) == (
            alone.seed,
            alone.task,
            alone.end,
            alone.terminated,
        )


def test_what_is_not_batched_says_why() -> None:
    assert batchable("RadialIBVS/Parking-v0", {"physics": "kinematic"}) is None
    assert "pymunk" in str(batchable("RadialIBVS/Parking-v0", {}))
    detected = {"physics": "kinematic", "measurement": "detected"}
    assert batchable("RadialIBVS/Parking-v0", detected) is None  # each robot renders its own
    assert "no vector env" in str(batchable("RadialIBVS/ParkingImage-v0", {}))
    with pytest.raises(ValueError, match="cannot be batched"):
        run_batch(make_policy("ibvs"), [0], "RadialIBVS/Parking-v0", {"physics": "pymunk"})
    physics = _variant("physics", "pymunk")
    job = jobs.Job("ibvs", replace(physics, episodes=1), 1)
    assert jobs.run_job(job).rows  # the scalar path runs it


def test_the_policy_sees_only_the_robots_whose_episodes_go_on(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from radial_ibvs_agents.analytic.pbvs_ekf import PBVSEKFPolicy

    sizes: list[int] = []
    predict = PBVSEKFPolicy.predict

    def recording(self, observation, state=None, episode_start=None, deterministic=True):
        sizes.append(len(observation["points"]))
        if state is not None:
            assert len(state.started) == sizes[-1]  # the filters of those robots only
        return predict(self, observation, state, episode_start, deterministic)

    monkeypatch.setattr(PBVSEKFPolicy, "predict", recording)
    logs = run_episodes(make_policy("pbvs-ekf"), [100_000 + k for k in range(6)], "random",
                        {"physics": "kinematic"})  # fmt: skip
    lengths = sorted(len(log.actions) for log in logs)
    assert lengths[0] < lengths[-1]  # the episodes end at different steps
    assert sizes[0] == 6 and sizes[-1] == sum(n == lengths[-1] for n in lengths)
    assert sizes == sorted(sizes, reverse=True) and len(sizes) == lengths[-1]


def test_run_episodes_names_an_env_the_policy_cannot_run_in_and_draws_tasks_from_the_scenario():
    from radial_ibvs_agents.rollouts import EnvMismatchError

    class Misfit:  # a policy whose training env took an argument these envs do not
        batch_mode = "batch"

        def __init__(self) -> None:
            self.env_kwargs = {"no_such_argument": 1}

        def predict(self, observation, state=None, episode_start=None, deterministic=True):
            raise AssertionError("never called: the env cannot be made")

    with pytest.raises(EnvMismatchError, match="no_such_argument"):
        run_episodes(Misfit(), [0], "random", {"physics": "kinematic"})
    policy = make_policy("ibvs-straight")
    with pytest.raises(ValueError, match="1 tasks for 2 seeds"):
        run_episodes(policy, [0, 1], "paper-sim", {"physics": "kinematic"}, tasks=[0])
    asked = []

    def cycle(n_tasks: int) -> list[int]:  # the paper's four tasks, one per episode
        asked.append(n_tasks)
        return [k % n_tasks for k in range(5)]

    logs = run_episodes(policy, range(5), "paper-sim", {"physics": "kinematic"}, tasks=cycle)
    assert asked == [4] and [log.task for log in logs] == [0, 1, 2, 3, 0]
