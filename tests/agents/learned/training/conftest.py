"""The tests that train models (stable-baselines3 runs, DAgger students): every test collected
in this folder is marked ``slow`` (deselect them with ``-m 'not slow'``)."""

from __future__ import annotations

from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark ``slow`` every test of this folder (the hook sees every test of the session)."""
    for item in items:
        if item.path.is_relative_to(HERE):
            item.add_marker(pytest.mark.slow)


@pytest.fixture(scope="session")
def student(tmp_path_factory):
    """A small DAgger student (``dagger_setup.SMALL``: 2 rounds), trained once for the tests of
    ``test_dagger_students.py`` and ``test_fine_tune_students.py``."""
    from dagger_setup import SMALL

    from radial_ibvs_agents.learned.dagger.distill import dagger, load_dagger_config

    path = tmp_path_factory.mktemp("dagger") / "config.yaml"
    path.write_text(SMALL)
    config = load_dagger_config(path)
    out = dagger(config, path.parent / "student", seed=3, progress=False)
    return config, out
