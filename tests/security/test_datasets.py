"""Datasets are data: a Minari dataset's metadata is checked, in pure Python, before Minari.

Minari builds the env from a dataset's ``env_spec`` (any ``module:callable``) when a space is
missing from its metadata: a dataset handed over could run code. ``check_dataset`` refuses
that, and every reader of datasets (``load_collected``, distill's ``initial_dataset``) calls it
first.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from radial_ibvs_agents.learned.dagger.datasets import (
    UnsafeDatasetError,
    check_dataset,
    load_collected,
)
from radial_ibvs_gym.registration import ENTRY_POINTS, VECTOR_ENTRY_POINTS

ENV_ID = "RadialIBVS/Parking-v0"
BOX = {"type": "Box", "dtype": "float32", "shape": [2], "low": [-1.0, -1.0], "high": [1.0, 1.0]}


def _spec(**changes: Any) -> str:
    spec = {
        "id": ENV_ID,
        "entry_point": ENTRY_POINTS[ENV_ID],
        "vector_entry_point": VECTOR_ENTRY_POINTS[ENV_ID],
        "max_episode_steps": 600,
        "additional_wrappers": [],
        "kwargs": {"scenario": "paper-sim"},
    }
    return json.dumps({**spec, **changes})


def _metadata(**changes: Any) -> dict[str, Any]:
    meta = {
        "total_episodes": 1,
        "observation_space": json.dumps({"type": "Dict", "subspaces": {"points": BOX}}),
        "action_space": json.dumps(BOX),
        "env_spec": _spec(),
        "eval_env_spec": _spec(),
        "dataset_id": "radial-ibvs/x-v0",
    }
    meta.update(changes)
    return {k: v for k, v in meta.items() if v is not ...}


def _dataset(tmp_path: Path, meta: dict[str, Any]) -> Path:
    directory = tmp_path / "datasets" / "radial-ibvs" / "x-v0"
    (directory / "data").mkdir(parents=True)
    (directory / "data" / "metadata.json").write_text(json.dumps(meta))
    return directory


def test_a_dataset_as_collect_writes_it_passes(tmp_path: Path) -> None:
    meta = check_dataset(_dataset(tmp_path, _metadata()))
    assert meta["dataset_id"] == "radial-ibvs/x-v0"


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"observation_space": ...}, "observation_space is missing"),
        ({"action_space": ...}, "action_space is missing"),
        ({"env_spec": _spec(entry_point="payload:make")}, "env_spec.entry_point"),
        ({"eval_env_spec": _spec(entry_point="os:system")}, "eval_env_spec.entry_point"),
        ({"env_spec": _spec(id="CartPole-v1")}, "env_spec.id"),
        ({"env_spec": _spec(vector_entry_point="payload:make")}, "vector_entry_point"),
        (
            {"env_spec": _spec(additional_wrappers=[{"entry_point": "payload:Wrap"}])},
            "additional_wrappers",
        ),
        ({"env_spec": ...}, "env_spec must be a JSON string"),
        ({"action_space": json.dumps({"type": "Text", "max_length": 9})}, "has type 'Text'"),
        (
            {"action_space": json.dumps({**BOX, "shape": [1 << 20, 1 << 20]})},
            "action_space.low",  # its bounds do not fit the shape asked
        ),
        (
            {"action_space": json.dumps({**BOX, "low": [-1e400, 0.0]})},
            "not a finite number",
        ),
        ({"action_space": json.dumps({"type": "Discrete", "n": 10**12})}, "action_space.n"),
        ({"action_space": "{not json"}, "action_space is not valid JSON"),
    ],
)
def test_a_hostile_dataset_gets_a_named_error(
    tmp_path: Path, changes: dict[str, Any], named: str
) -> None:
    directory = _dataset(tmp_path, _metadata(**changes))
    with pytest.raises(UnsafeDatasetError, match=r"metadata\.json") as error:
        check_dataset(directory)
    assert named in str(error.value)


def test_a_space_of_too_many_numbers_is_refused_before_it_is_read(tmp_path: Path) -> None:
    huge = {"type": "Box", "dtype": "float32", "shape": [1 << 23], "low": [0.0], "high": [1.0]}
    directory = _dataset(tmp_path, _metadata(observation_space=json.dumps(huge)))
    with pytest.raises(UnsafeDatasetError, match="numbers"):
        check_dataset(directory)


def test_reading_a_payload_dataset_runs_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a dataset without its spaces, whose env_spec names a module that leaves a marker
    marker = tmp_path / "ran"
    package = tmp_path / "payload_site"
    package.mkdir()
    (package / "dataset_payload.py").write_text(
        f"from pathlib import Path\nPath({str(marker)!r}).write_text('ran')\n"
        "def make(**kwargs):\n    raise SystemExit('payload')\n"
    )
    monkeypatch.syspath_prepend(str(package))
    meta = _metadata(
        observation_space=...,
        env_spec=_spec(id=ENV_ID, entry_point="dataset_payload:make"),
    )
    directory = _dataset(tmp_path, meta)
    with pytest.raises(UnsafeDatasetError):
        load_collected(directory)
    assert not marker.exists()


def test_a_folder_without_metadata_is_no_dataset(tmp_path: Path) -> None:
    with pytest.raises(UnsafeDatasetError, match="not a Minari dataset"):
        check_dataset(tmp_path)
