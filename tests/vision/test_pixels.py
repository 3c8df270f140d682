"""Rendered omnidirectional images, their measurement (OpenCV) and beacon correspondence."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from radial_ibvs_gym.camera import Imperfections, paper_camera
from radial_ibvs_gym.geometry import world_to_camera
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer, RoomScene
from radial_ibvs_gym.vision.detect import detect_beacons, fit_mirror_border, measure
from radial_ibvs_gym.vision.track import BeaconTracker, assign

HEIGHT = 1.0  # camera height above the floor, metres (the paper-lab robot)
ROOM = (6.0, 5.0)
#: beacons on the four walls, 0.6-1.3 m high (as in the paper-lab scenario)
BEACONS = np.array(
    [
        [1.2, 0.0, 1.10],
        [3.1, 0.0, 0.80],
        [4.9, 0.0, 1.25],
        [6.0, 1.6, 0.95],
        [6.0, 3.7, 1.20],
        [4.3, 5.0, 0.70],
        [2.0, 5.0, 1.05],
        [0.0, 3.9, 1.30],
        [0.0, 1.4, 0.60],
    ]
)
POSES = [np.array([3.0, 2.5, 0.0]), np.array([1.7, 1.4, 2.1]), np.array([4.4, 3.6, -1.2])]


def _scene(radius: float) -> RoomScene:
    return RoomScene(size=ROOM, height=2.8, beacons=BEACONS, beacon_radius=radius)


def _projected(renderer: OmniRenderer, pose: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Forward projection of world points into the rendered image (NaN where hidden)."""
    proj = renderer.camera.forward(world_to_camera(points, pose, HEIGHT))
    return renderer.sensor_to_image(proj.pixels)


def _disc_outline(centre: np.ndarray, radius: float, n: int = 720) -> np.ndarray:
    """Points ``(n, 3)`` on the rim of a beacon disc lying in its wall."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    along = np.array([0.0, 1.0, 0.0]) if centre[0] in (0.0, ROOM[0]) else np.array([1.0, 0, 0])
    return centre + radius * (np.cos(t)[:, None] * along + np.sin(t)[:, None] * [0.0, 0.0, 1.0])


def _polygon_centroid(poly: np.ndarray) -> np.ndarray:
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2.0
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6.0 * area)


@pytest.fixture(scope="module")
def camera():
    return paper_camera("A", non_central_offset=0.01)


@pytest.mark.parametrize("pose", POSES, ids=["goal", "corner", "turned"])
def test_small_beacon_centres_match_the_forward_projection_to_sub_pixel(camera, pose) -> None:
    renderer = OmniRenderer(camera, size=512, camera_height=HEIGHT)
    image = renderer.render(pose, _scene(0.03))
    result = measure(image)
    assert result.status == "ok"
    expected = _projected(renderer, pose, BEACONS)
    expected = expected[np.isfinite(expected[:, 0])]
    match = assign(expected, result.centres, gate=3.0)
    assert (match >= 0).all(), "every visible beacon is detected"
    error = np.linalg.norm(result.centres[match] - expected, axis=-1)
    assert error.max() < 0.35, error  # pixels of the 512 x 512 image


def test_large_beacons_have_the_known_bias_the_centroid_of_their_image(camera) -> None:
    # a 25 cm disc's image centroid is not the image of its centre (the mapping is not affine);
    # the detector finds the centroid of the disc's image, the known bias
    pose = POSES[0]
    renderer = OmniRenderer(camera, size=512, camera_height=HEIGHT)
    radius = 0.25
    result = measure(renderer.render(pose, _scene(radius)))
    centres = _projected(renderer, pose, BEACONS)
    biases, errors = [], []
    for beacon, centre in zip(BEACONS, centres, strict=True):
        outline = _projected(renderer, pose, _disc_outline(beacon, radius))
        if not np.isfinite(outline).all():
            continue  # partly outside the field of view
        centroid = _polygon_centroid(outline)
        found = result.centres[np.argmin(np.linalg.norm(result.centres - centroid, axis=-1))]
        errors.append(np.linalg.norm(found - centroid))
        biases.append(np.linalg.norm(centroid - centre))
    assert len(errors) >= 6
    assert max(errors) < 0.15, errors  # pixels of the 512 x 512 image
    assert min(biases) > 3.0 * max(errors), biases  # the bias is real, and it is found


def test_border_fit_finds_the_true_principal_point_and_focal_ratio(camera) -> None:
    offset, ratio_error = (7.0, -4.0), 0.02
    imperfect = paper_camera(
        "A",
        non_central_offset=0.01,
        imperfections=Imperfections(principal_point_offset=offset, focal_ratio_error=ratio_error),
    )
    renderer = OmniRenderer(imperfect, size=384, camera_height=HEIGHT)
    border = fit_mirror_border(renderer.render(POSES[1], _scene(0.06)))
    assert border is not None
    truth = renderer.sensor_to_image(imperfect.true_intrinsics.principal_point)
    nominal = renderer.sensor_to_image(imperfect.intrinsics.principal_point)
    assert np.linalg.norm(border.centre - truth) < 0.15  # rendered pixels
    assert np.linalg.norm(border.centre - nominal) > 1.0  # and it is not the nominal one
    assert border.rho_f == pytest.approx(1.0 / (1.0 + ratio_error), rel=2e-3)


def test_detection_survives_noise_blur_and_exposure(camera) -> None:
    renderer = OmniRenderer(camera, size=384, camera_height=HEIGHT)
    pose = POSES[2]
    expected = _projected(renderer, pose, BEACONS)
    expected = expected[np.isfinite(expected[:, 0])]
    quality = ImageQuality(noise_std=6.0, blur_sigma=0.8, exposure=0.7)
    # 8 cm beacons: the farthest (4.9 m) is 3 pixels wide, blurred to a contrast of 60 %
    image = renderer.render(pose, _scene(0.08), quality, np.random.default_rng(3))
    result = measure(image)
    match = assign(expected, result.centres, gate=3.0)
    assert (match >= 0).all()
    assert len(result.centres) == len(expected)  # and no noise blob
    assert np.linalg.norm(result.centres[match] - expected, axis=-1).max() < 0.5


def test_blobs_cut_by_the_rim_and_spurious_dark_regions_are_rejected(camera) -> None:
    renderer = OmniRenderer(camera, size=384, camera_height=HEIGHT)
    pose = POSES[0]
    image = renderer.render(pose, _scene(0.06))
    border = fit_mirror_border(image)
    assert border is not None
    clean = detect_beacons(image, border)
    spoiled = image.copy()
    cx, cy = border.centre
    r = border.semi_axes[0]
    # a dark line (not blob-shaped), a large dark patch, and a blob on the rim
    spoiled[int(cy) + 40 : int(cy) + 42, int(cx) - 60 : int(cx) - 20] = 5
    spoiled[int(cy) - 110 : int(cy) - 60, int(cx) + 10 : int(cx) + 60] = 5
    rim = (int(cx + r * math.cos(2.5)), int(cy + r * math.sin(2.5)))
    spoiled[rim[1] - 6 : rim[1] + 6, rim[0] - 6 : rim[0] + 6] = 5
    found = detect_beacons(spoiled, border)
    assert found.rejected["shape"] >= 1 and found.rejected["size"] >= 1
    assert found.rejected["rim"] >= clean.rejected["rim"] + 1
    match = assign(clean.centres, found.centres, gate=0.01)
    assert (match >= 0).sum() >= len(clean.centres) - 1  # the patch may hide one beacon
    assert len(found.centres) == (match >= 0).sum()  # nothing spurious is kept


def test_bad_frames_give_a_status_not_an_exception(camera) -> None:
    black = np.zeros((128, 128), np.uint8)
    assert measure(black).status == "border_not_found"
    blank = OmniRenderer(camera, size=128, camera_height=HEIGHT).render(
        POSES[0], RoomScene(size=ROOM, height=2.8, beacons=np.zeros((0, 3)))
    )
    result = measure(blank)
    assert result.status == "no_beacons" and result.x_n.shape == (0, 2)
    with pytest.raises(ValueError, match="uint8"):
        measure(np.zeros((64, 64), np.float32))
    with pytest.raises(ValueError, match="not on a wall"):
        RoomScene(size=ROOM, height=2.8, beacons=[[1.0, 1.0, 1.0]])


def test_rendering_is_deterministic_under_the_seed(camera) -> None:
    renderer = OmniRenderer(camera, size=64, camera_height=HEIGHT)
    quality = ImageQuality(noise_std=5.0)
    a = renderer.render(POSES[1], _scene(0.08), quality, np.random.default_rng(7))
    b = renderer.render(POSES[1], _scene(0.08), quality, np.random.default_rng(7))
    np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="rng"):
        renderer.render(POSES[1], _scene(0.08), quality)


# --- correspondence ---------------------------------------------------------------------------
def _ring(azimuths_deg: np.ndarray, centre=(100.0, 100.0), radius=60.0) -> np.ndarray:
    a = np.radians(azimuths_deg)
    return np.stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)], -1)


def test_tracker_keeps_identities_through_turns_losses_and_extra_blobs() -> None:
    rng = np.random.default_rng(0)
    base = np.array([0.0, 40.0, 85.0, 130.0, 175.0, 220.0, 265.0, 310.0])
    centre = np.array([100.0, 100.0])
    tracker = BeaconTracker(len(base), gate_px=5.0, coast_frames=2)
    first = _ring(base)
    in_view = np.arange(len(base)) != 7  # beacon 7 enters the view at frame 5
    perm = rng.permutation(int(in_view.sum()))  # the detector's order is arbitrary
    match = tracker.start(first[in_view][perm], first, centre)
    assert match[7] == -1
    np.testing.assert_array_equal(perm[match[:7]], np.arange(7))
    heading, rate = 0.0, 0.0
    for frame in range(1, 60):
        rate = min(rate + 2.0, 14.0) if frame < 30 else max(rate - 3.0, -10.0)  # turning
        heading += rate
        truth = _ring(base + heading)
        present = np.ones(len(base), bool)
        present[7] = frame >= 5
        if 10 <= frame < 25:
            present[3] = False  # beacon 3 leaves the view and comes back
        if frame in (40, 41):
            present[6] = False  # beacon 6 missed for two frames (coasting)
        blobs = truth[present]
        if frame % 7 == 0:
            blobs = np.vstack([blobs, _ring(np.array([heading + 20.0]), radius=30.0)])  # extra
        order = rng.permutation(len(blobs))
        match = tracker.update(blobs[order], centre)
        ids = np.flatnonzero(present)
        for k in range(len(base)):
            if match[k] >= 0:
                hit = blobs[order][match[k]]
                assert np.allclose(hit, truth[k]), f"frame {frame}: landmark {k} mislabelled"
        matched = {k for k in range(len(base)) if match[k] >= 0}
        if 6 <= frame < 10:
            assert 7 in matched, f"frame {frame}: beacon 7 not acquired on entering the view"
        if frame >= 26:
            assert set(ids) == matched, f"frame {frame}: {sorted(matched)} vs {sorted(ids)}"
    assert tracker.tracked.all()


def test_assign_respects_the_gate_and_takes_nearest_pairs_first() -> None:
    predicted = np.array([[0.0, 0.0], [10.0, 0.0], [np.nan, np.nan]])
    blobs = np.array([[9.0, 0.0], [0.5, 0.0], [50.0, 50.0]])
    np.testing.assert_array_equal(assign(predicted, blobs, gate=2.0), [1, 0, -1])
    np.testing.assert_array_equal(assign(predicted, blobs, gate=0.2), [-1, -1, -1])
    np.testing.assert_array_equal(assign(predicted, np.zeros((0, 2)), gate=2.0), [-1, -1, -1])


# --- the detected observation mode of the environments -----------------------------------------
def _detected_env(**kwargs):
    import gymnasium as gym

    import radial_ibvs_gym  # noqa: F401  (registers the envs)

    options = {"scenario": "paper-lab", "physics": "kinematic", "goal_depths": True}
    return gym.make("RadialIBVS/Parking-v0", **{**options, "measurement": "detected", **kwargs})


def _angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=-1)))


def test_detected_points_are_the_ideal_ones_with_the_right_identities() -> None:
    from radial_ibvs_agents import make_policy

    env = _detected_env()
    policy = make_policy("ibvs")
    obs, info = env.reset(seed=4)
    core = env.unwrapped
    worst, steps, done = 0.0, 0, False
    while not done:
        ideal, ideal_visible = core.image(
            core._setup, info["robot_pose"], "current", core.np_random
        )
        seen = obs["visible"] > 0.5
        assert (ideal_visible | ~seen).all()  # nothing is seen that the camera cannot see
        detected = obs["points"].reshape(-1, 2).astype(np.float64)[seen]
        worst = max(worst, float(np.degrees(_angle_between(detected, ideal[seen])).max()))
        action, _ = policy.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        done, steps = terminated or truncated, steps + 1
    assert info["is_success"]
    assert worst < 0.5, worst  # degrees: every tracked beacon is the right landmark


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_the_papers_ibvs_parks_from_pixels_in_paper_lab(seed: int) -> None:
    from radial_ibvs_agents import make_policy

    env = _detected_env(success_position_m=0.02, success_heading_deg=2.0)
    policy = make_policy("ibvs")
    obs, info = env.reset(seed=seed)
    done = False
    while not done:
        action, _ = policy.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        done = terminated or truncated
    assert info["is_success"], info
    assert info["position_error_m"] <= 0.02 and info["heading_error_deg"] <= 2.0
    assert info["detection"]["status"] == "ok"


def test_detected_mode_is_deterministic_under_the_seed() -> None:
    runs = []
    for _ in range(2):
        env = _detected_env(image_noise=4.0, image_size=128)
        obs, _ = env.reset(seed=11)
        trace = [obs["points"].copy()]
        for _ in range(10):
            obs, *_ = env.step(np.array([0.5, 0.3], np.float32))
            trace.append(obs["points"].copy())
        runs.append(np.stack(trace))
    np.testing.assert_array_equal(runs[0], runs[1])


def test_frames_without_beacons_give_a_status_then_the_episode_ends_lost() -> None:
    from radial_ibvs_agents import make_policy

    env = _detected_env()
    policy = make_policy("ibvs")
    obs, info = env.reset(seed=2)
    detector = env.unwrapped._detector
    renderer = detector._renderer("current")
    blank = np.full((renderer.size, renderer.size), 90, np.uint8)  # a grey frame: no beacon
    renderer.render = lambda *args, **kwargs: blank  # the camera goes blind
    statuses, visible = [], []
    for _ in range(10):
        action, _ = policy.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        statuses.append(info["detection"]["status"])
        visible.append(info["n_visible"])
        if terminated or truncated:
            break
    assert set(statuses) == {"no_beacons"}
    assert visible[0] > 0 and visible[-1] == 0  # coasting, then hidden
    assert terminated and not info["is_success"]
    assert info["reward_lost"] < 0
    last, _ = policy.predict(obs)
    np.testing.assert_array_equal(last, 0.0)  # the IBVS stops with too few points


def test_bad_detected_mode_arguments_are_rejected() -> None:
    with pytest.raises(ValueError, match="measurement"):
        _detected_env(measurement="pixels")
    with pytest.raises(ValueError, match="beacon_radius"):
        _detected_env(beacon_radius=0.0)
    with pytest.raises(ValueError, match="size"):
        _detected_env(image_size=8)


def test_the_image_command_draws_the_measurement(tmp_path) -> None:
    from radial_ibvs_agents.cli import main
    from radial_ibvs_agents.experiments.pixels import detection_accuracy

    out = tmp_path / "pixels.png"
    assert main(["image", "--scenario", "paper-lab", "--seed", "1", "--out", str(out)]) == 0
    assert out.stat().st_size > 10_000
    accuracy = detection_accuracy(n_images=4)
    assert accuracy["detected"] > 0.9 and accuracy["spurious"] == 0
    assert accuracy["p95_px"] < 0.5 and accuracy["principal_point_px"] < 0.1


def test_a_goal_image_without_a_mirror_border_is_a_clear_error_at_reset() -> None:
    env = _detected_env(exposure=1e-4)  # a black frame
    with pytest.raises(ValueError, match="mirror border was not found"):
        env.reset(seed=0)


def test_a_goal_image_from_another_mirror_gets_its_own_calibration_and_the_ibvs_parks() -> None:
    from radial_ibvs_agents import make_policy

    # mirror B, its principal point 8 px off: its own border fit must calibrate the goal image
    goal_camera = {
        "mirror": "B",
        "non_central_offset": 0.01,
        "imperfections": {"principal_point_offset": [8.0, -5.0]},
    }
    env = _detected_env(goal_camera=goal_camera)
    policy = make_policy("ibvs")
    obs, info = env.reset(seed=1)
    detector = env.unwrapped._detector
    goal_border = fit_mirror_border(detector.last["goal"].image)
    current_border = fit_mirror_border(detector.last["current"].image)
    assert goal_border is not None and current_border is not None
    assert np.linalg.norm(goal_border.centre - current_border.centre) > 1.0
    np.testing.assert_allclose(info["detection"]["principal_point_px"], current_border.centre)
    done = False
    while not done:
        action, _ = policy.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        done = terminated or truncated
    assert info["is_success"], info


def test_random_rooms_redraw_an_episode_whose_goal_image_shows_too_few_beacons() -> None:
    # 2 of these 60 first draws show only 2 detectable beacons at the goal: they are redrawn
    env = _detected_env(scenario="random")
    goals = []
    for seed in range(60):
        _, info = env.reset(seed=seed)
        assert (env.unwrapped._setup.goal_visible.sum()) >= 3
        goals.append(info["goal_pose"])
    _, info = env.reset(seed=17)
    np.testing.assert_array_equal(info["goal_pose"], goals[17])  # still one draw per seed
    tiny = _detected_env(scenario="random", beacon_radius=0.001)  # beacons nobody can see
    with pytest.raises(ValueError, match=r"detected at the goal .* \(in 10 draws\)"):
        tiny.reset(seed=0)


@settings(max_examples=60, deadline=None)
@given(values=st.lists(st.integers(0, 255), min_size=1, max_size=400))
def test_the_median_grey_level_is_numpys_median(values: list[int]) -> None:
    from radial_ibvs_gym.vision.detect import _median_grey

    grey = np.asarray(values, dtype=np.uint8)
    assert _median_grey(grey) == float(np.median(grey))


def test_a_beacon_larger_than_the_room_is_refused() -> None:
    with pytest.raises(ValueError, match="beacon_radius"):
        RoomScene(size=(0.1, 4.0), height=2.8, beacons=np.array([[0.0, 1.0, 1.0]]))


def _meet_every_surface(
    renderer: OmniRenderer, pose: np.ndarray, scene: RoomScene
) -> tuple[np.ndarray, list[np.ndarray]]:
    """The plain renderer: every ray met with the four walls, the floor and the ceiling.

    Returns the rays' shades ``(R,)`` and, for each beacon, the rays that meet it ``(R,)``.
    """
    x, y, yaw = (float(v) for v in pose)
    c, s = math.cos(yaw), math.sin(yaw)
    o, d = renderer._origins, renderer._directions
    ox = x + c * o[:, 0] - s * o[:, 1]
    oy = y + s * o[:, 0] + c * o[:, 1]
    dx = c * d[:, 0] - s * d[:, 1]
    dy = s * d[:, 0] + c * d[:, 1]
    oz = renderer.camera_height + o[:, 2]
    dz = d[:, 2]
    w, depth = scene.size
    with np.errstate(divide="ignore", invalid="ignore"):
        tz = np.where(dz > 0, scene.height - oz, -oz) / dz
        tx = np.where(dx > 0, w - ox, -ox) / dx
        ty = np.where(dy > 0, depth - oy, -oy) / dy
    tx, ty, tz = (np.where(t >= 0, t, np.inf) for t in (tx, ty, tz))
    on_x = (tx <= ty) & (tx <= tz)
    on_y = ~on_x & (ty <= tz)
    t = np.where(on_x, tx, np.where(on_y, ty, tz))
    shade = np.where(on_x, 0.78, np.where(on_y, 0.66, renderer._flat_shade))
    shade = shade / (1.0 + 0.03 * t)
    hit = np.stack([ox + t * dx, oy + t * dy, oz + t * dz], axis=-1)
    met = []
    for beacon, wall in zip(scene.beacons, scene.walls, strict=True):
        on_wall = (on_x if wall < 2 else on_y) & (
            ((dx if wall < 2 else dy) < 0) if wall % 2 == 0 else ((dx if wall < 2 else dy) > 0)
        )
        near = ((hit - beacon) ** 2).sum(axis=-1) < scene.beacon_radius**2
        met.append(on_wall & near)
        shade[on_wall & near] = 0.06
    return shade, met


def _shade_every_ray_with_every_surface(
    renderer: OmniRenderer, pose: np.ndarray, scene: RoomScene
) -> np.ndarray:
    """The plain renderer's image ``(S, S)``."""
    image = renderer._background.copy().reshape(-1)
    image[renderer._index] = _meet_every_surface(renderer, pose, scene)[0]
    return image.reshape(renderer.size, renderer.size)


_RENDERERS: dict[str, OmniRenderer] = {}


def _small_renderer(kind: str) -> OmniRenderer:
    if kind not in _RENDERERS:
        cameras = {
            "central": paper_camera("A"),
            "non-central": paper_camera("B", non_central_offset=0.01),
            "imperfect": paper_camera(
                "A",
                non_central_offset=-0.005,
                imperfections=Imperfections(tilt=(0.02, -0.01), axis_offset=(0.004, -0.003)),
            ),
        }
        _RENDERERS[kind] = OmniRenderer(cameras[kind], size=96, camera_height=HEIGHT)
    return _RENDERERS[kind]


@settings(max_examples=80, deadline=None)
@given(
    kind=st.sampled_from(["central", "non-central", "imperfect"]),
    height=st.sampled_from([2.8, 1.6, 3.5]),
    where=st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
    wall_gap=st.one_of(st.none(), st.integers(0, 10_000), st.floats(-1e-6, 1e-6)),
    yaw=st.floats(-math.pi, math.pi),
    exposure=st.sampled_from([1.0, 0.7, 1.6]),
)
def test_the_image_is_the_same_bits_as_meeting_every_ray_with_every_surface(
    kind: str, height: float, where: tuple[float, float], wall_gap, yaw: float, exposure: float
) -> None:
    """Poses anywhere in the room, at a wall, and at a ray's floor-hit distance from a wall.

    The grey levels, and the quantised image (which requantises only the rays met with the
    walls, over a cached image of the others).
    """
    renderer = _small_renderer(kind)
    scene = RoomScene(size=ROOM, height=height, beacons=BEACONS, beacon_radius=0.15)
    x, y = where[0] * ROOM[0], where[1] * ROOM[1]
    if wall_gap is not None:
        # the robot as far from the x = 0 wall as a ray's floor or ceiling hit reaches, the
        # edge between the rays sorted out as on the floor and those met with the walls
        reach = renderer._vertical(height).reach
        reach = reach[np.isfinite(reach) & (reach < min(ROOM) / 2)]
        if isinstance(wall_gap, int):
            x = float(reach[wall_gap % len(reach)])
        else:
            x = float(reach[len(reach) // 2]) + wall_gap
    pose = np.array([x, y, yaw])
    reference = _shade_every_ray_with_every_surface(renderer, pose, scene)
    np.testing.assert_array_equal(renderer.shade(pose, scene), reference)
    quantised = np.clip(np.rint(255.0 * exposure * reference), 0, 255).astype(np.uint8)
    image = renderer.render(pose, scene, ImageQuality(exposure=exposure))
    np.testing.assert_array_equal(image, quantised)


@settings(max_examples=60, deadline=None)
@given(
    kind=st.sampled_from(["central", "non-central", "imperfect"]),
    where=st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
    yaw=st.floats(-math.pi, math.pi),
    radius=st.sampled_from([0.02, 0.15, 0.6]),
)
def test_the_rays_tried_on_a_beacon_hold_every_ray_that_meets_it(
    kind: str, where: tuple[float, float], yaw: float, radius: float
) -> None:
    """The renderer tries each beacon on the rays of an azimuth window about its bearing.

    Near a wall, with beacons from a few pixels to larger than the window's fall-back
    distance, and rays from the tilted, off-axis mirror of the imperfect camera.
    """
    from radial_ibvs_gym.vision.room_rays import near_beacons

    renderer = _small_renderer(kind)
    scene = RoomScene(size=ROOM, height=2.8, beacons=BEACONS, beacon_radius=radius)
    pose = np.array([where[0] * ROOM[0], where[1] * ROOM[1], yaw])
    _, met = _meet_every_surface(renderer, pose, scene)
    v = renderer._vertical(scene.height)
    position = np.empty(len(v.index), dtype=np.intp)  # each ray's place in the sorted rays
    position[np.searchsorted(renderer._index, v.index)] = np.arange(len(v.index))
    k = len(v.index) // 3  # the rays from the k-th on
    c, s = math.cos(yaw), math.sin(yaw)
    for x_walls in (True, False):
        tried, owner = near_beacons(v, k, pose[0], pose[1], c, s, scene, x_walls)
        assert tried.min(initial=0) >= 0 and tried.max(initial=0) < len(v.index) - k
        for j, rays in enumerate(met):
            if (scene.walls[j] < 2) == x_walls:
                meeting = position[rays]
                assert np.isin(meeting[meeting >= k] - k, tried[owner == j]).all()


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    shape=st.tuples(st.integers(1, 70), st.integers(1, 70)),
    density=st.floats(0.0, 1.0),
)
def test_the_labelling_gives_opencvs_default_labels_and_statistics(
    seed: int, shape: tuple[int, int], density: float
) -> None:
    import cv2

    from radial_ibvs_gym.vision.detect import _label

    dark = (np.random.default_rng(seed).random(shape) < density).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(dark, connectivity=8)
    used, used_stats = _label(dark)
    np.testing.assert_array_equal(used, labels)
    np.testing.assert_array_equal(np.array(used_stats, dtype=np.int32).reshape(-1, 5), stats[1:])
    assert len(used_stats) == n - 1


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    threshold=st.one_of(
        st.floats(allow_nan=True, allow_infinity=True),
        st.floats(-2.0, 258.0),
        st.integers(-2, 258).map(float),
    ),
)
def test_the_integer_comparison_is_the_float_one(seed: int, threshold: float) -> None:
    from radial_ibvs_gym.vision.detect import _below

    image = np.random.default_rng(seed).integers(0, 256, (9, 31), dtype=np.uint8)
    image.flat[:4] = (0, 255, 128, 127)
    np.testing.assert_array_equal(_below(image, threshold), image < threshold)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), side=st.integers(1, 40), share=st.floats(0.01, 1.0))
def test_the_masked_median_is_numpys_median_of_the_masked_pixels(
    seed: int, side: int, share: float
) -> None:
    from radial_ibvs_gym.vision.detect import _median_in

    rng = np.random.default_rng(seed)
    image = rng.integers(0, 256, (side, side + 3), dtype=np.uint8)
    mask = rng.random(image.shape) < share
    mask.flat[rng.integers(mask.size)] = True  # at least one pixel
    assert _median_in(image, mask.astype(np.uint8)) == float(np.median(image[mask]))
