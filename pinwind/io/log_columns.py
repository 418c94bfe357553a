"""The columns of a pinwind log (format 3): a block's layout, and the arrays a read fills.

Every logged block is one ``/pinwind/columns`` message (docs/log_format.md, "Columns"): a layout
byte, the number of samples m and of posed samples p, then float64 values series after series:
the m values of each element of each array in the order of the channel's ``columns``, then the p
times and poses in the order of ``pose_columns``. Decoding a block is a view of the decompressed
chunk; a read copies each series into arrays that keep every series contiguous (``ColumnSink``),
so a block costs one whole-run copy per series, and the Result's arrays are views with the
sample index first, as ``simulate`` returns them.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics.result import Result
from pinwind.io.mcap_file import DamagedChunk
from pinwind.io.mcap_log import COLUMNS_LAYOUT

#: A columns payload's header: layout byte, samples m, posed samples p.
_HEAD = 9
#: A message record's header: opcode, length, channel, sequence, log and publish time.
_RECORD = 31

#: Destinations that have a value only at some samples (poses, at the pose rate): NaN elsewhere.
SPARSE = ("body_position", "body_quaternion")


@dataclass(frozen=True)
class ColumnLayout:
    """Where each destination's series are in a columns payload.

    Attributes:
        channel: the ``/pinwind/columns`` channel id.
        width: series per sample (all of ``columns``).
        pose_width: series per posed sample (time and poses).
        at: destination → (first series, series count, shape of one sample).
    """

    channel: int
    width: int
    pose_width: int
    at: dict[str, tuple[int, int, tuple[int, ...]]]

    @classmethod
    def of(cls, channel: int, metadata: dict[str, str], shapes: dict[str, tuple[int, ...]]):
        """The layout a channel's metadata gives, checked against the model's shapes.

        Raises:
            ValueError: the metadata is missing, unreadable or does not fit the model.
        """
        try:
            columns = json.loads(metadata["columns"])
            poses = json.loads(metadata["pose_columns"])
        except (KeyError, json.JSONDecodeError) as err:
            raise ValueError(f"the columns channel has no readable layout ({err})") from err
        at: dict[str, tuple[int, int, tuple[int, ...]]] = {}
        width = 0
        for key, shape in columns:
            count = math.prod(shape)
            at[key] = (width, count, tuple(shape))
            width += count
        pose_at = 0
        for key, shape in poses:
            count = math.prod(shape)
            if key != "time":
                at[key] = (pose_at, count, tuple(shape))
            pose_at += count
        for key, shape in shapes.items():
            if key not in at:
                if math.prod(shape):
                    raise ValueError(f"the columns hold no '{key}'")
                continue
            if at[key][2] != shape:
                raise ValueError(
                    f"'{key}' has the shape {list(at[key][2])} in the columns, {list(shape)} in "
                    "the model record"
                )
        if "time" not in at or at["time"][0] != 0:
            raise ValueError("the columns do not start with the time")
        return cls(channel, width, pose_at, at)


@dataclass
class ColumnBlock:
    """One logged block: views of a decompressed chunk.

    Attributes:
        time: sample times [s], (m,).
        values: every series, (width, m).
        pose_time: times of the samples with a pose, (p,).
        poses: time and pose series of those samples, (pose_width, p).
    """

    time: np.ndarray
    values: np.ndarray
    pose_time: np.ndarray
    poses: np.ndarray


def decode_chunk(data: bytes | np.ndarray, layout: ColumnLayout) -> list[ColumnBlock]:
    """The column blocks in a chunk's message records (other channels' records are skipped).

    Raises:
        DamagedChunk: a record or a columns payload that does not fit its lengths.
    """
    blocks = []
    size = len(data)
    pos = 0
    while pos < size:
        if pos + 9 > size:
            raise DamagedChunk(f"a record at byte {pos} of the chunk is cut")
        length = int.from_bytes(data[pos + 1 : pos + 9], "little")
        end = pos + 9 + length
        if end > size:
            raise DamagedChunk(f"a record at byte {pos} of the chunk runs past its end")
        if data[pos] == Opcode.MESSAGE and length >= 22:
            channel = int.from_bytes(data[pos + 9 : pos + 11], "little")
            if channel == layout.channel:
                block = _block(data, pos + _RECORD, end, layout)
                if len(block.time):  # not the closing record of a block
                    blocks.append(block)
        pos = end
    return blocks


def _block(data: bytes | np.ndarray, at: int, end: int, layout: ColumnLayout) -> ColumnBlock:
    if end - at < _HEAD or data[at] != COLUMNS_LAYOUT:
        raise DamagedChunk(f"a columns record at byte {at} has an unknown layout")
    m, p = np.frombuffer(data, "<u4", 2, at + 1).tolist()
    doubles = layout.width * m + layout.pose_width * p
    if end - at != _HEAD + 8 * doubles:
        raise DamagedChunk(
            f"a columns record at byte {at} holds {end - at} bytes, not the {_HEAD + 8 * doubles} "
            f"of {m} samples and {p} poses"
        )
    values = np.frombuffer(data, "<f8", layout.width * m, at + _HEAD).reshape(layout.width, m)
    poses = np.frombuffer(data, "<f8", layout.pose_width * p, at + _HEAD + 8 * layout.width * m)
    poses = poses.reshape(layout.pose_width, p)
    return ColumnBlock(values[0], values, poses[0], poses)


class ColumnSink:
    """The arrays a read fills, each series contiguous; unread destinations stay empty.

    Each destination is stored as (*shape, capacity) and handed out as a view (samples, *shape).
    """

    def __init__(
        self,
        layout: ColumnLayout,
        shapes: dict[str, tuple[int, ...]],
        keys: list[str],
        capacity: int,
    ):
        self.layout = layout
        self.shapes = shapes
        self.keys = keys
        #: the destinations that have series (an array of zero elements has none)
        self.copied = [k for k in keys if k in layout.at]
        self.n = 0
        self.capacity = capacity
        self.arrays = {
            k: self._allocate(k, capacity if k in self.keys else 0, s) for k, s in shapes.items()
        }

    @staticmethod
    def _allocate(key: str, n: int, shape: tuple[int, ...]) -> np.ndarray:
        if key in SPARSE:
            return np.full((*shape, n), np.nan)
        return np.empty((*shape, n))

    def put(self, block: ColumnBlock, rows: slice | np.ndarray, count: int) -> None:
        """Copy ``count`` samples (``rows`` of the block) after those already there."""
        if self.n + count > self.capacity:
            self._grow(self.n + count)
        n, end = self.n, self.n + count
        at = self.layout.at
        for key in self.copied:
            first, width, shape = at[key]
            target = self.arrays[key][..., n:end]
            if key in SPARSE:
                self._place(block, rows, count, target, first, width, shape)
                continue
            target[...] = block.values[first : first + width, rows].reshape(*shape, count)
        self.n = end

    @staticmethod
    def _place(block, rows, count, target, first, width, shape) -> None:
        """Poses of the samples in ``rows`` that have one; the rest stay NaN."""
        if not len(block.pose_time):
            return
        time = block.time[rows]
        where = np.minimum(np.searchsorted(time, block.pose_time), count - 1)
        inside = time[where] == block.pose_time
        if inside.any():
            poses = block.poses[first : first + width, inside]
            target[..., where[inside]] = poses.reshape(*shape, -1)

    def _grow(self, needed: int) -> None:
        """More room (a count from the index was missing or wrong: damaged or foreign file)."""
        self.capacity = max(needed, 2 * self.capacity)
        for key in self.keys:
            old = self.arrays[key]
            new = self._allocate(key, self.capacity, old.shape[:-1])
            new[..., : self.n] = old[..., : self.n]
            self.arrays[key] = new

    def result(self, names: dict[str, list[str]], terms: list[str]) -> Result:
        """The samples so far as a Result (views of the arrays, sample index first)."""
        arrays = {k: np.moveaxis(v[..., : self.n], -1, 0) for k, v in self.arrays.items()}
        return result_of(arrays, names, terms)


def result_of(arrays: dict[str, Any], names: dict[str, list[str]], terms: list[str]) -> Result:
    """A Result of a read's arrays (destination → array), with the log's names."""
    return Result(
        joint_names=names["joint_names"],
        mesh_names=names["mesh_names"],
        bearing_names=names["bearing_names"],
        body_names=names["body_names"],
        generator_names=names.get("generator_names", []),
        rotor_names=names.get("rotor_names", []),
        energy={t: arrays[f"energy/{t}"] for t in terms},
        **{name: arrays[name] for name in Result.ARRAYS},
    )
