"""The compiled root-find (numba, optional) gives the numpy path's bits, and stays optional."""

from __future__ import annotations

import os
import subprocess
import sys
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_catadioptric import scene_points

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.camera import CatadioptricCamera, meridian_jit, paper_camera
from radial_ibvs_gym.camera.mirrors import Hyperboloid
from radial_ibvs_gym.camera.presets import MIRROR_A, MIRROR_B

pytest.importorskip("numba")


def _both(call: Any, *args: Any) -> tuple[Any, Any]:
    """``call(*args)`` through numpy (``RADIAL_IBVS_JIT=0``) and through the compiled loop."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("RADIAL_IBVS_JIT", "0")
        assert meridian_jit.kernel() is None
        plain = call(*args)
        patch.setenv("RADIAL_IBVS_JIT", "1")
        assert meridian_jit.kernel() is not None
        compiled = call(*args)
    return plain, compiled


@settings(max_examples=30, deadline=None)
@given(
    mirror=st.sampled_from([MIRROR_A, MIRROR_B]),
    offset=st.floats(-0.01, 0.012),
    seed=st.integers(0, 2**32 - 1),
    near=st.booleans(),
)
def test_the_compiled_roots_have_the_numpy_bits(
    mirror: Hyperboloid, offset: float, seed: int, near: bool
) -> None:
    """Points all around, beyond the field of view too, and nearer than the table reaches."""
    intrinsics = paper_camera("A").intrinsics
    camera = CatadioptricCamera(mirror, intrinsics, camera_z=-mirror.e + offset)
    rng = np.random.default_rng(seed)
    points = scene_points(camera, rng, 300)
    if near:  # centimetres from the mirror: the grid search's points
        points *= rng.uniform(0.001, 0.2, (len(points), 1))
    rho, z = np.hypot(points[:, 0], points[:, 1]), points[:, 2] + camera.camera_z
    plain, compiled = _both(camera._solver.solve, rho, z)
    np.testing.assert_array_equal(plain, compiled)  # NaN where both find none
    assert np.isfinite(plain).any()


def test_an_imperfect_vector_env_steps_the_same_bits_with_and_without_numba() -> None:
    camera = {
        "mirror": "B",
        "non_central_offset": 0.01,
        "imperfection_ranges": {"principal_point_offset": 3.0, "pixel_noise_std": [0.5, 1.0]},
    }

    def run() -> list[np.ndarray]:
        envs = gym.make_vec(
            "RadialIBVS/Parking-v0",
            num_envs=8,
            vectorization_mode="vector_entry_point",
            physics="kinematic",
            camera=camera,
        )
        obs, _ = envs.reset(seed=11)
        rng = np.random.default_rng(0)
        seen = [obs["points"].copy()]
        for _ in range(30):
            obs, *_ = envs.step(rng.uniform(-1, 1, (8, 2)).astype(np.float32))
            seen.append(obs["points"].copy())
        return seen

    plain, compiled = _both(run)
    for a, b in zip(plain, compiled, strict=True):
        np.testing.assert_array_equal(a, b)


def test_the_maths_imports_without_numba_and_runs_without_it() -> None:
    """numba loads at the first root-find, never with the maths; RADIAL_IBVS_JIT=0 skips it."""
    code = (
        "import sys, numpy as np\n"
        "from radial_ibvs_gym.camera import paper_camera\n"
        "assert 'numba' not in sys.modules\n"
        "camera = paper_camera('A', non_central_offset=0.01)\n"
        "assert np.isfinite(camera.forward(np.array([[2.0, 1.0, 0.5]])).pixels).all()\n"
        "print('numba' in sys.modules)\n"
    )
    for flag, loaded in (("0", "False"), ("1", "True")):
        env = {**os.environ, "RADIAL_IBVS_JIT": flag}
        out = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        )
        assert out.stdout.strip() == loaded
