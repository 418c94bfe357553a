"""Reading logs of formats 1 and 2: every sample a row of message records, one per channel.

In formats 1 and 2 (format 3 stores columns, ``io/log_columns.py``), every sample is one row of
message records, one per channel in the same order, all of one length; the ``/tf`` records of the
samples that have a pose follow the rows (format 2; in format 1 they were the last record of
every row, their length changing with the time stamp's varint). Every value of a topic is then a
strided view of the decompressed chunk, copied once into the returned arrays (``RowSink``); poses
are placed at the rows of their sample numbers, then kept for those samples only
(``Result.pose_rows``). The framing (opcode, length, channel) and sample number of every record
are checked; the fixed payload bytes (CDR layout, joint and link names) on the first row of each
run of equal rows. A chunk laid out otherwise (rewritten by another tool) is decoded record by
record, to the same values. Format 3 logs carry the same ROS 2 topics for viewers, at the view
rate; pinwind reads their columns instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.io import mcap_file
from pinwind.io.log_channels import CHANNELS, TIME_TOPIC, ArrayLayout
from pinwind.io.log_columns import result_of
from pinwind.io.log_format import ENERGY_TOPIC, JOINTS_TOPIC, TF_TOPIC, WORLD_FRAME, array_topics
from pinwind.io.mcap_file import DamagedChunk, Scan
from pinwind.io.messages import (
    _POSE_DTYPE,
    Float64ArrayCodec,
    FrameTransformsCodec,
    JointStateCodec,
    PayloadError,
)


@dataclass
class RowPart:
    """Consecutive samples of a chunk: their times and, per destination, their values.

    ``values`` holds (destination, element index or None, (m, ...) array or strided view), a
    value for every sample; ``sparse`` holds (destination, rows, (k, ...) array) for the rows
    that have one (link poses, logged at the pose rate); ``seq`` the samples' numbers.
    """

    time: np.ndarray
    values: list[tuple[str, int | None, np.ndarray]]
    seq: np.ndarray | None = None
    sparse: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)


#: ``RowLayout.rows``' default: the chunk's rows were not looked for in a reading thread.
_NOT_LOOKED_FOR = object()


@dataclass
class RowChannel:
    """A channel whose values a read copies, and how to find them in a payload."""

    id: int
    topic: str
    kind: str  # "joints", "array", "tf"
    codec: Any
    keys: tuple[str, ...]
    record_length: int  # whole record [bytes]; 0 when it varies (/tf)


class RowLayout:
    """The codecs of a log's channels, and the decoding of its chunks of rows of records.

    Args:
        channels: the log's MCAP channels, by id.
        arrays: the arrays a read of the log fills.
    """

    def __init__(self, channels: dict[int, Any], arrays: ArrayLayout):
        names = arrays.names
        #: samples k with k mod pose_stride = 0 have a /tf record
        self.pose_stride = arrays.pose_stride
        self.terms = arrays.terms
        self.shapes = arrays.shapes
        self.by_topic: dict[str, RowChannel] = {}
        by_name = {c.topic: c.id for c in channels.values()}
        codecs: dict[str, tuple[str, Any, tuple[str, ...]]] = {
            JOINTS_TOPIC: ("joints", JointStateCodec(names["joint_names"], WORLD_FRAME), ()),
            TF_TOPIC: ("tf", FrameTransformsCodec(WORLD_FRAME, names["body_names"]), ()),
        }
        count = arrays.count
        for topic in array_topics():
            dims = [(topic.element, count[topic.element])] if topic.element else [("value", 1)]
            if topic.frame:
                dims.append(("axis", 3))
            if topic.field == "energy":
                keys = tuple(f"energy/{term}" for term in self.terms)
            else:
                keys = (topic.field,)
            codecs[topic.topic] = ("array", Float64ArrayCodec(dims), keys)
        for name, (kind, codec, keys) in codecs.items():
            if name in by_name:
                length = 31 + codec.size if kind != "tf" else 0  # whole record [bytes]
                keys = keys or CHANNELS[name]
                self.by_topic[name] = RowChannel(by_name[name], name, kind, codec, keys, length)
        self._tf_checks: dict[int, tuple[np.ndarray, np.ndarray, list[int]] | None] = {}
        #: records of samples not yet complete at the end of the last chunk decoded record by
        #: record (None when there are none)
        self.carry: Scan | None = None

    def row_bytes(self) -> int:
        """A lower bound of the bytes of one sample's records (to estimate counts)."""
        return max(1, sum(c.record_length for c in self.by_topic.values()))

    # fast path: rows of records ---------------------------------------------------------------

    def rows(
        self, data: bytes, wanted: list[RowChannel], where: str, parts: Any = _NOT_LOOKED_FOR
    ) -> list[RowPart]:
        """The samples of a chunk, as strided views of ``data`` (falls back to record by record).

        ``parts``: what ``find_rows`` gave for this chunk in a reading thread, if it was called.
        """
        if parts is _NOT_LOOKED_FOR:
            parts = self.find_rows(data, wanted)
        if parts is None:
            return self._records(data, wanted, where)
        self.carry = None
        return parts

    def find_rows(self, data: bytes, wanted: list[RowChannel]) -> list[RowPart] | None:
        """The rows of a chunk written as pinwind writes them, else None (thread-safe).

        Rows of records (one per channel), then, in format 2, the /tf records of the rows that
        have a pose.
        """
        size = len(data)
        parts: list[RowPart] = []
        pos = 0
        head = np.frombuffer(data, dtype=np.uint8)
        tf = self.by_topic.get(TF_TOPIC)
        time = self.by_topic.get(TIME_TOPIC)
        while pos < size:
            columns = _walk_row(data, pos)
            if columns is None:
                return None
            found = {channel: (column, length) for channel, column, length in columns}
            if tf is not None and len(found) == 1 and tf.id in found and parts:
                if tf in wanted and not self._place_poses(data, pos, parts, tf):
                    return None
                return parts
            if time is None or time.id not in found:
                return None
            in_row = [c for c in wanted if c.id in found]
            if any(c is not tf for c in wanted if c.id not in found):
                return None
            row = sum(length for _, _, length in columns)
            count = (size - pos) // row
            good = np.ones(count, dtype=bool)
            sample = np.ndarray((count,), "<u4", data, pos + columns[0][1] + 11, (row,))
            for _, column, _ in columns:
                # opcode, record length and channel of this column's record in every row (as
                # integers: numpy compares them far faster than 11-byte void values)
                for dtype, at in (("u1", 0), ("<u8", 1), ("<u2", 9)):
                    field = np.ndarray((count,), dtype, data, pos + column + at, (row,))
                    good &= field == field[0]
                # the records of a row belong to one sample (message sequence = sample index)
                good &= np.ndarray((count,), "<u4", data, pos + column + 11, (row,)) == sample
            if not good[0]:
                return None
            m = count if good.all() else int(np.argmin(good))
            part = self._views(data, head, pos, row, m, found, [time, *in_row])
            if part is None:
                return None
            part.seq = sample[:m].astype(np.int64)
            parts.append(part)
            pos += m * row
        return parts

    def _place_poses(self, data: bytes, pos: int, parts: list[RowPart], tf: RowChannel) -> bool:
        """Decode the /tf records from ``pos`` to the end of the chunk into the parts' rows.

        False if they are not all /tf records of samples of these parts.
        """
        size = len(data)
        offsets, seqs = [], []
        at = pos
        while at < size:
            if at + 31 > size or data[at] != Opcode.MESSAGE:
                return False
            length = int.from_bytes(data[at + 1 : at + 9], "little")
            if int.from_bytes(data[at + 9 : at + 11], "little") != tf.id or at + 9 + length > size:
                return False
            offsets.append((at + 31, at + 9 + length))
            seqs.append(int.from_bytes(data[at + 11 : at + 15], "little"))
            at += 9 + length
        seq = np.array(seqs, dtype=np.int64)
        if np.any(np.diff(seq) <= 0):
            return False
        try:
            position, quaternion = tf.codec.decode([data[a:b] for a, b in offsets], TF_TOPIC)
        except PayloadError:
            return False
        placed = 0
        for part in parts:
            part_seq = part.seq
            if part_seq is None:  # _rows numbers every part it makes
                raise RuntimeError("internal error: a part of a chunk without sample numbers")
            lo, hi = np.searchsorted(seq, [part_seq[0], part_seq[-1] + 1])
            rows = np.searchsorted(part_seq, seq[lo:hi])
            if np.any(part_seq[rows] != seq[lo:hi]):
                return False
            part.sparse += [
                ("body_position", rows, position[lo:hi]),
                ("body_quaternion", rows, quaternion[lo:hi]),
            ]
            placed += hi - lo
        return placed == len(seq)

    def _views(self, data, head, pos, row, m, found, channels) -> RowPart | None:
        """Views of the values of the m rows at pos, pos + row, ...

        None if a payload's fixed bytes differ from the codec's.
        """
        values: list[tuple[str, int | None, np.ndarray]] = []
        time = None
        for channel in channels:
            column, length = found[channel.id]
            at = pos + column + 9 + 22  # record header, then channel, sequence and times
            payload = head[at : at + length - 31]
            codec = channel.codec
            if channel.kind == "array":
                if length != channel.record_length or not np.array_equal(
                    payload[: codec.data_at], codec.template[: codec.data_at]
                ):
                    return None
                base = at + codec.data_at
                if channel.topic == TIME_TOPIC:
                    time = np.ndarray((m,), "<f8", data, base, (row,))
                    continue
                if channel.topic == ENERGY_TOPIC:
                    for i, term in enumerate(self.terms):
                        view = np.ndarray((m,), "V8", data, base + 8 * i, (row,))
                        values.append((f"energy/{term}", None, view))
                    continue
                if codec.count:
                    view = np.ndarray((m,), f"V{8 * codec.count}", data, base, (row,))
                    values.append((channel.keys[0], None, view))
            elif channel.kind == "joints":
                fixed = _joint_fixed(codec)
                if length != channel.record_length or not np.array_equal(
                    payload[fixed], codec.template[fixed]
                ):
                    return None
                nj = len(codec.names)
                for key, offset in zip(channel.keys, codec.fields_at, strict=True):
                    if nj:
                        view = np.ndarray((m,), f"V{8 * nj}", data, at + offset, (row,))
                        values.append((key, None, view))
            else:
                poses = self._tf_layout(codec, length - 31)
                if poses is None:
                    return None
                where, expected, offsets = poses
                if not np.array_equal(payload[where], expected):
                    return None
                # x y z and qx qy qz qw, each double after its one-byte protobuf tag
                for i, offset in enumerate(offsets):
                    position = np.ndarray((m, 3), "V8", data, at + offset + 3, (row, 9))
                    rotation = np.ndarray((m, 4), "V8", data, at + offset + 32, (row, 9))
                    values += [("body_position", i, position), ("body_quaternion", i, rotation)]
        if time is None:
            return None
        return RowPart(time, values)

    def _tf_layout(self, codec: FrameTransformsCodec, length: int):
        """(positions, bytes) of the fixed bytes of a /tf payload of that length, pose offsets."""
        if length not in self._tf_checks:
            layout = codec._fixed_layout(length)
            if layout is None:
                self._tf_checks[length] = None
            else:
                template, dtype = layout
                expected = template.copy()
                fixed = np.ones(length, dtype=bool)
                offsets = []
                tags = np.zeros(_POSE_DTYPE.itemsize, dtype=bool)
                pose = np.zeros(1, dtype=_POSE_DTYPE)
                pose_fields = _POSE_DTYPE.fields
                if pose_fields is None:  # a structured dtype, always has fields
                    raise RuntimeError("internal error: _POSE_DTYPE has no fields")
                for name, spec in pose_fields.items():
                    if name.endswith(("_tag", "_len")):
                        tags[spec[1]] = True
                pose["t_tag"], pose["t_len"] = 0x22, 27
                pose["r_tag"], pose["r_len"] = 0x2A, 36
                for i, key in enumerate("xyz"):
                    pose[f"{key}_tag"] = 0x09 + 8 * i
                for i, key in enumerate(("qx", "qy", "qz", "qw")):
                    pose[f"{key}_tag"] = 0x09 + 8 * i
                pose_bytes = pose.view(np.uint8)
                for name in dtype.names:
                    sub, offset = dtype.fields[name][:2]
                    fixed[offset : offset + sub.itemsize] = False
                    if name.startswith("pose"):
                        offsets.append(offset)
                        block = slice(offset, offset + _POSE_DTYPE.itemsize)
                        fixed[block] = tags
                        expected[block] = pose_bytes
                where = np.flatnonzero(fixed)
                self._tf_checks[length] = (where, expected[where], offsets)
        return self._tf_checks[length]

    # slow path: record by record -------------------------------------------------------------

    def _records(self, data: bytes, wanted: list[RowChannel], where: str) -> list[RowPart]:
        """Samples of a chunk in any layout: records gathered by channel, aligned on sequence.

        A sample whose records are split between this chunk and the next (another tool's
        chunking) is kept in ``self.carry`` and completed by the next chunk.
        """
        scan, self.carry = self.carry or Scan(), None
        try:
            mcap_file._chunk_messages(scan, data, where)
        except ValueError as err:
            raise DamagedChunk(str(err)) from err
        time = self.by_topic.get(TIME_TOPIC)
        if time is None:
            return []
        channels = [time, *wanted]
        gathered: dict[int, tuple[np.ndarray, list[bytes]]] = {}
        for channel in channels:
            blocks = scan.messages.get(channel.id, [])
            seqs = np.concatenate([b[0] for b in blocks]) if blocks else np.zeros(0, np.int64)
            flat = [bytes(p) for b in blocks for p in b[2]]
            order = np.argsort(seqs, kind="stable")
            gathered[channel.id] = (seqs[order], [flat[i] for i in order])
        tf = self.by_topic.get(TF_TOPIC)
        common = gathered[time.id][0]  # channels[0]: the time channel, never /tf
        for channel in channels[1:]:
            if channel is not tf:
                common = np.intersect1d(common, gathered[channel.id][0])
        posed = np.zeros(0, np.int64)
        if tf in wanted:
            # a sample is complete with its pose, if it has one; hold back from the first
            # sample whose pose is still to come (in the next chunk)
            posed = common[common % self.pose_stride == 0]
            missing = posed[~np.isin(posed, gathered[tf.id][0])]
            if len(missing):
                common, posed = common[common < missing[0]], posed[posed < missing[0]]
        last = common[-1] if len(common) else -1
        carry = Scan()
        for channel_id, (seqs, payloads) in gathered.items():
            rest = np.flatnonzero(~np.isin(seqs, common) & (seqs > last))
            if len(rest):
                block = (seqs[rest], np.zeros(len(rest), np.uint64), [payloads[i] for i in rest])
                carry.messages[channel_id].append(block)
        self.carry = carry if carry.messages else None
        if not len(common):
            return []
        values: list[tuple[str, int | None, np.ndarray]] = []
        sparse: list[tuple[str, np.ndarray, np.ndarray]] = []
        time_values = np.zeros(0)
        for channel in channels:
            seqs, payloads = gathered[channel.id]
            if channel is tf:
                rows = np.searchsorted(seqs, posed)
                found = channel.codec.decode([payloads[i] for i in rows], channel.topic)
                at = np.searchsorted(common, posed)
                sparse += [("body_position", at, found[0]), ("body_quaternion", at, found[1])]
                continue
            rows = np.searchsorted(seqs, common)
            found = channel.codec.decode([payloads[i] for i in rows], channel.topic)
            if channel.kind == "joints":
                values += [(k, None, v) for k, v in zip(channel.keys, found, strict=True)]
            elif channel.topic == TIME_TOPIC:
                time_values = found.reshape(-1)
            elif channel.topic == ENERGY_TOPIC:
                values += [(f"energy/{t}", None, found[:, i]) for i, t in enumerate(self.terms)]
            else:
                shape = self.shapes[channel.keys[0]]
                values.append((channel.keys[0], None, found.reshape(-1, *shape)))
        return [RowPart(time_values, values, common, sparse)]


def _walk_row(data: bytes, pos: int) -> list[tuple[int, int, int]] | None:
    """(channel, offset in the row, record length) of the message records of one row.

    A row ends where a channel comes again, at a record that is not a message, or at the end.
    """
    columns = []
    seen = set()
    at = pos
    size = len(data)
    while at + 9 + 22 <= size and data[at] == Opcode.MESSAGE:
        length = int.from_bytes(data[at + 1 : at + 9], "little")
        channel = int.from_bytes(data[at + 9 : at + 11], "little")
        if channel in seen or length < 22 or at + 9 + length > size:
            break
        seen.add(channel)
        columns.append((channel, at - pos, 9 + length))
        at += 9 + length
    if not columns or (at < size and data[at] == Opcode.MESSAGE and not _repeats(data, at, seen)):
        return None
    return columns


def _repeats(data: bytes, at: int, seen: set[int]) -> bool:
    return int.from_bytes(data[at + 9 : at + 11], "little") in seen


#: Fixed-byte positions by payload layout (size, stamp offset, value offsets, joint count). Keyed
#: by the layout, not the codec: a codec's id() is reused once it is garbage-collected, and a
#: cache keyed by it handed a later log's codec another log's positions (an IndexError).
_JOINT_FIXED: dict[tuple[int, int, tuple[int, ...], int], np.ndarray] = {}


def _joint_fixed(codec: JointStateCodec) -> np.ndarray:
    """Positions of the fixed bytes of a JointState payload (all but stamp and values)."""
    key = (codec.size, codec.stamp_at, tuple(codec.fields_at), len(codec.names))
    if key not in _JOINT_FIXED:
        fixed = np.ones(codec.size, dtype=bool)
        fixed[codec.stamp_at : codec.stamp_at + 8] = False
        for at in codec.fields_at:
            fixed[at : at + 8 * len(codec.names)] = False
        _JOINT_FIXED[key] = np.flatnonzero(fixed)
    return _JOINT_FIXED[key]


# --- the arrays a read fills ---------------------------------------------------------------------


#: Destinations that have a value only at some samples (poses, at the pose rate): NaN elsewhere
#: while a read fills them, then only the samples that have one.
_SPARSE = POSE_ARRAYS


class RowSink:
    """Preallocated arrays of the destinations read; unread ones stay empty."""

    def __init__(self, shapes: dict[str, tuple[int, ...]], keys: list[str], capacity: int):
        self.shapes = shapes
        self.keys = keys
        self.n = 0
        self.capacity = capacity
        self.arrays = {
            k: self._allocate(k, capacity if k in keys else 0, s) for k, s in shapes.items()
        }
        self.written: set[str] = set()  # the destinations the file gave values for

    @staticmethod
    def _allocate(key: str, n: int, shape: tuple[int, ...]) -> np.ndarray:
        return np.full((n, *shape), np.nan) if key in _SPARSE else np.empty((n, *shape))

    def put(self, part: RowPart, rows: slice | np.ndarray, count: int) -> None:
        """Copy ``count`` samples (``rows`` of the part) after those already there.

        Views of raw bytes (``V`` dtypes: a sample's doubles as one block, or one double) are
        copied as bytes, which numpy does much faster than unaligned float64 with odd strides.
        """
        if self.n + count > self.capacity:
            self._grow(self.n + count)
        n, end = self.n, self.n + count
        arrays = self.arrays
        arrays["time"][n:end] = part.time[rows]
        for key, sub, view in part.values:
            self.written.add(key)
            target = arrays[key][n:end] if sub is None else arrays[key][n:end, sub]
            if view.dtype.kind == "V":
                target = target.reshape(count, -1).view(view.dtype).reshape(count, *view.shape[1:])
            target[...] = view[rows]
        for key, at, values in part.sparse:
            if key not in self.keys:
                continue
            if isinstance(rows, slice):
                first = rows.start or 0
                inside = (at >= first) & (at < first + count)
                arrays[key][n + at[inside] - first] = values[inside]
            else:
                where = np.minimum(np.searchsorted(rows, at), len(rows) - 1)
                inside = rows[where] == at
                arrays[key][n + where[inside]] = values[inside]
        self.n = end

    def _grow(self, needed: int) -> None:
        """More room (a count from the index was missing or wrong: damaged or foreign file)."""
        self.capacity = max(needed, 2 * self.capacity)
        for key in self.keys:
            old = self.arrays[key]
            new = self._allocate(key, self.capacity, old.shape[1:])
            new[: self.n] = old[: self.n]
            self.arrays[key] = new

    def result(self, names: dict[str, list[str]], terms: list[str]) -> Result:
        """The samples so far as a Result (views of the arrays; the poses copied)."""
        arrays = {k: v[: self.n] for k, v in self.arrays.items()}
        for key in set(self.keys) - self.written - set(_SPARSE) - {"time"}:
            # a series this format does not store (added after it): NaN, not left-over memory
            arrays[key][...] = np.nan
        _flank_forces(arrays, self.written)
        position = arrays["body_position"]
        if position.shape[1]:  # the samples that have a pose: NaN at the others
            rows = np.flatnonzero(np.isfinite(position[:, 0, 0]))
        else:  # no links: a pose (of none) at every sample read
            rows = np.arange(len(position))
        arrays["pose_rows"] = rows
        for key in _SPARSE:
            arrays[key] = arrays[key][rows]
        return result_of(arrays, names, terms)


def _flank_forces(arrays: dict[str, np.ndarray], written: set[str]) -> None:
    """Each flank's normal force, which formats 1 and 2 do not store.

    Their meshes pushed on one flank at a time: the loaded one (``flank`` +1: front, −1: back)
    carries the normal force, the other none.
    """
    if not {"mesh_normal", "mesh_flank"} <= written:
        return
    normal, flank = arrays["mesh_normal"], arrays["mesh_flank"]
    for key, side in (("mesh_normal_front", 1.0), ("mesh_normal_back", -1.0)):
        if key not in written and arrays[key].shape == normal.shape:
            arrays[key][...] = np.where(flank == side, normal, 0.0)
