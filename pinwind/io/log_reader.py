"""Reading pinwind logs: whole, by time window and channel, or in blocks; damaged files too.

``LogReader`` opens a log (docs/log_format.md) by its summary section: the chunk index gives each
chunk's time span, place and size, so a read fetches only the chunks that overlap its time window
and hold its channels (``io/log_channels.py``). ``read_log`` returns one ``Result``; ``iter_log``
streams a log larger than memory as consecutive ``Result`` blocks; ``open_log`` gives the
metadata and attachments with the samples.

Decoding is done a chunk at a time with numpy. Format 3 stores every array as columns, one
message per block of samples (``io/log_columns.py``): the reading threads (``io/log_threads.py``),
one per core, each take a chunk, decompress it and copy its series into their place in one array,
known from the chunk index before anything is decompressed. Formats 1 and 2 store every sample
as a row of message records (``io/log_legacy.py``); the reading threads read, decompress and
CRC-check the next chunks while the main thread copies values.

Damage: a chunk that fails its CRC, does not decompress or is not where the index says is
skipped, and a ``LogDamaged`` warning gives the simulation time it covered. A damaged summary
section (the end of the file) is replaced by a walk through the data section.
"""

from __future__ import annotations

import math
import os
import threading
import warnings
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, cast

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.errors import (
    InputError,
    LogBeingWritten,
    LogError,
    LogRecovered,
    SamplesNotLogged,
)
from pinwind.io import mcap_file
from pinwind.io.log_channels import TIME_TOPIC, ArrayLayout, select_channels
from pinwind.io.log_columns import (
    ColumnBlock,
    ColumnLayout,
    ColumnSink,
    decode_chunk,
    zero_destinations,
)
from pinwind.io.log_format import COLUMNS_TOPIC, FORMAT, FORMAT_VERSION, NAMES_OF
from pinwind.io.log_legacy import RowChannel, RowLayout, RowSink
from pinwind.io.log_lock import held_by_writer
from pinwind.io.log_metadata import checksum_problem, json_values
from pinwind.io.log_threads import ChunkBuffers, read_ahead, run_all
from pinwind.io.mcap_file import MAGIC, ChunkRef, DamagedChunk, DamagedFile
from pinwind.io.messages import PayloadError


class LogDamaged(LogRecovered):
    """Part of a log is damaged (a chunk fails its CRC, the summary is unreadable).

    Every intact chunk was read; the message says what is damaged and which simulation time
    range was lost.
    """


#: What each pinwind metadata record holds, for the message when it fails its checksum.
_RECORD_HOLDS = {
    "pinwind": "format, pinwind version, command",
    "pinwind.run": "dt, duration, log_stride, loads, solver, scenario",
    "pinwind.end": "status, samples simulated and logged",
}


class LogTooLarge(LogError):
    """Reading the log needs more memory than there is."""


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


# --- the reader ---------------------------------------------------------------------------------


def _decoded(data: bytes | np.ndarray, layout: ColumnLayout) -> tuple[list[ColumnBlock], str]:
    """A decompressed columns chunk's blocks, or why it is damaged ([], the reason)."""
    try:
        return decode_chunk(data, layout), ""
    except DamagedChunk as err:
        return [], str(err)


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
        #: a run is still writing the file (it holds the log's lock, ``io/log_lock.py``)
        self.being_written = held_by_writer(fd)
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
        self.checksums = self._check_records(records)
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
        self.metadata = {name: json_values(rec) for name, rec in records.items()}
        for required in ("pinwind.run", "pinwind.model"):
            if required not in self.metadata:
                why = f": {self.problem}" if self.problem else ""
                raise LogError(where, f"the '{required}' metadata record is missing{why}")
        model = self.metadata["pinwind.model"]
        self.names = {k: list(model.get(k, [])) for k in (*NAMES_OF.values(), "body_names")}
        self.channels = {c.topic: dict(c.metadata) for c in contents.channels.values()}
        run = self.metadata["pinwind.run"]
        self._layout = ArrayLayout(self.names, run.get("pose_stride", run.get("log_stride", 1)))
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
        #: series computed in Python that this log lacks (written before they were declared):
        #: ``_finish`` derives them again from the series read and the log's model
        self._absent = [
            s
            for s in series.schema()
            if s.derive is not None
            and (
                s.name not in self._columns.at
                if self._columns is not None
                else s.topic not in self.channels
            )
        ]
        self._gearbox: Any = None
        if self._columns is None and TIME_TOPIC not in self._rows.by_topic and contents.chunks:
            raise LogError(where, "unexpected message contents: the log has no /run/time channel")
        end = self.metadata.get("pinwind.end")
        self.complete = end is not None and contents.data_end and not self.problem
        self._end_damaged = end is None and "pinwind.end" in contents.metadata
        self._attachments: dict[str, bytes] | None = None
        #: attachment name → why it could not be read (its CRC fails, ...)
        self.damaged_attachments: dict[str, str] = {}
        self._buffers = ChunkBuffers()
        #: what the end record says the run simulated but did not log, else ""
        self.not_logged = _not_logged(end, run.get("log_stride", 1))

    @cached_property
    def _rows(self) -> RowLayout:
        """Formats 1 and 2: the codecs of the ROS 2 topics, whose rows of records hold the arrays.

        Built on first use: a format 3 log (columns) never needs them.
        """
        return RowLayout(self._contents.channels, self._layout)

    def _check_records(self, records: dict[str, dict[str, str]]) -> str:
        """Check the pinwind records' CRC-32 (and remove it); say how they fared.

        A failed ``pinwind.model`` is refused: its names say which series is which joint, mesh
        or bearing, and an edited name would put one element's data under another's. Another
        failed record is read with a ``LogDamaged`` warning naming it (``dt``, ``log_stride``,
        the end status may be wrong); ``--from-log`` refuses a failed ``pinwind.run``.

        Raises:
            LogError: the ``pinwind.model`` record fails its check.
        """
        where = str(self.path)
        verdicts = {
            name: checksum_problem(record)
            for name, record in records.items()
            if name == "pinwind" or name.startswith("pinwind.")
        }
        #: record name → why it fails its checksum
        self.failed_records = {name: why for name, why in verdicts.items() if why}
        for name, why in self.failed_records.items():
            if name == "pinwind.model":
                raise LogError(
                    where,
                    f"the 'pinwind.model' metadata record {why}: the names of the joints, meshes "
                    "and bearings cannot be trusted to say whose data is whose; the file is "
                    "corrupted, restore it from a copy",
                )
            self._damage.append(
                f"the '{name}' metadata record {why}: its values ({_RECORD_HOLDS.get(name, '')}) "
                "may be wrong"
            )
        if self.failed_records:
            return "failed: " + ", ".join(self.failed_records)
        if verdicts and all(v is None for v in verdicts.values()):
            return "none: written by a pinwind that recorded no metadata checksums"
        return "verified"

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
        """Attachment name → bytes (the model file); a damaged attachment is left out.

        ``damaged_attachments`` then says which and why.
        """
        if self._attachments is None:
            self._attachments = {}
            for name, (offset, length) in self._contents.attachments.items():
                try:
                    self._attachments[name] = mcap_file.read_attachment(
                        self._descriptor(), offset, length
                    )
                except Exception as err:  # CRC, struct: damaged
                    self.damaged_attachments[name] = str(err)
                    self._damage.append(f"attachment '{name}' is damaged ({err})")
        return self._attachments

    @property
    def model_text(self) -> str:
        """The model file as attached to the log."""
        return _model_text(self.attachments)

    @property
    def model_problem(self) -> str:
        """Why the log gives no model file (damaged, or none attached), ``""`` when it does."""
        if self.attachments:
            return ""
        return _model_problem(self.damaged_attachments)

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
            sink: RowSink | ColumnSink
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

    def _sink(self, keys: list[str], capacity: int) -> RowSink | ColumnSink:
        """The arrays a read of ``keys`` fills, room for ``capacity`` samples to start with."""
        if self._columns is not None:
            return ColumnSink(self._columns, self._layout.shapes, keys, capacity)
        return RowSink(self._layout.shapes, keys, capacity)

    def _sample_chunks(self, topics: tuple[str, ...] | None) -> list[ChunkRef]:
        """Chunks that hold samples (the time channel), or whose index is unknown, in file order.

        File order is the order the writer produced: time order for pinwind's chunks; for
        chunks of other tools whose time spans overlap (their /tf records come after a block of
        samples), the order in which each sample's records complete.
        """
        if self._columns is not None:
            wanted = self._columns.channel
        else:
            time = self._rows.by_topic.get(TIME_TOPIC)
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
        time = self._rows.by_topic[TIME_TOPIC].id if chunks else 0
        capacity = 0
        for chunk in chunks:
            inside = lo <= chunk.start_ns and chunk.end_ns <= hi
            try:
                found = mcap_file.index_entries(
                    self._descriptor(), chunk.index[time], time, count_only=inside
                )
            except (KeyError, ValueError):  # no index (cut file) or a damaged one: estimate
                capacity += max(1, (chunk.length * 8) // self._rows.row_bytes())
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
        # The arrays are laid out once the first chunk is decompressed: the destinations that
        # are zero throughout it go last (``zero_destinations``). The other threads decompress
        # their chunks meanwhile, and wait for the layout to place them.
        sinks: list[ColumnSink] = []
        laid_out = threading.Event()

        def lay_out(blocks: list[ColumnBlock]) -> None:
            try:
                last = zero_destinations(blocks, layout) if blocks else ()
                sinks.append(ColumnSink(layout, self._layout.shapes, keys, places[-1], last))
            finally:
                laid_out.set()  # on failure too: the threads waiting see no sink and stop

        def load(chunk: ChunkRef, _) -> tuple[bytes, int | None, str]:
            at, room = place[chunk.offset]
            data, damage = self._decompress(chunk)
            if chunk is chunks[0]:
                blocks: list[ColumnBlock] = []
                if not damage:
                    blocks, damage = _decoded(data, layout)
                lay_out(blocks)
            else:
                laid_out.wait()
            if not sinks:
                return b"", 0, "not read: laying out the arrays failed"
            sink = sinks[0]
            if damage:
                return b"", 0, damage
            # every block of the chunk parsed and placed in one compiled call
            filled, damage = sink.place_chunk(data, at, room, start, stop)
            if damage:
                return b"", 0, damage
            if filled < 0:  # a block's samples in the window are not consecutive
                parts = [
                    (block, *_window(block.time, start, stop))
                    for block in decode_chunk(data, layout)
                ]
                filled = sum(count for _, _, count in parts)
                if filled <= room:
                    for block, rows, count in parts:
                        if count:
                            sink.place(block, rows, count, at)
                            at += count
            if filled > room:
                return b"", None, ""
            return b"", filled, ""

        n = 0
        damaged = []
        for chunk, _, filled, damage in run_all(chunks, load, []):
            if damage:
                damaged.append(
                    f"{damage}: t = {chunk.start_ns * 1e-9:.9g} to {chunk.end_ns * 1e-9:.9g} s lost"
                )
                continue
            if filled is None:
                return None
            sinks[0].move(place[chunk.offset][0], filled, n)
            n += filled
        sink = sinks[0]
        sink.n = n
        sink.finish()
        lost += damaged
        return sink

    def _parts(self, chunks, topics, start, stop, lost) -> Iterator[tuple[Any, Any, int]]:
        """(part, rows in the window, count) of every chunk, read ahead by the reading threads."""
        if self._columns is not None:
            for chunk, _, blocks, damage in read_ahead(chunks, self._load_columns, []):
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
            self._rows.by_topic[t] for t in topics if t in self._rows.by_topic and t != TIME_TOPIC
        ]
        for chunk, data, found, damage in read_ahead(chunks, self._load_rows, wanted):
            if damage:
                lost.append(
                    f"{damage}: t = {chunk.start_ns * 1e-9:.9g} to {chunk.end_ns * 1e-9:.9g} s lost"
                )
                continue
            where = f"the chunk at byte {chunk.offset}"
            try:
                parts = self._rows.rows(data, wanted, where, found)
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

    def _decompress(self, chunk: ChunkRef) -> tuple[bytes | np.ndarray, str]:
        """A chunk's records, decompressed and checked, or why it is damaged (thread-safe)."""
        try:
            return mcap_file.read_chunk(
                self._descriptor(), chunk, self._buffers.take(chunk.size)
            ), ""
        except DamagedChunk as err:
            return b"", str(err)

    def _load_columns(self, chunk: ChunkRef, _) -> tuple[bytes, list[ColumnBlock], str]:
        """A columns chunk's blocks, or why it is damaged (thread-safe)."""
        layout = self._columns
        if layout is None:
            raise RuntimeError("internal error: columns read from a log without them")
        data, damage = self._decompress(chunk)
        if damage:
            return b"", [], damage
        blocks, damage = _decoded(data, layout)
        return b"", blocks, damage

    def _load_rows(self, chunk: ChunkRef, wanted: list[RowChannel]) -> tuple[bytes, Any, str]:
        """A chunk's records and their rows (None: not rows), or why it is damaged (thread-safe)."""
        try:
            # no buffer given: the records come as bytes
            data = cast(bytes, mcap_file.read_chunk(self._descriptor(), chunk))
        except DamagedChunk as err:
            return b"", None, str(err)
        return data, self._rows.find_rows(data, wanted), ""

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
        return 8 * sum(
            (poses if k in POSE_ARRAYS else capacity) * math.prod(shapes[k]) for k in keys
        )

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

    def _derive_absent(self, result: Result) -> None:
        """Fill the derived series this log lacks (``_absent``) that were asked for.

        They are computed from the series read and the model the log carries, as the run did;
        NaN when their inputs were not read or the model no longer loads.
        """
        n = len(result)
        # A series of a family this model has none of (compliant bearing rows on a model
        # without) has nothing to fill: no model load for it.
        wanted = [
            s
            for s in self._absent
            if n and len(getattr(result, s.name)) == n and getattr(result, s.name).size
        ]
        if not wanted:
            return
        if self._gearbox is None:
            from pinwind.errors import PinwindError
            from pinwind.model.gearbox import loads

            try:
                self._gearbox = loads(self.model_text, path=str(self.path))
            except PinwindError:
                self._gearbox = False  # the model no longer loads: NaN, as for unread inputs
        for s in wanted:
            target, derive = getattr(result, s.name), s.derive
            try:
                target[...] = derive(result, self._gearbox) if derive and self._gearbox else np.nan
            except ValueError:  # an input not read (channels=): its array has no samples
                target[...] = np.nan

    def _finish(self, result: Result, topics, start, stop, lost: list[str]) -> None:
        """Run metadata, end status and log details on a Result read from this log."""
        # logs written before the slides record no kinds: every joint of theirs is revolute
        kinds = self.metadata["pinwind.model"].get("joint_kinds")
        if kinds is not None:
            result.joint_kinds = list(kinds)
        self._derive_absent(result)
        run = dict(self.metadata["pinwind.run"])
        end = self.metadata.get("pinwind.end")
        if end is not None:
            status = end.get("status", "unknown")
            run["wall_time_s"] = end.get("wall_time_s")
            # the run record holds the samples planned; the end record those simulated
            if "samples_simulated" in end:
                run["samples_simulated"] = end["samples_simulated"]
        elif self._end_damaged:
            status = "unknown: the end-status record is damaged"
        elif self.being_written:
            status = (
                "being written: the run is in progress (no end-status record yet); read up to "
                "the last complete block written"
            )
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
            "not_logged": self.not_logged,
            "metadata_checksums": self.checksums,
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
        if self.not_logged:
            warnings.warn(f"{self.path}: {self.not_logged}", SamplesNotLogged, stacklevel=4)
        if not self.complete and self.being_written:
            warnings.warn(
                f"{self.path}: still being written by a run in progress: read the {count} "
                "samples written so far"
                + (f" (t = {span[0]:.6g} to {span[1]:.6g} s)" if span else "")
                + "; read it again when the run has ended",
                LogBeingWritten,
                stacklevel=4,
            )
        elif not self.complete and not self._end_damaged:
            warnings.warn(
                f"{self.path}: {self.problem or 'no end-status record'}; recovered {count} "
                f"samples"
                + (f" (t = {span[0]:.6g} to {span[1]:.6g} s)" if span else "")
                + self._time_lost(),
                LogRecovered,
                stacklevel=4,
            )

    def _time_lost(self) -> str:
        """The span of the run that a cut file does not hold, in words (after a "; ")."""
        duration = self.metadata["pinwind.run"].get("duration")
        if isinstance(duration, bool) or not isinstance(duration, int | float):
            return ""
        span = self.span
        if span is None:
            return f"; all {duration:g} s of the run are lost (or were never simulated)"
        last = span[1]
        if last >= duration * (1 - 1e-12):
            return ""
        return (
            f"; t = {last:.6g} to {duration:.6g} s, {duration - last:.6g} s of the "
            f"{duration:g} s run, is not in the file (lost, or never simulated if the run was "
            "stopped there)"
        )


def _not_logged(end: dict[str, Any] | None, stride: int) -> str:
    """The samples the end record counts as simulated but not logged, in words ("" for none).

    Every sample a run simulates is handed to its log, even on Ctrl-C; a difference means the
    log lost samples without a write error (it used to drop the block in hand on Ctrl-C).

    Sample k of a run is logged when k mod stride = 0: n simulated samples log ⌈n / stride⌉.
    """
    if not end or "samples_simulated" not in end or "samples_logged" not in end:
        return ""
    if end.get("log_error"):  # a failed write: the status already says what the file holds
        return ""
    simulated, logged = int(end["samples_simulated"]), int(end["samples_logged"])
    stride = max(1, int(stride))
    expected = -(-simulated // stride)
    if logged >= expected:
        return ""
    return (
        f"the run simulated {simulated} samples but logged {logged} of the {expected} it "
        f"should have (log stride {stride}): {expected - logged} logged samples are missing"
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
        start: keep the samples with t ≥ start [s] (from the first when None).
        stop: keep the samples with t ≤ stop [s] (to the last when None).
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
        model_problem: why the log gives no model file (its attachment is damaged, or there is
            none), else ``""``.
    """

    path: Path
    result: Result
    metadata: dict[str, dict[str, Any]]
    attachments: dict[str, bytes]
    channels: dict[str, dict[str, str]]
    complete: bool
    problem: str = ""
    model_problem: str = ""

    @property
    def model(self) -> dict[str, Any]:
        """The ``pinwind.model`` record: names, gears, meshes, bearings."""
        return self.metadata.get("pinwind.model", {})

    @property
    def model_text(self) -> str:
        """The model file as attached to the log."""
        return _model_text(self.attachments)


def _model_problem(damaged: dict[str, str]) -> str:
    """Why a log without a readable attachment gives no model file."""
    if damaged:
        name, why = next(iter(damaged.items()))
        return f"the model file attached to the log ('{name}') is damaged ({why})"
    return "the log holds no model file"


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
            model_problem=log.model_problem,
        )
