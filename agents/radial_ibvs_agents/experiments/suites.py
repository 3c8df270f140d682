"""The benchmark's suites: which envs, variants and seeds every policy is run on.

Every suite is a list of variants; a variant is a label, a scenario, ``gym.make`` overrides and
an episode count. Episode ``k`` is seeded ``seed_offset + k`` (0, or :data:`HELD_OUT_SEED` in
the generalisation suites); in the suites built on ``paper-sim`` it runs task ``k % 4``.
Everything runs on the kinematic backend, except for the ``physics`` suite. The ``imperfect``
suite (100 held-out random rooms per variant) sees them through a real camera: 1 px of pixel
noise; a principal point 2 px and -1 px off with a focal ratio 1 % off; both; and
imperfections drawn per episode (principal point up to 3 px, focal ratio up to 2 %, noise
0.5-1 px). The ``unseen-scenes`` suite (200 episodes per variant) draws scenes from the
held-out family ``random-unseen``: larger rooms, more landmarks and a lower camera than any
training run saw, through the ideal camera and the real one (all imperfections; the goal
image one frame, or averaged over 30).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

__all__ = ["HELD_OUT_SEED", "SUITES", "Variant", "suite_variants"]

_MIRROR_A = {"mirror": "A", "non_central_offset": 0.01}  # paper-sim's camera
#: the detected-points set-ups: paper-sim's room is 15.6 m wide, so larger beacons and images
_PIXELS_SIM: dict[str, Any] = {"measurement": "detected", "image_size": 384, "beacon_radius": 0.1}
_PIXELS_LAB: dict[str, Any] = {"measurement": "detected", "image_size": 256, "beacon_radius": 0.08}


@dataclass(frozen=True)
class Variant:
    """One configuration of a suite.

    Attributes
    ----------
    suite, label
        Names in the rows (``suite``, ``variant``).
    scenario
        Scenario name.
    overrides
        ``gym.make`` keyword arguments on top of the policy's needs.
    episodes
        Default number of episodes.
    cycle_tasks
        Episode ``k`` runs task ``k % n_tasks`` (the paper's four tasks).
    seed_offset
        Episode ``k`` is seeded ``seed_offset + k`` (held-out seeds: no training run of this
        project draws its episodes from seeds this large).
    """

    suite: str
    label: str
    scenario: str
    overrides: dict[str, Any] = field(default_factory=dict)
    episodes: int = 8
    cycle_tasks: bool = True
    seed_offset: int = 0


#: first seed of the held-out episodes (training uses small seeds, its evaluations 10,000+)
HELD_OUT_SEED = 100_000


def _camera(**imperfections: Any) -> dict[str, Any]:
    return {"camera": {**_MIRROR_A, "imperfections": imperfections}}


#: the camera of the random rooms (configs/scenarios/random.yaml)
_RANDOM_CAMERA = {"mirror": "A", "non_central_offset": 0.01}
#: a real camera's calibration errors: principal point (2, -1) px, focal ratio +1 %
_CALIBRATION = {"principal_point_offset": [2.0, -1.0], "focal_ratio_error": 0.01}


def _imperfect(label: str, episodes: int = 100, **camera: Any) -> Variant:
    """Return a variant of the ``imperfect`` suite: held-out random rooms, a real camera."""
    overrides = {"physics": "kinematic", "camera": {**_RANDOM_CAMERA, **camera}}
    return Variant("imperfect", label, "random", overrides, episodes, False, HELD_OUT_SEED)


def _unseen(label: str, **overrides: Any) -> Variant:
    """Return a real-camera variant of ``unseen-scenes``: all imperfections together."""
    camera = {**_RANDOM_CAMERA, "imperfections": {**_CALIBRATION, "pixel_noise_std": 1.0}}
    overrides = {"physics": "kinematic", "camera": camera, **overrides}
    return Variant("unseen-scenes", label, "random-unseen", overrides, 200, False, HELD_OUT_SEED)


def _paper(suite: str, label: str, episodes: int = 8, **overrides: Any) -> Variant:
    return Variant(suite, label, "paper-sim", {"physics": "kinematic", **overrides}, episodes)


SUITES: dict[str, list[Variant]] = {
    "paper": [_paper("paper", "d*"), _paper("paper", "1.3 d*", depth_scale=1.3)],
    "random": [Variant("random", "random rooms", "random", {"physics": "kinematic"}, 200, False)],
    "noise": [
        _paper("noise", f"{sigma} px", **_camera(pixel_noise_std=sigma))
        for sigma in (0.0, 0.5, 1.0, 2.0)
    ],
    "calibration": [
        _paper("calibration", "exact"),
        _paper("calibration", "pp (2, -1) px", **_camera(principal_point_offset=[2.0, -1.0])),
        _paper("calibration", "pp (5, -3) px", **_camera(principal_point_offset=[5.0, -3.0])),
        _paper("calibration", "fy +2 %", **_camera(focal_ratio_error=0.02)),
    ],
    "mirror-swap": [
        _paper("mirror-swap", "goal mirror A"),
        _paper(
            "mirror-swap", "goal mirror B", goal_camera={"mirror": "B", "non_central_offset": 0.01}
        ),
    ],
    # generalisation: rooms, labs and cameras that no model was trained on
    "held-out": [
        Variant(
            "held-out",
            "random rooms",
            "random",
            {"physics": "kinematic"},
            200,
            False,
            HELD_OUT_SEED,
        ),
    ],
    # the held-out scene family: rooms, landmark counts and camera heights outside every
    # training range (configs/scenarios/random-unseen.yaml), ideal and through a real camera
    "unseen-scenes": [
        Variant(
            "unseen-scenes",
            "unseen scenes",
            "random-unseen",
            {"physics": "kinematic"},
            200,
            False,
            HELD_OUT_SEED,
        ),
        _unseen("unseen scenes, imperfect all together"),
        _unseen("unseen scenes, imperfect all together, goal over 30 frames", goal_image_frames=30),
    ],
    "paper-lab": [
        Variant("paper-lab", "zero-shot", "paper-lab", {"physics": "kinematic"}, 8, False),
    ],
    "cross-camera": [
        Variant(
            "cross-camera",
            "random rooms, mirror B",
            "random",
            {"physics": "kinematic", "camera": {"mirror": "B", "non_central_offset": 0.01}},
            100,
            False,
            HELD_OUT_SEED,
        ),
        Variant(
            "cross-camera",
            "random rooms, camera at 1.2 m",
            "random",
            {"physics": "kinematic", "camera_height": 1.2},
            100,
            False,
            HELD_OUT_SEED,
        ),
    ],
    "obstacles": [
        Variant(
            "obstacles",
            "random rooms with obstacles",
            "random-obstacles",
            {"physics": "kinematic"},
            200,
            False,
            HELD_OUT_SEED,
        ),
    ],
    "physics": [
        _paper("physics", "kinematic"),
        _paper("physics", "pymunk", physics="pymunk"),
    ],
    # held-out random rooms through imperfect cameras: noise, calibration errors, both, and
    # imperfections drawn per episode
    "imperfect": [
        _imperfect("noise 1 px", imperfections={"pixel_noise_std": 1.0}),
        _imperfect("pp (2, -1) px, fy +1 %", imperfections=_CALIBRATION),
        _imperfect("all together", imperfections={**_CALIBRATION, "pixel_noise_std": 1.0}),
        _imperfect(
            "drawn per episode",
            imperfection_ranges={
                "principal_point_offset": 3.0,
                "focal_ratio_error": 0.02,
                "pixel_noise_std": [0.5, 1.0],
            },
        ),
        # a robot parked at the goal averages 30 noisy frames into its goal image
        replace(
            _imperfect("all together", imperfections={**_CALIBRATION, "pixel_noise_std": 1.0}),
            label="all together, goal over 30 frames",
            overrides={
                "physics": "kinematic",
                "camera": {
                    **_RANDOM_CAMERA,
                    "imperfections": {**_CALIBRATION, "pixel_noise_std": 1.0},
                },
                "goal_image_frames": 30,
            },
        ),
    ],
    # ideal points vs points measured in rendered images (render, detect, calibrate, match)
    "pixels": [
        _paper("pixels", "paper-sim ideal"),
        _paper("pixels", "paper-sim detected", **_PIXELS_SIM),
        Variant("pixels", "paper-lab ideal", "paper-lab", {"physics": "kinematic"}, 8, False),
        Variant(
            "pixels",
            "paper-lab detected",
            "paper-lab",
            {"physics": "kinematic", **_PIXELS_LAB},
            8,
            False,
        ),
    ],
}


def suite_variants(names: list[str] | tuple[str, ...]) -> list[Variant]:
    """List the variants of the named suites, in order.

    Raises
    ------
    ValueError
        For an unknown suite (the message lists the valid ones).
    """
    unknown = [n for n in names if n not in SUITES]
    if unknown:
        raise ValueError(f"unknown suite(s) {unknown}; valid: {list(SUITES)}")
    return [variant for name in names for variant in SUITES[name]]
