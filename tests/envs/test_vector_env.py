"""The native vector envs: the same numbers as SyncVectorEnv, batched physics, bad input, SB3."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs.autoreset import AutoresetMode
from radial_ibvs_gym.envs.parking_vector import ParkingVectorEnv
from radial_ibvs_gym.physics import RobotConfig, limit_command
from radial_ibvs_gym.physics.fleet import KinematicFleet, PymunkFleet, limit_commands

MODES = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP}
#: pymunk: the rooms sit apart in one space, so positions round differently (measured: 2e-13)
PYMUNK_TOL = 1e-6


def _compare(a: Any, b: Any, path: str, tol: float) -> None:
    """Equal trees of dicts and arrays: bools and ints exactly, floats within ``tol``."""
    if isinstance(a, dict):
        assert set(a) == set(b), (path, sorted(set(a) ^ set(b)))
        for key in a:
            _compare(a[key], b[key], f"{path}/{key}", tol)
        return
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (path, a.shape, b.shape)
    if a.dtype == object:
        for x, y in zip(a, b, strict=True):
            assert (x is None) == (y is None), path
            if x is not None:
                _compare(x, y, path, tol)
    elif a.dtype == bool or np.issubdtype(a.dtype, np.integer):
        np.testing.assert_array_equal(a, b, err_msg=path)
    elif tol == 0:
        np.testing.assert_array_equal(a, b, err_msg=path)
    else:
        np.testing.assert_allclose(a, b, rtol=0, atol=tol, err_msg=path)


def _run_both(env_id: str, n: int, steps: int, mode: str, tol: float, **kwargs: Any) -> int:
    native = gym.make_vec(
        env_id, num_envs=n, vectorization_mode="vector_entry_point", autoreset_mode=mode, **kwargs
    )
    if hasattr(gym.vector, "AutoresetMode"):
        vector_kwargs: dict[str, Any] = {"autoreset_mode": MODES[mode]}
    elif mode == "next_step":  # Gymnasium 1.0: SyncVectorEnv resets on the next step only
        vector_kwargs = {}
    else:
        pytest.skip(f"Gymnasium {gym.__version__}'s SyncVectorEnv has no {mode} mode")
    sync = gym.make_vec(
        env_id, num_envs=n, vectorization_mode="sync", vector_kwargs=vector_kwargs, **kwargs
    )
    assert native.metadata["autoreset_mode"] == MODES[mode]
    assert native.single_observation_space == sync.single_observation_space
    _compare(native.reset(seed=7), sync.reset(seed=7), "reset", tol)
    rng = np.random.default_rng(1)
    ends = 0
    for t in range(steps):
        actions = rng.uniform(-1.2, 1.2, (n, 2)).astype(np.float32)
        a, b = native.step(actions), sync.step(actions)
        _compare(
            dict(zip("ortTi", a, strict=True)), dict(zip("ortTi", b, strict=True)), f"{t}", tol
        )
        ends += int((a[2] | a[3]).sum())
    return ends


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
@pytest.mark.parametrize("scenario", ["paper-sim", "paper-lab", "random", "random-obstacles"])
@pytest.mark.parametrize("env_id", ["RadialIBVS/Parking-v0", "RadialIBVS/ParkingGoal-v1"])
def test_native_equals_sync_on_the_kinematic_backend(env_id: str, scenario: str, mode: str) -> None:
    # a short time limit: truncations exercise the autoreset path besides the terminations
    kwargs: dict[str, Any] = {"scenario": scenario, "physics": "kinematic", "max_episode_steps": 90}
    if env_id.endswith("Parking-v0"):
        kwargs.update(obs_mode="features", goal_depths=True, privileged=True)
    ends = _run_both(env_id, 3, 250, mode, 0.0, **kwargs)
    assert ends > 0  # the autoreset path ran


@pytest.mark.parametrize("scenario", ["paper-sim", "paper-lab", "random", "random-obstacles"])
def test_native_equals_sync_on_pymunk_within_the_stated_tolerance(scenario: str) -> None:
    kwargs = {"scenario": scenario, "max_episode_steps": 90}
    assert _run_both("RadialIBVS/Parking-v0", 3, 250, "next_step", PYMUNK_TOL, **kwargs)


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_native_equals_sync_with_an_imperfect_camera_and_short_time_limit(mode: str) -> None:
    # pixel noise draws from each env's generator: the autoreset must leave it as Sync does
    camera = {"mirror": "A", "non_central_offset": 0.01, "imperfections": {"pixel_noise_std": 0.5}}
    ends = _run_both(
        "RadialIBVS/Parking-v0",
        2,
        60,
        mode,
        0.0,
        physics="kinematic",
        camera=camera,
        max_episode_steps=25,
        action_type="wheels",
    )
    assert ends >= 4  # truncations at 25 steps


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
@pytest.mark.parametrize(
    ("scenario", "image"),
    [
        ("paper-lab", {"image_size": 256, "beacon_radius": 0.08, "image_noise": 3.0}),
        ("paper-sim", {"image_size": 192, "beacon_radius": 0.1, "exposure": 0.8}),
    ],
)
def test_native_equals_sync_with_detected_points(
    scenario: str, image: dict[str, Any], mode: str
) -> None:
    """Each robot renders and detects its own frames: the points, features and detection info
    are Sync's bit for bit, the sensor noise drawn from each env's generator, through resets."""
    ends = _run_both(
        "RadialIBVS/Parking-v0",
        3,
        45,
        mode,
        0.0,
        scenario=scenario,
        physics="kinematic",
        measurement="detected",
        obs_mode="features",
        max_episode_steps=12,
        **image,
    )
    assert ends >= 6  # truncations at 12 steps


def test_the_goal_conditioned_vector_env_with_detected_points_equals_sync() -> None:
    ends = _run_both(
        "RadialIBVS/ParkingGoal-v1",
        2,
        20,
        "next_step",
        0.0,
        scenario="paper-lab",
        physics="kinematic",
        measurement="detected",
        image_size=256,
        max_episode_steps=8,
    )
    assert ends >= 4


def test_detected_points_in_rooms_of_different_heights_keep_one_cached_height_per_robot() -> None:
    """Random rooms with large beacons: the rendered rooms' heights differ per episode."""
    kwargs: dict[str, Any] = {"scenario": "random", "image_size": 128, "beacon_radius": 0.25}
    ends = _run_both(
        "RadialIBVS/Parking-v0",
        3,
        30,
        "next_step",
        0.0,
        physics="kinematic",
        measurement="detected",
        max_episode_steps=5,
        **kwargs,
    )
    assert ends >= 9
    # robots in rooms of three heights, stepping on: no room's floor and ceiling hits recomputed
    from radial_ibvs_gym.vision import room_rays

    native = ParkingVectorEnv(3, physics="kinematic", measurement="detected", **kwargs)
    native.reset(seed=1)
    assert len({d.scene.height for d in native._detectors.rows}) == 3  # type: ignore[union-attr]
    computed = []
    of = room_rays.VerticalHits.of
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(
            room_rays.VerticalHits, "of", lambda *a, **k: computed.append(1) or of(*a, **k)
        )
        for _ in range(10):
            native.step(np.zeros((3, 2), dtype=np.float32))
    assert computed == []


def test_the_vector_envs_frames_are_the_scalar_envs_by_hash() -> None:
    """The images each robot rendered and detected: the scalar env's, by SHA-256, step by step."""
    import hashlib

    kwargs: dict[str, Any] = {
        "scenario": "paper-sim",
        "physics": "kinematic",
        "measurement": "detected",
        "image_size": 256,
        "beacon_radius": 0.1,
        "image_noise": 2.0,
    }
    native = ParkingVectorEnv(2, **kwargs)
    singles = [gym.make("RadialIBVS/Parking-v0", **kwargs) for _ in range(2)]
    native.reset(seed=[5, 9])
    for single, seed in zip(singles, (5, 9), strict=True):
        single.reset(seed=seed)
    rng = np.random.default_rng(2)

    def digests(frames: dict[str, np.ndarray]) -> dict[str, str]:
        return {k: hashlib.sha256(v.tobytes()).hexdigest() for k, v in frames.items()}

    for _ in range(8):
        actions = rng.uniform(-1, 1, (2, 2)).astype(np.float32)
        _, _, terminated, truncated, _ = native.step(actions)
        assert not (terminated | truncated).any()  # no reset: the frames are the episode's
        for i, single in enumerate(singles):
            single.step(actions[i])
            mine = {k: f.image for k, f in native._detectors[i].last.items()}  # type: ignore[index]
            assert digests(mine) == digests(single.unwrapped.detected_frames)


def test_with_autoreset_disabled_an_ended_env_is_not_observed_until_reset() -> None:
    camera = {"mirror": "A", "non_central_offset": 0.01, "imperfections": {"pixel_noise_std": 0.5}}
    kwargs: dict[str, Any] = {"physics": "kinematic", "camera": camera}
    native = gym.make_vec(
        "RadialIBVS/Parking-v0", num_envs=2, vectorization_mode="vector_entry_point",
        autoreset_mode="disabled", max_episode_steps=5, **kwargs,
    )  # fmt: skip
    obs, _ = native.reset(seed=[3, 4])
    actions = np.tile(np.array([[0.5, 0.2]], dtype=np.float32), (2, 1))
    for _ in range(5):
        obs, _, terminated, truncated, _ = native.step(actions)
    assert (terminated | truncated).all()  # both ended at the time limit
    native.reset(seed=[None, 4], options={"reset_mask": np.array([False, True])})
    last = obs["points"][0].copy()
    for _ in range(3):
        obs, *_ = native.step(actions)
        np.testing.assert_array_equal(obs["points"][0], last)  # env 0: camera off
    assert not np.array_equal(obs["points"][1], last)
    # env 1 ran as a fresh env with its seed would: the ended env drew nothing from it
    single = gym.make("RadialIBVS/Parking-v0", **kwargs)
    single_obs, _ = single.reset(seed=4)
    for _ in range(3):
        single_obs, *_ = single.step(actions[0])
    np.testing.assert_array_equal(obs["points"][1], single_obs["points"])
    # a reset turns the camera back on, with the generator the env had
    obs, _ = native.reset(options={"reset_mask": np.array([True, False])})
    obs, *_ = native.step(actions)
    assert not np.array_equal(obs["points"][0], last)


def test_same_seed_gives_the_same_trajectory_bit_for_bit() -> None:
    def rollout() -> list[np.ndarray]:
        envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=4, scenario="random")
        obs, _ = envs.reset(seed=11)
        rng = np.random.default_rng(0)
        out = [obs["points"]]
        for _ in range(80):
            obs, reward, *_ = envs.step(rng.uniform(-1, 1, (4, 2)))
            out += [obs["points"], reward]
        return out

    for a, b in zip(rollout(), rollout(), strict=True):
        np.testing.assert_array_equal(a, b)


def test_random_rooms_differ_per_env_and_reset_mask_resets_only_the_masked_envs() -> None:
    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=4, scenario="random", physics="kinematic")
    _, info = envs.reset(seed=0)
    base: Any = envs.unwrapped
    rooms = base.fleet.rooms.copy()
    assert len({tuple(r) for r in rooms}) == 4
    goals = info["goal_pose"].copy()
    mask = np.array([False, True, False, False])
    _, info = envs.reset(options={"reset_mask": mask})
    assert info["_robot_pose"].tolist() == mask.tolist()
    assert not np.array_equal(base.fleet.rooms[1], rooms[1])
    np.testing.assert_array_equal(base.fleet.rooms[~mask], rooms[~mask])
    np.testing.assert_array_equal(base.batch.goals[~mask], goals[~mask])


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
def test_collisions_are_reported_per_env(physics: str) -> None:
    envs = gym.make_vec(
        "RadialIBVS/Parking-v0",
        num_envs=3,
        physics=physics,
        terminate_on_collision=False,
        max_episode_steps=2000,
    )
    envs.reset(seed=0, options={"start": [0.6, 3.0, np.pi], "goal": [7.0, 7.0, 0.0]})
    actions = np.zeros((3, 2))
    actions[1, 0] = 1.0  # env 1 drives forward, heading pi: into the wall x = 0
    hit = np.zeros(3, dtype=bool)
    for _ in range(30):
        _, _, _, _, info = envs.step(actions)
        hit |= info["collision"]
    assert hit.tolist() == [False, True, False]
    poses = info["robot_pose"]
    if physics == "pymunk":  # the wall stops the robot
        assert poses[1, 0] > 0.1
    np.testing.assert_allclose(poses[[0, 2], 0], 0.6)


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
@pytest.mark.parametrize("copy_with", ["pickle", "deepcopy"])
def test_a_copy_mid_episode_steps_as_the_original_bit_for_bit(physics: str, copy_with: str) -> None:
    """Pickled (AsyncVectorEnv, Ray, TorchRL's ParallelEnv) or deep-copied, collisions too."""
    import copy
    import pickle

    envs = gym.make_vec(
        "RadialIBVS/Parking-v0", num_envs=3, physics=physics, terminate_on_collision=False
    )
    envs.reset(seed=0, options={"start": [0.6, 3.0, np.pi], "goal": [7.0, 7.0, 0.0]})
    actions = np.array([[0.2, 0.3], [1.0, 0.0], [0.5, -0.2]])
    envs.step(actions)
    clone = pickle.loads(pickle.dumps(envs)) if copy_with == "pickle" else copy.deepcopy(envs)
    hit = np.zeros(3, dtype=bool)
    for _ in range(30):
        *mine, info = envs.step(actions)
        *theirs, info_copy = clone.step(actions)
        for a, b in zip(mine, theirs, strict=True):
            if isinstance(a, dict):
                for key in a:
                    np.testing.assert_array_equal(a[key], b[key])
            else:
                np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(info["collision"], info_copy["collision"])
        np.testing.assert_array_equal(info["robot_pose"], info_copy["robot_pose"])
        hit |= info["collision"]
    assert hit[1]  # the copy met the wall as the original did


def test_pymunk_robots_share_one_space_and_only_meet_their_own_walls() -> None:
    fleet = PymunkFleet(RobotConfig(), 5, physics_dt=0.01, max_room=(10.0, 10.0))
    rooms = np.full((5, 2), 10.0)
    fleet.reset(np.arange(5), rooms, np.tile([5.0, 5.0, 0.0], (5, 1)))
    assert len(fleet.space.bodies) == 10  # 5 robots, 5 control bodies
    # rooms at least a room plus 5 m apart: no robot can reach another room
    gaps = np.abs(fleet.offsets[:, None, :] - fleet.offsets[None, :, :]).max(axis=-1)
    assert (gaps[~np.eye(5, dtype=bool)] >= 15.0).all()
    poses, collision = fleet.step(np.tile([1.0, 0.5], (5, 1)), 0.1)
    assert not collision.any()
    np.testing.assert_allclose(poses, np.tile(poses[0], (5, 1)), atol=1e-9)  # same motion


def test_batched_limits_equal_the_scalar_limits() -> None:
    rng = np.random.default_rng(0)
    for saturation in ("scale", "clip"):
        robot = RobotConfig(saturation=saturation)
        command = rng.uniform(-5, 5, (200, 2))
        previous = rng.uniform(-2, 2, (200, 2))
        batched = limit_commands(command, previous, 0.1, robot)
        scalar = [limit_command(c, p, 0.1, robot) for c, p in zip(command, previous, strict=True)]
        np.testing.assert_array_equal(batched, np.array(scalar))


def test_kinematic_fleet_rejects_a_start_in_a_wall() -> None:
    fleet = KinematicFleet(RobotConfig(), 2)
    with pytest.raises(ValueError, match="into a wall"):
        fleet.reset([0, 1], [[5.0, 5.0], [5.0, 5.0]], [[2.0, 2.0, 0.0], [0.05, 2.0, 0.0]])


# --- bad input ---------------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_action_names_the_env(bad: float) -> None:
    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=4, physics="kinematic")
    envs.reset(seed=0)
    actions = np.zeros((4, 2))
    actions[2, 1] = bad
    with pytest.raises(ValueError, match="env 2"):
        envs.step(actions)


def test_bad_shapes_and_counts_are_clear_errors() -> None:
    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=3, physics="kinematic")
    envs.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(3, 2\)"):
        envs.step(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="num_envs"):
        gym.make_vec("RadialIBVS/Parking-v0", num_envs=0)
    with pytest.raises(ValueError, match="sync"):
        ParkingVectorEnv(2, render_mode="rgb_array")
    # the scalar env's checks of detected points, in the vector env too
    with pytest.raises(ValueError, match=r"measurement='detected' renders through one camera"):
        ParkingVectorEnv(2, scenario="random", measurement="detected", mirrors=["A", "B"])
    with pytest.raises(ValueError, match="autoreset_mode"):
        ParkingVectorEnv(2, autoreset_mode="sometimes")
    with pytest.raises(ValueError, match="obs_mode"):
        ParkingVectorEnv(2, obs_mode="pixels")


def test_step_before_reset_is_an_error() -> None:
    envs = ParkingVectorEnv(2, physics="kinematic")
    with pytest.raises(RuntimeError, match="reset"):
        envs.step(np.zeros((2, 2)))


@pytest.mark.slow
def test_fuzz_ten_thousand_random_episodes_raise_nothing_and_give_no_nan() -> None:
    episodes = 0
    rng = np.random.default_rng(0)
    for k, scenario in enumerate(("paper-sim", "paper-lab", "random")):
        envs = gym.make_vec(
            "RadialIBVS/Parking-v0",
            num_envs=512,
            scenario=scenario,
            physics="kinematic",
            obs_mode="features",
            goal_depths=True,
            max_episode_steps=150,
        )
        envs.reset(seed=k)
        target = 3400
        done_here = 0
        while done_here < target:
            # mostly uniform actions, some saturated and far out of range (clipped)
            actions = rng.uniform(-1.0, 1.0, (512, 2))
            wild = rng.random(512) < 0.1
            actions[wild] = rng.choice([-1e6, -1.0, 1.0, 1e6], (int(wild.sum()), 2))
            obs, reward, terminated, truncated, info = envs.step(actions)
            for key, value in obs.items():
                assert np.isfinite(value).all(), key
            assert np.isfinite(reward).all()
            assert np.isfinite(info["robot_pose"]).all()
            done_here += int((terminated | truncated).sum())
        episodes += done_here
    assert episodes >= 10_000


# --- stable-baselines3 -------------------------------------------------------------------------


def test_make_vec_env_follows_sb3_semantics_like_dummy_vec_env() -> None:
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env

    from radial_ibvs_agents import make_vec_env

    kwargs = {"physics": "kinematic", "scenario": "random", "max_episode_steps": 40}
    ours = make_vec_env("RadialIBVS/Parking-v0", 3, seed=5, monitor=False, **kwargs)
    reference = sb3_make_vec_env("RadialIBVS/Parking-v0", n_envs=3, seed=5, env_kwargs=kwargs)
    _compare(ours.reset(), reference.reset(), "reset", 0.0)
    rng = np.random.default_rng(0)
    finished = 0
    for t in range(120):
        actions = rng.uniform(-1, 1, (3, 2)).astype(np.float32)
        o1, r1, d1, i1 = ours.step(actions)
        o2, r2, d2, i2 = reference.step(actions)
        _compare(o1, o2, f"{t}/obs", 0.0)
        np.testing.assert_allclose(r1, r2, rtol=1e-6)
        np.testing.assert_array_equal(d1, d2)
        for i in np.flatnonzero(d1).tolist():
            finished += 1
            _compare(i1[i]["terminal_observation"], i2[i]["terminal_observation"], "final", 0.0)
            assert i1[i]["TimeLimit.truncated"] == i2[i]["TimeLimit.truncated"]
            assert i1[i]["is_success"] == i2[i]["is_success"]
    assert finished >= 3


def test_make_vec_env_trains_ppo_under_vec_normalize() -> None:
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    from radial_ibvs_agents import make_vec_env

    venv = VecNormalize(make_vec_env("RadialIBVS/Parking-v0", 8, seed=0, physics="kinematic"))
    model = PPO(
        "MultiInputPolicy",
        venv,
        n_steps=32,
        batch_size=64,
        n_epochs=1,
        policy_kwargs={"net_arch": [16]},
        device="cpu",
        seed=0,
    )
    model.learn(256)
    assert model.num_timesteps == 256
    assert venv.obs_rms["points"].count > 256  # the statistics saw every env's observations
    with pytest.raises(ValueError, match="no native vector env"):
        make_vec_env("RadialIBVS/ParkingImage-v0", 2)


def test_make_vec_env_applies_one_set_of_reset_options_and_refuses_per_env_ones() -> None:
    from radial_ibvs_agents import make_vec_env

    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, monitor=False, physics="kinematic")
    venv.set_options({"task": 2})
    venv.reset()
    assert [info["task"] for info in venv.reset_infos] == [2, 2]
    venv.set_options([{"task": 1}, {"task": 2}])
    with pytest.raises(ValueError, match="one set of reset options"):
        venv.reset()


@pytest.mark.parametrize("slot_order", ["fixed", "random"])
def test_native_equals_sync_with_landmark_slots(slot_order: str) -> None:
    kwargs = {"scenario": "paper-lab", "physics": "kinematic", "max_landmarks": 16,
              "slot_order": slot_order}  # fmt: skip
    assert _run_both("RadialIBVS/Parking-v0", 3, 120, "same_step", 0.0, obs_mode="features",
                     max_episode_steps=50, **kwargs)  # fmt: skip


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
def test_each_robot_meets_only_its_own_rooms_obstacles(physics: str) -> None:
    from radial_ibvs_gym.physics import RobotConfig, make_fleet

    fleet = make_fleet(physics, RobotConfig(), 2)
    rooms = np.array([[6.0, 6.0], [6.0, 6.0]])
    starts = np.array([[2.0, 3.0, 0.0], [2.0, 3.0, 0.0]])
    fleet.reset([0, 1], rooms, starts, obstacles=[[[3.2, 3.0, 0.4]], np.zeros((0, 3))])
    hit = np.zeros(2, dtype=bool)
    for _ in range(20):  # 1 m/s towards x: robot 0 meets its pillar, robot 1 drives past
        _, collision = fleet.step(np.array([[1.0, 0.0], [1.0, 0.0]]), 0.1)
        hit |= collision
    assert hit.tolist() == [True, False]
    with pytest.raises(ValueError, match="obstacle"):
        fleet.reset([1], rooms[:1], starts[:1], obstacles=[[[2.0, 3.0, 0.3]]])
    with pytest.raises(ValueError, match=r"obstacles\[0\] must be \(x, y, radius > 0\)"):
        fleet.reset([1], rooms[:1], starts[:1], obstacles=[[[5.0, 5.0, -1.0]]])


@pytest.mark.parametrize("imperfect", [False, True])
@pytest.mark.parametrize("env_id", ["RadialIBVS/Parking-v0", "RadialIBVS/ParkingGoal-v1"])
def test_native_equals_sync_when_scenes_draw_landmark_counts_camera_heights_and_mirrors(
    env_id: str, imperfect: bool
) -> None:
    # each robot its own count, height and mirror: the absent landmarks, heights and cameras
    kwargs: dict[str, Any] = {
        "scenario": "random-unseen", "physics": "kinematic", "max_episode_steps": 60,
        "max_landmarks": 16, "slot_order": "random", "mirrors": ["A", "B"],
    }  # fmt: skip
    if imperfect:
        imperfections = {"principal_point_offset": [2.0, -1.0], "pixel_noise_std": 0.5}
        kwargs["camera"] = {
            "mirror": "A",
            "non_central_offset": 0.01,
            "imperfections": imperfections,
        }
    if env_id.endswith("Parking-v0"):
        kwargs.update(obs_mode="features", goal_depths=True, privileged=True)
    assert _run_both(env_id, 4, 150, "next_step", 0.0, **kwargs) > 0


def test_native_equals_sync_with_noise_drawn_per_episode_and_mixed_mirrors() -> None:
    # noise levels drawn per episode (some robots nearly quiet), the mirror drawn too: the
    # batch shares one reflection at some steps and not at others, and the noise drawn ahead
    # in blocks must leave every generator where SyncVectorEnv's envs leave theirs
    camera = {
        "mirror": "A",
        "non_central_offset": 0.01,
        "imperfection_ranges": {"principal_point_offset": 2.0, "pixel_noise_std": [0.0, 1.0]},
    }
    kwargs: dict[str, Any] = {
        "scenario": "random", "physics": "kinematic", "camera": camera, "mirrors": ["A", "B"],
        "max_episode_steps": 20, "obs_mode": "features", "max_landmarks": 12,
    }  # fmt: skip
    assert _run_both("RadialIBVS/Parking-v0", 3, 80, "next_step", 0.0, **kwargs) >= 6
