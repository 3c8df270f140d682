"""Files a user hands over are data: never code, never a hang, never a memory bomb.

Each attack here is shown to be live first where it can be (the payload module runs when
imported the way Gymnasium's ``"module:EnvId"`` form would import it; the bomb's size is what
an unchecked read would allocate), then refused by name: a marker file that must never appear,
a memory cap (``resource.setrlimit``, in a subprocess) under which a bomb must be refused with
a named error, a time bound (``signal.setitimer``) under which a hang must be refused.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import zipfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from radial_ibvs_agents import load, make_policy
from radial_ibvs_agents.cli import main
from radial_ibvs_agents.learned import MODELS_DIR
from radial_ibvs_agents.learned.files.model_files import (
    DESCRIPTION,
    WEIGHTS,
    load_policy,
    read_normalization,
)
from radial_ibvs_agents.untrusted import MAX_ARCHIVE_MEMBER_BYTES, UntrustedFileError, check_archive
from radial_ibvs_gym.registration import UnknownEnvIdError, check_env_id

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = "dagger-student"
#: the address space a bomb test's subprocess may use: loading a shipped model takes ~1.1 GB
MEMORY_CAP = 3 << 30
#: hypothesis examples per fuzz test; FUZZ_EXAMPLES=3000 for the long run
FUZZ_EXAMPLES = int(os.environ.get("FUZZ_EXAMPLES", "40"))


@contextlib.contextmanager
def time_bound(seconds: float) -> Iterator[None]:
    """Raise ``TimeoutError`` in the body if it runs longer than ``seconds`` (a hang)."""

    def _raise(_signum: int, _frame: object) -> None:
        raise TimeoutError(f"still running after {seconds} s: a hang")

    previous = signal.signal(signal.SIGALRM, _raise)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _copy_shipped(tmp_path: Path, name: str = "copy") -> Path:
    model = tmp_path / name
    shutil.copytree(MODELS_DIR / SHIPPED, model)
    return model


def _edit_json(path: Path, **changes: object) -> None:
    path.write_text(json.dumps({**json.loads(path.read_text()), **changes}))


# --- 1. an env id from a file is one of this package's ids, or an error ---------------------


@pytest.fixture
def evil_model(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[Path, Path]:
    """A model folder ``evilmodel`` whose metadata's env id imports ``evilmodel.payload``."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    model = _copy_shipped(tmp_path, "evilmodel")
    marker = tmp_path / "marker"
    (model / "__init__.py").write_text("")
    (model / "payload.py").write_text(f"open({str(marker)!r}, 'w').write('ran')\n")
    _edit_json(model / "metadata.json", env_id="evilmodel.payload:RadialIBVS/Parking-v0")
    return model, marker


def test_the_env_id_payload_is_live_when_imported(evil_model: tuple[Path, Path]) -> None:
    _model, marker = evil_model
    importlib.import_module("evilmodel.payload")  # what gym.make("evilmodel.payload:...") does
    assert marker.is_file()
    sys.modules.pop("evilmodel.payload", None)
    sys.modules.pop("evilmodel", None)


def test_an_env_id_from_a_model_file_never_imports_a_module(
    evil_model: tuple[Path, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    model, marker = evil_model
    with pytest.raises(UnknownEnvIdError, match=r"metadata\.json: env_id"):
        load("./evilmodel")
    argv = ["evaluate", "--policy", "./evilmodel", "--scenario", "paper-lab", "--episodes", "1"]
    assert main(argv) == 2
    assert "metadata.json: env_id" in capsys.readouterr().err
    argv = ["benchmark", "--policies", "./evilmodel", "--suites", "paper-lab", "--episodes", "1"]
    assert main([*argv, "--out", str(model.parent / "bench"), "--no-progress"]) == 2
    assert not marker.exists()
    assert "evilmodel.payload" not in sys.modules


@pytest.mark.parametrize("env_id", ["this:RadialIBVS/Parking-v0", "CartPole-v1", "", 3, None])
def test_only_the_package_ids_pass(env_id: object) -> None:
    with pytest.raises(UnknownEnvIdError, match=r"where\.txt"):
        check_env_id(env_id, "where.txt")
    assert check_env_id("RadialIBVS/Parking-v0", "x") == "RadialIBVS/Parking-v0"


def test_a_training_config_section_name_never_imports_a_module(tmp_path: Path) -> None:
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    text = (ROOT / "configs" / "agents" / "ppo_parking.yaml").read_text()
    config = tmp_path / "evil.yaml"
    config.write_text(text.replace("RadialIBVS/Parking-v0:", "this:RadialIBVS/Parking-v0:", 1))
    assert "this:RadialIBVS" in config.read_text()
    with pytest.raises(ValueError, match=r"evil\.yaml.*is not an env"):
        load_train_config(config)
    assert "this" not in sys.modules


def test_a_local_folder_never_shadows_a_shipped_model(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    impostor = _copy_shipped(tmp_path, SHIPPED)
    (impostor / WEIGHTS).write_bytes(b"not the shipped weights")
    assert load(SHIPPED).name == SHIPPED  # the shipped one: the impostor's weights would fail
    with pytest.raises(ValueError, match="SHA-256"):
        load(f"./{SHIPPED}")  # the folder, by its path, is what was asked for
    _copy_shipped(tmp_path, "my-model")
    with pytest.raises(ValueError, match=r"my-model.*give its path: \./my-model"):
        make_policy("my-model")
    assert load("./my-model").predict is not None


# --- 2. bounds before work: hangs ------------------------------------------------------------


@pytest.mark.parametrize("kwarg", ["physics_dt=1e-9", "control_dt=1000000.0"])
def test_a_sub_step_count_that_would_hang_is_refused(
    kwarg: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["evaluate", "--policy", "ibvs", "--scenario", "paper-lab", "--episodes", "1"]
    with time_bound(60):
        assert main([*argv, "--env-kwarg", "physics=pymunk", "--env-kwarg", kwarg]) == 2
    assert "MAX_SUBSTEPS" in capsys.readouterr().err


def test_a_model_whose_metadata_asks_for_a_hang_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    model = _copy_shipped(tmp_path)
    meta = json.loads((model / "metadata.json").read_text())
    env_kwargs = {**meta.get("env_kwargs", {}), "physics": "pymunk", "physics_dt": 1e-9}
    _edit_json(model / "metadata.json", env_kwargs=env_kwargs)
    argv = ["evaluate", "--policy", str(model), "--scenario", "paper-lab", "--episodes", "1"]
    with time_bound(60):  # evaluate runs kinematic unless asked: ask for pymunk
        assert main([*argv, "--env-kwarg", "physics=pymunk"]) == 2
    assert "MAX_SUBSTEPS" in capsys.readouterr().err


def test_a_room_too_large_for_finite_rewards_is_refused(tmp_path: Path) -> None:
    from radial_ibvs_gym.scenarios import load_scenario

    text = (ROOT / "configs" / "scenarios" / "random.yaml").read_text()
    scenario = tmp_path / "huge.yaml"
    scenario.write_text(text.replace("width: [6.0, 12.0]", "width: [6.0, 1.0e300]"))
    with pytest.raises(ValueError, match=r"huge\.yaml.*MAX_WORLD_M"):
        load_scenario(scenario)


# --- 2. bounds before work: memory bombs, under a memory cap ---------------------------------


def _under_memory_cap(code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """Run ``code`` in a fresh interpreter whose address space is capped at ``MEMORY_CAP``.

    The code's last line prints ``REFUSED:`` and the error when it raises ``ValueError``;
    a ``MemoryError`` (the bomb went off) ends the process with a traceback instead.
    """
    script = textwrap.dedent(
        f"""
        import resource, sys
        sys.path.insert(0, {str(ROOT)!r})
        resource.setrlimit(resource.RLIMIT_AS, ({MEMORY_CAP}, {MEMORY_CAP}))
        try:
        {textwrap.indent(textwrap.dedent(code), "    ")}
        except ValueError as error:
            print("REFUSED:", type(error).__name__, error)
        else:
            print("ACCEPTED")
        """
    )
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    return subprocess.run(
        [sys.executable, "-c", script],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


def _refused(result: subprocess.CompletedProcess[str], *words: str) -> str:
    out = result.stdout + result.stderr
    assert "REFUSED:" in result.stdout, out[-3000:]
    assert "MemoryError" not in out, out[-3000:]
    for word in words:
        assert word in result.stdout, out[-3000:]
    return result.stdout


def _bomb_model(tmp_path: Path) -> Path:
    return _copy_shipped(tmp_path, "bomb")


@pytest.mark.slow  # a real bomb (6 s)
def test_the_memory_cap_lets_a_model_load_and_stops_a_real_bomb(tmp_path: Path) -> None:
    """The cap is tight enough to matter: an honest load passes, a 16 GiB network does not."""
    result = _under_memory_cap(f"from radial_ibvs_agents import load; load({SHIPPED!r})", tmp_path)
    assert "ACCEPTED" in result.stdout, result.stderr[-3000:]
    result = _under_memory_cap("import torch; torch.nn.Linear(65536, 65536)", tmp_path)
    assert "MemoryError" in result.stderr or "DefaultCPUAllocator" in result.stderr


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"net_arch": [65536, 65536, 65536]}, "MAX_LAYER_WIDTH"),
        ({"net_arch": {"pi": [8192, 8192], "vf": [8192, 8192]}}, "weights"),
    ],
)
def test_a_network_larger_than_its_weights_is_refused_before_it_is_built(
    change: dict, named: str, tmp_path: Path
) -> None:
    model = _bomb_model(tmp_path)
    described = json.loads((model / DESCRIPTION).read_text())
    described["policy_kwargs"] = {**described["policy_kwargs"], **change}
    (model / DESCRIPTION).write_text(json.dumps(described))  # the weights' SHA-256 still holds
    code = f"from radial_ibvs_agents import load; load({str(model)!r})"
    _refused(_under_memory_cap(code, tmp_path), named, "policy.json")


def test_a_huge_action_space_is_refused_before_it_is_built(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    described = json.loads((model / DESCRIPTION).read_text())
    described["action_space"] = {"type": "Discrete", "n": 10**11, "start": 0}
    (model / DESCRIPTION).write_text(json.dumps(described))
    code = (
        "from radial_ibvs_agents.learned.files.model_files import load_policy; "
        f"load_policy({str(model)!r})"
    )
    _refused(_under_memory_cap(code, tmp_path), "MAX_SPACE_ELEMENTS")


def _zip_bomb(path: Path, member: str, inflated: int) -> None:
    """An archive whose ``member`` is ``inflated`` zero bytes (compressed ~200:1, quickly)."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as archive:
        with archive.open(member, "w", force_zip64=True) as handle:
            block = bytes(8 << 20)
            for _ in range(inflated // len(block)):
                handle.write(block)


@pytest.mark.slow  # writes and reads a large archive (11 s)
def test_a_normalization_member_that_inflates_past_the_cap_is_refused(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    _zip_bomb(model / "normalization.npz", "mean/observation.npy", 4 << 30)
    assert (model / "normalization.npz").stat().st_size < 32 << 20  # small on disk
    code = f"from radial_ibvs_agents import load; load({str(model)!r})"
    _refused(_under_memory_cap(code, tmp_path), "normalization.npz", "MAX_ARCHIVE_MEMBER_BYTES")


def test_a_model_zip_member_that_inflates_past_the_cap_is_refused(tmp_path: Path) -> None:
    from radial_ibvs_agents.learned.training.train import _resume

    source = tmp_path / "source"
    source.mkdir()
    _zip_bomb(source / "model.zip", "data", MAX_ARCHIVE_MEMBER_BYTES + (8 << 20))
    assert (source / "model.zip").stat().st_size < 1 << 20
    # refused before the model or the env is touched (neither is given here)
    with pytest.raises(ValueError, match=r"model\.zip.*'data'.*MAX_ARCHIVE_MEMBER_BYTES"):
        _resume(None, None, source)
    with pytest.raises(UntrustedFileError, match="MAX_ARCHIVE_MEMBER_BYTES"):
        check_archive(source / "model.zip", source)


@pytest.mark.parametrize("name", ["metadata.json", DESCRIPTION, WEIGHTS])
def test_a_sparse_64_gib_file_is_refused_without_being_read(name: str, tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    with open(model / name, "r+b") as handle:
        handle.truncate(64 << 30)  # sparse: no disk used, 64 GiB to a whole-file read
    code = f"from radial_ibvs_agents import load; load({str(model)!r})"
    _refused(_under_memory_cap(code, tmp_path), name, "MAX_")


def test_a_link_out_of_the_model_folder_is_refused(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    outside = tmp_path / "elsewhere.safetensors"
    shutil.move(model / WEIGHTS, outside)
    (model / WEIGHTS).symlink_to(outside)
    with pytest.raises(ValueError, match=r"policy\.safetensors: a link to .*outside"):
        load(model)


# --- 6. unnamed errors: each a ValueError naming the file ------------------------------------


def test_an_npy_posing_as_npz_is_named(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    np.save(model / "normalization.npy", np.zeros(3))
    (model / "normalization.npy").rename(model / "normalization.npz")
    with pytest.raises(ValueError, match=r"normalization\.npz"):
        read_normalization(model / "normalization.npz")
    with pytest.raises(ValueError, match=r"normalization\.npz"):
        load(model)


def _rewrite_weights(model: Path, transform: object) -> None:
    """Replace the weights by ``transform(tensors)`` and record their new SHA-256."""
    import hashlib

    from safetensors.numpy import load_file, save_file

    tensors = load_file(str(model / WEIGHTS))
    save_file(transform(tensors), str(model / WEIGHTS))  # type: ignore[operator]
    digest = hashlib.sha256((model / WEIGHTS).read_bytes()).hexdigest()
    _edit_json(model / DESCRIPTION, weights_sha256=digest)


def test_nan_weights_are_named(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)

    def poison(tensors: dict) -> dict:
        first = sorted(tensors)[0]
        tensors[first] = np.full_like(tensors[first], np.nan)
        return tensors

    _rewrite_weights(model, poison)
    with pytest.raises(ValueError, match=r"policy\.safetensors.*NaN or infinite"):
        load_policy(model)


def test_integer_weights_are_not_cast_silently(tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)

    def to_int(tensors: dict) -> dict:
        first = sorted(tensors)[0]
        tensors[first] = tensors[first].astype(np.int64)
        return tensors

    _rewrite_weights(model, to_int)
    with pytest.raises(ValueError, match="int64"):
        load_policy(model)


@pytest.mark.parametrize("name", ["metadata.json", DESCRIPTION])
def test_deeply_nested_json_is_named(name: str, tmp_path: Path) -> None:
    model = _bomb_model(tmp_path)
    (model / name).write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match=rf"{name.replace('.', '[.]')}.*MAX_JSON_DEPTH"):
        load(model)


def test_an_out_path_that_is_a_file_is_refused_before_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    argv = ["benchmark", "--policies", "ibvs", "--suites", "paper-lab", "--episodes", "1"]
    with time_bound(30):
        assert main([*argv, "--out", str(blocker), "--no-progress"]) == 2
    assert "a-file" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("n_steps", -64, "n_steps must be an integer"),
        ("batch_size", 0, "batch_size must be an integer"),
        ("learning_rate", "fast", "learning_rate"),
        ("gamma", 1.5, "gamma must be a number"),
        ("n_epochs", 2.5, "n_epochs must be an integer"),
    ],
)
def test_training_hyper_parameters_are_checked_before_sb3(
    key: str, value: object, message: str, tmp_path: Path
) -> None:
    import yaml

    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    source = ROOT / "configs" / "agents" / "ppo_parking.yaml"
    data = yaml.safe_load(source.read_text())
    data["RadialIBVS/Parking-v0"][key] = value
    config = tmp_path / "bad.yaml"
    config.write_text(yaml.safe_dump(data))
    with pytest.raises(ValueError, match=rf"bad\.yaml.*{message}"):
        load_train_config(config)


def test_whole_float_hyper_parameters_become_integers(tmp_path: Path) -> None:
    import yaml

    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    source = ROOT / "configs" / "agents" / "ppo_parking.yaml"
    data = yaml.safe_load(source.read_text())
    data["RadialIBVS/Parking-v0"]["n_steps"] = 128.0
    config = tmp_path / "floats.yaml"
    config.write_text(yaml.safe_dump(data))
    n_steps = load_train_config(config).algo_kwargs["n_steps"]
    assert n_steps == 128 and isinstance(n_steps, int)


# --- 7. a killed sweep's scratch folders go with the next seed ------------------------------


def test_scratch_folders_of_dead_workers_are_removed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import tempfile

    from radial_ibvs_agents.experiments import sweep

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        check=True,
        capture_output=True,
        text=True,
    )
    stale = tmp_path / f"{sweep.SCRATCH_PREFIX}{int(dead.stdout)}-abc"
    alive = tmp_path / f"{sweep.SCRATCH_PREFIX}{os.getpid()}-def"
    other = tmp_path / "someone-elses-folder"
    for folder in (stale, alive, other):
        (folder / "model").mkdir(parents=True)
    assert sweep.remove_stale_scratch() == [stale]
    assert not stale.exists() and alive.exists() and other.exists()


# --- 5. a fuzz of the files of a model directory and of chunks ------------------------------

_json_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=False, allow_infinity=False),
    st.text(max_size=20),
)
_json_values = st.recursive(
    _json_scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=12), inner, max_size=4)
    ),
    max_leaves=12,
)
FUZZ = settings(
    max_examples=FUZZ_EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _copy_shipped(tmp_path_factory.mktemp("pristine"))


def _mutated(pristine: Path, scratch: Path, name: str, key: str, value: object) -> Path:
    model = scratch / "model"
    if model.exists():
        shutil.rmtree(model)
    shutil.copytree(pristine, model)
    data = json.loads((model / name).read_text())
    if key in data or isinstance(value, dict):
        data[key] = value
    (model / name).write_text(json.dumps(data))
    return model


@FUZZ
@given(
    name=st.sampled_from(["metadata.json", DESCRIPTION]),
    key=st.sampled_from(
        [
            "env_id",
            "env_kwargs",
            "history",
            "residual",
            "algo",
            "policy_kwargs",
            "observation_space",
            "action_space",
            "policy_class",
            "format_version",
        ]
    ),
    value=_json_values,
)
def test_any_model_file_value_loads_or_is_a_value_error(
    name: str, key: str, value: object, pristine: Path, tmp_path: Path
) -> None:
    model = _mutated(pristine, tmp_path, name, key, value)
    with time_bound(60):
        try:
            policy = load(model)
        except ValueError:
            return
    assert callable(policy.predict)


@FUZZ
@given(text=st.binary(max_size=300))
def test_any_bytes_as_a_model_file_are_a_value_error(text: bytes, tmp_path: Path) -> None:
    model = tmp_path / "model"
    if not model.exists():
        shutil.copytree(MODELS_DIR / SHIPPED, model)
    original = (MODELS_DIR / SHIPPED / "metadata.json").read_bytes()
    for name in ("metadata.json", DESCRIPTION, "normalization.npz"):
        (model / name).write_bytes(text)
        with pytest.raises(ValueError):
            load(model)
        (model / name).write_bytes((MODELS_DIR / SHIPPED / name).read_bytes())
    assert (model / "metadata.json").read_bytes() == original


@pytest.fixture(scope="module")
def chunk_store(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    """A benchmark store holding one real chunk: its file and its job's result."""
    from radial_ibvs_agents.experiments import benchmark

    out = tmp_path_factory.mktemp("store")
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(benchmark, "CHUNK", 2)
        run = dict(policies=["ibvs"], suites=["paper-lab"], episodes=2, progress=False)
        results = benchmark.run_benchmark(**run, store=out)
    chunks = sorted(out.glob("*.json"))
    assert len(chunks) == len(results) >= 1, sorted(out.rglob("*"))
    result = next(r for r in results if (out / f"{chunks[0].stem}.json").exists())
    return out, result


@FUZZ
@given(key=st.sampled_from(["rows", "skipped", "digest", "paths", "extra"]), value=_json_values)
def test_a_damaged_chunk_is_run_again_never_used(
    key: str, value: object, chunk_store: tuple[Path, object]
) -> None:
    from radial_ibvs_agents.experiments.store import ChunkStore

    folder, result = chunk_store
    store = ChunkStore(folder)
    chunk = store.path(result.job)  # type: ignore[attr-defined]
    backup = chunk.read_bytes()
    data = json.loads(backup)
    damaged = {**data, key: value}
    try:
        chunk.write_text(json.dumps(damaged))
        loaded = store.load(result.job)  # type: ignore[attr-defined]
    finally:
        chunk.write_bytes(backup)
    if key == "extra":  # a key the check does not read
        assert loaded is not None
    elif damaged != data:
        assert loaded is None
    assert store.load(result.job) is not None  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("replace", "named"),
    [
        (("wall_clearance: 0.6", "wall_clearance: 100"), "wall_clearance"),
        (("width: [6.0, 12.0]", "width: [1.0, 1.0e308]"), "MAX_WORLD_M"),
        (("camera_height: 1.8", "camera_height: 1.8\nobstacles: [[.nan, 2.0, 0.3]]"), "obstacles"),
        (("min_visible_at_goal: 4", "min_visible_at_goal: 1.0e6"), "min_visible_at_goal"),
    ],
)
def test_a_scene_that_would_break_the_maths_is_named(
    replace: tuple[str, str], named: str, tmp_path: Path
) -> None:
    from radial_ibvs_gym.scenarios import load_scenario

    text = (ROOT / "configs" / "scenarios" / "random.yaml").read_text()
    assert replace[0] in text
    scenario = tmp_path / "bad.yaml"
    scenario.write_text(text.replace(*replace))
    with time_bound(30), pytest.raises(ValueError, match=rf"bad\.yaml.*{named}"):
        load_scenario(scenario).sample(np.random.default_rng(0))


@pytest.mark.parametrize(
    ("extra", "named"),
    [
        (["--env-kwarg", "task=1.5"], "task"),
        (["--env-kwarg", "task=true"], "task"),
        (["--env-kwarg", "control_dt=1e6"], "MAX_SUBSTEPS"),
        (["--seed", "-1"], "seed"),
        (["--seed", "1" * 5000], "seed"),
    ],
)
def test_bad_command_line_values_are_named(
    extra: list[str], named: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["evaluate", "--policy", "ibvs", "--scenario", "paper-lab", "--episodes", "1"]
    with time_bound(60):
        try:
            code = main([*argv, "--env-kwarg", "physics=pymunk", *extra])
        except SystemExit as exit_:  # argparse's own error for an option's type
            code = int(exit_.code or 0)
    assert code == 2
    err = capsys.readouterr().err
    assert named in err and "Traceback" not in err, err


def test_a_full_disk_is_named_with_the_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import errno

    from radial_ibvs_agents.experiments import store

    def full(path: Path, _data: object) -> Path:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(store, "write_atomic", full)
    argv = ["benchmark", "--policies", "ibvs", "--suites", "paper-lab", "--episodes", "1"]
    assert main([*argv, "--out", str(tmp_path / "bench"), "--no-progress", "--workers", "1"]) == 1
    err = capsys.readouterr().err
    assert str(tmp_path / "bench") in err and "No space left" in err, err
    assert "Traceback" not in err and "rerun the same command" in err, err


def test_a_killed_worker_ends_with_the_resume_hint(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from concurrent.futures.process import BrokenProcessPool

    from radial_ibvs_agents.cli import benchmark as benchmark_cli

    def die(_args: object) -> int:
        raise BrokenProcessPool("a child process terminated abruptly")

    monkeypatch.setattr(benchmark_cli, "run", die)
    argv = ["benchmark", "--policies", "ibvs", "--suites", "paper-lab", "--episodes", "1"]
    assert main([*argv, "--out", str(tmp_path / "bench"), "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert "worker process died" in err and "rerun the same command" in err, err
