from __future__ import annotations

import numpy as np
import pytest

from radial_ibvs_gym.camera import CameraSpec, load_camera
from radial_ibvs_gym.config import ConfigError, configs_dir

SHIPPED = sorted(p.stem for p in (configs_dir() / "cameras").glob("*.yaml"))


def test_some_camera_configs_ship() -> None:
    assert {"paper-a-central", "paper-a-noncentral", "paper-b-noncentral"} <= set(SHIPPED)


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_camera_configs_load_and_build(name: str) -> None:
    camera = load_camera(name).build()
    lo, hi = camera.elevation_range()
    assert lo < 0 < hi
    assert camera.is_central == (name == "paper-a-central")


def test_imperfect_config_reads_every_field() -> None:
    spec = load_camera("paper-a-imperfect")
    assert spec.imperfections.principal_point_offset == (2.0, -1.5)
    assert spec.imperfections.pixel_noise_std == 0.5
    np.testing.assert_allclose(spec.build().true_intrinsics.mu_x - 639.5, 2.0)


def test_overrides_and_errors() -> None:
    assert load_camera("paper-a-central", mirror="B").mirror == "B"
    with pytest.raises(ConfigError, match=r"unknown cameras config 'nope'; available: \["):
        load_camera("nope")
    with pytest.raises(ConfigError, match=r"unknown key\(s\) \['mirorr'\]"):
        load_camera("paper-a-central", mirorr="B")
    with pytest.raises(ConfigError, match=r"mirror: 'C' is not one of \['A', 'B'\]"):
        load_camera("paper-a-central", mirror="C")
    with pytest.raises(ConfigError, match="pixel_noise_std must be >= 0"):
        load_camera("paper-a-imperfect", imperfections={"pixel_noise_std": -1.0})
    assert CameraSpec().build().is_central
