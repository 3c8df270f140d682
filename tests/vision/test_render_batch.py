"""A batch of frames rendered in one pass: each image the one rendered alone, by hash."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from radial_ibvs_gym.camera import Imperfections, paper_camera
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer, RoomScene

ROOM = (6.0, 5.0)
BEACONS = np.array(
    [[1.2, 0.0, 1.10], [4.9, 0.0, 1.25], [6.0, 1.6, 0.95], [2.0, 5.0, 1.05], [0.0, 1.4, 0.60]]
)
_RENDERERS: dict[str, OmniRenderer] = {}


def _renderer(kind: str) -> OmniRenderer:
    if kind not in _RENDERERS:
        camera = {
            "central": paper_camera("A"),
            "imperfect": paper_camera(
                "B",
                non_central_offset=0.01,
                imperfections=Imperfections(tilt=(0.02, -0.01), axis_offset=(0.004, -0.003)),
            ),
        }[kind]
        _RENDERERS[kind] = OmniRenderer(camera, size=80, camera_height=1.0)
    return _RENDERERS[kind]


def _digest(image: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(image).tobytes()).hexdigest()


_POSE = st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(-math.pi, math.pi))


@settings(max_examples=40, deadline=None)
@given(
    kind=st.sampled_from(["central", "imperfect"]),
    places=st.lists(_POSE, min_size=1, max_size=6),
    quality=st.sampled_from(
        [
            ImageQuality(),
            ImageQuality(exposure=0.7),
            ImageQuality(noise_std=4.0),
            ImageQuality(noise_std=2.0, blur_sigma=0.8, exposure=1.2),
        ]
    ),
    seed=st.integers(0, 2**31),
)
def test_a_batch_gives_each_frame_the_image_rendered_alone(
    kind: str, places: list[tuple[float, float, float]], quality: ImageQuality, seed: int
) -> None:
    """Poses anywhere (at the walls too), through a central and a tilted non-central camera."""
    renderer = _renderer(kind)
    scene = RoomScene(size=ROOM, height=2.8, beacons=BEACONS, beacon_radius=0.15)
    poses = np.array([[a * ROOM[0], b * ROOM[1], yaw] for a, b, yaw in places])
    seeds = [seed + i for i in range(len(poses))]
    batch = renderer.render_batch(
        poses, scene, quality, [np.random.default_rng(s) for s in seeds]
    )
    assert batch.shape == (len(poses), 80, 80) and batch.dtype == np.uint8
    alone = [
        renderer.render(pose, scene, quality, np.random.default_rng(s))
        for pose, s in zip(poses, seeds, strict=True)
    ]
    assert [_digest(image) for image in batch] == [_digest(image) for image in alone]


def test_bad_batches_are_clear_errors() -> None:
    renderer = _renderer("central")
    scene = RoomScene(size=ROOM, height=2.8, beacons=BEACONS, beacon_radius=0.15)
    with pytest.raises(ValueError, match=r"poses must have shape \(B, 3\)"):
        renderer.render_batch(np.zeros((0, 3)), scene)
    with pytest.raises(ValueError, match="one generator per pose"):
        renderer.render_batch(np.ones((2, 3)), scene, rngs=[None])
    with pytest.raises(ValueError, match="see render_batch"):
        renderer.render(np.ones((2, 3)), scene)
    with pytest.raises(ValueError, match="finite"):
        renderer.render_batch(np.array([[1.0, np.nan, 0.0]]), scene)
