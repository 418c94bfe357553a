"""The columns of a pinwind log (format 3): a block's layout, and the arrays a read fills.

Every logged block is one ``/pinwind/columns`` message (docs/log_format.md, "Columns"): a layout
byte, the number of samples m and of posed samples p, a bit per series saying whether it is
constant over the block, then the m values of each series that varies as byte planes (byte 0 of
every value, then byte 1, ...), the one value of each series that does not (both in the order of
the channel's ``columns``), then the p times and poses in the order of ``pose_columns``. Decoding
a block gives views of the decompressed chunk; a read turns the planes back into values
straight into one array that keeps every series contiguous (``ColumnSink``, in the compiled
module, without the GIL), fills the constant ones, and the Result's arrays are views of it with
the sample index first, as ``simulate`` returns them.
"""

from __future__ import annotations

import json
import math
from collections.abc import Collection
from dataclasses import dataclass
from typing import Any

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics._native import fill_rows, place_columns_chunk, unshuffle_series
from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.dynamics.series import get as declared_series
from pinwind.io.log_format import COLUMNS_LAYOUT, mask_bytes
from pinwind.io.mcap_file import DamagedChunk
from pinwind.io.read_memory import read_arrays, written

#: A columns payload's header: layout byte, samples m, posed samples p.
_HEAD = 9
#: A message record's header: opcode, length, channel, sequence, log and publish time.
_RECORD = 31
_MESSAGE = int(Opcode.MESSAGE)

#: Destinations that have a value only at some samples (poses, at the pose rate).
SPARSE = POSE_ARRAYS


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
                # A series computed in Python that a log written before its declaration lacks
                # is derived again on read (``LogReader``).
                if math.prod(shape) and not _derived(key):
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


def _derived(key: str) -> bool:
    """A Result array computed in Python from the others (``Series.derive``)."""
    try:
        return declared_series(key).derive is not None
    except KeyError:  # an energy term or the poses' row numbers
        return False


@dataclass
class ColumnBlock:
    """One logged block: views of a decompressed chunk.

    Attributes:
        time: sample times [s], (m,).
        planes: the series that vary over the block (V of them, in column order), as the byte
            planes of their V · m values one after the other, (8 · V · m,) bytes.
        constants: the value of each series that does not, in column order, (C,).
        same: per series of ``columns``, whether it is constant over the block, (width,).
        slot: per series, its place among the varying series or in ``constants``, (width,).
        pose_time: times of the samples with a pose, (p,).
        poses: time and pose series of those samples, (pose_width, p).
    """

    time: np.ndarray
    planes: np.ndarray
    constants: np.ndarray
    same: np.ndarray
    slot: np.ndarray
    pose_time: np.ndarray
    poses: np.ndarray

    @property
    def samples(self) -> int:
        """m, the samples of the block."""
        return len(self.time)

    def unshuffle(
        self,
        into: np.ndarray,
        rows: np.ndarray,
        first: int,
        count: int,
        at: int,
        stream: bool = False,
    ) -> None:
        """Samples ``first`` to ``first + count`` of varying series j into ``into[rows[j], at:]``.

        ``into``: float64 (series, samples) with contiguous rows; series j is skipped where
        ``rows[j]`` < 0. ``stream``: write around the caches (``byte_planes.hpp``).
        """
        unshuffle_series(self.planes, self.samples, first, count, rows, into, at, stream)

    def varying(self) -> np.ndarray:
        """The varying series' values, (V, m): a new array."""
        vary = len(self.planes) // (8 * self.samples) if self.samples else 0
        values = np.empty((vary, self.samples))
        self.unshuffle(values, np.arange(vary), 0, self.samples, 0)
        return values


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
        if data[pos] == _MESSAGE and length >= 22:
            channel = int.from_bytes(data[pos + 9 : pos + 11], "little")
            if channel == layout.channel:
                block = _block(data, pos + _RECORD, end, layout)
                if block is not None:
                    blocks.append(block)
        pos = end
    return blocks


def _block(data: bytes | np.ndarray, at: int, end: int, layout: ColumnLayout) -> ColumnBlock | None:
    """The block of a columns record, None for the closing record of a block (no samples)."""
    width = layout.width
    flags = mask_bytes(width)
    if end - at < _HEAD + flags or data[at] != COLUMNS_LAYOUT:
        raise DamagedChunk(f"a columns record at byte {at} has an unknown layout")
    m, p = np.frombuffer(data, "<u4", 2, at + 1).tolist()
    if m == 0 and p == 0 and end - at == _HEAD + flags:
        return None
    bits = np.frombuffer(data, np.uint8, flags, at + _HEAD)
    same = np.unpackbits(bits, count=width, bitorder="little").view(bool)
    constant = int(np.count_nonzero(same))
    vary = width - constant
    doubles = vary * m + constant + layout.pose_width * p
    start = at + _HEAD + flags
    if end - start != 8 * doubles or (m == 0 and constant):
        raise DamagedChunk(
            f"a columns record at byte {at} holds {end - at} bytes, not the "
            f"{start - at + 8 * doubles} of {m} samples ({constant} series constant) and "
            f"{p} poses"
        )
    planes = np.frombuffer(data, np.uint8, 8 * vary * m, start)
    start += 8 * vary * m
    constants = np.frombuffer(data, "<f8", constant, start)
    poses = np.frombuffer(data, "<f8", layout.pose_width * p, start + 8 * constant)
    poses = poses.reshape(layout.pose_width, p)
    slot = np.where(same, np.cumsum(same), np.cumsum(~same)) - 1
    time = np.full(m, constants[0]) if same[0] else np.empty(m)
    if not same[0]:  # the time varies: it is the first of the varying series
        first_only = np.full(vary, -1)
        first_only[0] = 0
        unshuffle_series(planes, m, 0, m, first_only, time[None, :], 0)
    return ColumnBlock(time, planes, constants, same, slot, poses[0], poses)


def zero_destinations(blocks: list[ColumnBlock], layout: ColumnLayout) -> set[str]:
    """The destinations whose every series is +0.0 (all bits zero) over all of ``blocks``.

    Those of the first chunk say which arrays are likely zero for the whole run (a third of a
    shipped model's bytes: rigid bearings' displacements, friction of a run without it):
    ``ColumnSink`` puts them after the others, where the pages nobody writes are never touched.
    """
    zero = np.ones(layout.width, dtype=bool)
    for block in blocks:
        constant = np.zeros(layout.width, dtype=bool)
        constant[block.same] = block.constants.view(np.uint64) == 0
        zero &= constant
    return {
        key
        for key, (first, count, _) in layout.at.items()
        if key not in SPARSE and count and zero[first : first + count].all()
    }


class ColumnSink:
    """The arrays a read fills: the columns' series, and the poses of the samples with one.

    The series read are the rows of one (series, capacity) array, each contiguous, in column
    order but for the destinations of ``last``, which come after the others. A destination's
    array is a view of its rows, (samples, *shape), so one allocation holds the samples of the
    whole read (and its memory is returned when the last of its arrays is dropped); unread
    destinations are empty. The poses (at the log's pose rate, a few in a
    hundred samples) are kept as the pieces each block gives, and joined by ``arrays``.
    """

    def __init__(
        self,
        layout: ColumnLayout,
        shapes: dict[str, tuple[int, ...]],
        keys: list[str],
        capacity: int,
        last: Collection[str] = (),
    ):
        self.layout = layout
        self.shapes = shapes
        self.keys = chosen = set(keys)
        #: the destinations that have series in the columns (an array of zero elements has
        #: none), in column order but those of ``last`` after the others (``zero_destinations``)
        copied = sorted(
            (k for k in chosen if k in layout.at and k not in SPARSE),
            key=lambda k: (k in last, layout.at[k][0]),
        )
        #: destination → its first row in ``base``, series count, shape of one sample
        self.rows: dict[str, tuple[int, int, tuple[int, ...]]] = {}
        row = 0
        for key in copied:
            _, width, shape = layout.at[key]
            self.rows[key] = (row, width, shape)
            row += width
        self.height = row
        #: the columns' series copied, and the rows they go to (in column order, both)
        source = [np.arange(layout.at[k][0], layout.at[k][0] + self.rows[k][1]) for k in copied]
        self.source = np.concatenate(source) if source else np.zeros(0, dtype=np.intp)
        #: per series of the columns, its row in ``base``, -1 when it is not read
        self.row_of = np.full(layout.width, -1)
        self.row_of[self.source] = np.arange(len(self.source))
        #: whether the poses are read, and their series among a block's pose series
        self.posed = any(k in chosen for k in SPARSE)
        self.pose_series = np.concatenate(
            [np.zeros(0, np.intp)]
            + [
                np.arange(layout.at[k][0], layout.at[k][0] + layout.at[k][1])
                for k in SPARSE
                if k in layout.at
            ]
        )
        #: (samples, their poses (pose series, k)) of each block placed, in any order
        self.poses: list[tuple[np.ndarray, np.ndarray]] = []
        self.n = 0
        self.capacity = capacity
        # New memory is zeros, and a series that is +0.0 over a block is not written
        # (``place``): a large array is new pages from the kernel, zeroed on first touch, so
        # np.zeros costs what np.empty does, and the pages of series that are zero throughout
        # (half of a shipped model's: rigid bearings' displacements, friction of a run without
        # it) are never written. In memory an earlier read used (``read_arrays``), the rows
        # before ``zeroed_from`` hold its values and have every value written.
        self.base, self.zeroed_from = read_arrays(self.height, capacity)
        #: the last row given a value other than +0.0 by each chunk or block placed
        self.last_rows: list[int] = []

    def put(self, block: ColumnBlock, rows: slice | np.ndarray, count: int) -> None:
        """Copy ``count`` samples (``rows`` of the block) after those already there."""
        if self.n + count > self.capacity:
            self._grow(self.n + count)
        self.place(block, rows, count, self.n)
        self.n += count

    def place(self, block: ColumnBlock, rows: slice | np.ndarray, count: int, at: int) -> None:
        """Copy ``count`` samples (``rows`` of the block) to samples ``at`` to ``at + count``.

        There must be room. Threads may place samples at the same time in other samples: the
        compiled copies run without the GIL.
        """
        if len(self.source):
            if isinstance(rows, slice):
                block.unshuffle(self.base, self.row_of[~block.same], rows.start, count, at, True)
            else:  # samples that are not consecutive (a window of a foreign file)
                vary = ~block.same[self.source]
                slot = block.slot[self.source]
                self.base[:, at : at + count][vary] = block.varying()[slot[vary]][:, rows]
            # in zeroed rows a constant +0.0 (all bits zero, not -0.0) is already there
            filled = self.row_of[block.same]
            zero = block.constants.view(np.uint64) == 0
            filled = np.where(zero & (filled >= self.zeroed_from), -1, filled)
            self.last_rows.append(self.height - 1)  # not worked out here
            fill_rows(block.constants, filled, self.base, at, count, True)
        if self.posed and len(block.pose_time):
            time = block.time[rows]
            where = np.minimum(np.searchsorted(time, block.pose_time), count - 1)
            inside = time[where] == block.pose_time
            if inside.any():
                poses = block.poses[self.pose_series]  # a copy: the chunk's buffer is reused
                if not inside.all():
                    poses = poses[:, inside]
                self.poses.append((at + where[inside], poses))

    def place_chunk(
        self,
        data: bytes | np.ndarray,
        at: int,
        room: int,
        start: float | None = None,
        stop: float | None = None,
    ) -> tuple[int, str]:
        """A decompressed chunk's samples with start ≤ t ≤ stop [s] placed from sample ``at``.

        What ``decode_chunk`` and ``place`` do for each block, in one compiled call without
        the GIL (``cpp/column_chunks.hpp``), which parses the chunk's records and places every
        block. Returns (samples, damage): damage is "" or why the chunk is damaged, in the
        words of ``decode_chunk``; samples is -1 when a block's samples in the window are not
        consecutive (a foreign file: ``decode_chunk`` and ``place`` then). Nothing is placed
        when the chunk is damaged, when samples is -1, or when it is more than ``room``.
        """
        chunk = data if isinstance(data, np.ndarray) else np.frombuffer(data, np.uint8)
        layout = self.layout
        filled, rows, poses, damage, last_row = place_columns_chunk(
            chunk,
            layout.channel,
            layout.width,
            layout.pose_width,
            self.row_of,
            self.base,
            at,
            room,
            start,
            stop,
            self.pose_series,
            self.posed,
            self.zeroed_from,
        )
        if damage:
            return 0, damage
        self.last_rows.append(last_row)
        if 0 <= filled <= room and len(rows):
            self.poses.append((rows, poses))
        return filled, ""

    def move(self, at: int, count: int, to: int) -> None:
        """Samples ``at`` to ``at + count`` moved back to ``to`` (≤ ``at``): closes a gap."""
        if to == at:
            return
        self.base[:, to : to + count] = self.base[:, at : at + count]
        for samples, _ in self.poses:
            if at <= samples[0] < at + count:
                samples -= at - to

    def _grow(self, needed: int) -> None:
        """More room (a count from the index was missing or wrong: damaged or foreign file)."""
        self.capacity = max(needed, 2 * self.capacity)
        base, zeroed_from = read_arrays(self.height, self.capacity)  # see __init__
        base[:, : self.n] = self.base[:, : self.n]
        self.base, self.zeroed_from = base, zeroed_from

    def finish(self) -> None:
        """Tell the memory kept for the next read which rows this one left at +0.0."""
        written(self.base, max(self.last_rows, default=-1), self.n == self.capacity)

    def arrays(self) -> dict[str, np.ndarray]:
        """Every destination's samples so far, (samples, *shape): views of ``base``.

        The poses are (poses, *shape), at the samples ``pose_rows`` (also returned).
        """
        out: dict[str, np.ndarray] = {}
        for key, shape in self.shapes.items():
            if key in self.rows:
                row, width, _ = self.rows[key]
                series = self.base[row : row + width, : self.n].reshape(*shape, self.n)
                out[key] = _samples_first(series)
            elif key not in SPARSE:
                # not in the log (a series added after it was written): NaN, never left-over
                # memory; not read: no samples
                out[key] = np.full((self.n if key in self.keys else 0, *shape), np.nan)
        pieces = sorted((p for p in self.poses if p[0][0] < self.n), key=lambda p: p[0][0])
        rows = np.concatenate([s for s, _ in pieces]) if pieces else np.zeros(0, np.int64)
        kept = rows < self.n
        values = (
            np.concatenate([v for _, v in pieces], axis=1)
            if pieces
            else np.empty((len(self.pose_series), 0))
        )
        if not kept.all():  # samples moved past the end (a gap closed)
            rows, values = rows[kept], values[:, kept]
        out["pose_rows"] = rows
        at = 0
        for key in SPARSE:
            shape = self.shapes[key]
            width = math.prod(shape)
            series = values[at : at + width].reshape(*shape, values.shape[1])
            out[key] = _samples_first(series)
            at += width
        return out

    def result(self, names: dict[str, list[str]], terms: list[str]) -> Result:
        """The samples so far as a Result (views of ``base``, sample index first)."""
        return result_of(self.arrays(), names, terms)


def _samples_first(series: np.ndarray) -> np.ndarray:
    """``np.moveaxis(series, -1, 0)``: a view with the samples' axis (the last) first.

    numpy's own checks its arguments in Python, 5 µs an array.
    """
    last = series.ndim - 1
    return series.transpose(last, *range(last))


def result_of(arrays: dict[str, Any], names: dict[str, list[str]], terms: list[str]) -> Result:
    """A Result of a read's arrays (destination → array), with the log's names."""
    return Result(
        joint_names=names["joint_names"],
        mesh_names=names["mesh_names"],
        bearing_names=names["bearing_names"],
        body_names=names["body_names"],
        generator_names=names.get("generator_names", []),
        rotor_names=names.get("rotor_names", []),
        row_names=names.get("row_names", []),
        slice_names=names.get("slice_names", []),
        energy={t: arrays[f"energy/{t}"] for t in terms},
        pose_rows=arrays["pose_rows"],
        **{name: arrays[name] for name in Result.ARRAYS},
    )
