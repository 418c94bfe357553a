"""Message payloads of a pinwind log, encoded and decoded a block of samples at a time.

A log holds one message per sample and topic (docs/log_format.md). Encoding each message with a
Python serialiser would cost more than the step it records, so every codec here turns a block of
samples into payloads with numpy. Each topic has a fixed byte layout, so decoding is a view of the
stored bytes: float64 values come back bit for bit.

Payload formats, chosen for what readers understand without pinwind:

- ``Float64ArrayCodec``: ROS 2 ``std_msgs/msg/Float64MultiArray`` (``ros2msg`` schema, CDR
  payload). Rerun turns it into ``Scalars`` (time-series plots) on opening the file.
- ``JointStateCodec``: ROS 2 ``sensor_msgs/msg/JointState``; Rerun plots position, velocity and
  effort with one named series per joint.
- ``FrameTransformsCodec``: ``foxglove.FrameTransforms`` (protobuf); Rerun and Foxglove move
  link frames with it.
- ``encode_string``: ROS 2 ``std_msgs/msg/String``, for the model on ``/robot_description``.

CDR (OMG XCDR1, little endian): a 4-byte encapsulation header, then fields aligned to their size
counted from the end of that header; strings are a uint32 length (with the NUL) and the bytes;
sequences a uint32 count and the elements.
"""

from __future__ import annotations

import functools
import struct
from dataclasses import dataclass

import numpy as np

#: CDR encapsulation header: plain CDR, little endian, no options.
CDR_LE = b"\x00\x01\x00\x00"

_RULE = "=" * 80

#: ROS 2 message definitions (``ros2msg`` schema encoding: the message, then its dependencies).
FLOAT64_MULTI_ARRAY_MSG = f"""\
# Float64MultiArray: a float64 array with its layout (dimension labels and sizes).
std_msgs/MultiArrayLayout layout
float64[] data
{_RULE}
MSG: std_msgs/MultiArrayLayout
MultiArrayDimension[] dim
uint32 data_offset
{_RULE}
MSG: std_msgs/MultiArrayDimension
string label
uint32 size
uint32 stride
"""

JOINT_STATE_MSG = f"""\
std_msgs/Header header
string[] name
float64[] position
float64[] velocity
float64[] effort
{_RULE}
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
{_RULE}
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
"""

STRING_MSG = "string data\n"


@dataclass(frozen=True)
class Schema:
    """An MCAP schema: name, encoding and definition."""

    name: str
    encoding: str
    data: bytes


FLOAT64_MULTI_ARRAY = Schema(
    "std_msgs/msg/Float64MultiArray", "ros2msg", FLOAT64_MULTI_ARRAY_MSG.encode()
)
JOINT_STATE = Schema("sensor_msgs/msg/JointState", "ros2msg", JOINT_STATE_MSG.encode())
STRING = Schema("std_msgs/msg/String", "ros2msg", STRING_MSG.encode())


@functools.cache
def frame_transforms_schema() -> Schema:
    """foxglove.FrameTransforms as an MCAP protobuf schema (a FileDescriptorSet)."""
    from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
    from mcap_protobuf.schema import build_file_descriptor_set

    fds = build_file_descriptor_set(FrameTransforms)
    return Schema("foxglove.FrameTransforms", "protobuf", fds.SerializeToString())


class PayloadError(ValueError):
    """A payload does not have the layout its topic's codec expects."""


class _CdrLayout:
    """Builds a CDR payload template and remembers where the variable parts go."""

    def __init__(self) -> None:
        self.buf = bytearray(CDR_LE)

    def _align(self, size: int) -> None:
        self.buf += b"\0" * ((-(len(self.buf) - len(CDR_LE))) % size)

    def u32(self, value: int) -> int:
        self._align(4)
        at = len(self.buf)
        self.buf += struct.pack("<I", value)
        return at

    def string(self, text: str) -> None:
        data = text.encode("utf-8") + b"\0"
        self.u32(len(data))
        self.buf += data

    def f64_sequence(self, count: int) -> int:
        """A float64[] of ``count`` zeros; returns the byte offset of the first element."""
        self.u32(count)
        if count:
            self._align(8)
        at = len(self.buf)
        self.buf += bytes(8 * count)
        return at

    def template(self) -> np.ndarray:
        return np.frombuffer(bytes(self.buf), dtype=np.uint8)


def _stamp_columns(log_time_ns: np.ndarray) -> np.ndarray:
    """builtin_interfaces/Time (int32 sec, uint32 nanosec) as (n, 8) bytes."""
    ns = np.asarray(log_time_ns, dtype=np.uint64)
    out = np.empty(len(ns), dtype=[("sec", "<i4"), ("nanosec", "<u4")])
    out["sec"] = ns // np.uint64(1_000_000_000)
    out["nanosec"] = ns % np.uint64(1_000_000_000)
    return out.view(np.uint8).reshape(len(ns), 8)


def _rows(payloads: list[bytes] | np.ndarray, template: np.ndarray, topic: str) -> np.ndarray:
    """Stack equal-length payloads into (n, L) bytes, checking the length."""
    if isinstance(payloads, np.ndarray):
        rows = payloads
    else:
        lengths = {len(p) for p in payloads}
        if lengths and lengths != {len(template)}:
            raise PayloadError(
                f"{topic}: payloads of {sorted(lengths)} bytes, expected {len(template)}"
            )
        rows = np.frombuffer(b"".join(payloads), dtype=np.uint8)
    return rows.reshape(-1, len(template))


class Float64ArrayCodec:
    """std_msgs/msg/Float64MultiArray of a fixed shape, e.g. ``[("bearing", 8), ("axis", 3)]``.

    ``layout.dim`` carries the dimension labels and sizes (stride = product of the sizes from that
    dimension on, as in ROS); the element names go in the channel metadata.
    """

    def __init__(self, dims: list[tuple[str, int]]):
        self.shape = tuple(size for _, size in dims)
        self.count = int(np.prod(self.shape, dtype=int))
        layout = _CdrLayout()
        layout.u32(len(dims))
        for i, (label, size) in enumerate(dims):
            layout.string(label)
            layout.u32(size)
            layout.u32(int(np.prod(self.shape[i:], dtype=int)))
        layout.u32(0)  # data_offset
        self.data_at = layout.f64_sequence(self.count)
        self.template = layout.template()

    @property
    def size(self) -> int:
        """Payload length [bytes]."""
        return len(self.template)

    def encode(self, values: np.ndarray) -> np.ndarray:
        """(n, *shape) float64 → (n, size) payload bytes."""
        values = np.ascontiguousarray(values, dtype="<f8").reshape(-1, self.count)
        out = np.empty((len(values), self.size), dtype=np.uint8)
        out[:, : self.data_at] = self.template[: self.data_at]
        out[:, self.data_at :] = values.view(np.uint8)
        return out

    def decode(self, payloads: list[bytes] | np.ndarray, topic: str = "") -> np.ndarray:
        """Payloads written by ``encode`` → (n, *shape) float64 (a copy)."""
        rows = _rows(payloads, self.template, topic)
        if not np.array_equal(
            rows[:, : self.data_at],
            np.broadcast_to(self.template[: self.data_at], (len(rows), self.data_at)),
        ):
            raise PayloadError(f"{topic}: array layout differs from the one the log declares")
        data = np.ascontiguousarray(rows[:, self.data_at :])
        return data.view("<f8").astype(np.float64).reshape(len(rows), *self.shape)


class JointStateCodec:
    """sensor_msgs/msg/JointState with fixed joint names; the header stamp is the sample time."""

    def __init__(self, names: list[str], frame_id: str = "world"):
        self.names = list(names)
        layout = _CdrLayout()
        self.stamp_at = len(layout.buf)
        layout.buf += bytes(8)  # builtin_interfaces/Time: int32 sec, uint32 nanosec
        layout.string(frame_id)
        layout.u32(len(self.names))
        for name in self.names:
            layout.string(name)
        n = len(self.names)
        self.fields_at = [layout.f64_sequence(n) for _ in range(3)]
        self.template = layout.template()

    @property
    def size(self) -> int:
        """Payload length [bytes]."""
        return len(self.template)

    def encode(
        self,
        log_time_ns: np.ndarray,
        position: np.ndarray,
        velocity: np.ndarray,
        effort: np.ndarray,
    ) -> np.ndarray:
        """Stamps (n,) [ns] and three (n, joints) arrays → (n, size) payload bytes."""
        n, nj = len(log_time_ns), len(self.names)
        out = np.empty((n, self.size), dtype=np.uint8)
        out[:] = self.template
        out[:, self.stamp_at : self.stamp_at + 8] = _stamp_columns(log_time_ns)
        for at, values in zip(self.fields_at, (position, velocity, effort), strict=True):
            block = np.ascontiguousarray(values, dtype="<f8").reshape(n, nj)
            out[:, at : at + 8 * nj] = block.view(np.uint8)
        return out

    def decode(
        self, payloads: list[bytes] | np.ndarray, topic: str = ""
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Payloads written by ``encode`` → (position, velocity, effort), each (n, joints)."""
        rows = _rows(payloads, self.template, topic)
        fixed = np.ones(self.size, dtype=bool)
        fixed[self.stamp_at : self.stamp_at + 8] = False
        for at in self.fields_at:
            fixed[at : at + 8 * len(self.names)] = False
        if not np.array_equal(
            rows[:, fixed], np.broadcast_to(self.template[fixed], (len(rows), int(fixed.sum())))
        ):
            raise PayloadError(f"{topic}: joint names or layout differ from the log's")
        nj = len(self.names)
        return tuple(  # type: ignore[return-value]
            np.ascontiguousarray(rows[:, at : at + 8 * nj]).view("<f8").astype(np.float64)
            for at in self.fields_at
        )


def encode_string(text: str) -> bytes:
    """std_msgs/msg/String payload."""
    layout = _CdrLayout()
    layout.string(text)
    return bytes(layout.buf)


def decode_string(payload: bytes) -> str:
    """Inverse of ``encode_string``."""
    (length,) = struct.unpack_from("<I", payload, len(CDR_LE))
    start = len(CDR_LE) + 4
    return bytes(payload[start : start + length - 1]).decode("utf-8")


def _varint(value: int) -> bytes:
    out = bytearray()
    while True:
        byte = value & 0x7F
        value >>= 7
        if value:
            out.append(byte | 0x80)
        else:
            out.append(byte)
            return bytes(out)


def _field(number: int, payload: bytes) -> bytes:
    """A length-delimited protobuf field."""
    return _varint(number << 3 | 2) + _varint(len(payload)) + payload


def _varint_length(values: np.ndarray) -> np.ndarray:
    """Bytes of the protobuf varint of each value (uint64)."""
    length = np.ones(len(values), dtype=np.int64)
    for j in range(1, 10):
        length += values >= np.uint64(1 << (7 * j))
    return length


def _varint_columns(values: np.ndarray, length: int) -> np.ndarray:
    """Varints of ``length`` bytes each (values that need exactly that many) as (n, length)."""
    out = np.empty((len(values), length), dtype=np.uint8)
    for j in range(length):
        byte = (values >> np.uint64(7 * j)) & np.uint64(0x7F)
        out[:, j] = byte | np.uint64(0x80 if j < length - 1 else 0)
    return out


#: Per link: translation (foxglove.Vector3, tag 4) and rotation (foxglove.Quaternion, tag 5), every
#: double written with its tag (x = 1, y = 2, z = 3, w = 4), zeros included.
_POSE_DTYPE = np.dtype(
    [
        ("t_tag", "u1"),
        ("t_len", "u1"),
        ("x_tag", "u1"),
        ("x", "<f8"),
        ("y_tag", "u1"),
        ("y", "<f8"),
        ("z_tag", "u1"),
        ("z", "<f8"),
        ("r_tag", "u1"),
        ("r_len", "u1"),
        ("qx_tag", "u1"),
        ("qx", "<f8"),
        ("qy_tag", "u1"),
        ("qy", "<f8"),
        ("qz_tag", "u1"),
        ("qz", "<f8"),
        ("qw_tag", "u1"),
        ("qw", "<f8"),
    ]
)


class FrameTransformsCodec:
    """foxglove.FrameTransforms: a transform parent → child per link, stamped with the sample time.

    The protobuf bytes are assembled with numpy and read back with the protobuf library. Every
    double is written with its tag, zeros included (valid protobuf; a parser reads the same
    values), so the payload layout only depends on the stamp's varint lengths and poses
    round-trip bit for bit.
    """

    def __init__(self, parent: str, children: list[str]):
        self.parent = parent
        self.children = list(children)
        self._names = [_field(2, parent.encode()) + _field(3, c.encode()) for c in self.children]
        self._layouts: dict[int, tuple[np.ndarray, np.dtype]] = {}

    def _layout(self, stamp: int) -> tuple[np.ndarray, np.dtype]:
        """Template row for a stamp of that size, and a row dtype naming its stamp and pose bytes.

        The dtype's fields ``stamp{i}`` and ``pose{i}`` (link i) are whole byte blocks, so that
        filling them copies a block per row instead of byte by byte.
        """
        if stamp not in self._layouts:
            row, fields = bytearray(), {}
            pose_size = _POSE_DTYPE.itemsize
            for i, names in enumerate(self._names):
                size = 2 + stamp + len(names) + pose_size
                row += b"\x0a" + _varint(size) + b"\x0a" + _varint(stamp)
                if stamp:
                    fields[f"stamp{i}"] = (np.dtype(f"V{stamp}"), len(row))
                row += bytes(stamp) + names
                fields[f"pose{i}"] = (np.dtype(f"V{pose_size}"), len(row))
                row += bytes(pose_size)
            dtype = np.dtype(
                {
                    "names": list(fields),
                    "formats": [f[0] for f in fields.values()],
                    "offsets": [f[1] for f in fields.values()],
                    "itemsize": len(row),
                }
            )
            self._layouts[stamp] = (np.frombuffer(bytes(row), dtype=np.uint8), dtype)
        return self._layouts[stamp]

    def encode_runs(
        self, log_time_ns: np.ndarray, position: np.ndarray, quaternion: np.ndarray
    ) -> list[tuple[int, int, np.ndarray]]:
        """Payloads of consecutive samples with equally long stamps: [(start, stop, (m, L) bytes)].

        Args:
            log_time_ns: stamps (n,) [ns].
            position: link positions (n, links, 3) [m].
            quaternion: link orientations (n, links, 4), x y z w.
        """
        ns = np.asarray(log_time_ns, dtype=np.uint64)
        n, nl = len(ns), len(self.children)
        if n == 0:
            return []
        poses = np.zeros((n, nl), dtype=_POSE_DTYPE)
        poses["t_tag"], poses["t_len"] = 0x22, 27
        poses["r_tag"], poses["r_len"] = 0x2A, 36
        for i, key in enumerate("xyz"):
            poses[f"{key}_tag"] = 0x09 + 8 * i
            poses[key] = position[..., i]
        for i, key in enumerate(("qx", "qy", "qz", "qw")):
            poses[f"{key}_tag"] = 0x09 + 8 * i
            poses[key] = quaternion[..., i]
        pose_blocks = poses.view(f"V{_POSE_DTYPE.itemsize}").reshape(n, nl)
        sec = ns // np.uint64(1_000_000_000)
        nanos = ns % np.uint64(1_000_000_000)
        # google.protobuf.Timestamp, zero fields omitted as proto3 writes them.
        sec_len = np.where(sec > 0, _varint_length(sec), 0)
        nanos_len = np.where(nanos > 0, _varint_length(nanos), 0)
        stamp_lengths = sec_len * 16 + nanos_len
        breaks = np.flatnonzero(np.diff(stamp_lengths)) + 1
        out = []
        for start, stop in zip(np.r_[0, breaks], np.r_[breaks, n], strict=True):
            s_len, n_len = int(sec_len[start]), int(nanos_len[start])
            stamp = (1 + s_len if s_len else 0) + (1 + n_len if n_len else 0)
            template, dtype = self._layout(stamp)
            m = stop - start
            rows = np.empty(m, dtype=dtype)
            flat = rows.view(np.uint8).reshape(m, len(template))
            flat[:] = template
            if stamp:
                parts = []
                if s_len:
                    parts += [
                        np.full((m, 1), 0x08, np.uint8),
                        _varint_columns(sec[start:stop], s_len),
                    ]
                if n_len:
                    parts += [
                        np.full((m, 1), 0x10, np.uint8),
                        _varint_columns(nanos[start:stop], n_len),
                    ]
                stamp_block = np.ascontiguousarray(np.concatenate(parts, axis=1)).view(f"V{stamp}")
            for i in range(nl):
                if stamp:
                    rows[f"stamp{i}"] = stamp_block[:, 0]
                rows[f"pose{i}"] = pose_blocks[start:stop, i]
            out.append((int(start), int(stop), flat))
        return out

    def encode(
        self, log_time_ns: np.ndarray, position: np.ndarray, quaternion: np.ndarray
    ) -> list[bytes]:
        """One payload per sample (see ``encode_runs``)."""
        return [
            row.tobytes()
            for _, _, rows in self.encode_runs(log_time_ns, position, quaternion)
            for row in rows
        ]

    def decode(
        self, payloads: list[bytes] | np.ndarray, topic: str = ""
    ) -> tuple[np.ndarray, np.ndarray]:
        """Payloads → positions (n, links, 3) and quaternions (n, links, 4), links by child name.

        Payloads laid out as ``encode`` writes them are read with numpy views; any other valid
        FrameTransforms is parsed with the protobuf library.
        """
        if isinstance(payloads, np.ndarray):
            payloads = [row.tobytes() for row in payloads]
        n, nl = len(payloads), len(self.children)
        position = np.zeros((n, nl, 3))
        quaternion = np.zeros((n, nl, 4))
        seen = np.zeros((n, nl), dtype=bool)
        lengths = np.array([len(p) for p in payloads], dtype=np.int64)
        slow: list[int] = []
        for length in np.unique(lengths):
            rows = np.flatnonzero(lengths == length)
            fixed = self._fixed_layout(int(length))
            if fixed is None:
                slow.extend(rows)
                continue
            template, dtype = fixed
            block = np.frombuffer(b"".join(payloads[i] for i in rows), np.uint8)
            block = block.reshape(len(rows), int(length))
            constant = np.ones(int(length), dtype=bool)
            for name in dtype.names:
                field, offset = dtype.fields[name][:2]
                constant[offset : offset + field.itemsize] = False
            same = np.all(block[:, constant] == template[constant], axis=1)
            slow.extend(rows[~same])
            good = rows[same]
            records = np.ascontiguousarray(block[same]).reshape(-1).view(dtype)
            poses = np.stack([records[f"pose{i}"] for i in range(nl)], axis=1)
            poses = np.ascontiguousarray(poses).view(_POSE_DTYPE).reshape(len(good), nl)
            position[good] = np.stack([poses[k] for k in "xyz"], axis=-1)
            quaternion[good] = np.stack([poses[k] for k in ("qx", "qy", "qz", "qw")], axis=-1)
            seen[good] = True
        if slow:
            self._decode_protobuf(payloads, sorted(slow), position, quaternion, seen, topic)
        missing = [c for i, c in enumerate(self.children) if not seen[:, i].all()]
        if missing:
            raise PayloadError(f"{topic}: no transform for link(s) {', '.join(missing)}")
        return position, quaternion

    def _fixed_layout(self, length: int):
        """The ``encode`` layout of payloads ``length`` bytes long, if there is one."""
        for stamp in range(0, 18):  # a Timestamp holds at most 1 + 10 + 1 + 5 bytes
            layout = self._layout(stamp)
            if len(layout[0]) == length:
                return layout
        return None

    def _decode_protobuf(self, payloads, rows, position, quaternion, seen, topic) -> None:
        from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
        from google.protobuf.message import DecodeError

        index = {name: i for i, name in enumerate(self.children)}
        msg = FrameTransforms()
        for k in rows:
            try:
                msg.ParseFromString(bytes(payloads[k]))
            except DecodeError as err:
                raise PayloadError(f"{topic}: message {k} is not a FrameTransforms: {err}") from err
            for tf in msg.transforms:
                i = index.get(tf.child_frame_id)
                if i is None:
                    continue
                t, r = tf.translation, tf.rotation
                position[k, i] = (t.x, t.y, t.z)
                quaternion[k, i] = (r.x, r.y, r.z, r.w)
                seen[k, i] = True
