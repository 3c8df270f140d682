"""radial-ibvs replay: a recording's frames through the pixel pipeline and a policy."""

from __future__ import annotations

import csv
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

pytest.importorskip("rosbags", reason="the [ros] extra")
mcap_reader = pytest.importorskip("mcap.reader", reason="the [ros] extra")
mcap_decoder = pytest.importorskip("mcap_ros2.decoder", reason="the [ros] extra")

from rosbags.rosbag2 import Reader, StoragePlugin, Writer  # noqa: E402

from radial_ibvs_agents.bags import bag_reader  # noqa: E402
from radial_ibvs_agents.bags import replay as replay_module  # noqa: E402
from radial_ibvs_agents.bags.messages import Messages  # noqa: E402
from radial_ibvs_agents.bags.record import record_episodes  # noqa: E402
from radial_ibvs_agents.bags.replay import BagError, replay_bag  # noqa: E402
from radial_ibvs_agents.cli import main  # noqa: E402

DETECTED = {"measurement": "detected", "image_size": 128}
POLICY = "pbvs-ekf"  # filters the pose: predicts from its commands over each frame's interval


def _read(bag: Path, topic: str) -> list[tuple[int, Any]]:
    """``topic``'s messages (log time, decoded), read with the mcap library."""
    (path,) = bag.glob("*.mcap")
    with path.open("rb") as stream:
        reader = mcap_reader.make_reader(stream, decoder_factories=[mcap_decoder.DecoderFactory()])
        return [(m.log_time, d) for _, _, m, d in reader.iter_decoded_messages(topics=[topic])]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[Any]]:
    out = tmp_path_factory.mktemp("bags") / "run"
    episodes = record_episodes(
        POLICY, out, "paper-lab", episodes=2, seed=1, env_kwargs=DETECTED, max_steps=25,
        progress=False,
    )  # fmt: skip
    return out, episodes


def _copy(src: Path, dst: Path, edit: Callable[[str, int, Any, int], Any]) -> None:
    """Copy a bag, each image message through ``edit(topic, log_ns, message, k)`` (None: drop)."""
    messages = Messages()
    store = messages.store
    with Reader(src) as reader, Writer(dst, version=9, storage_plugin=StoragePlugin.MCAP) as out:
        connections = {
            c.id: out.add_connection(c.topic, c.msgtype, typestore=store)
            for c in reader.connections
        }
        counts: dict[str, int] = {}
        for connection, log_ns, raw in reader.messages():
            data = raw
            if connection.msgtype == "sensor_msgs/msg/Image":
                k = counts.get(connection.topic, 0)
                counts[connection.topic] = k + 1
                message = edit(
                    connection.topic, log_ns, store.deserialize_cdr(raw, connection.msgtype), k
                )
                if message is None:
                    continue
                data = messages.serialize(message)
            out.write(connections[connection.id], log_ns, data)


@pytest.mark.parametrize("episode", [0, 1])
def test_a_replay_gives_the_recorded_commands_and_detections_frame_for_frame(
    recorded: Any, episode: int, tmp_path: Path
) -> None:
    bag, episodes = recorded
    out = tmp_path / "commands"
    result = replay_bag(
        bag, POLICY, out, "paper-lab", env_kwargs=DETECTED, episode=episode, progress=False
    )
    before = sum(e.steps + 1 for e in episodes[:episode])
    steps = episodes[episode].steps
    frames = [m for _, m in _read(bag, "/image_points")][before : before + steps + 1]
    commands = [m for _, m in _read(bag, "/cmd_vel")][before - episode : before - episode + steps]
    assert len(result.commands) == steps + 1 and result.dropped == 0
    recorded_commands = np.array([[m.linear.x, m.angular.z] for m in commands])
    np.testing.assert_array_equal(result.commands[:steps], recorded_commands)  # bit for bit
    for k, message in enumerate(frames):
        xy = np.asarray(message.data).reshape(-1, 2)
        np.testing.assert_array_equal(np.isnan(xy[:, 0]), ~result.visible[k])
        np.testing.assert_array_equal(xy[result.visible[k]], result.points[k][result.visible[k]])
    # the output: the commands as a bag (read with the other library) and a CSV
    written = _read(out, "/cmd_vel")
    assert [t for t, _ in written] == result.stamps_ns.tolist()
    np.testing.assert_array_equal([[m.linear.x, m.angular.z] for _, m in written], result.commands)
    rows = list(csv.DictReader((out / "commands.csv").open()))
    assert [float(r["v_m_s"]) for r in rows] == result.commands[:, 0].tolist()
    assert {r["status"] for r in rows} <= {"ok", "no_beacons"}


def test_a_dropped_frame_is_measured_as_nothing_seen_and_the_tracks_coast(
    recorded: Any, tmp_path: Path
) -> None:
    bag, _ = recorded
    gapped = tmp_path / "gapped"
    _copy(bag, gapped, lambda topic, t, m, k: None if topic == "/camera/image" and k == 5 else m)
    full = replay_bag(bag, POLICY, tmp_path / "a", env_kwargs=DETECTED, progress=False)
    cut = replay_bag(gapped, POLICY, tmp_path / "b", env_kwargs=DETECTED, progress=False)
    assert cut.dropped == 1 and len(cut.commands) == len(full.commands) - 1
    np.testing.assert_array_equal(cut.commands[:5], full.commands[:5])  # before the gap
    # after it, the same landmarks are tracked: those seen before coasted over the gap
    np.testing.assert_array_equal(cut.visible[5], full.visible[6])
    assert cut.stamps_ns[5] - cut.stamps_ns[4] == 200_000_000


def test_frames_out_of_order_are_refused_by_index(recorded: Any, tmp_path: Path) -> None:
    bag, _ = recorded
    swapped = tmp_path / "swapped"

    def swap(topic: str, t: int, message: Any, k: int) -> Any:
        if topic == "/camera/image" and k == 3:
            message.header.stamp.nanosec = 0  # stamped before the frames before it
        return message

    _copy(bag, swapped, swap)
    with pytest.raises(BagError, match=r"/camera/image\[3\] is stamped .* out of order"):
        replay_bag(swapped, POLICY, tmp_path / "o", env_kwargs=DETECTED, progress=False)


def test_another_encoding_is_refused_by_name(recorded: Any, tmp_path: Path) -> None:
    bag, _ = recorded
    rgb = tmp_path / "rgb"

    def colour(topic: str, t: int, message: Any, k: int) -> Any:
        message.encoding = "rgb8" if k == 2 and topic == "/camera/image" else message.encoding
        return message

    _copy(bag, rgb, colour)
    with pytest.raises(BagError, match=r"/camera/image\[2\]: encoding 'rgb8'"):
        replay_bag(rgb, POLICY, tmp_path / "o", env_kwargs=DETECTED, progress=False)


def test_a_missing_topic_is_named_with_the_bags_topics(recorded: Any, tmp_path: Path) -> None:
    bag, _ = recorded
    with pytest.raises(BagError, match=r"no topic '/camera/nope'; the bag has \["):
        replay_bag(bag, POLICY, tmp_path / "o", image_topic="/camera/nope", progress=False)


def test_sizes_are_bounded_before_anything_is_decoded(
    recorded: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bag, _ = recorded
    monkeypatch.setattr(replay_module, "MAX_FRAME_PIXELS", 64 * 64)
    with pytest.raises(BagError, match=r"a 128 x 128 frame \(at most 4096 pixels\)"):
        replay_bag(bag, POLICY, tmp_path / "o", env_kwargs=DETECTED, progress=False)
    monkeypatch.setattr(bag_reader, "MAX_RECORD_BYTES", 1000)
    with pytest.raises(BagError, match=r"exceeds limit 1000|\(at most 1000\)"):
        replay_bag(bag, POLICY, tmp_path / "p", env_kwargs=DETECTED, progress=False)


def test_what_is_not_a_bag_is_refused(tmp_path: Path) -> None:
    fake = tmp_path / "fake.mcap"
    fake.write_bytes(b"not an mcap file" * 10)
    with pytest.raises(BagError, match="not a readable MCAP file"):
        replay_bag(fake, POLICY, tmp_path / "o", progress=False)
    with pytest.raises(BagError, match="no such bag"):
        replay_bag(tmp_path / "nothing", POLICY, tmp_path / "o", progress=False)


def test_a_policy_that_needs_the_true_pose_is_refused(recorded: Any, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="image-only policies"):
        replay_bag(recorded[0], "oracle", tmp_path / "o", env_kwargs=DETECTED, progress=False)


def test_the_command_line(
    recorded: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "cli"
    args = ["replay", str(recorded[0]), "--policy", POLICY, "--out", str(out), "--no-progress"]
    assert main([*args, "--env-kwarg", "image_size=128"]) == 0
    assert "0 dropped" in capsys.readouterr().out
    assert (out / "commands.csv").is_file()
    assert main([*args, "--env-kwarg", "image_size=128"]) == 2  # the output exists
    assert "exists" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["replay", str(recorded[0]), "--policy", POLICY, "--out", str(tmp_path / "x"),
              "--start", "1,2"])  # fmt: skip
    assert "expected X,Y,YAW" in capsys.readouterr().err


def _commands(bag: Path) -> NDArray[np.float64]:
    return np.array([[m.linear.x, m.angular.z] for _, m in _read(bag, "/cmd_vel")])


def test_the_filter_predicts_from_the_recorded_commands_when_asked(
    recorded: Any, tmp_path: Path
) -> None:
    bag, _ = recorded
    own = replay_bag(bag, POLICY, tmp_path / "own", env_kwargs=DETECTED, progress=False)
    executed = replay_bag(
        bag, POLICY, tmp_path / "rec", env_kwargs=DETECTED, motion="recorded", progress=False
    )
    # it executed its own commands, as recorded: the float32 actions times the speed limits
    # (the filter's own are float64), so equal to their rounding
    np.testing.assert_allclose(executed.commands, own.commands, rtol=0, atol=1e-6)
    # a robot that stood still whatever it was told: the filter predicts no motion
    still = tmp_path / "still"
    _zero_commands(bag, still)
    moved = replay_bag(
        still, POLICY, tmp_path / "st", env_kwargs=DETECTED, motion="recorded", progress=False
    )
    np.testing.assert_array_equal(moved.commands[:1], own.commands[:1])  # nothing predicted yet
    assert not np.array_equal(moved.commands, own.commands)
    with pytest.raises(ValueError, match="does not"):
        replay_bag(bag, "ibvs", tmp_path / "i", motion="recorded", progress=False)


def _zero_commands(src: Path, dst: Path) -> None:
    messages = Messages()
    with Reader(src) as reader, Writer(dst, version=9, storage_plugin=StoragePlugin.MCAP) as out:
        store = messages.store
        connections = {
            c.id: out.add_connection(c.topic, c.msgtype, typestore=store)
            for c in reader.connections
        }
        for connection, log_ns, raw in reader.messages():
            data = (
                messages.serialize(messages.twist(0.0, 0.0))
                if connection.topic == "/cmd_vel"
                else raw
            )
            out.write(connections[connection.id], log_ns, data)


def test_labels_goal_depths_and_a_goal_image_file_stand_in_for_the_map(
    recorded: Any, tmp_path: Path
) -> None:
    # what the map gives, written as a robot's owner would: the same commands
    bag, _ = recorded
    by_map = replay_bag(bag, POLICY, tmp_path / "map", env_kwargs=DETECTED, progress=False)
    goal_image = _read(bag, "/camera/goal_image")[0][1]
    pixels = np.frombuffer(bytes(goal_image.data), np.uint8).reshape(128, 128)
    np.save(tmp_path / "goal.npy", pixels)
    from PIL import Image

    Image.fromarray(pixels).save(tmp_path / "goal.png")  # a 2-D uint8 array: mode L
    from radial_ibvs_agents import make_policy
    from radial_ibvs_agents.rollouts import make_env

    env = make_env(make_policy(POLICY), "paper-lab", DETECTED)
    env.reset(seed=1)  # the recorded episode 0
    setup = env.unwrapped.episode_setup
    detector = env.unwrapped._detector
    ep = setup.episode

    def listed(xy: NDArray[np.float64]) -> list[Any]:
        return [None if np.isnan(p).any() else [float(p[0]), float(p[1])] for p in xy]

    import yaml

    labels = {
        "goal": listed(detector.predicted(ep.goal, "goal")),
        "first": listed(detector.predicted(ep.start, "current")),
        "goal_depths": setup.goal_depths.tolist(),
    }
    (tmp_path / "labels.yaml").write_text(yaml.safe_dump(labels))
    labelled = replay_bag(
        bag, POLICY, tmp_path / "lab", env_kwargs=DETECTED, labels=tmp_path / "labels.yaml",
        progress=False,
    )  # fmt: skip
    np.testing.assert_array_equal(labelled.commands, by_map.commands)
    n = len(by_map.commands)
    for name in ("goal.npy", "goal.png"):  # every frame of the topic: episode 0 comes first
        from_file = replay_bag(
            bag, POLICY, tmp_path / f"out-{name}", env_kwargs=DETECTED, goal_image=tmp_path / name,
            labels=tmp_path / "labels.yaml", progress=False,
        )  # fmt: skip
        np.testing.assert_array_equal(from_file.commands[:n], by_map.commands)
    at = replay_bag(
        bag, POLICY, tmp_path / "at", env_kwargs=DETECTED, goal_at=0.0,
        labels=tmp_path / "labels.yaml", progress=False,
    )  # fmt: skip
    assert len(at.commands) == len(_read(bag, "/camera/image"))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("goal: [[1, 2]]\n", r"missing keys \['first'\]"),
        ("goal: [[1, 2]]\nfirst: [[1, 2]]\nextra: 1\n", r"unknown keys \['extra'\]"),
        ("goal: [[1, 2]]\nfirst: [[1, .nan]]\n", r"first\[0\] must be \[column, row\]"),
        ("goal: [[1, 2]]\nfirst: [[1, 2], [3, 4]]\n", "goal has 1 landmarks, first 2"),
        ("goal: [[1, 2]]\nfirst: [[1, 2]]\ngoal_depths: [-1]\n", "goal_depths must be 1"),
        ("goal: 3\nfirst: [[1, 2]]\n", "goal must be a list"),
    ],
)
def test_a_bad_labels_file_is_refused_by_key(tmp_path: Path, text: str, message: str) -> None:
    from radial_ibvs_agents.bags.labels import read_labels

    path = tmp_path / "labels.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        read_labels(path)


def test_a_bad_goal_image_file_is_refused(tmp_path: Path) -> None:
    from radial_ibvs_agents.bags.labels import read_goal_image

    np.save(tmp_path / "rgb.npy", np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(ValueError, match=r"a \(H, W\) uint8 array"):
        read_goal_image(tmp_path / "rgb.npy", 1000)
    np.save(tmp_path / "big.npy", np.zeros((40, 40), np.uint8))
    with pytest.raises(ValueError, match="at most 1000 pixels"):
        read_goal_image(tmp_path / "big.npy", 1000)
    np.save(tmp_path / "objects.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with pytest.raises(ValueError, match="uint8"):  # refused from its header: never unpickled
        read_goal_image(tmp_path / "objects.npy", 1000)
    (tmp_path / "goal.jpg").write_bytes(b"x")
    with pytest.raises(ValueError, match=r"a \.png or a \.npy"):
        read_goal_image(tmp_path / "goal.jpg", 1000)


def test_the_camera_comes_from_a_file_and_a_bad_key_is_named(
    recorded: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "camera.yaml").write_text("mirror: A\nnon_central_offset: 0.01\n")  # paper-lab's
    args = ["replay", str(recorded[0]), "--policy", POLICY, "--no-progress"]
    args += ["--env-kwarg", "image_size=128", "--camera", str(tmp_path / "camera.yaml")]
    assert main([*args, "--out", str(tmp_path / "a")]) == 0
    same = replay_bag(recorded[0], POLICY, tmp_path / "b", env_kwargs=DETECTED, progress=False)
    assert _commands(tmp_path / "a").tolist() == same.commands.tolist()
    (tmp_path / "camera.yaml").write_text("mirror: A\nfocal: 3\n")
    assert main([*args, "--out", str(tmp_path / "c")]) == 2
    assert "focal" in capsys.readouterr().err


def _recompressed(src: Path, dst: Path, compression: str) -> Path:
    """The bag's messages in one .mcap file written by the mcap library, chunks compressed."""
    from mcap.writer import CompressionType
    from mcap.writer import Writer as McapWriter

    dst.mkdir()
    path = dst / f"{dst.name}.mcap"
    kind = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4}[compression]
    store = Messages().store
    with Reader(src) as reader, path.open("wb") as stream:
        writer = McapWriter(stream, compression=kind, chunk_size=64 * 1024)
        writer.start(profile="ros2", library="tests")
        channels = {}
        for c in reader.connections:
            schema = writer.register_schema(
                c.msgtype, "ros2msg", store.generate_msgdef(c.msgtype)[0].encode()
            )
            channels[c.id] = writer.register_channel(c.topic, "cdr", schema)
        for connection, log_ns, raw in reader.messages():
            writer.add_message(channels[connection.id], log_ns, bytes(raw), log_ns)
        writer.finish()
    return path


@pytest.mark.parametrize("compression", ["zstd", "lz4"])
def test_compressed_chunks_replay_alike_and_a_lying_chunk_is_refused(
    recorded: Any, tmp_path: Path, compression: str
) -> None:
    bag, _ = recorded
    plain = replay_bag(bag, POLICY, tmp_path / "plain", env_kwargs=DETECTED, progress=False)
    path = _recompressed(bag, tmp_path / compression, compression)
    packed = replay_bag(path, POLICY, tmp_path / "packed", env_kwargs=DETECTED, progress=False)
    np.testing.assert_array_equal(packed.commands, plain.commands)
    # every chunk's header and index claim 1000 bytes uncompressed: a bomb to zstd and lz4
    from mcap.reader import make_reader

    with path.open("rb") as stream:
        chunk = make_reader(stream).get_summary().chunk_indexes[0]
    data = path.read_bytes()
    claimed = chunk.uncompressed_size.to_bytes(8, "little")
    lying = tmp_path / "lying.mcap"
    lying.write_bytes(data.replace(claimed, (1000).to_bytes(8, "little")))
    refused = r"zstd frame claims .*1000|lz4 frame does not hold|LZ4F_decompress failed"
    with pytest.raises(BagError, match=refused):
        replay_bag(lying, POLICY, tmp_path / "o", env_kwargs=DETECTED, progress=False)
    # a header that disagrees with its index
    header = data.index(claimed, chunk.chunk_start_offset)
    odd = tmp_path / "odd.mcap"
    odd.write_bytes(data[:header] + (1000).to_bytes(8, "little") + data[header + 8 :])
    with pytest.raises(BagError, match=r"1000 bytes uncompressed \(its index"):
        replay_bag(odd, POLICY, tmp_path / "p", env_kwargs=DETECTED, progress=False)


def test_a_break_in_the_recording_is_an_error_not_a_long_coast(
    recorded: Any, tmp_path: Path
) -> None:
    bag, _ = recorded
    late = tmp_path / "late"

    def jump(topic: str, t: int, message: Any, k: int) -> Any:
        if topic == "/camera/image" and k >= 4:
            message.header.stamp.sec += 3600  # an hour later: a clock jump, not 36,000 drops
        return message

    _copy(bag, late, jump)
    with pytest.raises(
        BagError, match=r"/camera/image\[4\] comes 3.6e\+03 s after .* more than 100"
    ):
        replay_bag(late, POLICY, tmp_path / "o", env_kwargs=DETECTED, progress=False)


def test_a_command_topic_without_commands_and_a_bad_goal_time_are_refused(
    recorded: Any, tmp_path: Path
) -> None:
    bag, _ = recorded
    with pytest.raises(BagError, match="/room holds geometry_msgs/msg/PolygonStamped, not"):
        replay_bag(bag, POLICY, tmp_path / "o", motion="recorded", command_topic="/room",
                   env_kwargs=DETECTED, progress=False)  # fmt: skip
    for value in (float("nan"), -1.0, float("inf")):
        with pytest.raises(ValueError, match="goal_at must be a time"):
            replay_bag(bag, POLICY, tmp_path / "o", goal_at=value, progress=False)


def test_a_goal_frame_by_time_is_labelled_from_where_the_robot_stood(
    recorded: Any, tmp_path: Path
) -> None:
    # the goal image: the last frame of episode 0, the robot's pose then from /odom
    bag, episodes = recorded
    at = episodes[0].steps * 0.1
    result = replay_bag(bag, POLICY, tmp_path / "at", env_kwargs=DETECTED, goal_at=at,
                        progress=False)  # fmt: skip
    assert len(result.commands) == len(_read(bag, "/camera/image"))
    assert result.visible[0].sum() >= 3  # the first frame's landmarks were labelled
