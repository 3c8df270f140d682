"""Resumed benchmarks never reuse stale rows: chunk keys and chunk checks; orphan workers."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents.experiments import benchmark, store
from radial_ibvs_agents.experiments.jobs import Job
from radial_ibvs_agents.experiments.store import job_key
from radial_ibvs_agents.experiments.suites import SUITES, Variant
from radial_ibvs_agents.learned import MODELS_DIR
from radial_ibvs_agents.rows import RUN_FIELDS
from radial_ibvs_gym.config import configs_dir

ROOT = Path(__file__).resolve().parents[3]


def _lab(scenario: str = "paper-lab") -> Variant:
    return Variant("lab", "beacons", scenario, {"physics": "kinematic"}, 2, False)


def test_every_file_of_a_model_directory_is_in_the_key(tmp_path: Path) -> None:
    model = tmp_path / "model"
    shutil.copytree(MODELS_DIR / "dagger-student", model)
    job = Job(str(model), _lab(), 2)
    before = job_key(job)
    metadata = json.loads((model / "metadata.json").read_text())
    metadata["teacher_kwargs"]["line_speed"] = 0.1  # a metadata edit once reused every chunk
    (model / "metadata.json").write_text(json.dumps(metadata))
    edited = job_key(job)
    assert edited != before
    with np.load(model / "normalization.npz") as data:
        arrays = {k: data[k] for k in data.files}
    np.savez(model / "normalization.npz", **{**arrays, "epsilon": np.array(1e-3)})
    assert job_key(job) != edited


def test_the_scenario_content_is_in_the_key(tmp_path: Path) -> None:
    path = tmp_path / "lab.yaml"
    shutil.copy(configs_dir() / "scenarios" / "paper-lab.yaml", path)
    job = Job("ibvs", _lab(str(path)), 2)
    before = job_key(job)
    text = path.read_text()
    path.write_text(re.sub(r"(?m)^camera_height: .*$", "camera_height: 1.5", text))
    assert job_key(job) != before


def test_a_store_reads_each_scenario_once_and_names_chunks_as_job_key(
    tmp_path: Path, monkeypatch
) -> None:
    read: list[str] = []
    real = store._scenario_content
    monkeypatch.setattr(store, "_scenario_content", lambda name: read.append(name) or real(name))
    chunks = store.ChunkStore(tmp_path / "out")
    jobs = [Job(p, v, 2) for v in SUITES["paper"] + SUITES["paper-lab"] for p in ("ibvs", "pbvs")]
    names = [chunks.path(job).name for job in jobs + jobs]
    assert sorted(read) == sorted({job.variant.scenario for job in jobs})
    assert names == [f"{job_key(job)}.json" for job in jobs + jobs]
    assert len(set(names)) == len(jobs)


def test_a_scenario_edited_during_a_run_changes_the_next_runs_keys(tmp_path: Path) -> None:
    path = tmp_path / "lab.yaml"
    shutil.copy(configs_dir() / "scenarios" / "paper-lab.yaml", path)
    job = Job("ibvs", _lab(str(path)), 2)
    running = store.ChunkStore(tmp_path / "out")
    before = running.path(job)
    text = path.read_text()
    path.write_text(re.sub(r"(?m)^camera_height: .*$", "camera_height: 1.5", text))
    assert running.path(job) == before  # read once, when the run first named the chunk
    assert store.ChunkStore(tmp_path / "out").path(job) != before


def test_the_policy_settings_and_the_version_are_in_the_key(monkeypatch) -> None:
    job = Job("ibvs", SUITES["paper"][0], 2)
    before = job_key(job)
    from radial_ibvs_agents import registry
    from radial_ibvs_agents.analytic import IBVSPolicy

    monkeypatch.setitem(registry._FACTORIES, "ibvs", lambda **kw: IBVSPolicy("paper", lam=0.7))
    assert job_key(job) != before
    monkeypatch.undo()
    assert job_key(job) == before
    monkeypatch.setattr(store, "__version__", "9.9.9")
    assert job_key(job) != before


@pytest.mark.parametrize("damage", ["duplicated", "seeds", "policy", "variant", "skipped", "value"])
def test_a_chunk_that_fails_its_check_runs_again(damage: str, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(benchmark, "CHUNK", 2)
    run = dict(policies=["ibvs"], suites=["paper"], episodes=2, progress=False, store=tmp_path)
    reference = benchmark.run_benchmark(**run)
    victim = sorted(tmp_path.glob("*.json"))[0]
    data = json.loads(victim.read_text())
    rows = data["rows"]
    if damage == "duplicated":  # 2 episodes turned into 200 rows: once a 96-100 % interval
        data["rows"] = rows * 100
    elif damage == "skipped":  # once passed the check, and dropped the chunk's rows
        data["rows"], data["skipped"] = [], "no reason"
    elif damage == "value":  # once used as it was
        data["rows"] = [{**row, "success": not row["success"]} for row in rows]
    elif damage == "seeds":
        data["rows"] = [{**row, "seed": row["seed"] + 1} for row in rows]
    else:
        data["rows"] = [{**row, damage: "other"} for row in rows]
    victim.write_text(json.dumps(data))
    said: list[str] = []
    again = benchmark.run_benchmark(**run, notify=said.append)
    assert any(victim.name in line and "failed its check" in line for line in said), said
    assert _rows(again) == _rows(reference)
    assert len(json.loads(victim.read_text())["rows"]) == 2


def _rows(results: list) -> list[dict]:
    return [
        {k: v for k, v in row.items() if k not in RUN_FIELDS} for r in results for row in r.rows
    ]


def _children(pid: int) -> list[int]:
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            if ppid == pid:
                out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")
def test_workers_die_with_their_killed_parent(tmp_path: Path) -> None:
    argv = [sys.executable, "-m", "radial_ibvs_agents.cli", "benchmark", "--suites", "random",
            "--policies",
            "ibvs", "--workers", "2", "--no-progress", "--out", str(tmp_path)]  # fmt: skip
    main = subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        workers: list[int] = []
        while time.monotonic() < deadline:
            workers = [p for p in _children(main.pid) if "spawn_main" in _cmdline(p)]
            if len(workers) >= 2:
                break
            time.sleep(0.2)
        assert len(workers) >= 2, "the pool never started"
        os.kill(main.pid, signal.SIGKILL)
        main.wait()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(_alive(p) for p in workers):
            time.sleep(0.2)
        assert not [p for p in workers if _alive(p)], "a worker outlived its parent by 10 s"
    finally:
        if main.poll() is None:
            main.kill()


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""
