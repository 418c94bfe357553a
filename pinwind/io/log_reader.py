"""Reading pinwind logs: whole, by time window and channel, or in blocks; damaged files too.

``LogReader`` opens a log (docs/log_format.md) by its summary section: the chunk index gives each
chunk's time span, place and size, so a read fetches only the chunks that overlap its time window
and hold its channels. ``read_log`` returns one ``Result``; ``iter_log`` streams a log larger than
memory as consecutive ``Result`` blocks.

Decoding is done a chunk at a time with numpy. Format 3 stores every array as columns, one
message per block of samples (``log_columns``): the reading threads, one per core, each take a
chunk, decompress it and copy its series into their place in one array, known from the chunk
index before anything is decompressed. In formats 1 and 2, every sample is one
row of message records, one per channel in the same order, all of one length; the ``/tf``
records of the samples that have a pose follow the rows (format 2; in format 1 they were the
last record of every row, their length changing with the time stamp's varint). Every value of a
topic is then a strided view of the decompressed chunk, copied once into the returned arrays;
poses are placed at the rows of their sample numbers, then kept for those samples only
(``Result.pose_rows``). The framing (opcode,
length, channel) and sample number of every record are checked; the fixed payload bytes (CDR
layout, joint and link names) on the first row of each run of equal rows. A chunk laid out
otherwise (rewritten by another tool) is decoded record by record, to the same values. The
reading threads read, decompress and CRC-check the next chunks (zstd and zlib release the GIL)
while the main thread copies values.

Damage: a chunk that fails its CRC, does not decompress or is not where the index says is
skipped, and a ``LogDamaged`` warning gives the simulation time it covered. A damaged summary
section (the end of the file) is replaced by a walk through the data section.
"""

from __future__ import annotations

import json
import math
import os
import sys
import threading
import warnings
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.errors import InputError, LogError, LogRecovered
from pinwind.io import mcap_file
from pinwind.io.log_columns import (
    ColumnBlock,
    ColumnLayout,
    ColumnSink,
    decode_chunk,
    result_of,
)
from pinwind.io.log_format import (
    COLUMNS_TOPIC,
    FORMAT,
    FORMAT_VERSION,
    JOINTS_TOPIC,
    NAMES_OF,
    TF_TOPIC,
    WORLD_FRAME,
    array_topics,
)
from pinwind.io.mcap_file import MAGIC, ChunkRef, DamagedChunk, DamagedFile, Scan
from pinwind.io.messages import (
    _POSE_DTYPE,
    Float64ArrayCodec,
    FrameTransformsCodec,
    JointStateCodec,
    PayloadError,
)

TIME_TOPIC = "/run/time"


class _Channels(Mapping[str, tuple[str, ...]]):
    """Every channel (MCAP topic) that holds samples, and the Result arrays it fills.

    ``/run/time`` is always read. ``channels=`` takes these names, or a folder of them
    (``/meshes``, ``/bearings``, ``/run``). Read from the schema of series
    (``dynamics/series.py``) when used, so a series declared at run time has its channel.
    """

    def _table(self) -> dict[str, tuple[str, ...]]:
        return {
            JOINTS_TOPIC: ("angle", "speed", "torque"),
            **{t.topic: (t.field,) for t in array_topics()},
            TF_TOPIC: ("body_position", "body_quaternion"),
        }

    def __getitem__(self, topic: str) -> tuple[str, ...]:
        return self._table()[topic]

    def __iter__(self) -> Iterator[str]:
        return iter(self._table())

    def __len__(self) -> int:
        return len(self._table())


CHANNELS = _Channels()


def _cores() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 2


#: Threads that read, decompress and (format 3) copy chunks: one per core this process may
#: use, 2 to 8 (beyond that the copies are bound by memory bandwidth).
READ_THREADS = max(2, min(8, _cores()))
#: Chunks read ahead of the one being copied (1000 samples of a shipped model: ~1 MB decompressed).
READ_AHEAD = 2 * READ_THREADS - 1


class LogDamaged(LogRecovered):
    """Part of a log is damaged (a chunk fails its CRC, the summary is unreadable).

    Every intact chunk was read; the message says what is damaged and which simulation time
    range was lost.
    """


class LogTooLarge(LogError):
    """Reading the log needs more memory than there is."""


class UnknownChannel(InputError):
    """``channels=`` (``--channels``) names a channel that pinwind logs do not have."""

    def __init__(self, name: str):
        self.name = name
        super().__init__(
            f'unknown channel "{name}"; channels are: {", ".join(CHANNELS)} (or a folder of '
            "them: /meshes, /bearings, /run)"
        )


def select_channels(channels: Iterable[str] | str | None) -> tuple[str, ...]:
    """The topics asked for: names of ``CHANNELS``, or folders of them; None for every one.

    ``/run/time`` is always included.

    Raises:
        UnknownChannel: a name that is neither a channel nor a folder of channels.
    """
    if channels is None:
        return tuple(CHANNELS)
    if isinstance(channels, str):
        channels = [c for c in channels.split(",") if c.strip()]
    picked = {TIME_TOPIC}
    for name in channels:
        name = name.strip().rstrip("/")
        if name in CHANNELS:
            picked.add(name)
            continue
        under = [t for t in CHANNELS if t.startswith(name + "/")] if name.startswith("/") else []
        if not under:
            raise UnknownChannel(name)
        picked.update(under)
    return tuple(t for t in CHANNELS if t in picked)


def _time_bounds(start: float | None, stop: float | None) -> tuple[int, int]:
    """Log-time bounds [ns] that hold every sample with start ≤ t ≤ stop.

    log_time = rint(t · 1e9) is monotonic in t, so t ≥ start gives log_time ≥ floor(start · 1e9)
    and t ≤ stop gives log_time ≤ ceil(stop · 1e9).
    """
    for name, value in (("start", start), ("stop", stop)):
        if value is not None and math.isnan(value):
            raise InputError(f"the {name} of the time window is NaN; give a time [s]")
    lo = 0 if start is None or start <= 0 else math.floor(min(start, 1e10) * 1e9)
    hi = 2**64 - 1 if stop is None or stop >= 1e10 else math.ceil(stop * 1e9)
    return lo, hi


def _available_memory() -> int | None:
    """Bytes this process can still allocate: MemAvailable, bounded by a cgroup limit; or None."""
    found = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    try:
        cgroup = Path("/sys/fs/cgroup")
        limit = (cgroup / "memory.max").read_text().strip()
        if limit != "max":
            used = int((cgroup / "memory.current").read_text())
            for line in (cgroup / "memory.stat").read_text().splitlines():
                if line.startswith("file "):  # page cache: given back when memory is needed
                    used -= int(line.split()[1])
            found.append(int(limit) - used)
    except (OSError, ValueError, IndexError):
        pass
    return min(found) if found else None


# --- where the values are in a chunk -----------------------------------------------------------


@dataclass
class _Part:
    """Consecutive samples of a chunk: their times and, per destination, their values.

    ``values`` holds (destination, element index or None, (m, ...) array or strided view), a
    value for every sample; ``sparse`` holds (destination, rows, (k, ...) array) for the rows
    that have one (link poses, logged at the pose rate); ``seq`` the samples' numbers.
    """

    time: np.ndarray
    values: list[tuple[str, int | None, np.ndarray]]
    seq: np.ndarray | None = None
    sparse: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)


#: ``_Layout.rows``' default: the chunk's rows were not looked for in a reading thread.
_NOT_LOOKED_FOR = object()


@dataclass
class _Channel:
    """A channel whose values a read copies, and how to find them in a payload."""

    id: int
    topic: str
    kind: str  # "joints", "array", "tf"
    codec: Any
    keys: tuple[str, ...]
    record_length: int  # whole record [bytes]; 0 when it varies (/tf)


class _Layout:
    """The codecs and destinations of one log, and the decoding of its chunks."""

    def __init__(self, channels: dict[int, Any], names: dict[str, list[str]], pose_stride: int = 1):
        self.names = names
        #: samples k with k mod pose_stride = 0 have a /tf record
        self.pose_stride = max(1, int(pose_stride))
        self.terms = names["energy_terms"]
        nj, nm, nb, nl = (
            len(names[k]) for k in ("joint_names", "mesh_names", "bearing_names", "body_names")
        )
        count = {"joint": nj, "mesh": nm, "bearing": nb, "term": len(self.terms)}
        count.update({kind: len(names.get(key, [])) for kind, key in NAMES_OF.items()})
        #: destination → shape of one sample
        self.shapes: dict[str, tuple[int, ...]] = {
            "time": (),
            "angle": (nj,),
            "speed": (nj,),
            "torque": (nj,),
            "body_position": (nl, 3),
            "body_quaternion": (nl, 4),
        }
        self.by_topic: dict[str, _Channel] = {}
        by_name = {c.topic: c.id for c in channels.values()}
        codecs: dict[str, tuple[str, Any, tuple[str, ...]]] = {
            JOINTS_TOPIC: ("joints", JointStateCodec(names["joint_names"], WORLD_FRAME), ()),
            TF_TOPIC: ("tf", FrameTransformsCodec(WORLD_FRAME, names["body_names"]), ()),
        }
        for topic in array_topics():
            dims = [(topic.element, count[topic.element])] if topic.element else [("value", 1)]
            if topic.frame:
                dims.append(("axis", 3))
            shape = tuple(size for _, size in dims)
            if topic.field == "energy":
                keys = tuple(f"energy/{term}" for term in self.terms)
                self.shapes.update({key: () for key in keys})
            else:
                keys = (topic.field,)
                self.shapes[topic.field] = () if not topic.element else shape
            codecs[topic.topic] = ("array", Float64ArrayCodec(dims), keys)
        for name, (kind, codec, keys) in codecs.items():
            if name in by_name:
                length = 31 + codec.size if kind != "tf" else 0  # whole record [bytes]
                keys = keys or CHANNELS[name]
                self.by_topic[name] = _Channel(by_name[name], name, kind, codec, keys, length)
        self._tf_checks: dict[int, tuple[np.ndarray, np.ndarray, list[int]] | None] = {}
        #: records of samples not yet complete at the end of the last chunk decoded record by
        #: record (None when there are none)
        self.carry: Scan | None = None

    def keys(self, topics: Iterable[str]) -> list[str]:
        """Destinations filled by the topics (energy split into its terms)."""
        out = []
        for topic in topics:
            if topic == "/run/energy":
                out += [f"energy/{term}" for term in self.terms]
            elif topic == TIME_TOPIC:
                out.append("time")
            else:
                out += list(CHANNELS[topic])
        return out

    # fast path: rows of records ---------------------------------------------------------------

    def rows(
        self, data: bytes, wanted: list[_Channel], where: str, parts: Any = _NOT_LOOKED_FOR
    ) -> list[_Part]:
        """The samples of a chunk, as strided views of ``data`` (falls back to record by record).

        ``parts``: what ``find_rows`` gave for this chunk in a reading thread, if it was called.
        """
        if parts is _NOT_LOOKED_FOR:
            parts = self.find_rows(data, wanted)
        if parts is None:
            return self._records(data, wanted, where)
        self.carry = None
        return parts

    def find_rows(self, data: bytes, wanted: list[_Channel]) -> list[_Part] | None:
        """The rows of a chunk written as pinwind writes them, else None (thread-safe).

        Rows of records (one per channel), then, in format 2, the /tf records of the rows that
        have a pose.
        """
        size = len(data)
        parts: list[_Part] = []
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

    def _place_poses(self, data: bytes, pos: int, parts: list[_Part], tf: _Channel) -> bool:
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

    def _views(self, data, head, pos, row, m, found, channels) -> _Part | None:
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
                if channel.topic == "/run/energy":
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
        return _Part(time, values)

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

    def _records(self, data: bytes, wanted: list[_Channel], where: str) -> list[_Part]:
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
            elif channel.topic == "/run/energy":
                values += [(f"energy/{t}", None, found[:, i]) for i, t in enumerate(self.terms)]
            else:
                shape = self.shapes[channel.keys[0]]
                values.append((channel.keys[0], None, found.reshape(-1, *shape)))
        return [_Part(time_values, values, common, sparse)]


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


class _Sink:
    """Preallocated arrays of the destinations read; unread ones stay empty."""

    def __init__(self, shapes: dict[str, tuple[int, ...]], keys: list[str], capacity: int):
        self.shapes = shapes
        self.keys = keys
        self.n = 0
        self.capacity = capacity
        self.arrays = {
            k: self._allocate(k, capacity if k in keys else 0, s) for k, s in shapes.items()
        }

    @staticmethod
    def _allocate(key: str, n: int, shape: tuple[int, ...]) -> np.ndarray:
        return np.full((n, *shape), np.nan) if key in _SPARSE else np.empty((n, *shape))

    def put(self, part: _Part, rows: slice | np.ndarray, count: int) -> None:
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
        position = arrays["body_position"]
        if position.shape[1]:  # the samples that have a pose: NaN at the others
            rows = np.flatnonzero(np.isfinite(position[:, 0, 0]))
        else:  # no links: a pose (of none) at every sample read
            rows = np.arange(len(position))
        arrays["pose_rows"] = rows
        for key in _SPARSE:
            arrays[key] = arrays[key][rows]
        return result_of(arrays, names, terms)


# --- the reader ---------------------------------------------------------------------------------


class _Buffers:
    """Decompression buffers used again once nothing refers to them (thread-safe).

    A chunk's column blocks are views of its buffer; when the last view is gone (its samples
    are copied), only this list holds the buffer, and the next chunk decompresses into it.
    """

    #: references to a free buffer while ``take`` looks at it: the list, the loop variable and
    #: the argument of getrefcount
    _FREE = 3

    def __init__(self) -> None:
        self._all: list[np.ndarray] = []
        self._lock = threading.Lock()

    def take(self, size: int) -> np.ndarray | None:
        """A free buffer larger than ``size`` bytes (None when size is unknown)."""
        if size <= 0:
            return None
        with self._lock:
            for buffer in self._all:
                if buffer.size > size and sys.getrefcount(buffer) == self._FREE:
                    return buffer
            buffer = np.empty(size + size // 8 + 64, dtype=np.uint8)
            self._all.append(buffer)
            return buffer


def _json_values(record: dict[str, str]) -> dict[str, Any]:
    out = {}
    for key, text in record.items():
        try:
            out[key] = json.loads(text)
        except json.JSONDecodeError:
            out[key] = text
    return out


class LogReader:
    """An open pinwind log: metadata at once, samples on demand (``read``, ``blocks``).

    Args:
        path: the MCAP file.

    Attributes:
        path: the file.
        size: its size [bytes].
        metadata: MCAP metadata records, name → {key: decoded JSON value}.
        channels: topic → channel metadata (names, unit, description, ...).
        complete: the file has its end-status record and its data section ends properly.
        problem: where a file that was cut short ends, else ``""``.

    Raises:
        LogError: the file is missing, not an MCAP file, not a pinwind log, of a newer format,
            or damaged before its first chunk; the message names the file and what is wrong.
    """

    def __init__(self, path: str | os.PathLike):
        self.path = Path(path)
        where = str(self.path)
        if not self.path.exists():
            raise LogError(where, "no such file")
        if self.path.is_dir():
            raise LogError(where, "is a folder, not a log file")
        try:
            self._fd: int | None = os.open(self.path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
        except OSError as err:
            raise LogError(where, f"cannot read the file: {err.strerror}") from err
        try:
            self._open()
        except BaseException:
            self.close()
            raise

    def _open(self) -> None:
        where = str(self.path)
        fd = self._descriptor()
        self.size = os.fstat(fd).st_size
        start = mcap_file.read_at(fd, 0, len(MAGIC))
        if start != MAGIC:
            what = "is empty" if not start else f"starts with {start!r}"
            raise LogError(
                where,
                f"not an MCAP file (it {what}, not the MCAP magic bytes \\x89MCAP0\\r\\n)",
            )
        try:
            contents = mcap_file.read_contents(fd, self.size)
        except DamagedFile as err:
            raise LogError(where, str(err)) from err
        self._contents = contents
        self.problem = contents.problem
        self._damage = list(contents.damage)
        records: dict[str, dict[str, str]] = {}
        for name, (offset, length) in contents.metadata.items():
            try:
                records[name] = mcap_file.read_metadata(fd, offset, length)
            except Exception as err:  # struct, UTF-8: the record is damaged
                if name in ("pinwind", "pinwind.run", "pinwind.model"):
                    raise LogError(
                        where,
                        f"the '{name}' metadata record at byte {offset} is damaged "
                        f"({err}): the file is corrupted",
                    ) from err
                self._damage.append(f"the '{name}' metadata record at byte {offset} is damaged")
        ident = records.get("pinwind")
        if ident is None and self.problem and contents.library.startswith("pinwind"):
            raise LogError(where, f"{self.problem}, before the run's metadata: nothing to recover")
        if ident is None or ident.get("format") != FORMAT:
            topics = sorted({c.topic for c in contents.channels.values()})
            raise LogError(
                where,
                "an MCAP file but not a pinwind log (no 'pinwind' metadata record); it was "
                f"written by '{contents.library or 'an unknown library'}' and has topics "
                f"{', '.join(topics) or 'none'}",
            )
        version = int(ident.get("format_version", "0"))
        if version > FORMAT_VERSION:
            raise LogError(
                where,
                f"log format version {version} is newer than this pinwind reads "
                f"({FORMAT_VERSION}); install the pinwind version that wrote it "
                f"({ident.get('pinwind_version', '?')}) or newer",
            )
        self.metadata = {name: _json_values(rec) for name, rec in records.items()}
        for required in ("pinwind.run", "pinwind.model"):
            if required not in self.metadata:
                why = f": {self.problem}" if self.problem else ""
                raise LogError(where, f"the '{required}' metadata record is missing{why}")
        model = self.metadata["pinwind.model"]
        self.names = {k: list(model.get(k, [])) for k in (*NAMES_OF.values(), "body_names")}
        self.channels = {c.topic: dict(c.metadata) for c in contents.channels.values()}
        run = self.metadata["pinwind.run"]
        self._layout = _Layout(
            contents.channels, self.names, run.get("pose_stride", run.get("log_stride", 1))
        )
        #: format 3: the arrays are read from the columns (None: from the ROS 2 topics)
        self._columns: ColumnLayout | None = None
        for channel in contents.channels.values():
            if channel.topic == COLUMNS_TOPIC:
                try:
                    self._columns = ColumnLayout.of(
                        channel.id, dict(channel.metadata), self._layout.shapes
                    )
                except ValueError as err:
                    raise LogError(where, f"unexpected message contents: {err}") from err
        if self._columns is None and TIME_TOPIC not in self._layout.by_topic and contents.chunks:
            raise LogError(where, "unexpected message contents: the log has no /run/time channel")
        end = self.metadata.get("pinwind.end")
        self.complete = end is not None and contents.data_end and not self.problem
        self._end_damaged = end is None and "pinwind.end" in contents.metadata
        self._attachments: dict[str, bytes] | None = None
        self._buffers = _Buffers()

    # --- file ----------------------------------------------------------------------------------

    def close(self) -> None:
        """Close the file."""
        fd, self._fd = getattr(self, "_fd", None), None
        if fd is not None:
            os.close(fd)

    def _descriptor(self) -> int:
        """The open file's descriptor."""
        if self._fd is None:
            raise ValueError(f"I/O operation on a closed log ({self.path})")
        return self._fd

    def __enter__(self) -> LogReader:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @property
    def attachments(self) -> dict[str, bytes]:
        """Attachment name → bytes (the model file); a damaged attachment is left out."""
        if self._attachments is None:
            self._attachments = {}
            for name, (offset, length) in self._contents.attachments.items():
                try:
                    self._attachments[name] = mcap_file.read_attachment(
                        self._descriptor(), offset, length
                    )
                except Exception as err:  # CRC, struct: damaged
                    self._damage.append(f"attachment '{name}' is damaged ({err})")
        return self._attachments

    @property
    def model_text(self) -> str:
        """The model file as attached to the log."""
        return _model_text(self.attachments)

    @property
    def span(self) -> tuple[float, float] | None:
        """Times of the first and last sample [s] (log times, to 1 ns), None without samples."""
        chunks = self._sample_chunks(None)
        if not chunks:
            return None
        first = min(c.start_ns for c in chunks) * 1e-9
        return (first, max(c.end_ns for c in chunks) * 1e-9)

    # --- reading -------------------------------------------------------------------------------

    def read(
        self,
        *,
        start: float | None = None,
        stop: float | None = None,
        channels: Iterable[str] | str | None = None,
    ) -> Result:
        """The samples with start ≤ t ≤ stop [s] of the channels asked for, as one Result.

        Arrays of channels not asked for are empty (0 samples); ``time`` is always read.
        ``result.metadata["log"]`` says which channels and window were read.

        Raises:
            UnknownChannel: a channel name that is not in ``CHANNELS``.
            LogTooLarge: not enough memory for the arrays.
        """
        topics = select_channels(channels)
        keys = self._layout.keys(topics)
        capacity = None
        lost: list[str] = []
        try:
            chunks, capacity = self._plan(start, stop, topics)
            self._check_memory(capacity, keys)
            placed = None
            if self._columns is not None and capacity:
                placed = self._read_columns(chunks, keys, start, stop, lost)
            sink: _Sink | ColumnSink
            if placed is not None:
                sink = placed
            else:  # rows of records, or columns whose counts were not all known
                sink = self._sink(keys, capacity)
                for part, rows, count in self._parts(chunks, topics, start, stop, lost):
                    sink.put(part, rows, count)
            result = sink.result(self.names, self._layout.terms)
        except MemoryError as err:
            raise self._too_large(capacity, keys) from err
        self._finish(result, topics, start, stop, lost)
        self._warn(len(result), _span(result), lost)
        return result

    def blocks(
        self,
        samples: int = 100_000,
        *,
        start: float | None = None,
        stop: float | None = None,
        channels: Iterable[str] | str | None = None,
        progress: Callable[[float, float], None] | None = None,
    ) -> Iterator[Result]:
        """Consecutive Results of at most ``samples`` samples each, start ≤ t ≤ stop [s].

        Memory stays at about one block whatever the size of the log.

        Args:
            progress: called before each block is handed out with (simulated time read so
                far, simulated time of the window) [s], both from the window's start (or the
                log's first sample) to its stop (or the log's last sample).

        Raises:
            UnknownChannel: a channel name that is not in ``CHANNELS``.
            LogTooLarge: not enough memory for one block.
        """
        if samples < 1:
            raise InputError(f"blocks of {samples} samples: give at least 1")
        topics = select_channels(channels)
        keys = self._layout.keys(topics)
        lost: list[str] = []
        report = self._progress(start, stop, progress)
        total = 0
        first: float | None = None
        last = math.nan
        try:
            chunks, _ = self._plan(start, stop, topics, counts=False)
            sink = self._sink(keys, samples)
            for part, rows, count in self._parts(chunks, topics, start, stop, lost):
                done = 0
                while done < count:
                    take = min(count - done, samples - sink.n)
                    if isinstance(rows, slice):
                        row0 = rows.start or 0
                        piece = slice(row0 + done, row0 + done + take)
                    else:
                        piece = rows[done : done + take]
                    sink.put(part, piece, take)
                    done += take
                    if sink.n == samples:
                        block = sink.result(self.names, self._layout.terms)
                        self._finish(block, topics, start, stop, lost)
                        total += len(block)
                        first = block.time[0] if first is None else first
                        last = block.time[-1]
                        report(last)
                        yield block
                        sink = self._sink(keys, samples)
            if sink.n or total == 0:
                block = sink.result(self.names, self._layout.terms)
                self._finish(block, topics, start, stop, lost)
                if len(block):
                    total += len(block)
                    first = block.time[0] if first is None else first
                    last = block.time[-1]
                    report(last)
                yield block
        except MemoryError as err:
            raise self._too_large(samples, keys) from err
        self._warn(total, (first, last) if total and first is not None else None, lost)

    def _progress(
        self,
        start: float | None,
        stop: float | None,
        progress: Callable[[float, float], None] | None,
    ) -> Callable[[float], None]:
        """``progress`` as a function of the last sample time read [s] (``blocks``)."""
        if progress is None:
            return lambda _: None
        span = self.span or (0.0, 0.0)
        first = span[0] if start is None else max(start, span[0])
        end = span[1] if stop is None else min(stop, span[1])
        length = max(end - first, 0.0)
        return lambda t: progress(min(max(float(t) - first, 0.0), length), length)

    def _sink(self, keys: list[str], capacity: int) -> _Sink | ColumnSink:
        """The arrays a read of ``keys`` fills, room for ``capacity`` samples to start with."""
        if self._columns is not None:
            return ColumnSink(self._columns, self._layout.shapes, keys, capacity)
        return _Sink(self._layout.shapes, keys, capacity)

    def _sample_chunks(self, topics: tuple[str, ...] | None) -> list[ChunkRef]:
        """Chunks that hold samples (the time channel), or whose index is unknown, in file order.

        File order is the order the writer produced: time order for pinwind's chunks; for
        chunks of other tools whose time spans overlap (their /tf records come after a block of
        samples), the order in which each sample's records complete.
        """
        if self._columns is not None:
            wanted = self._columns.channel
        else:
            time = self._layout.by_topic.get(TIME_TOPIC)
            if time is None:
                return []
            wanted = time.id
        chunks = [c for c in self._contents.chunks if not c.index or wanted in c.index]
        return sorted(chunks, key=lambda c: c.offset)

    def _plan(self, start, stop, topics, counts: bool = True) -> tuple[list[ChunkRef], int]:
        """The chunks overlapping the window, and how many samples they hold there (at least)."""
        lo, hi = _time_bounds(start, stop)
        if self._columns is not None:
            return self._plan_columns(lo, hi)
        chunks = [c for c in self._sample_chunks(topics) if c.end_ns >= lo and c.start_ns <= hi]
        if not counts:
            return chunks, 0
        time = self._layout.by_topic[TIME_TOPIC].id if chunks else 0
        capacity = 0
        for chunk in chunks:
            inside = lo <= chunk.start_ns and chunk.end_ns <= hi
            try:
                found = mcap_file.index_entries(
                    self._descriptor(), chunk.index[time], time, count_only=inside
                )
            except (KeyError, ValueError):  # no index (cut file) or a damaged one: estimate
                capacity += max(1, (chunk.length * 8) // self._row_estimate())
                continue
            if isinstance(found, int):  # count_only=inside: the count
                capacity += found
            else:
                stamps = found[:, 0]
                capacity += int(np.count_nonzero((stamps >= lo) & (stamps <= hi)))
        return chunks, capacity

    def _plan_columns(self, lo: int, hi: int) -> tuple[list[ChunkRef], int]:
        """The columns chunks with samples in [lo, hi] [ns], and about how many samples."""
        chunks = [c for c in self._sample_chunks(None) if c.end_ns >= lo and c.start_ns <= hi]
        return chunks, sum(self._column_counts(chunks, lo, hi))

    def _column_counts(self, chunks: list[ChunkRef], lo: int, hi: int) -> list[int]:
        """About how many samples in [lo, hi] [ns] each columns chunk holds (0: unknown).

        A block's samples are evenly spaced (``dt · log_stride``) from the chunk's start to its
        end time, so the count needs no decompression; a count that is too high leaves a gap
        that is closed, one that is too low makes the read start again in order.
        """
        run = self.metadata["pinwind.run"]
        try:
            spacing = float(run["dt"]) * int(run.get("log_stride", 1)) * 1e9
        except (KeyError, TypeError, ValueError):
            spacing = math.nan
        if not spacing > 0:
            return [0] * len(chunks)
        counts = []
        for chunk in chunks:
            m = round((chunk.end_ns - chunk.start_ns) / spacing) + 1
            first = max(0, math.ceil((lo - chunk.start_ns) / spacing - 1e-6))
            last = min(m - 1, math.floor((hi - chunk.start_ns) / spacing + 1e-6))
            counts.append(max(0, last - first + 1))
        return counts

    def _read_columns(
        self,
        chunks: list[ChunkRef],
        keys: list[str],
        start: float | None,
        stop: float | None,
        lost: list[str],
    ) -> ColumnSink | None:
        """The samples of a columns log, each chunk copied into its place by a reading thread.

        Each chunk is decompressed and copied by one of the reading threads into its place in the
        arrays (known from the chunk index). None when a chunk holds more samples than its place
        (a foreign or odd file: the caller reads in order).

        A damaged chunk, or one with fewer samples than its place, leaves a gap that is closed
        by moving the samples after it, in order as the chunks finish.
        """
        layout = self._columns
        if layout is None:
            raise RuntimeError("internal error: columns read from a log without them")
        counts = self._column_counts(chunks, *_time_bounds(start, stop))
        if not all(counts):
            return None
        places = np.concatenate([[0], np.cumsum(counts)]).tolist()
        place = {chunk.offset: (places[i], counts[i]) for i, chunk in enumerate(chunks)}
        sink = ColumnSink(layout, self._layout.shapes, keys, places[-1])

        def load(chunk: ChunkRef, _) -> tuple[bytes, int | None, str]:
            at, room = place[chunk.offset]
            _, blocks, damage = self._load_columns(chunk, None)
            if damage:
                return b"", 0, damage
            parts = [(block, *_window(block.time, start, stop)) for block in blocks]
            filled = sum(count for _, _, count in parts)
            if filled > room:
                return b"", None, ""
            for block, rows, count in parts:
                if count:
                    sink.place(block, rows, count, at)
                    at += count
            return b"", filled, ""

        n = 0
        damaged = []
        for chunk, _, filled, damage in self._chunk_data(chunks, [], load):
            if damage:
                damaged.append(
                    f"{damage}: t = {chunk.start_ns * 1e-9:.9g} to {chunk.end_ns * 1e-9:.9g} s lost"
                )
                continue
            if filled is None:
                return None
            sink.move(place[chunk.offset][0], filled, n)
            n += filled
        sink.n = n
        lost += damaged
        return sink

    def _row_estimate(self) -> int:
        """A lower bound of the bytes of one sample's records (to estimate counts)."""
        return max(1, sum(c.record_length for c in self._layout.by_topic.values()))

    def _parts(self, chunks, topics, start, stop, lost) -> Iterator[tuple[Any, Any, int]]:
        """(part, rows in the window, count) of every chunk, read ahead by the reading threads."""
        if self._columns is not None:
            for chunk, _, blocks, damage in self._chunk_data(chunks, [], self._load_columns):
                if damage:
                    lost.append(
                        f"{damage}: t = {chunk.start_ns * 1e-9:.9g} to "
                        f"{chunk.end_ns * 1e-9:.9g} s lost"
                    )
                    continue
                for block in blocks:
                    rows, count = _window(block.time, start, stop)
                    if count:
                        yield block, rows, count
            return
        wanted = [
            self._layout.by_topic[t]
            for t in topics
            if t in self._layout.by_topic and t != TIME_TOPIC
        ]
        for chunk, data, found, damage in self._chunk_data(chunks, wanted):
            if damage:
                lost.append(
                    f"{damage}: t = {chunk.start_ns * 1e-9:.9g} to {chunk.end_ns * 1e-9:.9g} s lost"
                )
                continue
            where = f"the chunk at byte {chunk.offset}"
            try:
                parts = self._layout.rows(data, wanted, where, found)
            except DamagedChunk as err:
                lost.append(
                    f"{err}: t = {chunk.start_ns * 1e-9:.9g} to {chunk.end_ns * 1e-9:.9g} s lost"
                )
                continue
            except PayloadError as err:
                raise LogError(str(self.path), f"unexpected message contents: {err}") from err
            for part in parts:
                rows, count = _window(part.time, start, stop)
                if count:
                    yield part, rows, count

    def _load_columns(self, chunk: ChunkRef, _) -> tuple[bytes, list[ColumnBlock], str]:
        """A columns chunk's blocks, or why it is damaged (thread-safe)."""
        layout = self._columns
        if layout is None:
            raise RuntimeError("internal error: columns read from a log without them")
        try:
            data = mcap_file.read_chunk(self._descriptor(), chunk, self._buffers.take(chunk.size))
            return b"", decode_chunk(data, layout), ""
        except DamagedChunk as err:
            return b"", [], str(err)

    def _chunk_data(
        self, chunks: list[ChunkRef], wanted: list[_Channel], load=None
    ) -> Iterator[tuple]:
        """(chunk, its records, their rows or None, "" or why it is damaged), in order.

        ``READ_THREADS`` threads read ahead: they read, decompress, CRC-check the chunks and run
        ``load`` on them (find their rows, or copy their columns) while the chunk is in their
        cache.
        """
        if not chunks:
            return
        load = load or self._load
        with ThreadPoolExecutor(READ_THREADS, thread_name_prefix="pinwind-read") as pool:
            pending: deque = deque()
            ahead = iter(chunks)
            try:
                for chunk in ahead:
                    pending.append((chunk, pool.submit(load, chunk, wanted)))
                    if len(pending) > READ_AHEAD:
                        break
                while pending:
                    chunk, future = pending.popleft()
                    following = next(ahead, None)
                    if following is not None:
                        pending.append((following, pool.submit(load, following, wanted)))
                    yield (chunk, *future.result())
            finally:
                for _, future in pending:
                    future.cancel()

    def _load(self, chunk: ChunkRef, wanted: list[_Channel]) -> tuple[bytes, Any, str]:
        try:
            # no buffer given: the records come as bytes
            data = cast(bytes, mcap_file.read_chunk(self._descriptor(), chunk))
        except DamagedChunk as err:
            return b"", None, str(err)
        return data, self._layout.find_rows(data, wanted), ""

    def _check_memory(self, capacity: int, keys: list[str]) -> None:
        needed = self._bytes_of(capacity, keys)
        available = _available_memory()
        if available is not None and needed > available:
            raise MemoryError(f"{needed} bytes needed, {available} available")

    def _bytes_needed(self, capacity: int | None, keys: list[str]) -> int | None:
        if capacity is None:
            return None
        return self._bytes_of(capacity, keys)

    def _bytes_of(self, capacity: int, keys: list[str]) -> int:
        """Bytes of the arrays of ``capacity`` samples of ``keys`` (poses at the pose rate)."""
        shapes = self._layout.shapes
        poses = capacity
        if self._columns is not None:  # formats 1 and 2 fill the poses at every sample first
            log_stride = max(1, int(self.metadata["pinwind.run"].get("log_stride", 1)))
            poses = capacity // max(1, self._layout.pose_stride // log_stride) + 1
        return 8 * sum((poses if k in _SPARSE else capacity) * math.prod(shapes[k]) for k in keys)

    def _too_large(self, capacity: int | None, keys: list[str]) -> LogTooLarge:
        needed = self._bytes_needed(capacity, keys)
        available = _available_memory()
        asked = (
            f"; the {capacity} samples asked for need {needed / 1e9:.2f} GB as arrays"
            if needed is not None
            else ""
        )
        free = f", {available / 1e9:.2f} GB is available" if available is not None else ""
        return LogTooLarge(
            str(self.path),
            f"memory ran out while reading the log ({self.size / 1e6:.0f} MB on disk{asked}"
            f"{free}); read part of it: a time window (start=/stop=, CLI --from/--to), fewer "
            "channels (channels=, CLI --channels), or stream it in blocks "
            "(pinwind.io.iter_log)",
        )

    def _finish(self, result: Result, topics, start, stop, lost: list[str]) -> None:
        """Run metadata, end status and log details on a Result read from this log."""
        run = dict(self.metadata["pinwind.run"])
        end = self.metadata.get("pinwind.end")
        if end is not None:
            status = end.get("status", "unknown")
            run["wall_time_s"] = end.get("wall_time_s")
        elif self._end_damaged:
            status = "unknown: the end-status record is damaged"
        else:
            status = (
                "log cut short: no end-status record (the run was killed or the file "
                "truncated); " + (self.problem or "the file ends without one")
            )
        run["status"] = status
        ident = self.metadata["pinwind"]
        run["pinwind_version"] = ident.get("pinwind_version")
        run["command"] = ident.get("command")
        run["log"] = {
            "path": str(self.path),
            "complete": self.complete,
            "problem": self.problem,
            "samples": len(result),
            "stride": run.get("log_stride", 1),
            "channels": list(topics),
            "window": [start, stop],
            "damage": [*self._damage, *lost],
        }
        result.metadata = run
        result.status = status

    def _warn(self, count: int, span: tuple[float, float] | None, lost: list[str]) -> None:
        """Warn of damage (``LogDamaged``) and of a file cut short (``LogRecovered``)."""
        read = f"{count} samples" + (f", t = {span[0]:.6g} to {span[1]:.6g} s" if span else "")
        damage = [*self._damage, *lost]
        if damage:
            warnings.warn(
                f"{self.path}: damaged; every intact chunk was read ({read}): " + "; ".join(damage),
                LogDamaged,
                stacklevel=4,
            )
        if not self.complete and not self._end_damaged:
            warnings.warn(
                f"{self.path}: {self.problem or 'no end-status record'}; recovered {count} "
                f"samples" + (f" (t = {span[0]:.6g} to {span[1]:.6g} s)" if span else ""),
                LogRecovered,
                stacklevel=4,
            )


def _span(result: Result) -> tuple[float, float] | None:
    return (float(result.time[0]), float(result.time[-1])) if len(result) else None


def _window(time: np.ndarray, start: float | None, stop: float | None):
    """(rows, count) of the samples with start ≤ t ≤ stop: a slice when they are consecutive."""
    m = len(time)
    if start is None and stop is None:
        return slice(0, m), m
    mask = np.ones(m, dtype=bool)
    if start is not None:
        mask &= time >= start
    if stop is not None:
        mask &= time <= stop
    rows = np.flatnonzero(mask)
    if not len(rows):
        return slice(0, 0), 0
    if rows[-1] - rows[0] + 1 == len(rows):
        return slice(int(rows[0]), int(rows[-1]) + 1), len(rows)
    return rows, len(rows)


# --- functions ----------------------------------------------------------------------------------


def read_log(
    path: str | os.PathLike,
    *,
    start: float | None = None,
    stop: float | None = None,
    channels: Iterable[str] | str | None = None,
) -> Result:
    """The Result of a logged run, as ``simulate`` returned it (decimated if the log was).

    Arrays are bit-identical to the in-memory run at the logged samples (float64 throughout);
    link poses are logged at the pose rate (``pinwind.run`` metadata ``pose_stride``), and the
    Result has them at those samples only (``pose_rows``, ``pose_time``).
    Only the chunks that overlap the window and hold the channels asked for are read.

    Args:
        path: the log (MCAP file).
        start, stop: keep the samples with start ≤ t ≤ stop [s] (open ends when None).
        channels: topics to read (``CHANNELS``: ``/joints``, ``/meshes/normal``, ``/tf``, ...,
            or a folder such as ``/bearings``); ``/run/time`` is always read. The arrays of the
            others are empty (0 samples). Default: every channel.

    Raises:
        LogError: missing, foreign or corrupted file (see ``LogReader``).
        LogTooLarge: not enough memory: read a window, fewer channels, or use ``iter_log``.
        UnknownChannel: a channel name that pinwind logs do not have.
    """
    with LogReader(path) as log:
        return log.read(start=start, stop=stop, channels=channels)


def iter_log(
    path: str | os.PathLike,
    *,
    block: int = 100_000,
    start: float | None = None,
    stop: float | None = None,
    channels: Iterable[str] | str | None = None,
) -> Iterator[Result]:
    """A log as consecutive Results of at most ``block`` samples (for logs larger than memory).

    Concatenating the blocks gives ``read_log(path, start=..., stop=..., channels=...)``.
    """
    with LogReader(path) as log:
        yield from log.blocks(block, start=start, stop=stop, channels=channels)


@dataclass
class LogFile:
    """Everything read from a log.

    Attributes:
        path: the file.
        result: the logged samples as a Result (``result.metadata`` holds the run metadata, the
            end status and ``log`` details: stride, recovery).
        metadata: MCAP metadata records, name → {key: decoded JSON value}.
        attachments: attachment name → bytes (the model file).
        channels: topic → channel metadata.
        complete: the file has its end-status record and footer.
        problem: what was wrong with a file that was cut short, else ``""``.
    """

    path: Path
    result: Result
    metadata: dict[str, dict[str, Any]]
    attachments: dict[str, bytes]
    channels: dict[str, dict[str, str]]
    complete: bool
    problem: str = ""

    @property
    def model(self) -> dict[str, Any]:
        """The ``pinwind.model`` record: names, gears, meshes, bearings."""
        return self.metadata.get("pinwind.model", {})

    @property
    def model_text(self) -> str:
        """The model file as attached to the log."""
        return _model_text(self.attachments)


def _model_text(attachments: dict[str, bytes]) -> str:
    """The model file among a log's attachments (the first one if none is named .urdf/.xml)."""
    for name, data in attachments.items():
        if name.endswith((".urdf", ".xml")):
            return data.decode("utf-8")
    return next(iter(attachments.values()), b"").decode("utf-8")


def open_log(
    path: str | os.PathLike,
    *,
    start: float | None = None,
    stop: float | None = None,
    channels: Iterable[str] | str | None = None,
) -> LogFile:
    """Read a pinwind MCAP log: its samples (as ``read_log``), metadata and attachments.

    A file that was cut short (killed run, full disk) gives the samples of its complete chunks,
    with a ``LogRecovered`` warning and ``complete = False``.

    Raises:
        LogError: the file is missing, not an MCAP file, not a pinwind log, of a newer format,
            or corrupted; the message names the file and what is wrong.
    """
    with LogReader(path) as log:
        attachments = log.attachments
        result = log.read(start=start, stop=stop, channels=channels)
        return LogFile(
            path=log.path,
            result=result,
            metadata=log.metadata,
            attachments=attachments,
            channels=log.channels,
            complete=log.complete,
            problem=log.problem,
        )
