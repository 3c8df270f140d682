"""DAgger (agents.learned.distill), the observation history and the error-scale extractor."""

from __future__ import annotations

import itertools
import json
from dataclasses import replace

import numpy as np
import pytest
import torch
from gymnasium import spaces

from agents import load
from agents.analytic import make_analytic
from agents.learned.distill import dagger, goal_in_robot_frame, load_dagger_config
from agents.learned.extractors import ErrorScaleExtractor, LandmarkSetExtractor
from agents.learned.history import HistoryConfig, HistoryStack, history_key, history_space
from agents.learned.sb3_vec_env import make_vec_env

ENV = {
    "scenario": "random", "physics": "kinematic", "obs_mode": "features", "goal_depths": True,
    "max_landmarks": 16,
}  # fmt: skip

SMALL = f"""
dagger:
  env_kwargs: {json.dumps(ENV)}
  teacher_kwargs:
    {{goal_tolerance: 0.01, waypoint_tolerance: 0.1, hold_radius: 0.0, drive_gate: 0.35,
      reverse: false, final_radius: 0.3}}
  n_envs: 16
  rounds: 2
  steps_per_round: 1024
  updates_per_round: 20
  batch_size: 128
  dataset_size: 5000
  history: {{frames: 3}}
  eval_episodes: 4
"""


def test_history_stack_shifts_and_restarts():
    config = HistoryConfig(frames=3, keys=("a",))
    stack = HistoryStack(config, 2)
    first = stack.reset({"a": np.array([[1.0], [10.0]]), "b": np.zeros((2, 1))})
    np.testing.assert_array_equal(first[history_key("a", 1)], [[1.0], [10.0]])  # filled
    second = stack.step({"a": np.array([[2.0], [20.0]])}, np.array([False, False]))
    np.testing.assert_array_equal(second[history_key("a", 1)], [[1.0], [10.0]])
    np.testing.assert_array_equal(second[history_key("a", 2)], [[1.0], [10.0]])
    third = stack.step({"a": np.array([[3.0], [30.0]])}, np.array([False, True]))
    np.testing.assert_array_equal(third[history_key("a", 1)], [[2.0], [30.0]])  # env 1 anew
    np.testing.assert_array_equal(third[history_key("a", 2)], [[1.0], [30.0]])
    assert "b" in first and history_key("b", 1) not in first


def test_history_space_names_a_missing_key():
    space = spaces.Dict({"points": spaces.Box(-1, 1, (4,))})
    assert set(history_space(HistoryConfig(2, ("points",)), space).spaces) == {
        "points", "points@-1"
    }  # fmt: skip
    with pytest.raises(ValueError, match="c_error"):
        history_space(HistoryConfig(2, ("c_error",)), space)
    with pytest.raises(ValueError, match="frames"):
        HistoryConfig.from_mapping({"frames": 1}, "history")


def test_error_scale_extractor_is_scale_invariant_in_direction():
    space = spaces.Dict(
        {
            "c_error": spaces.Box(-2, 2, (6,)),
            "alpha_m_error": spaces.Box(-4, 4, (1,)),
            "points": spaces.Box(-1, 1, (4,)),
        }
    )
    extractor = ErrorScaleExtractor(space)
    assert extractor.features_dim == 7 + 2 + 4
    e = torch.tensor([[0.3, -0.1, 0.0, 0.2, 0.05, -0.4]])
    obs = {"alpha_m_error": torch.tensor([[0.01]]), "c_error": e, "points": torch.zeros(1, 4)}
    small = {**obs, "c_error": e * 1e-2}
    big, tiny = extractor(obs), extractor(small)
    # keys in the Dict's order: alpha_m_error (value, soft sign), c_error (6 + 1), points (4)
    np.testing.assert_allclose(big[0, :2], [0.01, 0.01 / (0.01 + 1e-3)], rtol=1e-5)
    # the direction keeps its size near the goal (to eps), the log-size tells how far
    np.testing.assert_allclose(big[0, 2:8], tiny[0, 2:8], atol=0.2)
    assert float(big[0, 8]) - float(tiny[0, 8]) > 3.0
    np.testing.assert_array_equal(big[0, 9:], 0.0)


def test_angle_keys_are_continuous_across_the_wrap_and_sharp_near_zero():
    space = spaces.Dict(
        {"alpha_m_error": spaces.Box(-4, 4, (1,)), "c_error": spaces.Box(-2, 2, (3,))}
    )
    plain = ErrorScaleExtractor(space)
    angles = ErrorScaleExtractor(space, angle_keys=["alpha_m_error"])
    assert angles.features_dim == plain.features_dim + 1

    def features(extractor, a):
        return extractor({"alpha_m_error": torch.tensor([[a]]), "c_error": torch.ones(1, 3)})[0, :3]

    below, above = np.pi - 1e-4, -np.pi + 1e-4  # the same heading, either side of the wrap
    torch.testing.assert_close(features(angles, below), features(angles, above), atol=1e-3, rtol=0)
    assert float(features(plain, below)[1] - features(plain, above)[1]) > 1.9  # the old jump
    near = features(angles, 0.01)  # sin, cos, soft sign: still sharp near zero
    assert float(near[2]) > 0.9 and float(features(angles, -0.01)[2]) < -0.9
    with pytest.raises(ValueError, match="angle key 'c_error'"):
        ErrorScaleExtractor(space, angle_keys=["c_error"])


def _set_space(n: int = 5):
    return spaces.Dict(
        {
            "alpha_m_error": spaces.Box(-4, 4, (1,)),
            "goal_depths": spaces.Box(0, 1e3, (n,)),
            "goal_points": spaces.Box(-1, 1, (2 * n,)),
            "points": spaces.Box(-1, 1, (2 * n,)),
            "visible": spaces.Box(0, 1, (n,)),
        }
    )


def _set_obs(rng, n: int = 5, seen: int = 4):
    angle = rng.uniform(-np.pi, np.pi, (2, n))
    now, goal = (np.stack([np.cos(a), np.sin(a)], axis=-1) for a in angle)
    visible = np.zeros(n)
    visible[:seen] = 1.0
    now *= visible[:, None]
    return {
        "alpha_m_error": torch.tensor([[0.02]]),
        "goal_depths": torch.tensor(rng.uniform(0.5, 4.0, (1, n)), dtype=torch.float32),
        "goal_points": torch.tensor(goal.reshape(1, -1), dtype=torch.float32),
        "points": torch.tensor(now.reshape(1, -1), dtype=torch.float32),
        "visible": torch.tensor(visible[None], dtype=torch.float32),
    }


def test_landmark_set_extractor_is_the_same_whichever_slots_the_landmarks_fill():
    torch.manual_seed(0)
    extractor = LandmarkSetExtractor(_set_space(), token_dim=16)
    base = ErrorScaleExtractor(_set_space(), point_error=True)
    assert extractor.features_dim == base.features_dim + 2 * 16 + 1
    obs = _set_obs(np.random.default_rng(1))
    order = torch.tensor([3, 0, 4, 1, 2])  # the landmarks moved to other slots

    def permute(key, value):
        width = value.shape[1] // 5
        if key == "alpha_m_error":
            return value
        return value.reshape(1, 5, width)[:, order].reshape(1, -1)

    moved = {k: permute(k, v) for k, v in obs.items()}
    a, b = extractor(obs), extractor(moved)
    tail = 2 * 16 + 1  # the set encoding: permutation invariant
    torch.testing.assert_close(a[:, -tail:], b[:, -tail:])
    assert float(a[0, -1].detach()) == pytest.approx(4 / 5)  # the share of slots seen
    assert (a[0, -tail:-1] > 0).any()  # the encoding is not empty
    # a hidden landmark's slot changes nothing, whatever numbers it holds
    hidden = {k: v.clone() for k, v in obs.items()}
    hidden["goal_points"][0, 8:] = torch.tensor([0.6, 0.8])
    hidden["goal_depths"][0, 4] = 9.0
    torch.testing.assert_close(extractor(hidden)[:, -tail:], a[:, -tail:])


def test_landmark_set_extractor_names_a_missing_key():
    space = _set_space()
    del space.spaces["goal_depths"]
    with pytest.raises(ValueError, match="goal_depths"):
        LandmarkSetExtractor(space)


def test_goal_in_robot_frame():
    obs = {"robot_pose": np.array([[1.0, 1.0, np.pi / 2]]), "goal_pose": np.array([[1, 4, 0.0]])}
    np.testing.assert_allclose(goal_in_robot_frame(obs), [[1.0, 0.0, 0.0, -1.0]], atol=1e-7)


def test_the_teachers_labels_still_park():
    """The teacher's settings (turn and drive together, forwards only, the smooth law in the
    last 30 cm) park 32 of 32 rooms, and hand over to the oracle near the goal."""
    from agents.analytic import PoseOracle

    teacher = make_analytic(
        "planner", goal_tolerance=0.01, waypoint_tolerance=0.1, hold_radius=0.0,
        drive_gate=0.35, reverse=False, final_radius=0.3,
    )  # fmt: skip
    oracle, handed_over = PoseOracle(), 0
    n = 32
    venv = make_vec_env(
        "RadialIBVS/Parking-v0", n, seed=10_000, monitor=False, privileged=True,
        privileged_map=True, **ENV,
    )  # fmt: skip
    obs, state, starts = venv.reset(), None, np.ones(n, dtype=bool)
    done, success = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    while not done.all():
        action, state = teacher.predict(obs, state, starts)
        near = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T) < 0.3
        if near.any():  # a straight room: the last segment is the only one
            expected = oracle.predict({k: v[near] for k, v in obs.items()})[0]
            np.testing.assert_array_equal(action[near], expected)
            handed_over += int(near.sum())
        assert (action[~near, 0] >= 0).all()  # forwards only
        obs, _, starts, infos = venv.step(action)
        for i in np.flatnonzero(starts & ~done):
            success[i] = infos[i]["is_success"]
        done |= starts
    assert success.all() and handed_over > 100


@pytest.fixture(scope="module")
def student(tmp_path_factory):
    path = tmp_path_factory.mktemp("dagger") / "config.yaml"
    path.write_text(SMALL)
    config = load_dagger_config(path)
    out = dagger(config, path.parent / "student", seed=3, progress=False)
    return config, out


def test_dagger_writes_a_model_agents_load_runs(student):
    config, out = student
    rows = (out / "progress.csv").read_text().splitlines()
    assert len(rows) == 1 + config.rounds
    assert (out / "learning_curve.png").stat().st_size > 0
    policy = load(out)
    assert type(policy).__name__ == "HistoryPolicy"
    meta = policy.metadata
    assert meta["trained_by"] == "dagger" and meta["teacher"] == "planner"
    assert policy.env_kwargs == ENV and meta["algo"] == "ppo"  # what evaluate makes the env with
    assert meta["best_round"] in range(config.rounds)
    assert "residual" not in meta  # no analytic policy inside at deployment
    import gymnasium as gym

    env = gym.make("RadialIBVS/Parking-v0", **ENV)
    policy.check_observation_space(env.observation_space)
    obs, _ = env.reset(seed=1)
    state = None
    for step in range(5):
        action, state = policy.predict(obs, state, np.array([step == 0]))
        assert env.action_space.contains(action)
        obs, *_ = env.step(action)
    assert set(state) == set(config.history.keys)


def test_history_policy_sees_what_training_saw(student):
    """Step by step with its state, the loaded policy acts as on the training-side stack."""
    config, out = student
    policy = load(out)
    n = 3
    venv = make_vec_env("RadialIBVS/Parking-v0", n, seed=7, monitor=False, **ENV)
    stack = HistoryStack(config.history, n)
    obs = venv.reset()
    stacked = stack.reset(obs)
    state, starts = None, np.ones(n, dtype=bool)
    for _ in range(12):
        action, state = policy.predict(obs, state, starts)
        direct, _ = policy.learned.predict(stacked)
        np.testing.assert_array_equal(action, direct)
        obs, _, starts, _ = venv.step(action)
        stacked = stack.step(obs, starts)


def test_dagger_is_deterministic_under_a_seed(student, tmp_path):
    config, out = student
    again = dagger(config, tmp_path / "again", seed=3, progress=False)
    assert (again / "policy.safetensors").read_bytes() == (out / "policy.safetensors").read_bytes()
    assert (again / "normalization.npz").read_bytes() == (out / "normalization.npz").read_bytes()


def test_a_round_depends_only_on_the_rounds_before_it(student, tmp_path):
    """A shorter run's rounds are the longer run's first rounds, bit for bit (so a config's
    fewer-rounds twin shares its seeds' checkpoints)."""
    config, out = student
    fewer = replace(config, rounds=config.rounds - 1)
    shorter = dagger(fewer, tmp_path / "short", seed=3, progress=False)
    for k in range(config.rounds - 1):
        for name in ("policy.safetensors", "normalization.npz"):
            a = (shorter / "rounds" / f"round_{k}" / name).read_bytes()
            assert a == (out / "rounds" / f"round_{k}" / name).read_bytes(), (k, name)
    assert not (shorter / "rounds" / f"round_{config.rounds - 1}").exists()


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ("  rounds: 0", "rounds"),
        ("  beta: 1.5", "beta"),
        ("  teacher: teleport", "teleport"),
        ("  net_arch: [64, -1]", "net_arch"),
        ("  rouns: 3", "rouns"),
        ("  aux_weight: -1", "aux_weight"),
        ("  relative_floor: -0.1", "relative_floor"),
        ("  relative_floor: true", "relative_floor"),
        ("  extractor: transformer", "transformer"),
        ("  angle_keys: [points]", "angle_keys"),
        ("  final_learning_rate: 0.5", r"final_learning_rate .*up to learning_rate"),
        ("  final_learning_rate: -1.0e-4", "final_learning_rate"),
    ],
)
def test_config_errors_name_the_key(tmp_path, line, match):
    path = tmp_path / "bad.yaml"
    path.write_text(SMALL + line + "\n")
    with pytest.raises(ValueError, match=match):
        load_dagger_config(path)


def test_each_rounds_fit_anneals_the_step_size_from_the_full_one(tmp_path):
    """final_learning_rate: every round starts at learning_rate and ends at the final one,
    along a cosine (half-way: the mean); without it the step size is left alone."""
    from agents.learned.distill import round_schedule

    path = tmp_path / "config.yaml"
    path.write_text(SMALL + "  learning_rate: 0.001\n  final_learning_rate: 0.0001\n")
    config = load_dagger_config(path)
    weight = torch.nn.Parameter(torch.zeros(1))
    optimiser = torch.optim.Adam([weight], lr=config.learning_rate)
    for _ in range(2):  # two rounds
        schedule = round_schedule(optimiser, config)
        seen = [optimiser.param_groups[0]["lr"]]
        for _ in range(config.updates_per_round):
            optimiser.step()
            schedule.step()
            seen.append(optimiser.param_groups[0]["lr"])
        assert seen[0] == pytest.approx(1e-3) and seen[-1] == pytest.approx(1e-4)
        assert all(a >= b for a, b in itertools.pairwise(seen))
        half = seen[config.updates_per_round // 2]
        assert half == pytest.approx(5.5e-4, rel=0.05)
    path.write_text(SMALL)
    assert round_schedule(optimiser, load_dagger_config(path)) is None


@pytest.mark.slow
@pytest.mark.parametrize(
    ("extractor", "cls"),
    [
        ("landmark_set", "LandmarkSetExtractor"),
        ("landmark_pose", "LandmarkPoseExtractor"),
        ("landmark_pose\n  pose_history: true", "LandmarkPoseExtractor"),
    ],
)
def test_a_landmark_set_student_is_stored_without_a_pickle_and_loads(tmp_path, extractor, cls):
    path = tmp_path / "config.yaml"
    history = "  history: {frames: 3}\n"
    small = SMALL.replace(history, "" if "history" not in extractor else history)
    path.write_text(small.replace("rounds: 2", "rounds: 1") + f"  extractor: {extractor}\n")
    config = load_dagger_config(path)
    assert config.extractor == extractor.split()[0]
    out = dagger(config, tmp_path / "student", seed=0, progress=False)
    policy = load(out)
    assert cls in (out / "policy.json").read_text()
    files = np.load(out / "normalization.npz").files
    normalised = {k.split("/", 1)[1] for k in files if k.startswith("mean/")}
    assert "landmark_mask" in normalised  # the extractor reads the landmark keys raw:
    assert not normalised & {"points", "goal_points", "goal_depths", "visible"}
    if config.pose_history:  # the past frames' points are solved for poses: read raw too
        assert not any(k.startswith(("points@", "visible@")) for k in normalised)
    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=5, monitor=False, **ENV)
    action, _ = policy.predict(venv.reset())
    assert action.shape == (2, 2) and np.isfinite(action).all()


def test_ppo_fine_tuning_starts_from_the_student(student, tmp_path):
    """train(init_from=DIR) takes the student's architecture, weights, history, statistics."""
    from agents.learned.training import train
    from agents.learned.zoo_config import load_train_config

    _, out = student
    config_path = tmp_path / "ppo.yaml"
    config_path.write_text(
        "RadialIBVS/Parking-v0:\n  n_envs: 4\n  policy: MultiInputPolicy\n"
        '  normalize: "dict(norm_obs=True, norm_reward=True, gamma=0.99)"\n'
        "  n_steps: 16\n  batch_size: 32\n  n_epochs: 1\n  learning_rate: 0.0\n"
        f"radial_ibvs_gym:\n  env_kwargs: {json.dumps(ENV)}\n  eval_freq: 1000000\n"
        "  eval_episodes: 1\n"
    )
    tuned_dir = train(
        load_train_config(config_path), tmp_path / "tuned", total_timesteps=64,
        init_from=out, progress=False,
    )  # fmt: skip
    tuned, original = load(tuned_dir), load(out)
    assert type(tuned).__name__ == "HistoryPolicy"  # the history came along
    assert tuned.metadata["init_from"] == str(out)
    venv = make_vec_env("RadialIBVS/Parking-v0", 3, seed=11, monitor=False, **ENV)
    obs, state_a, state_b = venv.reset(), None, None
    starts = np.ones(3, dtype=bool)
    for _ in range(6):  # learning rate 0: the same weights; the statistics moved a little
        a, state_a = tuned.predict(obs, state_a, starts)  # (256 more samples in them)
        b, state_b = original.predict(obs, state_b, starts)
        np.testing.assert_allclose(a, b, atol=0.03)
        assert np.abs(b).max() > 0.3  # not a fresh network's near-zero actions
        obs, _, starts, _ = venv.step(a)


def _fine_tune_config(tmp_path, extra: str) -> object:
    from agents.learned.zoo_config import load_train_config

    path = tmp_path / "ppo.yaml"
    path.write_text(
        "RadialIBVS/Parking-v0:\n  n_envs: 4\n  policy: MultiInputPolicy\n"
        '  normalize: "dict(norm_obs=True, norm_reward=True, gamma=0.99)"\n'
        "  n_steps: 16\n  batch_size: 32\n  n_epochs: 2\n  learning_rate: 0.001\n"
        f"radial_ibvs_gym:\n  env_kwargs: {json.dumps(ENV)}\n  eval_freq: 1000000\n"
        f"  eval_episodes: 1\n{extra}"
    )
    return load_train_config(path)


def _fine_tuned(student, tmp_path, fine_tune: str, steps: int):
    """Fine-tune the student for ``steps`` env steps; return the directory, the tuned policy
    and the student's parameters by name."""
    from agents.learned.loading import load_policy
    from agents.learned.training import train

    _, out = student
    config = _fine_tune_config(tmp_path, f"  fine_tune: {fine_tune}\n")
    tuned_dir = train(
        config, tmp_path / "tuned", total_timesteps=steps, init_from=out, progress=False
    )
    tuned, _ = load_policy(tuned_dir)
    original, _ = load_policy(out)
    return tuned_dir, tuned, dict(original.named_parameters())


def test_fine_tuning_sets_the_noise_and_trains_the_critic_alone_first(student, tmp_path):
    """fine_tune.log_std sets the exploration noise; during critic_warmup the actor's weights
    (and the features it shares with the critic) stay bit for bit the student's, the critic's
    move."""
    from agents.learned.fine_tune import critic_parameters

    tuned_dir, tuned, before = _fine_tuned(
        student, tmp_path, "{log_std: -2.0, critic_warmup: 128}", 128
    )
    critic = critic_parameters(tuned)
    assert critic and "log_std" not in critic
    for name, parameter in tuned.named_parameters():
        if name == "log_std":
            assert torch.all(parameter == -2.0)
        elif name in critic:
            continue
        else:
            assert torch.equal(parameter, before[name]), name
    assert any(not torch.equal(p, before[n]) for n, p in tuned.named_parameters() if n in critic)
    assert load(tuned_dir).metadata["fine_tune"] == {"log_std": -2.0, "critic_warmup": 128}


def test_after_the_warmup_the_actor_learns(student, tmp_path):
    """Past critic_warmup the actor's own layers move too."""
    _, tuned, before = _fine_tuned(student, tmp_path, "{critic_warmup: 64}", 192)
    moved = [n for n, p in tuned.named_parameters() if not torch.equal(p, before[n])]
    assert any(n.startswith("mlp_extractor.policy_net") for n in moved)


def test_the_warmup_freezes_the_actor_and_releases_it_at_the_end():
    """CriticWarmup freezes every parameter but the critic's for its steps, and a run that
    ends inside the warm-up still leaves the policy wholly trainable."""
    from stable_baselines3 import PPO

    from agents.learned.fine_tune import CriticWarmup, critic_parameters

    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, monitor=False, **ENV)
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, device="cpu")
    warmup = CriticWarmup(1_000)
    seen: list[set[str]] = []

    class Spy(CriticWarmup):
        def _on_rollout_start(self) -> None:
            names = model.policy.named_parameters()
            seen.append({n for n, p in names if p.requires_grad})

    model.learn(64, callback=[warmup, Spy(0)])
    assert seen and all(trainable == critic_parameters(model.policy) for trainable in seen)
    assert not warmup.frozen and all(p.requires_grad for p in model.policy.parameters())


@pytest.mark.parametrize(
    ("fine_tune", "match"),
    [
        ("{log_std: nan}", "log_std must be a number"),
        ("{log_std: 5}", "log_std must be a number"),
        ("{critic_warmup: -1}", "critic_warmup must be an integer"),
        ("{noise: 1}", r"unknown key\(s\) \['noise'\]"),
        ("3", "must be a mapping"),
    ],
)
def test_fine_tune_errors_name_the_value(tmp_path, fine_tune, match):
    with pytest.raises(ValueError, match=match):
        _fine_tune_config(tmp_path, f"  fine_tune: {fine_tune}\n")


def test_fine_tune_without_a_student_is_refused(tmp_path):
    from agents.learned.training import train

    config = _fine_tune_config(tmp_path, "  fine_tune: {log_std: -2.0}\n")
    with pytest.raises(ValueError, match="fine_tune starts from a student"):
        train(config, tmp_path / "run", total_timesteps=64, progress=False)


def test_the_relative_loss_weighs_a_small_labels_error_as_a_large_ones():
    """With relative_floor, missing a label of 0.02 by 0.01 costs what missing a label of 1 by
    0.5 does (about); the plain loss makes the first 2,500 times cheaper."""
    from agents.learned.distill import action_loss

    labels = torch.tensor([[0.02, 1.0]])
    small_miss = torch.tensor([[0.03, 1.0]])
    large_miss = torch.tensor([[0.02, 1.5]])
    ones = torch.ones(2)
    plain = [float(action_loss(a, labels, ones)) for a in (small_miss, large_miss)]
    assert plain[1] / plain[0] == pytest.approx(2500.0)
    relative = [float(action_loss(a, labels, ones, 1e-3)) for a in (small_miss, large_miss)]
    assert relative[0] / relative[1] == pytest.approx(1.0, rel=0.1)
    assert float(action_loss(labels, labels, ones, 0.05)) == 0.0


def test_an_exported_student_ships_as_an_sb3_ppo_model(student, tmp_path):
    """export_model ships a student with its kept round noted, and a stable-baselines3 PPO
    model.zip (for SB3 users; agents.load never reads it) that acts as agents.load's policy."""
    from stable_baselines3 import PPO

    from agents.learned.loading import load_policy
    from agents.learned.training import export_model

    _, out = student
    shipped = export_model(out, tmp_path / "dagger-student")
    meta = json.loads((shipped / "metadata.json").read_text())
    assert meta["shipped"].startswith(f"round {meta['best_round']}:")
    policy, _ = load_policy(shipped)
    model = PPO.load(shipped / "model.zip", device="cpu")  # our own file: a test may unpickle
    obs = {
        k: np.stack([v.sample() for _ in range(4)])
        for k, v in policy.observation_space.spaces.items()
    }
    ours, _ = policy.predict(obs, deterministic=True)
    theirs, _ = model.predict(obs, deterministic=True)
    np.testing.assert_array_equal(ours, theirs)
    assert isinstance(model, PPO) and load(shipped).metadata["best_round"] == meta["best_round"]
