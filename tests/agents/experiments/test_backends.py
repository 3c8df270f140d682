"""Benchmark backends (local pool, Ray), per-chunk persistence, resuming, fault tolerance."""

from __future__ import annotations

import importlib.util
import ipaddress
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments import benchmark
from radial_ibvs_agents.experiments.backends import RayBackend, import_ray, make_backend
from radial_ibvs_agents.experiments.jobs import Job
from radial_ibvs_agents.experiments.store import job_key
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rows import RUN_FIELDS

POLICIES, SUITE_NAMES = ["ibvs", "oracle"], ["paper"]
TIMING = RUN_FIELDS  # how a row was run (a timing, the batch), not the episode


def _rows(results) -> str:
    """The rows as JSON text, timing stripped: equal text is bit-for-bit equal values."""
    rows = [{k: v for k, v in row.items() if k not in TIMING} for r in results for row in r.rows]
    return json.dumps(rows, sort_keys=True)


@pytest.fixture
def small_chunks(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(benchmark, "CHUNK", 2)  # 4 episodes per variant: 2 chunks


@pytest.fixture(scope="module")
def reference() -> str:
    """The rows of an undisturbed local run in one process."""
    import radial_ibvs_agents.experiments.benchmark as b

    saved, b.CHUNK = b.CHUNK, 2
    try:
        return _rows(b.run_benchmark(POLICIES, SUITE_NAMES, episodes=4, progress=False))
    finally:
        b.CHUNK = saved


@pytest.fixture(scope="module")
def ray_backend():
    """One private Ray instance (2 CPUs, 127.0.0.1 only) for the module's tests."""
    if importlib.util.find_spec("ray") is None:  # not importing it: the backend configures it
        pytest.skip("Ray is not installed")
    backend = RayBackend(num_cpus=2)
    yield backend
    backend.close()


# --- errors -----------------------------------------------------------------------------------
def test_without_ray_the_error_names_the_extra(monkeypatch, capsys) -> None:
    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` raises ImportError
    with pytest.raises(ValueError, match=r"radial_ibvs_gym\[ray\]"):
        import_ray()
    code = main(["benchmark", "--backend", "ray", "--suites", "paper", "--episodes", "1",
                 "--policies", "ibvs", "--no-progress", "--out", "unused"])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "radial_ibvs_gym[ray]" in err


def test_bad_backend_arguments_are_named() -> None:
    with pytest.raises(ValueError, match="unknown backend 'spark'"):
        make_backend("spark")
    with pytest.raises(ValueError, match="--address needs --backend ray"):
        make_backend("local", address="auto")
    with pytest.raises(ValueError, match="workers must be >= 1, got 0"):
        make_backend("local", workers=0)


# --- persistence and resuming ---------------------------------------------------------------
def test_chunk_keys_change_with_what_defines_the_rows() -> None:
    variant = SUITES["paper"][0]
    job = Job("ibvs", variant, 2, 0)
    assert job_key(job) == job_key(Job("ibvs", variant, 2, 0))
    changed = [
        Job("oracle", variant, 2, 0),
        Job("ibvs", variant, 3, 0),
        Job("ibvs", variant, 2, 2),
        Job("ibvs", SUITES["paper"][1], 2, 0),
    ]
    assert len({job_key(j) for j in [job, *changed]}) == 5


def test_a_retrained_model_gets_new_chunk_keys(tmp_path: Path) -> None:
    model = tmp_path / "model"
    model.mkdir()
    (model / "model.zip").write_bytes(b"first training")
    job = Job(str(model), SUITES["paper"][0], 2, 0)
    before = job_key(job)
    (model / "model.zip").write_bytes(b"second training, longer")
    assert job_key(job) != before


def test_an_interrupted_local_run_resumes_without_running_a_chunk_twice(
    small_chunks, reference: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls: list[Job] = []
    real = benchmark.run_job

    def interrupted(job: Job):
        if len(calls) == 3:
            raise KeyboardInterrupt  # Ctrl-C during the fourth chunk
        calls.append(job)
        return real(job)

    monkeypatch.setattr(benchmark, "run_job", interrupted)
    with pytest.raises(KeyboardInterrupt):
        benchmark.run_benchmark(POLICIES, SUITE_NAMES, episodes=4, progress=False, store=tmp_path)
    assert len(list(tmp_path.glob("*.json"))) == 3  # the finished chunks were kept
    first = list(calls)
    calls.clear()
    monkeypatch.setattr(benchmark, "run_job", lambda job: (calls.append(job), real(job))[1])
    said: list[str] = []
    results = benchmark.run_benchmark(
        POLICIES, SUITE_NAMES, episodes=4, progress=False, store=tmp_path, notify=said.append
    )
    assert said == [f"resuming: 3 of 8 chunks already done in {tmp_path}, skipping them; 5 to run"]
    assert len(calls) == 5 and not set(map(job_key, calls)) & set(map(job_key, first))
    assert _rows(results) == reference
    calls.clear()
    again = benchmark.run_benchmark(
        POLICIES, SUITE_NAMES, episodes=4, progress=False, store=tmp_path
    )
    assert calls == [] and _rows(again) == reference  # all done: nothing runs


def test_a_damaged_chunk_file_runs_again(small_chunks, reference: str, tmp_path: Path) -> None:
    benchmark.run_benchmark(POLICIES, SUITE_NAMES, episodes=4, progress=False, store=tmp_path)
    victim = sorted(tmp_path.glob("*.json"))[0]
    victim.write_text('{"rows": [')  # a half-written file (the writes are atomic; still)
    results = benchmark.run_benchmark(
        POLICIES, SUITE_NAMES, episodes=4, progress=False, store=tmp_path
    )
    assert _rows(results) == reference and json.loads(victim.read_text())["rows"]


def test_the_cli_says_it_resumes(tmp_path: Path, capsys) -> None:
    argv = ["benchmark", "--suites", "paper", "--policies", "ibvs", "--episodes", "2",
            "--no-progress", "--workers", "1", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    assert len(list((tmp_path / "chunks").glob("*.json"))) == 2
    capsys.readouterr()
    assert main(argv) == 0
    assert "resuming: 2 of 2 chunks already done" in capsys.readouterr().out
    assert main([*argv, "--fresh"]) == 0
    assert "resuming" not in capsys.readouterr().out


# --- Ray ----------------------------------------------------------------------------------------
@pytest.mark.slow
def test_ray_rows_are_bit_for_bit_the_local_ones(small_chunks, reference, ray_backend) -> None:
    results = benchmark.run_benchmark(
        POLICIES, SUITE_NAMES, episodes=4, progress=False, backend=ray_backend
    )
    assert _rows(results) == reference


def test_ray_servers_listen_on_localhost_only(ray_backend) -> None:
    ours = _ray_pids()
    assert ours, "no Ray process found"
    sockets = _listening_sockets(ours)
    assert sockets, "no listening socket found"
    for ip, port in sockets:
        mapped = getattr(ip, "ipv4_mapped", None)
        assert ip.is_loopback or (mapped is not None and mapped.is_loopback), (ip, port)


@pytest.mark.slow
def test_a_killed_ray_worker_is_retried_and_the_rows_are_complete(
    small_chunks, reference, ray_backend, tmp_path: Path
) -> None:
    out: dict[str, object] = {}

    def run() -> None:
        out["results"] = benchmark.run_benchmark(
            POLICIES, SUITE_NAMES, episodes=4, progress=False, backend=ray_backend, store=tmp_path
        )

    thread = threading.Thread(target=run)
    thread.start()
    killed = None
    deadline = time.monotonic() + 60
    while killed is None and thread.is_alive() and time.monotonic() < deadline:
        for pid, title in _ray_processes():
            if title.startswith("ray::_call"):  # a worker running a chunk
                os.kill(pid, signal.SIGKILL)
                killed = pid
                break
        time.sleep(0.02)
    thread.join(300)
    assert killed is not None, "no busy Ray worker was seen"
    assert _rows(out["results"]) == reference
    assert len(list(tmp_path.glob("*.json"))) == 8


def test_ray_without_authentication_is_refused(monkeypatch) -> None:
    monkeypatch.setenv("RAY_AUTH_MODE", "disabled")
    with pytest.raises(ValueError, match="RAY_AUTH_MODE='disabled' turns Ray's token auth"):
        import_ray(local=True)


_DRIVER = """
import os, sys, time
from radial_ibvs_agents.experiments.backends import RayBackend
RayBackend(num_cpus=1)
print("ready", flush=True)
time.sleep(600)
"""


@pytest.mark.slow
def test_a_private_ray_instance_is_on_the_loopback_and_dies_with_a_killed_driver() -> None:
    """Even with RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=1 preset; after SIGKILL of the driver."""
    import subprocess

    if importlib.util.find_spec("ray") is None:
        pytest.skip("Ray is not installed")
    before = _ray_pids()
    env = {**os.environ, "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "1"}
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[3]), *sys.path])
    driver = subprocess.Popen(
        [sys.executable, "-c", _DRIVER], env=env, stdout=subprocess.PIPE, text=True
    )
    try:
        assert driver.stdout is not None and driver.stdout.readline().strip() == "ready"
        ours = _ray_pids() - before
        assert ours, "no Ray process found"
        for ip, port in _listening_sockets(ours):
            mapped = getattr(ip, "ipv4_mapped", None)
            assert ip.is_loopback or (mapped is not None and mapped.is_loopback), (ip, port)
    finally:
        driver.kill()
        driver.wait()
    deadline = time.monotonic() + 20  # the watchdog polls every 0.5 s; Ray alone took 52-72 s
    while _ray_pids() & ours and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not _ray_pids() & ours, "Ray processes outlived their killed driver"


# --- helpers --------------------------------------------------------------------------------
def _ray_processes() -> list[tuple[int, str]]:
    """(pid, command line) of this user's Ray processes (workers show their task's name)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            cmd = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode().strip()
        except OSError:
            continue
        if cmd.startswith("ray::") or "ray/core/src" in cmd or "/ray/_private/" in cmd:
            found.append((int(entry.name), cmd))
    return found


def _ray_pids() -> set[int]:
    return {pid for pid, _ in _ray_processes()}


def _listening_sockets(pids: set[int]) -> list[tuple[Any, int]]:
    """(address, port) of the TCP sockets the processes listen on (from /proc)."""
    inodes: set[str] = set()
    for pid in pids:
        try:
            for fd in Path(f"/proc/{pid}/fd").iterdir():
                target = os.readlink(fd)
                if target.startswith("socket:["):
                    inodes.add(target[8:-1])
        except OSError:
            continue
    out = []
    for table, v6 in (("/proc/net/tcp", False), ("/proc/net/tcp6", True)):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[3] != "0A" or fields[9] not in inodes:  # 0A: LISTEN
                continue
            out.append(_address(fields[1], v6))
    return out


def _address(hex_address: str, v6: bool) -> tuple[Any, int]:
    host, port = hex_address.split(":")
    raw = bytes.fromhex(host)
    if v6:  # four little-endian 32-bit words
        raw = b"".join(raw[i : i + 4][::-1] for i in range(0, 16, 4))
        return ipaddress.IPv6Address(raw), int(port, 16)
    return ipaddress.IPv4Address(raw[::-1]), int(port, 16)


def test_ctrl_c_in_the_cli_exits_130_and_says_how_to_resume(monkeypatch, capsys) -> None:
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(benchmark, "run_benchmark", interrupted)
    code = main(["benchmark", "--suites", "paper", "--policies", "ibvs", "--no-progress",
                 "--out", "unused"])  # fmt: skip
    assert code == 130
    assert "interrupted; the finished chunks are in OUT/chunks" in capsys.readouterr().err


@pytest.mark.slow
def test_ray_imported_first_is_refused_for_a_private_instance() -> None:
    import subprocess

    if importlib.util.find_spec("ray") is None:
        pytest.skip("Ray is not installed")
    code = (
        "import ray\n"
        "from radial_ibvs_agents.experiments.backends import import_ray\n"
        "try:\n    import_ray()\nexcept ValueError as error:\n    print('refused:', error)\n"
        "else:\n    print('accepted')\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"}
    root = Path(__file__).resolve().parents[3]

    def run(extra: dict[str, str]) -> str:
        return subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            check=True,
            cwd=root,
            env={**env, **extra},
        ).stdout

    out = run({})
    assert "refused:" in out and "every network interface" in out, out
    assert "accepted" in run({"RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0"})  # loopback: fine
