"""Many cameras projected at once: the same numbers as each camera's own projection."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.camera import (
    CatadioptricCamera,
    Imperfections,
    Intrinsics,
    Sphere,
    forward_batch,
    paper_camera,
    shares_reflection,
)
from radial_ibvs_gym.camera import measurement as logic

K = Intrinsics(fx=1100.0, fy=1000.0, mu_x=640.5, mu_y=511.0, width=1280, height=1024)


def _points(rng: np.random.Generator, k: int, n: int) -> np.ndarray:
    """Landmarks around the camera, 0.3-8 m away, from below to above the mirror's view.

    Each row ends with a point the mirror shows (3 m away, 1 m below the camera) and one it
    cannot (on the axis), so that every test sees both kinds.
    """
    r = rng.uniform(0.3, 8.0, (k, n))
    phi = rng.uniform(-np.pi, np.pi, (k, n))
    z = rng.uniform(-0.6, 1.5, (k, n))
    drawn = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
    fixed = np.broadcast_to([[3.0, 0.0, -1.0], [0.0, 0.0, 2.0]], (k, 2, 3))
    return np.concatenate([drawn, fixed], axis=1)


def _imperfections(rng: np.random.Generator) -> Imperfections:
    return Imperfections(
        principal_point_offset=(float(rng.uniform(-4, 4)), float(rng.uniform(-4, 4))),
        focal_ratio_error=float(rng.uniform(-0.03, 0.03)),
        pixel_noise_std=float(rng.choice([0.0, rng.uniform(0.1, 1.5)])),
    )


def _assert_rows_equal(batch: Any, rows: list[Any]) -> None:
    for field in ("pixels", "mirror_points", "visible"):
        expected = np.stack([getattr(r, field) for r in rows])
        np.testing.assert_array_equal(getattr(batch, field), expected, err_msg=field)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    mirror=st.sampled_from(["A", "B"]),
    offset=st.sampled_from([0.0, 0.01, -0.005]),
    k=st.integers(1, 6),
)
def test_the_batch_equals_each_cameras_forward_bit_for_bit(
    seed: int, mirror: str, offset: float, k: int
) -> None:
    rng = np.random.default_rng(seed)
    cameras = [paper_camera(mirror, offset, _imperfections(rng)) for _ in range(k)]
    points = _points(rng, k, 12)
    batch = forward_batch(cameras, points, [np.random.default_rng(seed + i) for i in range(k)])
    rows = [c.forward(points[i], np.random.default_rng(seed + i)) for i, c in enumerate(cameras)]
    _assert_rows_equal(batch, rows)
    assert batch.visible[:, -2].all() and not batch.visible[:, -1].any()  # both kinds seen


def test_a_concave_mirror_keeps_its_self_occlusion() -> None:
    rng = np.random.default_rng(3)
    mirror = Sphere(radius=0.03, rim_radius=0.02)
    cameras = [
        CatadioptricCamera(mirror, K, camera_z=-0.08, imperfections=_imperfections(rng))
        for _ in range(3)
    ]
    points = _points(rng, 3, 40)
    batch = forward_batch(cameras, points)
    _assert_rows_equal(batch, [c.forward(points[i]) for i, c in enumerate(cameras)])


def test_tilted_or_mixed_cameras_fall_back_to_one_projection_each() -> None:
    rng = np.random.default_rng(4)
    tilted = paper_camera("A", 0.0, Imperfections(tilt=(0.01, 0.0), pixel_noise_std=0.5))
    plain = paper_camera("B", 0.0, _imperfections(rng))
    assert not shares_reflection([tilted, plain])
    assert not shares_reflection([paper_camera("A"), plain])  # another mirror
    assert shares_reflection([paper_camera("B"), plain])
    points = _points(rng, 2, 10)
    batch = forward_batch([tilted, plain], points, [np.random.default_rng(1), None])
    rows = [tilted.forward(points[0], np.random.default_rng(1)), plain.forward(points[1])]
    _assert_rows_equal(batch, rows)


def test_bad_shapes_and_counts_are_errors_naming_them() -> None:
    cameras = [paper_camera("A"), paper_camera("A")]
    with pytest.raises(ValueError, match=r"shape \(2, N, 3\)"):
        forward_batch(cameras, np.ones((3, 4, 3)))
    with pytest.raises(ValueError, match="1 generators for 2 cameras"):
        forward_batch(cameras, np.ones((2, 4, 3)), [None])
    with pytest.raises(ValueError, match="points"):
        forward_batch(cameras, np.full((2, 4, 3), np.nan))
    empty = forward_batch([], np.zeros((0, 4, 3)))
    assert empty.pixels.shape == (0, 4, 2) and empty.visible.shape == (0, 4)


def test_camera_images_equal_camera_image_per_row_mixed_ideal_and_imperfect() -> None:
    rng = np.random.default_rng(5)
    cameras = [paper_camera("A", 0.01, _imperfections(rng)) for _ in range(4)]
    cameras.insert(2, paper_camera("A", 0.01))  # an ideal one among them
    points = _points(rng, 5, 16)
    got = logic.camera_images(cameras, points, [np.random.default_rng(i) for i in range(5)])
    for i, camera in enumerate(cameras):
        want = logic.camera_image(camera, points[i], np.random.default_rng(i))
        np.testing.assert_array_equal(got[0][i], want[0])
        np.testing.assert_array_equal(got[1][i], want[1])


def test_vector_env_with_drawn_cameras_and_missed_detections_equals_sync() -> None:
    kwargs: dict[str, Any] = {
        "scenario": "random",
        "physics": "kinematic",
        "obs_mode": "features",
        "max_landmarks": 16,
        "max_episode_steps": 40,
        "camera": {
            "mirror": "A",
            "non_central_offset": 0.01,
            "imperfection_ranges": {
                "principal_point_offset": 3.0,
                "focal_ratio_error": 0.02,
                "pixel_noise_std": [0.5, 1.0],
            },
        },
        "missed_detections": {"rate": 0.05, "steps": [1, 4]},
    }
    native = gym.make_vec(
        "RadialIBVS/Parking-v0", num_envs=5, vectorization_mode="vector_entry_point", **kwargs
    )
    sync = gym.make_vec("RadialIBVS/Parking-v0", num_envs=5, vectorization_mode="sync", **kwargs)
    a, _ = native.reset(seed=9)
    b, _ = sync.reset(seed=9)
    rng = np.random.default_rng(2)
    ends = 0
    for _ in range(90):
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
        actions = rng.uniform(-1, 1, (5, 2))
        a, ra, ta, ua, _ = native.step(actions)
        b, rb, tb, ub, _ = sync.step(actions)
        np.testing.assert_array_equal(ra, rb)
        np.testing.assert_array_equal(ta | ua, tb | ub)
        ends += int((ta | ua).sum())
    assert ends >= 5  # the autoreset path ran
