"""The Gymnasium environments: API checks, determinism, pickling, bad input, fuzzing."""

from __future__ import annotations

import math
import pickle
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs import ENV_IDS
from radial_ibvs_gym.envs.rules import REWARD_TERMS, reward_terms_in

SCENARIOS = ("paper-sim", "paper-lab", "random")
INFO_KEYS = {
    "robot_pose",
    "goal_pose",
    "position_error_m",
    "heading_error_deg",
    "is_success",
    "collision",
    "n_visible",
    "reward_progress",
    "reward_success",
}


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("scenario", SCENARIOS)
@pytest.mark.parametrize("obs_mode", ["points", "features"])
def test_gymnasium_and_sb3_checks_pass_without_warnings(env_id, scenario, obs_mode) -> None:
    if env_id.startswith("RadialIBVS/ParkingGoal-") and obs_mode == "features":
        with pytest.raises(ValueError, match="obs_mode='points' only"):
            gym.make(env_id, scenario=scenario, obs_mode=obs_mode)
        return
    kwargs = {"scenario": scenario, "obs_mode": obs_mode}
    if env_id == "RadialIBVS/ParkingImage-v0":  # images, no point observation modes
        if obs_mode == "features":
            with pytest.raises(ValueError, match="obs_mode"):
                gym.make(env_id, **kwargs)
            return
        kwargs.pop("obs_mode")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        envs = [gym.make(env_id, **kwargs).unwrapped for _ in range(2)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(envs[0])
        sb3_check_env(envs[1])


def rollout(env: gym.Env, seed: int, steps: int = 60) -> list[np.ndarray]:
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    trace = [np.concatenate([v.ravel() for v in obs.values()])]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        trace.append(np.concatenate([info["robot_pose"], [reward], obs["points"]]))
        if terminated or truncated:
            break
    return trace


@pytest.mark.parametrize("physics", ["pymunk", "kinematic"])
@pytest.mark.parametrize("scenario", SCENARIOS)
def test_same_seed_same_trajectory_bit_for_bit(scenario: str, physics: str) -> None:
    a = rollout(gym.make("RadialIBVS/Parking-v0", scenario=scenario, physics=physics), seed=7)
    b = rollout(gym.make("RadialIBVS/Parking-v0", scenario=scenario, physics=physics), seed=7)
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)
    c = rollout(gym.make("RadialIBVS/Parking-v0", scenario=scenario, physics=physics), seed=8)
    assert not all(np.array_equal(x, y) for x, y in zip(a, c, strict=False))


@pytest.mark.parametrize("physics", ["pymunk", "kinematic"])
def test_env_pickles_mid_episode(physics: str) -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=2, physics=physics)
    env.reset(seed=1)
    for _ in range(5):
        env.step(np.array([0.5, 0.2], np.float32))
    clone = pickle.loads(pickle.dumps(env))
    for _ in range(5):
        o1, r1, *_ = env.step(np.array([0.3, -0.4], np.float32))
        o2, r2, *_ = clone.step(np.array([0.3, -0.4], np.float32))
        assert r1 == r2
        np.testing.assert_array_equal(o1["points"], o2["points"])


def test_observation_matches_the_radial_model_and_info_has_the_contract() -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=1)
    obs, info = env.reset(seed=0)
    assert INFO_KEYS <= set(info)
    assert reward_terms_in(info) == dict.fromkeys(REWARD_TERMS, 0.0)
    np.testing.assert_array_equal(info["robot_pose"], [3.0, 3.0, 0.0])
    np.testing.assert_allclose(info["goal_pose"], [7.0, 7.0, math.pi / 2])
    assert info["position_error_m"] == pytest.approx(4 * math.sqrt(2))
    assert info["heading_error_deg"] == pytest.approx(90.0)
    points = obs["points"].reshape(-1, 2)
    np.testing.assert_allclose(np.linalg.norm(points, axis=-1), 1.0, atol=1e-6)
    # first eq. (39) point (15.6, 7.62) seen from (3, 3) heading 0
    expected = np.array([12.6, 4.62]) / math.hypot(12.6, 4.62)
    np.testing.assert_allclose(points[0], expected, atol=1e-6)
    obs, reward, *_, info = env.step(np.zeros(2, np.float32))
    assert INFO_KEYS <= set(info)
    assert reward == pytest.approx(sum(reward_terms_in(info).values()))


def test_reset_options_fix_start_and_goal() -> None:
    env = gym.make("RadialIBVS/Parking-v0")
    _, info = env.reset(seed=0, options={"start": [4.0, 5.0, 0.5], "goal": [6.0, 6.0, 0.0]})
    np.testing.assert_array_equal(info["robot_pose"], [4.0, 5.0, 0.5])
    np.testing.assert_array_equal(info["goal_pose"], [6.0, 6.0, 0.0])


def test_driving_to_the_goal_succeeds_and_terminates() -> None:
    env = gym.make("RadialIBVS/Parking-v0", control_dt=0.05)
    _, info = env.reset(seed=0, options={"start": [5.0, 5.0, 0.0], "goal": [5.5, 5.0, 0.0]})
    for _ in range(200):
        # a proportional law on the true pose (the oracle lands with the controller issue)
        err = info["position_error_m"]
        *_, terminated, _, info = env.step(np.array([min(err, 0.5), 0.0]))
        if terminated:
            break
    assert info["is_success"] and terminated
    assert info["reward_success"] > 0


def test_collision_terminates() -> None:
    env = gym.make("RadialIBVS/Parking-v0")
    env.reset(seed=0, options={"start": [14.8, 7.0, 0.0]})
    for _ in range(50):
        *_, terminated, _, info = env.step(np.array([1.0, 0.0], np.float32))
        if terminated:
            break
    assert terminated and info["collision"] and info["reward_collision"] < 0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"scenario": "nope"}, "unknown scenarios config 'nope'"),
        ({"physics": "bullet"}, r"unknown physics .bullet.; valid: \[.pymunk., .kinematic.\]"),
        ({"physics_dt": 0.03}, "must be a multiple of physics_dt"),
        ({"obs_mode": "pixels"}, "unknown obs_mode"),
        ({"task": 9}, r"task must be in 0\.\.3, got 9"),
        ({"control_dt": 0.0}, "control_dt must be finite and positive"),
        ({"min_visible": 2}, r"min_visible must be in 3\.\.8"),
        ({"render_mode": "rgb"}, "render_mode .rgb. is not supported"),
        ({"depth_scael": 1.3}, r"unexpected keyword argument 'depth_scael' \(did you mean"),
        ({"robot": {"wheel_base": 0.0}}, "wheel_base must be a positive number"),
    ],
)
@pytest.mark.filterwarnings("ignore:.*render_mode:UserWarning")
def test_bad_arguments_are_named(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        gym.make("RadialIBVS/Parking-v0", **kwargs)


def test_an_unknown_argument_is_the_type_error_python_would_raise() -> None:
    from radial_ibvs_gym.envs import UnknownArgumentError

    for make in (gym.make, lambda i, **kw: gym.make_vec(i, num_envs=2, **kw)):
        with pytest.raises(TypeError, match=r"__init__\(\) got an unexpected keyword argument"):
            make("RadialIBVS/Parking-v0", frameskip=4)  # what TorchRL's GymEnv passes
    with pytest.raises(UnknownArgumentError) as caught:
        gym.make("RadialIBVS/ParkingGoal-v1", frameskip=4)
    assert isinstance(caught.value, ValueError)
    assert "ParkingGoalEnv.__init__() got an unexpected keyword argument 'frameskip'" in str(
        caught.value
    )


def test_bad_actions_and_options_are_named() -> None:
    env = gym.make("RadialIBVS/Parking-v0").unwrapped
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(2))
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be two finite real numbers"):
        env.step(np.array([np.nan, 0.0]))
    with pytest.raises(ValueError, match="action must be two finite real numbers"):
        env.step(np.array([0.1, 0.2, 0.3]))
    with pytest.raises(ValueError, match="got an array of complex128"):
        env.step(np.array([0.1 + 0.5j, 0.2]))  # numpy would drop the imaginary part
    with pytest.raises(ValueError, match="got an array of bool"):
        env.step(np.array([True, False]))
    with pytest.raises(ValueError, match=r"unknown reset option\(s\) \['strat'\]"):
        env.reset(options={"strat": [1, 1, 0]})
    with pytest.raises(ValueError, match="into a wall"):
        env.reset(options={"start": [0.05, 5.0, 0.0]})


@pytest.mark.slow
def test_fuzz_random_actions_over_all_scenarios() -> None:
    """1,000 random-action episodes (50 steps each): no exception, no NaN in observations."""
    rng = np.random.default_rng(0)
    envs = [
        gym.make("RadialIBVS/Parking-v0", scenario=s, obs_mode=m, max_episode_steps=50)
        for s in SCENARIOS
        for m in ("points", "features")
    ]
    for episode in range(1000):
        env = envs[episode % len(envs)]
        obs, _ = env.reset(seed=int(rng.integers(2**31)))
        done = False
        while not done:
            action = rng.uniform(-1.5, 1.5, 2).astype(np.float32)  # out of range is clipped
            obs, reward, terminated, truncated, _ = env.step(action)
            assert math.isfinite(reward)
            assert all(np.isfinite(v).all() for v in obs.values())
            assert env.observation_space.contains(obs)
            done = terminated or truncated


def test_goal_env_reward_is_consistent_with_compute_reward() -> None:
    env = gym.make("RadialIBVS/ParkingGoal-v1", task=0)
    obs, _ = env.reset(seed=0)
    assert set(obs) == {"observation", "achieved_goal", "desired_goal"}
    obs, reward, _, _, info = env.step(np.array([0.4, 0.1], np.float32))
    r = env.unwrapped.compute_reward(obs["achieved_goal"], obs["desired_goal"], info)
    assert reward == float(r)
    assert reward == pytest.approx(sum(reward_terms_in(info).values()))
    # batched, as HER calls it; zero when the images agree
    batch = np.stack([obs["achieved_goal"], obs["desired_goal"]])
    out = env.unwrapped.compute_reward(batch, np.stack([obs["desired_goal"]] * 2), [info] * 2)
    # identical images: no distance term, the success bonus (success in the image)
    assert out.shape == (2,) and out[1] == env.unwrapped.config.success_bonus and out[0] < out[1]


@pytest.mark.slow
def test_goal_env_trains_with_sb3_her_smoke() -> None:
    from stable_baselines3 import SAC, HerReplayBuffer

    env = gym.make("RadialIBVS/ParkingGoal-v1", scenario="random", max_episode_steps=40)
    model = SAC(
        "MultiInputPolicy",
        env,
        replay_buffer_class=HerReplayBuffer,
        learning_starts=100,
        batch_size=16,
        policy_kwargs={"net_arch": [16, 16]},
        seed=0,
    )
    model.learn(200)
    action, _ = model.predict(env.reset(seed=1)[0], deterministic=True)
    assert env.action_space.contains(action)


def test_rgb_array_frames_show_the_robot_moving() -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=1, render_mode="rgb_array")
    env.reset(seed=0)
    first = env.render()
    for _ in range(10):
        env.step(np.array([1.0, 0.3], np.float32))
    later = env.render()
    assert first.shape == later.shape == (320, 640, 3) and first.dtype == np.uint8
    assert (first != later).any()
    env.close()


def test_render_without_a_mode_warns_and_returns_none() -> None:
    env = gym.make("RadialIBVS/Parking-v0").unwrapped
    env.reset(seed=0)
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.render() is None


@pytest.mark.parametrize("physics", ["pymunk", "kinematic"])
def test_obstacle_collision_terminates(physics: str) -> None:
    env = gym.make("RadialIBVS/Parking-v0", physics=physics, obstacles=[[5.0, 3.0, 0.4]])
    env.reset(seed=0, options={"start": [3.0, 3.0, 0.0]})
    for _ in range(60):
        *_, terminated, _, info = env.step(np.array([0.8, 0.0], np.float32))
        if terminated:
            break
    assert terminated and info["collision"]


def test_wheel_actions_drive_like_the_equivalent_twist() -> None:
    wheels = gym.make("RadialIBVS/Parking-v0", physics="kinematic", action_type="wheels")
    twist = gym.make("RadialIBVS/Parking-v0", physics="kinematic")
    wheels.reset(seed=0)
    twist.reset(seed=0)
    for _ in range(10):
        # equal wheel speeds at half scale: straight ahead at half the top speed
        *_, info_w = wheels.step(np.array([0.5, 0.5], np.float32))
        *_, info_t = twist.step(np.array([0.5, 0.0], np.float32))
    np.testing.assert_allclose(info_w["robot_pose"], info_t["robot_pose"], atol=1e-12)
    _, info = wheels.reset(seed=0)
    *_, info = wheels.step(np.array([-0.2, 0.2], np.float32))  # turn in place, to the left
    assert info["robot_pose"][2] > 0 and info["position_error_m"] == pytest.approx(
        math.hypot(4.0, 4.0)
    )
    with pytest.raises(ValueError, match="unknown action_type 'tracks'"):
        gym.make("RadialIBVS/Parking-v0", action_type="tracks")


def test_camera_imperfections_reach_the_observations() -> None:
    """The paper-a-imperfect camera (0.5 px noise, 2 px principal-point offset, 1 % rho_f)."""
    imperfect = {"mirror": "A", "non_central_offset": 0.01}
    imperfect["imperfections"] = {
        "principal_point_offset": [2.0, -1.5],
        "focal_ratio_error": 0.01,
        "pixel_noise_std": 0.5,
    }
    ideal_env = gym.make("RadialIBVS/Parking-v0", task=0)
    a = gym.make("RadialIBVS/Parking-v0", task=0, camera=imperfect)
    b = gym.make("RadialIBVS/Parking-v0", task=0, camera=imperfect)
    ideal, _ = ideal_env.reset(seed=3)
    obs_a, _ = a.reset(seed=3)
    obs_b, _ = b.reset(seed=3)
    np.testing.assert_array_equal(obs_a["points"], obs_b["points"])  # seeded noise
    err = np.abs(obs_a["points"] - ideal["points"]).max()
    assert 1e-5 < err < 0.05  # a few pixels on a ~400 px image radius: milliradians
    np.testing.assert_allclose(
        np.linalg.norm(obs_a["points"].reshape(-1, 2), axis=-1), 1.0, atol=1e-6
    )
    step_a = a.step(np.zeros(2, np.float32))[0]
    assert (step_a["points"] != obs_a["points"]).any()  # fresh noise every step


def test_human_render_mode_runs_headless() -> None:
    import matplotlib

    matplotlib.use("Agg")  # no display in CI: the window is drawn off-screen
    env = gym.make("RadialIBVS/Parking-v0", render_mode="human")
    env.reset(seed=0)
    assert env.step(np.zeros(2, np.float32))[0] is not None
    assert env.render() is None
    env.close()


def test_privileged_observation_passes_the_checkers_and_wraps_the_goal_yaw() -> None:
    kwargs = {"privileged": True, "goal_depths": True}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(gym.make("RadialIBVS/Parking-v0", **kwargs).unwrapped)
        sb3_check_env(gym.make("RadialIBVS/Parking-v0", **kwargs).unwrapped)
    env = gym.make("RadialIBVS/Parking-v0", task=3, depth_scale=1.3, **kwargs)
    obs, info = env.reset(seed=0)
    np.testing.assert_allclose(obs["goal_pose"], [7.0, 7.0, -math.pi / 2])  # 270 deg wrapped
    np.testing.assert_array_equal(obs["robot_pose"], info["robot_pose"])
    # goal depths: the scaled d* of info; depths: the true current horizontal distances
    np.testing.assert_allclose(obs["goal_depths"], info["goal_depths"], rtol=1e-6)
    landmarks = env.unwrapped.episode.landmarks
    np.testing.assert_allclose(
        obs["depths"], np.hypot(*(landmarks[:, :2] - [3.0, 3.0]).T), rtol=1e-6
    )
    obs, *_ = env.step(np.array([1.0, 0.0], np.float32))
    assert not np.allclose(obs["depths"], np.hypot(*(landmarks[:, :2] - [3.0, 3.0]).T))


def test_feature_observation_at_the_goal_position_measures_the_rotation() -> None:
    """At the goal position turned by gamma: c*_ij - c_ij = 0 and alpha_m* - alpha_m = gamma."""
    env = gym.make("RadialIBVS/Parking-v0", obs_mode="features", task=0)
    gamma = 0.3
    obs, _ = env.reset(seed=0, options={"start": [7.0, 7.0, gamma]})
    np.testing.assert_allclose(obs["c_error"], 0.0, atol=1e-6)
    assert float(obs["alpha_m_error"][0]) == pytest.approx(gamma, abs=1e-6)


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_fast_observation_path_equals_projection_through_the_camera(scenario: str) -> None:
    # the env's per-step shortcut (bearings + an interval of visible distances) must give
    # exactly what the camera layer gives for the same poses
    from radial_ibvs_gym.geometry import world_to_camera

    env = gym.make("RadialIBVS/Parking-v0", scenario=scenario, physics="kinematic")
    base = env.unwrapped
    rng = np.random.default_rng(1)
    for seed in range(5):
        env.reset(seed=seed)
        w, d = base.episode.room
        for _ in range(40):
            pose = np.array(
                [rng.uniform(0.3, w - 0.3), rng.uniform(0.3, d - 0.3), rng.uniform(-4, 4)]
            )
            points, visible = base.image(base._setup, pose, "current", base.np_random)
            p_cam = world_to_camera(
                base.episode.landmarks, pose, base.scenario.config.camera_height
            )
            expected_visible = base.scenario.camera.visible(p_cam)
            np.testing.assert_array_equal(visible, expected_visible)
            bearing = p_cam[:, :2] / np.hypot(p_cam[:, 0], p_cam[:, 1])[:, None]
            np.testing.assert_allclose(points[visible], bearing[visible], atol=1e-12)
            assert (points[~visible] == 0.0).all()


def test_precision_shaping_is_the_difference_of_a_log_potential() -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=0, physics="kinematic", w_precision=2.0)
    _, info = env.reset(seed=0)

    def phi(i: dict) -> float:
        return -math.log(i["position_error_m"] + 0.01) - 0.5 * math.log(
            math.radians(i["heading_error_deg"]) + 0.02
        )

    before = phi(info)
    _, reward, *_, info = env.step(np.array([1.0, 0.0], np.float32))
    assert info["reward_precision"] == pytest.approx(2.0 * (phi(info) - before))
    assert reward == pytest.approx(sum(reward_terms_in(info).values()))
    default = gym.make("RadialIBVS/Parking-v0", task=0)
    default.reset(seed=0)
    assert default.step(np.zeros(2, np.float32))[-1]["reward_precision"] == 0.0
    with pytest.raises(ValueError, match="w_precision must be finite and >= 0"):
        gym.make("RadialIBVS/Parking-v0", w_precision=float("nan"))


# --- max_landmarks: one observation space for every scene ---------------------------------------


def test_max_landmarks_pads_every_scene_to_one_observation_space() -> None:
    kwargs = {"obs_mode": "features", "goal_depths": True, "privileged": True}
    spaces_seen = []
    for scenario in ("paper-sim", "paper-lab", "random"):
        plain = gym.make("RadialIBVS/Parking-v0", scenario=scenario, **kwargs)
        padded = gym.make("RadialIBVS/Parking-v0", scenario=scenario, max_landmarks=16, **kwargs)
        spaces_seen.append(padded.observation_space)
        a, _ = plain.reset(seed=3)
        b, _ = padded.reset(seed=3)
        n = len(a["visible"])
        assert padded.observation_space.contains(b)
        np.testing.assert_array_equal(b["landmark_mask"], [1.0] * n + [0.0] * (16 - n))
        for key, width in (("points", 2), ("goal_points", 2), ("visible", 1), ("depths", 1)):
            np.testing.assert_array_equal(b[key][: width * n], a[key])
            assert (b[key][width * n :] == 0).all()
        slots = padded.unwrapped.slots
        np.testing.assert_array_equal(b["c_error"][slots.pair_slots], a["c_error"])
        assert np.count_nonzero(b["c_error"]) == np.count_nonzero(a["c_error"])
        np.testing.assert_array_equal(b["alpha_m_error"], a["alpha_m_error"])
    assert spaces_seen[0] == spaces_seen[1] == spaces_seen[2]


@pytest.mark.parametrize("scenario", ["paper-lab", "random"])
def test_random_slot_order_moves_each_landmark_to_its_drawn_slot(scenario: str) -> None:
    kwargs = {"scenario": scenario, "obs_mode": "features", "goal_depths": True,
              "privileged": True, "max_landmarks": 16, "physics": "kinematic"}  # fmt: skip
    fixed = gym.make("RadialIBVS/Parking-v0", **kwargs)
    drawn = gym.make("RadialIBVS/Parking-v0", slot_order="random", **kwargs)
    orders = []
    for seed in (3, 4):
        a, info_a = fixed.reset(seed=seed)
        b, info_b = drawn.reset(seed=seed)
        np.testing.assert_array_equal(info_a["robot_pose"], info_b["robot_pose"])  # same episode
        slots = drawn.unwrapped.slots
        order = drawn.unwrapped._setup.slot_order
        orders.append(order.tolist())
        assert sorted(set(order.tolist())) == sorted(order.tolist())  # distinct slots
        for _ in range(3):  # the same slots all episode
            assert drawn.observation_space.contains(b)
            np.testing.assert_array_equal(np.flatnonzero(b["landmark_mask"]), np.sort(order))
            for key in ("points", "goal_points", "visible", "depths", "goal_depths"):
                width = len(a[key]) // 16
                moved = b[key].reshape(16, width)
                np.testing.assert_array_equal(moved[order], a[key].reshape(16, width)[: slots.n])
                assert (np.delete(moved, order, axis=0) == 0).all()
            np.testing.assert_array_equal(b["c_error"][slots.pair_index(order)],
                                          a["c_error"][slots.pair_slots])  # fmt: skip
            assert np.count_nonzero(b["c_error"]) == np.count_nonzero(a["c_error"])
            np.testing.assert_array_equal(b["alpha_m_error"], a["alpha_m_error"])
            a, *_ = fixed.step(np.array([0.3, 0.2]))
            b, *_ = drawn.step(np.array([0.3, 0.2]))
    assert orders[0] != orders[1]  # drawn per episode
    assert orders[0] != list(range(slots.n))


def test_slot_order_is_checked() -> None:
    with pytest.raises(ValueError, match="unknown slot_order 'shuffled'"):
        gym.make("RadialIBVS/Parking-v0", max_landmarks=16, slot_order="shuffled")
    with pytest.raises(ValueError, match="slot_order='random' needs max_landmarks"):
        gym.make("RadialIBVS/Parking-v0", slot_order="random")


def test_max_landmarks_below_the_scene_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match="max_landmarks"):
        gym.make("RadialIBVS/Parking-v0", scenario="paper-lab", max_landmarks=8)
    with pytest.raises(ValueError, match="max_landmarks"):
        gym.make("RadialIBVS/ParkingGoal-v1", scenario="paper-lab", max_landmarks=8)


def test_the_ibvs_parks_with_padded_observations() -> None:
    from radial_ibvs_agents import IBVSPolicy
    from radial_ibvs_agents.rollouts import make_env, run_episode

    policy = IBVSPolicy()
    env = make_env(policy, "paper-sim", {"task": 1, "physics": "kinematic", "max_landmarks": 16})
    assert run_episode(policy, env, seed=0).success


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_reset_and_step_give_the_same_info_keys_all_numbers(env_id: str) -> None:
    """One info structure (Minari's record_infos), flat numbers and arrays (TorchRL)."""
    env = gym.make(env_id, scenario="paper-lab", physics="kinematic")
    _, at_reset = env.reset(seed=0)
    _, _, _, _, at_step = env.step(env.action_space.sample())
    assert set(at_reset) == set(at_step)
    for key, value in at_step.items():
        if key in ("is_success", "reached", "collision", "lost"):  # bool arrays once batched
            assert isinstance(value, bool), key
        else:  # numpy: TorchRL's info reader reads the dtype
            assert isinstance(value, np.generic | np.ndarray), (key, value)
        assert type(value) is type(at_reset[key]), key
    vec = gym.make_vec(env_id, num_envs=2, scenario="paper-lab", physics="kinematic")
    _, at_reset = vec.reset(seed=0)
    _, _, _, _, at_step = vec.step(vec.action_space.sample())
    assert set(at_reset) == set(at_step)
    assert all(isinstance(v, np.ndarray) for v in at_step.values())
    assert at_reset["reached"].shape == at_step["reached"].shape == (2,)


def test_a_goal_image_averaged_over_frames_is_closer_to_the_true_one() -> None:
    camera = {"mirror": "A", "non_central_offset": 0.01, "imperfections": {"pixel_noise_std": 1.0}}
    kwargs = {"scenario": "random", "physics": "kinematic", "camera": camera}
    ideal = gym.make("RadialIBVS/Parking-v0", scenario="random", physics="kinematic")
    errors = {}
    for frames in (1, 30):
        env = gym.make("RadialIBVS/Parking-v0", goal_image_frames=frames, **kwargs)
        total = []
        for seed in range(20):
            noisy, _ = env.reset(seed=seed)
            true, _ = ideal.reset(seed=seed)
            total.append(np.abs(noisy["goal_points"] - true["goal_points"]).mean())
        errors[frames] = float(np.mean(total))
    assert errors[30] < 0.5 * errors[1], errors  # about 1 / sqrt(30) of the noise
    default, _ = gym.make("RadialIBVS/Parking-v0", **kwargs).reset(seed=3)
    one, _ = gym.make("RadialIBVS/Parking-v0", goal_image_frames=1, **kwargs).reset(seed=3)
    np.testing.assert_array_equal(default["goal_points"], one["goal_points"])
    for bad in (0, 1001, 2.5, True):
        with pytest.raises(ValueError, match="goal_image_frames"):
            gym.make("RadialIBVS/Parking-v0", goal_image_frames=bad, **kwargs)


def test_the_goal_frames_projected_together_are_the_frames_taken_one_by_one() -> None:
    from radial_ibvs_gym.camera import CatadioptricCamera, Imperfections
    from radial_ibvs_gym.camera.measurement import camera_image, camera_images
    from radial_ibvs_gym.camera.presets import MIRROR_A, paper_intrinsics

    noisy = Imperfections(pixel_noise_std=1.0, principal_point_offset=(2.0, -1.0))
    camera = CatadioptricCamera(MIRROR_A, paper_intrinsics(), camera_z=-0.026, imperfections=noisy)
    rng = np.random.default_rng(0)
    p_cam = np.stack([rng.uniform(-4, 4, 12), rng.uniform(-4, 4, 12), rng.uniform(0, 2, 12)], -1)
    one, together = np.random.default_rng(5), np.random.default_rng(5)
    frames = [camera_image(camera, p_cam, one) for _ in range(30)]
    points, visible = camera_images(
        [camera] * 30, np.broadcast_to(p_cam, (30, 12, 3)), [together] * 30
    )
    np.testing.assert_array_equal(points, np.stack([x for x, _ in frames]))
    np.testing.assert_array_equal(visible, np.stack([v for _, v in frames]))
    assert visible.any() and not visible.all()


def test_every_title_of_a_rendered_frame_lies_inside_it() -> None:
    # the titles were cut off at the top of every frame (and of the README's GIF)
    env = gym.make("RadialIBVS/Parking-v0", render_mode="rgb_array", physics="kinematic")
    env.reset(seed=0)
    frame = env.render()
    figure = env.unwrapped._renderer.figure
    renderer = env.unwrapped._renderer.canvas.get_renderer()
    height, width = frame.shape[:2]
    for axes in figure.axes:
        box = axes.title.get_window_extent(renderer)
        assert axes.get_title() and 0 <= box.y0 and box.y1 <= height, axes.get_title()
        assert 0 <= box.x0 and box.x1 <= width, axes.get_title()
    env.close()


@pytest.mark.parametrize("action_type", ["twist", "wheels"])
def test_the_scalar_envs_command_is_rules_twist_commands(action_type: str) -> None:
    """The scalar env's Python-float hot path gives the commands of the shared rule."""
    from radial_ibvs_gym.envs.rules import twist_commands

    env = gym.make("RadialIBVS/Parking-v0", physics="kinematic", action_type=action_type)
    base = env.unwrapped
    env.reset(seed=0)
    sent: list[tuple[float, float]] = []
    step = base.world.step
    base.world.step = lambda command, dt: (sent.append(command), step(command, dt))[1]
    rng = np.random.default_rng(4)
    actions = rng.uniform(-2.5, 2.5, (40, 2)).astype(np.float32)  # beyond [-1, 1] too
    actions[:4] = [[1.0, -1.0], [0.0, 0.0], [-1.0, 1.0], [1e-9, -1e-9]]
    for action in actions:
        env.step(action)
    expected = twist_commands(actions.astype(np.float64), base.config)
    np.testing.assert_array_equal(np.array(sent, dtype=np.float64), expected)
