"""radial-ibvs record: a policy's episodes as a ROS 2 bag, read back by another library."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("rosbags", reason="the [ros] extra")
mcap_reader = pytest.importorskip("mcap.reader", reason="the [ros] extra")
mcap_decoder = pytest.importorskip("mcap_ros2.decoder", reason="the [ros] extra")

from radial_ibvs_agents import make_policy  # noqa: E402
from radial_ibvs_agents.bags import FOXGLOVE_LAYOUT  # noqa: E402
from radial_ibvs_agents.bags.messages import TOPICS  # noqa: E402
from radial_ibvs_agents.bags.record import EPISODE_GAP_NS, record_episodes, twist_of  # noqa: E402
from radial_ibvs_agents.cli import main  # noqa: E402
from radial_ibvs_agents.rollouts import make_env  # noqa: E402

DETECTED = {"measurement": "detected", "image_size": 128}
STEPS = 12


def _read(bag: Path) -> dict[str, list[tuple[int, str, Any]]]:
    """Every message of the bag's .mcap, by topic: (log time, schema name, decoded message),
    read with the mcap library (not rosbags, which wrote it)."""
    (path,) = bag.glob("*.mcap")
    topics: dict[str, list[tuple[int, str, Any]]] = {}
    with path.open("rb") as stream:
        reader = mcap_reader.make_reader(stream, decoder_factories=[mcap_decoder.DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            topics.setdefault(channel.topic, []).append((message.log_time, schema.name, decoded))
    return topics


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[Any]]:
    out = tmp_path_factory.mktemp("bags") / "run"
    episodes = record_episodes(
        "ibvs", out, "paper-lab", episodes=2, seed=3, env_kwargs=DETECTED, max_steps=STEPS,
        progress=False,
    )  # fmt: skip
    return out, episodes


def test_every_topic_has_its_standard_type_and_a_message_per_step(recorded: Any) -> None:
    out, episodes = recorded
    topics = _read(out)
    assert set(topics) == set(TOPICS) - {"/goal_image_frames"}  # one goal image, not averaged
    for topic, messages in topics.items():
        assert {schema for _, schema, _ in messages} == {TOPICS[topic][0]}, topic
    frames = sum(e.steps + 1 for e in episodes)
    for topic in ("/camera/image", "/image_points", "/odom", "/tf", "/errors", "/episode_info"):
        assert len(topics[topic]) == frames, topic
    assert len(topics["/cmd_vel"]) == sum(e.steps for e in episodes)
    for topic in ("/camera/goal_image", "/goal_image_points", "/landmarks", "/room"):
        assert len(topics[topic]) == 2, topic


def test_stamps_follow_the_control_period_and_episodes_follow_each_other(recorded: Any) -> None:
    out, episodes = recorded
    info = _read(out)["/episode_info"]
    stamps = np.array([t for t, _, _ in info])
    records = [json.loads(m.data) for _, _, m in info]
    first = episodes[0].steps + 1
    np.testing.assert_array_equal(stamps[:first], np.arange(first) * 100_000_000)
    assert stamps[first] == stamps[first - 1] + EPISODE_GAP_NS
    assert [r["episode"] for r in records] == [0] * first + [1] * (episodes[1].steps + 1)
    assert [r["seed"] for r in records[:: len(records) - 1]] == [3, 4]
    assert records[first - 1]["end"] == episodes[0].end
    image = _read(out)["/camera/image"][0][2]
    assert (image.header.stamp.sec, image.header.stamp.nanosec) == (0, 0)


def test_the_bag_holds_what_the_env_and_the_policy_did(recorded: Any) -> None:
    # the same episode run again: the frames the detector read, the points, poses, commands
    out, episodes = recorded
    topics = _read(out)
    policy = make_policy("ibvs")
    env = make_env(policy, "paper-lab", DETECTED)  # as record makes it
    base = env.unwrapped
    obs, info = env.reset(seed=3)
    state, start = None, np.ones(1, dtype=bool)
    for k in range(episodes[0].steps + 1):
        image = topics["/camera/image"][k][2]
        assert (image.encoding, image.height, image.width) == ("mono8", 128, 128)
        frame = np.frombuffer(bytes(image.data), dtype=np.uint8).reshape(128, 128)
        np.testing.assert_array_equal(frame, base.detected_frames["current"])
        points, visible = base.image_points
        recorded_points = np.asarray(topics["/image_points"][k][2].data).reshape(-1, 2)
        np.testing.assert_array_equal(np.isnan(recorded_points[:, 0]), ~visible)
        np.testing.assert_array_equal(recorded_points[visible], points[visible])
        odom = topics["/odom"][k][2].pose.pose
        pose = info["robot_pose"]
        assert (odom.position.x, odom.position.y) == (pose[0], pose[1])
        assert math.isclose(2 * math.atan2(odom.orientation.z, odom.orientation.w), pose[2])
        if k == episodes[0].steps:
            break
        action, state = policy.predict(obs, state, start, deterministic=True)
        start = np.zeros(1, dtype=bool)
        twist = topics["/cmd_vel"][k][2]
        assert (twist.linear.x, twist.angular.z) == twist_of(base.config, action)
        obs, _, _, _, info = env.step(action)
    goal = np.frombuffer(bytes(topics["/camera/goal_image"][0][2].data), np.uint8)
    env.reset(seed=3)
    np.testing.assert_array_equal(goal.reshape(128, 128), base.detected_frames["goal"])
    landmarks = topics["/landmarks"][0][2].poses
    want = base.episode_setup.episode.landmarks
    np.testing.assert_array_equal(
        [[p.position.x, p.position.y, p.position.z] for p in landmarks], want
    )


def test_every_topic_the_shipped_foxglove_layout_shows_is_in_a_recorded_bag(
    recorded: Any,
) -> None:
    layout = json.loads(FOXGLOVE_LAYOUT.read_text())
    shown: set[str] = set()
    for config in layout["configById"].values():
        if "imageMode" in config:
            shown.add(config["imageMode"]["imageTopic"])
        shown.update(config.get("topics", {}))
        shown.update(p["value"].split(".", 1)[0] for p in config.get("paths", []))
        if "topicPath" in config:
            shown.add(config["topicPath"])
    configs = layout["configById"].values()
    frames = {f.split(":", 1)[1] for c in configs for f in c.get("transforms", {})}
    topics = _read(recorded[0])
    assert shown and shown <= set(topics)
    children = {t.child_frame_id for _, _, m in topics["/tf"] for t in m.transforms}
    assert frames <= children


def test_without_rendering_the_bag_has_no_images(tmp_path: Path) -> None:
    out = tmp_path / "ideal"
    record_episodes("pbvs", out, "paper-sim", max_steps=3, progress=False)
    topics = _read(out)
    assert set(topics) == set(TOPICS) - {
        "/camera/image",
        "/camera/goal_image",
        "/goal_image_frames",
    }


def test_bad_input_is_refused_by_name(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "taken").mkdir()
    assert main(["record", "--policy", "pbvs", "--out", str(tmp_path / "taken")]) == 2
    assert "exists" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["record", "--policy", "pbvs", "--episodes", "0", "--out", str(tmp_path / "x")])
    assert "--episodes: must be at least 1" in capsys.readouterr().err
    with pytest.raises(ValueError, match=r"unknown policy|not a policy|no policy"):
        record_episodes("no-such-policy", tmp_path / "y", progress=False)
    assert not (tmp_path / "y").exists()
    assert [p.name for p in tmp_path.iterdir()] == ["taken"]  # no staging folder left


def test_without_the_extra_the_command_says_which(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "rosbags" else real(name, *a)
    )
    assert main(["record", "--policy", "pbvs", "--out", str(tmp_path / "z")]) == 2
    assert "[ros] extra" in capsys.readouterr().err


def test_the_docs_table_lists_every_topic_with_its_type() -> None:
    page = (Path(__file__).parents[3] / "docs" / "on-your-robot.md").read_text()
    for topic, (msgtype, _) in TOPICS.items():
        assert f"| `{topic}` | `{msgtype}` |" in page, topic


def test_each_frame_an_averaged_goal_image_took_is_recorded(tmp_path: Path) -> None:
    camera = {"mirror": "A", "non_central_offset": 0.01, "imperfections": {"pixel_noise_std": 1.0}}
    out = tmp_path / "averaged"
    record_episodes(
        "pbvs", out, "paper-sim", episodes=2, max_steps=2, progress=False,
        env_kwargs={"camera": camera, "goal_image_frames": 3},
    )  # fmt: skip
    topics = _read(out)
    frames = [np.asarray(m.data).reshape(-1, 2) for _, _, m in topics["/goal_image_frames"]]
    goals = [np.asarray(m.data).reshape(-1, 2) for _, _, m in topics["/goal_image_points"]]
    assert len(frames) == 6 and len(goals) == 2
    stamps = [t for t, _, _ in topics["/goal_image_frames"]]
    assert stamps[:3] == [0, 0, 0] and len(set(stamps[3:])) == 1
    for k, goal in enumerate(goals):  # the goal image: each landmark's mean direction
        shots = np.stack(frames[3 * k : 3 * k + 3])
        seen = ~np.isnan(shots[..., 0])
        total = np.where(seen[..., None], shots, 0.0).sum(axis=0)
        visible = seen.sum(axis=0) * 2 >= 3
        np.testing.assert_array_equal(~np.isnan(goal[:, 0]), visible)
        mean = total[visible] / np.linalg.norm(total[visible], axis=-1, keepdims=True)
        np.testing.assert_allclose(goal[visible], mean, rtol=0, atol=1e-12)


def test_odometry_holds_the_motion_that_moved_the_robot(tmp_path: Path) -> None:
    # the exact unicycle with the recorded (v, omega) over a period gives the next pose
    out = tmp_path / "odom"
    record_episodes("pbvs", out, "paper-sim", max_steps=20, progress=False,
                    env_kwargs={"physics": "kinematic"})  # fmt: skip
    odom = [m for _, _, m in _read(out)["/odom"]]
    poses = [
        (m.pose.pose.position.x, m.pose.pose.position.y,
         2 * math.atan2(m.pose.pose.orientation.z, m.pose.pose.orientation.w))
        for m in odom
    ]  # fmt: skip
    moved = 0
    for (x, y, yaw), (x1, y1, _), m in zip(poses, poses[1:], odom[1:], strict=False):
        v, w, dt = m.twist.twist.linear.x, m.twist.twist.angular.z, 0.1
        half = 0.5 * w * dt
        chord = v * dt * (math.sin(half) / half if half else 1.0)
        np.testing.assert_allclose(
            [x + chord * math.cos(yaw + half), y + chord * math.sin(yaw + half)], [x1, y1],
            rtol=0, atol=1e-9,
        )  # fmt: skip
        moved += abs(v) > 1e-3
    assert moved > 5
