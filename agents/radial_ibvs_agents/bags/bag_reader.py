"""Reading a ROS 2 bag (MCAP) a user hands over, as data: every size bounded before it is used.

:class:`BagReader` opens an indexed MCAP file with the ``mcap`` library and checks, before any
message is read:

- every record at most :data:`MAX_RECORD_BYTES` (the reader's own limit);
- every chunk, read raw from where the index says it is: its header's uncompressed size equal
  to the index's and at most :data:`MAX_RECORD_BYTES`; a zstd frame whose own content size
  says the same (zstd allocates what the frame claims); an lz4 frame decompressed here with
  that bound first (lz4 has none of its own); no other compression;
- each topic's message type, from its schema's name.

Messages are decoded with the trusted ROS 2 type store of ``rosbags`` for the type expected,
not with the definitions the file carries; a message that does not decode, or any read error,
is a :class:`BagError` naming the file, the topic and the message's index.
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from radial_ibvs_agents.bags.messages import Messages

__all__ = ["MAX_MESSAGES", "MAX_RECORD_BYTES", "BagError", "BagReader", "mcap_path"]

#: the largest record or chunk (uncompressed) a bag may hold, bytes
MAX_RECORD_BYTES = 256 * 2**20
#: messages read from one topic
MAX_MESSAGES = 1_000_000


class BagError(ValueError):
    """A bag that cannot be replayed; the message names the file, topic and value."""


def mcap_path(bag: Path) -> Path:
    """Return the ``.mcap`` file of a rosbag2 folder (or ``bag`` itself, a file)."""
    if bag.is_file():
        return bag
    if not bag.is_dir():
        raise BagError(f"{bag}: no such bag (a rosbag2 folder or an .mcap file)")
    files = sorted(bag.glob("*.mcap"))
    if len(files) != 1:
        raise BagError(f"{bag}: a rosbag2 folder with one .mcap file, found {len(files)}")
    return files[0]


class BagReader:
    """An indexed MCAP file whose sizes were checked, read topic by topic.

    Parameters
    ----------
    path
        The ``.mcap`` file.

    Raises
    ------
    BagError
        For a file that is not an indexed MCAP file or breaks a bound (module docs).
    """

    def __init__(self, path: Path) -> None:
        try:
            from mcap.exceptions import McapError
            from mcap.reader import SeekingReader
        except ModuleNotFoundError as error:  # pragma: no cover - the extra is missing
            raise ModuleNotFoundError(
                "replaying ROS 2 bags needs the [ros] extra: pip install 'radial_ibvs_gym[ros]'"
            ) from error
        self.path = path
        self.store = Messages().store
        self._errors = (McapError, struct.error, EOFError, ValueError, RuntimeError, KeyError)
        self._stream = path.open("rb")
        try:
            self._reader = SeekingReader(
                self._stream, validate_crcs=True, record_size_limit=MAX_RECORD_BYTES
            )
            summary = self._reader.get_summary()
            if summary is None:
                raise BagError(f"{path}: the MCAP file has no index (summary); re-index it first")
            if summary.channels and not summary.chunk_indexes:
                raise BagError(f"{path}: the MCAP file has no chunk index; re-index it first")
            for index in summary.chunk_indexes:
                self._check_chunk(index)
        except BagError:
            self._stream.close()
            raise
        except self._errors as error:
            self._stream.close()
            raise BagError(f"{path}: not a readable MCAP file ({error})") from None
        self.types = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()
                      if c.schema_id in summary.schemas}  # fmt: skip

    def _check_chunk(self, index: Any) -> None:
        """Read one chunk raw where the index puts it and bound its decompression."""
        from mcap.records import Chunk
        from mcap.stream_reader import StreamReader

        self._stream.seek(index.chunk_start_offset)
        records = StreamReader(
            self._stream, skip_magic=True, emit_chunks=True, record_size_limit=MAX_RECORD_BYTES
        ).records
        chunk = next(iter(records), None)
        where = f"{self.path}: the chunk at byte {index.chunk_start_offset}"
        if not isinstance(chunk, Chunk):
            raise BagError(f"{where} is not a chunk")
        size = chunk.uncompressed_size
        if size != index.uncompressed_size or size > MAX_RECORD_BYTES:
            raise BagError(
                f"{where}: {size} bytes uncompressed (its index: {index.uncompressed_size}; at "
                f"most {MAX_RECORD_BYTES})"
            )
        if chunk.compression == "zstd":
            import zstandard

            claimed = zstandard.frame_content_size(chunk.data)
            if claimed not in (-1, size):  # -1: unknown, then decompressed to `size` at most
                raise BagError(f"{where}: its zstd frame claims {claimed} bytes, not {size}")
        elif chunk.compression == "lz4":
            import lz4.frame

            decompressor = lz4.frame.LZ4FrameDecompressor()
            data = decompressor.decompress(chunk.data, max_length=size)
            if len(data) != size or not decompressor.eof:
                raise BagError(f"{where}: its lz4 frame does not hold {size} bytes")
        elif chunk.compression != "":
            raise BagError(f"{where}: compression {chunk.compression!r} (zstd, lz4 or none)")

    def close(self) -> None:
        """Close the file."""
        self._stream.close()

    def messages(self, topic: str, msgtype: str) -> Iterator[tuple[int, int, Any]]:
        """Yield ``(index, log time ns, message)`` of ``topic``, in the file's order.

        Raises
        ------
        BagError
            For a missing topic, another type, more than :data:`MAX_MESSAGES` messages, or a
            message that does not decode.
        """
        if topic not in self.types:
            raise BagError(f"{self.path}: no topic {topic!r}; the bag has {sorted(self.types)}")
        if self.types[topic] != msgtype:
            raise BagError(f"{self.path}: {topic} holds {self.types[topic]}, not {msgtype}")
        k = -1
        try:
            for k, (_, _, message) in enumerate(
                self._reader.iter_messages(topics=[topic], log_time_order=False)
            ):
                if k >= MAX_MESSAGES:
                    raise BagError(f"{self.path}: {topic} holds over {MAX_MESSAGES} messages")
                try:
                    decoded = self.store.deserialize_cdr(message.data, msgtype)
                except Exception as error:  # a malformed message: data, not our bug
                    raise BagError(
                        f"{self.path}: {topic}[{k}] is not a valid {msgtype} ({error})"
                    ) from None
                yield k, message.log_time, decoded
        except BagError:
            raise
        except self._errors as error:
            raise BagError(f"{self.path}: {topic}[{k + 1}] cannot be read ({error})") from None
