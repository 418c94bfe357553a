"""The log writer: ``McapLogger``, a ``RunObserver`` that writes a run to an MCAP file.

A log is one self-contained MCAP file (docs/log_format.md, its topics in ``io/log_format.py``):
the model file as an attachment and on ``/robot_description``, metadata records (versions, model
hash, solver settings, dt, loads, the command, the gear geometry) and one message per logged
sample on each topic, with log time = simulation time. ``McapLogger`` writes it while
``simulate`` runs, one MCAP chunk of columns per block of samples, flushed to the OS as it goes,
so a killed run leaves every block but the last (the viewers' topics go in chunks of
``VIEW_BATCH`` samples: a killed run loses up to that many of them, not of the columns);
``end`` writes the held views, the end-status record and the summary even when the run raised.
``read_log`` (``io/log_reader.py``) gives back the ``Result``; it recovers the complete blocks
of a file that was cut short.

Payloads are encoded a block of samples at a time (``io/messages.py``) and laid out as message
records with numpy, then written by ``io/mcap_file.py``: the ``mcap`` package's own writer spends
about 4 µs per message, which at 18 messages per sample would be 30 % of a drivetrain step.
"""

from __future__ import annotations

import errno
import functools
import json
import math
import os
import queue
import shlex
import sys
import threading
import warnings
from pathlib import Path
from typing import BinaryIO

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics._native import shuffle_series
from pinwind.dynamics.result import POSE_ARRAYS, Result, concatenate
from pinwind.errors import (
    InvalidLogRate,
    LogError,
    LogExists,
    LogRecovered,
    LogWriteFailed,
)
from pinwind.interrupts import interrupts_deferred
from pinwind.io import messages
from pinwind.io.log_format import (
    COLUMNS_ENCODING,
    COLUMNS_LAYOUT,
    COLUMNS_TOPIC,
    FORMAT,
    FORMAT_VERSION,
    JOINTS_TOPIC,
    MODEL_TOPIC,
    NAMES_OF,
    TF_TOPIC,
    WORLD_FRAME,
    array_topics,
    mask_bytes,
)
from pinwind.io.log_lock import hold_for_writing
from pinwind.io.log_metadata import json_record, utc_now, versions, with_checksum
from pinwind.io.log_model import model_geometry, model_names
from pinwind.io.log_size import MAX_LOG_BYTES, check_log_fits, estimate_log_size
from pinwind.io.mcap_file import (
    RECORD_HEADER,
    McapWriter,
    message_records,
)
from pinwind.io.messages import (
    Float64ArrayCodec,
    FrameTransformsCodec,
    JointStateCodec,
)

#: Link poses per simulated second on /tf and /pinwind/poses [Hz]: a display rate.
POSE_RATE = 100.0
#: Samples per simulated second on the ROS 2 topics that viewers plot (/joints, /meshes/...,
#: /bearings/..., /run/...) [Hz]: a display rate. pinwind reads the columns, at the log rate.
VIEW_RATE = 100.0
#: Chunk compression and its level.
COMPRESSION = "zstd"
COMPRESSION_LEVEL = -1


def _resolve_rate(dt: float | None, log_rate: float | None, what: str = "log") -> tuple[int, float]:
    """(stride, logged rate [Hz]) for a wanted log (or pose) rate at time step dt.

    dt None only checks the value.
    """
    sample_rate = 1.0 / dt if dt is not None else math.inf
    if log_rate is None:
        return 1, sample_rate
    log_rate = float(log_rate)
    if not math.isfinite(log_rate) or log_rate <= 0.0:
        raise InvalidLogRate(f"the {what} rate must be a positive number [Hz]; got {log_rate}")
    if dt is None:
        return 1, log_rate
    if log_rate > sample_rate * (1.0 + 1e-9):
        raise InvalidLogRate(
            f"{what} rate {log_rate:g} Hz is above the sample rate 1/dt = {sample_rate:g} Hz "
            f"(dt = {dt:g} s): a run cannot log more samples than it computes; give at most "
            f"{sample_rate:g} Hz, or omit --{what}-rate to log every sample"
        )
    stride = max(1, round(sample_rate / log_rate))
    return stride, sample_rate / stride


class _RowLayout:
    """Byte layout of one logged sample: one message record per channel but /tf, fixed length.

    Built once per log: the row template holds every fixed byte (opcodes, lengths, channel ids,
    CDR headers, joint names); a block of samples is the template repeated, with the sample
    number and time written into each record header, the JointState stamp, and each topic's
    values copied in as whole blocks of bytes.
    """

    def __init__(self, records: list[tuple[int, np.ndarray]], stamp_record: int, stamp_at: int):
        """A row of ``records``: (channel, payload template) in row order.

        The stamp goes in the payload of record ``stamp_record`` at byte ``stamp_at``.
        """
        width = RECORD_HEADER.itemsize
        template = bytearray()
        self.columns: list[int] = []
        self.channels: list[int] = []
        for channel, payload in records:
            head = np.zeros(1, dtype=RECORD_HEADER)
            head["op"] = Opcode.MESSAGE
            head["length"] = 22 + len(payload)
            head["channel"] = channel
            self.columns.append(len(template))
            self.channels.append(channel)
            template += head.tobytes() + payload.tobytes()
        self.template = np.frombuffer(bytes(template), dtype=np.uint8)
        self.size = len(template)
        self.stamp_at = self.columns[stamp_record] + width + stamp_at
        self._width = width

    def dtype(self, values: list[tuple[int, int]]) -> np.dtype:
        """A row dtype whose fields are raw bytes.

        ``h<i>``: sequence and times of record i; ``stamp``: the JointState stamp; ``v<j>``:
        the j-th value block of ``values`` ((byte offset, size) each).
        """
        names, formats, offsets = [], [], []
        for i, column in enumerate(self.columns):
            names.append(f"h{i}")
            formats.append(np.dtype("V20"))  # sequence (u4), log time and publish time (u8)
            offsets.append(column + 11)
        names.append("stamp")
        formats.append(np.dtype("V8"))
        offsets.append(self.stamp_at)
        for j, (at, size) in enumerate(values):
            names.append(f"v{j}")
            formats.append(np.dtype(f"V{size}"))
            offsets.append(at)
        return np.dtype(
            {"names": names, "formats": formats, "offsets": offsets, "itemsize": self.size}
        )


#: Where the values of a columns record start in it: after the 31-byte header, the layout byte
#: and the two counts, so at a multiple of 8 bytes when the record does.
_COLUMNS_AT = RECORD_HEADER.itemsize + 9


#: sequence, log time, publish time: the variable part of a message record header
_TIMES = np.dtype([("sequence", "<u4"), ("log_time", "<u8"), ("publish_time", "<u8")])


#: Blocks handed to the log's writer thread and not yet written, at most (the run waits).
MAX_QUEUED_BLOCKS = 4
#: Samples of the viewers' topics gathered before their chunk is written. Laying out a chunk of
#: them costs about 0.45 ms whatever its size and 1.2 µs a sample: at 100 Hz, a block of 1000
#: steps of 0.1 ms views 10 samples, so one chunk a block cost a step's time every sample.
VIEW_BATCH = 256


class McapLogger:
    """Writes a run to one MCAP file while it is simulated (a ``RunObserver``).

    Args:
        path: the file to write; its folder is created.
        log_rate: logged samples per simulated second [Hz]; default every sample. The logger
            keeps every ``stride``-th sample, stride = round(1 / (dt · log_rate)) ≥ 1, counted from
            sample 0.
        pose_rate: link poses (``/tf``, ``/pinwind/poses``) per simulated second [Hz], for
            display; default ``POSE_RATE`` (100 Hz), None for every viewed sample. Poses go with
            every ``pose_stride``-th sample, a multiple of the view stride.
        view_rate: samples per simulated second on the ROS 2 topics that Rerun and Foxglove
            plot [Hz]; default ``VIEW_RATE`` (100 Hz), None for every logged sample. They go with
            every ``view_stride``-th sample, a multiple of the log stride. Every array is on
            ``/pinwind/columns`` at the log rate whatever this says (``read_log`` reads that).
        overwrite: replace an existing file (otherwise ``LogExists`` before anything runs).
        command: the command line or call that started the run (default ``sys.argv``).
        compression: chunk compression, ``"zstd"`` (default), ``"lz4"`` or ``""``.
        compression_level: level of that compression.
        max_bytes: refuse a run whose log would be larger [bytes] (``LogTooLargeToWrite``);
            default ``MAX_LOG_BYTES``; None for no limit (and no free-space check).

    Raises:
        LogExists: the file exists and ``overwrite`` is false.
    """

    #: The writer thread keeps the blocks it is handed: the run gives it new arrays each block.
    holds: int | None = None

    def __init__(
        self,
        path: str | os.PathLike,
        *,
        log_rate: float | None = None,
        pose_rate: float | None = POSE_RATE,
        view_rate: float | None = VIEW_RATE,
        overwrite: bool = False,
        command: str | None = None,
        compression: str = COMPRESSION,
        compression_level: int = COMPRESSION_LEVEL,
        max_bytes: float | None = MAX_LOG_BYTES,
    ):
        self.path = Path(path)
        if self.path.is_dir():
            raise LogError(str(self.path), "is a folder; give a file name such as run.mcap")
        if self.path.exists() and not overwrite:
            raise LogExists(str(self.path))
        for name, rate in (("log", log_rate), ("pose", pose_rate), ("view", view_rate)):
            if rate is not None:
                _resolve_rate(None, rate, name)  # check the value before the run starts
        self.log_rate = log_rate
        self.pose_rate = pose_rate
        self.view_rate = view_rate
        self.overwrite = overwrite
        self.command = command if command is not None else shlex.join(sys.argv)
        self.compression = compression
        self.compression_level = compression_level
        self.max_bytes = max_bytes
        self.stride = 1
        self.view_stride = 1
        self.pose_stride = 1
        self.samples_logged = 0
        self._next_sample = 0
        self._last_time = math.nan
        self._stream: BinaryIO | None = None
        self._file: McapWriter | None = None
        self._failed: BaseException | None = None
        self._failed_at = math.nan
        self._lost = False
        self._queued = 0
        # Bounded: when the writer falls behind the steps (zstd costs about a step per
        # sample), the run waits for it instead of queueing blocks without end.
        self._jobs: queue.Queue = queue.Queue(maxsize=MAX_QUEUED_BLOCKS)
        self._writer: threading.Thread | None = None
        self._buffer = np.empty(0, dtype=np.uint8)  # the records of one chunk (_assemble)
        self._column_buffer = np.empty(0, dtype=np.float64)  # _assemble_columns
        self._column_scratch = np.empty(0, dtype=np.float64)
        #: the viewed samples of blocks whose columns are written and whose views are not yet
        #: (their sample numbers beside them), and how many samples they hold
        self._views: list[tuple[Result, np.ndarray]] = []
        self._views_held = 0

    # --- RunObserver -----------------------------------------------------------------------

    def begin(self, gearbox, result: Result) -> None:
        """Check the log's size; open the file; write schemas, channels, model and metadata.

        Raises:
            LogTooLargeToWrite: the log would be larger than ``max_bytes`` or the free space.
            LogError: the file cannot be created.
        """
        meta = result.metadata
        dt = float(meta["dt"])
        self.stride, rate = _resolve_rate(dt, self.log_rate)
        self.view_stride = self.stride
        if self.view_rate is not None:
            self.view_stride = self.stride * max(1, round(rate / float(self.view_rate)))
        self.pose_stride = self.view_stride
        if self.pose_rate is not None:
            view = rate * self.stride / self.view_stride
            self.pose_stride = self.view_stride * max(1, round(view / float(self.pose_rate)))
        self.estimate = estimate_log_size(
            result,
            samples=int(meta.get("samples_simulated", len(result))),
            stride=self.stride,
            pose_stride=self.pose_stride,
            view_stride=self.view_stride,
            model_bytes=len(gearbox.source_text.encode("utf-8")),
        )
        if self.max_bytes is not None:
            check_log_fits(self.path, self.estimate, result, rate=rate, max_bytes=self.max_bytes)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise LogError(
                str(self.path),
                f"cannot create the folder {self.path.parent} for the log: "
                f"{err.strerror or err}; choose another --out (or log=) or fix its permissions",
            ) from err
        try:
            stream = self._stream = self._open_file()
        except FileExistsError as err:
            raise LogExists(str(self.path)) from err
        except OSError as err:
            raise LogError(str(self.path), f"cannot write the log: {err.strerror}") from err
        hold_for_writing(stream.fileno())  # a reader meanwhile says "being written"
        try:
            self._start(stream, gearbox, result, rate)
        except BaseException as err:
            stream.close()
            self._file = None
            self.path.unlink(missing_ok=True)
            if isinstance(err, OSError):  # a full disk (with allow_large_log: not foreseen)
                raise LogError(
                    str(self.path),
                    f"cannot write the log's first records, its model and run metadata "
                    f"({err.strerror or err}), so the run was not started and the file is "
                    "removed. Free some disk space or log less (--log-rate, --no-log)",
                ) from err
            raise
        # Chunks are encoded, compressed and written by a thread of their own, so that they
        # overlap the next samples' steps (the compiled step loop releases the GIL).
        self._writer = threading.Thread(target=self._write_chunks, name="pinwind-log", daemon=True)
        self._writer.start()

    def _open_file(self) -> BinaryIO:
        """The file, unbuffered: every write reaches the OS at once, a failed one can be cut."""
        return open(self.path, "wb" if self.overwrite else "xb", buffering=0)  # noqa: SIM115

    def _start(self, stream: BinaryIO, gearbox, result: Result, rate: float) -> None:
        meta = result.metadata
        f = self._file = McapWriter(
            stream, compression=self.compression, compression_level=self.compression_level
        )
        recorded = dict(versions())
        f.start(library=f"pinwind {recorded['pinwind']} (mcap {recorded['mcap']})")

        names = model_names(result)
        self._terms = names["energy_terms"]
        view_rate = rate * self.stride / self.view_stride
        array_schema = f.schema(messages.FLOAT64_MULTI_ARRAY)
        joint_schema = f.schema(messages.JOINT_STATE)
        string_schema = f.schema(messages.STRING)
        tf_schema = f.schema(messages.frame_transforms_schema())
        model_channel = f.channel(
            MODEL_TOPIC, "cdr", string_schema, {"content": "model file (URDF with <gearbox>)"}
        )
        joint_codec = JointStateCodec(names["joint_names"], WORLD_FRAME)
        joint_channel = f.channel(
            JOINTS_TOPIC,
            "cdr",
            joint_schema,
            {
                "names": json.dumps(names["joint_names"]),
                "position": "joint angle [rad], unwrapped; a slide's displacement [m] "
                "(Result.angle)",
                "velocity": "joint speed relative to the parent body [rad/s; a slide's m/s] "
                "(Result.speed)",
                "effort": "applied plus driver or lock torque [N*m; a slide's force, N] "
                "(Result.torque)",
                "rate_hz": repr(view_rate),
                "stride": str(self.view_stride),
            },
        )
        records = [(joint_channel, joint_codec.template)]
        #: (Result field or energy, byte offset in the payload, doubles per sample)
        sources: list[tuple[str, int, int]] = []
        for field in ("angle", "speed", "torque"):
            sources.append((field, 0, len(names["joint_names"])))
        joint_fields = list(joint_codec.fields_at)
        array_fields = []
        for topic in array_topics():
            dims = []
            channel_meta = {
                "field": topic.field,
                "unit": topic.unit,
                "description": topic.description,
            }
            if topic.element:
                element_names = names[NAMES_OF[topic.element]]
                if not element_names:
                    continue  # e.g. a model without meshes: no mesh topics
                dims.append((topic.element, len(element_names)))
                channel_meta["names"] = json.dumps(element_names)
            else:
                dims.append(("value", 1))
            if topic.frame:
                dims.append(("axis", 3))
                channel_meta["frame"] = topic.frame
                channel_meta["axes"] = json.dumps(["x", "y", "z"])
            channel_meta["rate_hz"] = repr(view_rate)
            channel_meta["stride"] = str(self.view_stride)
            channel = f.channel(topic.topic, "cdr", array_schema, channel_meta)
            codec = Float64ArrayCodec(dims)
            array_fields.append((len(records), codec.data_at))
            records.append((channel, codec.template))
            sources.append((topic.field, 0, codec.count))
        self._tf_codec = FrameTransformsCodec(WORLD_FRAME, names["body_names"])
        pose_rate = rate * self.stride / self.pose_stride
        self._tf_channel = f.channel(
            TF_TOPIC,
            "protobuf",
            tf_schema,
            {
                "content": f"world pose of every link, parent frame '{WORLD_FRAME}'",
                "rate_hz": repr(pose_rate),
                "stride": str(self.pose_stride),
            },
        )
        # The columns pinwind reads back: every array but the poses, at the log rate.
        columns: list[tuple[str, list[int]]] = [("time", [])]
        for name in result.ARRAYS:  # the run's own schema
            shape = list(getattr(result, name).shape[1:])
            if name != "time" and name not in POSE_ARRAYS and math.prod(shape):
                columns.append((name, shape))
        columns += [(f"energy/{term}", []) for term in self._terms]
        self._columns = [(key, math.prod(shape)) for key, shape in columns]
        self._column_width = sum(width for _, width in self._columns)
        bodies = len(names["body_names"])
        self._pose_width = 1 + 7 * bodies
        layout = (
            f"a layout byte ({COLUMNS_LAYOUT}), the number of samples m and of poses p (uint32 "
            "each), a bit per series of 'columns' (bit i of byte i // 8, 1: the series is "
            "constant over the block), zero-padded to a multiple of 8 bytes, then the m values of "
            "each of the V varying series as the byte planes of these V * m float64 values "
            "(byte 0 of every value, then byte 1, ..., byte 7), then the float64 value of each "
            "constant series, both in the order of 'columns' (each array's elements in C order), "
            "then the p posed samples' float64 series in the order of 'pose_columns'; all "
            "little-endian"
        )
        self._columns_channel = f.channel(
            COLUMNS_TOPIC,
            COLUMNS_ENCODING,
            0,
            {
                "content": "every Result array at the log rate, link poses at the pose rate; "
                "one message per block of samples, log time = its first sample's",
                "columns": json.dumps(columns),
                "pose_columns": json.dumps(
                    [("time", []), ("body_position", [bodies, 3]), ("body_quaternion", [bodies, 4])]
                ),
                "layout": layout,
                "rate_hz": repr(rate),
                "stride": str(self.stride),
                "pose_rate_hz": repr(pose_rate),
                "pose_stride": str(self.pose_stride),
            },
        )
        self._rows = _RowLayout(records, 0, joint_codec.stamp_at)
        width = RECORD_HEADER.itemsize
        offsets = [self._rows.columns[0] + width + at for at in joint_fields]
        offsets += [self._rows.columns[r] + width + at for r, at in array_fields]
        self._sources = [
            (field, at, 8 * count)
            for (field, _, count), at in zip(sources, offsets, strict=True)
            if count
        ]
        self._row_dtype = self._rows.dtype([(at, size) for _, at, size in self._sources])

        source = gearbox.source_text.encode("utf-8")
        f.attachment(
            Path(str(gearbox.path)).name or f"{gearbox.name}.urdf",
            "application/xml",
            source,
            create_time=0,
        )
        f.metadata(
            "pinwind",
            with_checksum(
                {
                    "format": FORMAT,
                    "format_version": str(FORMAT_VERSION),
                    "pinwind_version": recorded["pinwind"],
                    "created_utc": utc_now(),
                    "command": self.command,
                    "versions": json.dumps(recorded),
                }
            ),
        )
        run = {k: v for k, v in meta.items() if k not in ("status", "wall_time_s")}
        run.update(
            log_stride=self.stride,
            log_rate_hz=rate,
            sample_rate_hz=1.0 / meta["dt"],
            view_stride=self.view_stride,
            view_rate_hz=view_rate,
            pose_stride=self.pose_stride,
            pose_rate_hz=pose_rate,
            log_estimate_bytes=self.estimate.bytes,
        )
        f.metadata("pinwind.run", with_checksum(json_record(run)))
        f.metadata(
            "pinwind.model", with_checksum(json_record({**names, **model_geometry(gearbox)}))
        )
        payload = messages.encode_string(gearbox.source_text)
        record = message_records(
            model_channel,
            np.zeros(1, np.uint32),
            np.zeros(1, np.uint64),
            np.frombuffer(payload, np.uint8)[None, :],
        )
        f.chunk(record.tobytes(), {model_channel: np.zeros((1, 2), np.uint64)})

    def samples(self, block: Result, start: int) -> None:
        """Queue the samples of a block (every ``stride``-th, counted from 0) as one chunk.

        The block holds samples start … start + len(block) − 1 in its rows.

        The arrays of ``block`` must not change afterwards (the simulation writes each block
        into new arrays), and it has a pose at every sample (as ``simulate`` makes them).
        Samples already queued are skipped, so a block handed over again after an interrupt is
        not logged twice.

        Raises:
            LogWriteFailed: writing an earlier chunk failed (disk full, ...): the run stops.
        """
        if self._file is None:
            return
        if len(block.pose_rows) != len(block):
            raise ValueError(
                f"a block of {len(block)} samples with {len(block.pose_rows)} poses: the log "
                "takes the poses at its pose rate from a block with a pose at every sample"
            )
        self._raise_if_failed()
        stop = start + len(block)
        first = max(start, self._queued)
        first += -first % self.stride
        if first >= stop:
            return
        samples = np.arange(first, stop, self.stride)
        if self.stride == 1:
            rows: slice | np.ndarray = slice(first - start, stop - start)
        else:
            rows = samples - start
        # Waits while MAX_QUEUED_BLOCKS wait for the writer; counted as queued only once in
        # the queue, so that a Ctrl-C during the wait leaves these samples to be handed again.
        self._jobs.put((block, rows, samples))
        self._queued = int(samples[-1]) + 1

    def flush(self) -> None:
        """Wait until every queued chunk is in the file."""
        if self._writer is not None:
            self._jobs.join()
        self._raise_if_failed()

    def _raise_if_failed(self) -> None:
        if self._failed is not None:
            raise self._write_error()

    def _write_error(self) -> LogWriteFailed:
        err = self._failed
        return LogWriteFailed(
            str(self.path),
            cause=getattr(err, "strerror", None) or str(err),
            failed_at=self._failed_at,
            samples_logged=self.samples_logged,
            last_time=self._last_time,
            kept=not self._lost,
        )

    def _write_chunks(self) -> None:
        """The writer thread: one chunk per queued block, in order, until None."""
        while True:
            job = self._jobs.get()
            try:
                if job is None:  # the run's end: the views held go out first
                    if self._failed is None and self._views:
                        at = float(self._views[0][0].time[0])
                        self._write_or_fail(self._write_views, at)
                    return
                if self._failed is None:
                    block, rows, samples = job
                    self._write_or_fail(
                        functools.partial(self._write_block, block, rows, samples),
                        block.time[rows][0],
                    )
            finally:
                self._jobs.task_done()

    def _write_or_fail(self, write, at: float) -> None:
        """Call ``write``; a failure (disk full, ...) is kept for ``samples()`` to report.

        ``at``: the simulated time [s] of the first sample it was writing.
        """
        try:
            write()
        except Exception as err:
            self._failed_at = float(at)
            self._failed = err
            self._rewind()

    def _write_block(self, block: Result, rows: slice | np.ndarray, samples: np.ndarray) -> None:
        """A block's columns chunk; its viewed samples are held, and written once enough are."""
        self._mcap().chunk(*self._assemble_columns(block, rows, samples))
        if self._deleted():
            self._lost = True
            raise FileNotFoundError(
                errno.ENOENT,
                "the file was deleted, or its folder removed, while the run was writing it",
            )
        self._next_sample = int(samples[-1]) + 1
        self.samples_logged += len(samples)
        self._last_time = float(block.time[rows][-1])
        viewed = self._viewed(rows, samples)
        if viewed is not None:
            self._views.append((block.take(viewed[0]), viewed[1]))
            self._views_held += len(viewed[1])
        if self._views_held >= VIEW_BATCH:
            self._write_views()

    def _write_views(self) -> None:
        """One chunk of the viewers' topics for the viewed samples held."""
        views, self._views, self._views_held = self._views, [], 0
        block = concatenate([v for v, _ in views])
        samples = np.concatenate([s for _, s in views])
        self._mcap().chunk(*self._assemble(block, slice(0, len(samples)), samples))

    def _mcap(self) -> McapWriter:
        """The MCAP writer, open between ``begin`` and ``end``."""
        if self._file is None:
            raise RuntimeError(f"internal error: the log {self.path} is not open for writing")
        return self._file

    def _open_stream(self) -> BinaryIO:
        """The log's file, open from ``begin``."""
        if self._stream is None:
            raise RuntimeError(f"internal error: the log {self.path} has no open file")
        return self._stream

    def _deleted(self) -> bool:
        """The file being written has no name any more (deleted, or its folder removed)."""
        try:
            return os.fstat(self._open_stream().fileno()).st_nlink == 0
        except OSError:
            return True

    def _rewind(self) -> None:
        """Cut the file back to its last complete chunk, so that it reads as a cut log."""
        try:
            self._mcap().rewind()
        except Exception:  # the file is gone or the disk refuses: nothing more to do
            pass

    def _stop_writer(self) -> None:
        if self._writer is not None:
            self._jobs.put(None)
            self._writer.join()
            self._writer = None

    def end(self, result: Result, status: str) -> None:
        """Write the end-status record and the summary, close the file.

        After a failed write, the file is cut back to its last complete chunk and the end
        record and summary are tried once more there (a full disk may take them now); if that
        fails too the file stays a cut log, which ``read_log`` recovers.

        Raises:
            LogWriteFailed: writing failed and no other exception is in flight.
        """
        if self._file is None:
            return
        in_flight = sys.exc_info()[1]
        cause = f"{type(in_flight).__name__}: {in_flight}" if in_flight is not None else ""
        try:
            with interrupts_deferred():
                self._stop_writer()
                self._finish(result, status, cause)
        except Exception as err:
            self._rewind()
            if self._failed is None:
                self._failed = err
                self._failed_at = math.nan
        finally:
            self._file = None
            if self._stream is not None:
                self._stream.close()
        if self._failed is not None and not isinstance(in_flight, LogWriteFailed):
            error = self._write_error()
            if in_flight is None:
                raise error
            warnings.warn(str(error), LogRecovered, stacklevel=2)

    def _finish(self, result: Result, status: str, cause: str) -> None:
        f = self._mcap()
        if self._failed is not None:
            status = f"{status}; {self._write_error()}"
        f.metadata(
            "pinwind.end",
            with_checksum(
                json_record(
                    {
                        "status": status,
                        "cause": cause,
                        "samples_simulated": result.metadata.get("samples_simulated", len(result)),
                        "samples_logged": self.samples_logged,
                        "log_error": str(self._failed) if self._failed else "",
                        "wall_time_s": result.metadata.get("wall_time_s"),
                        "ended_utc": utc_now(),
                    }
                )
            ),
        )
        f.finish()

    # --- chunks ----------------------------------------------------------------------------

    def _viewed(
        self, rows: slice | np.ndarray, samples: np.ndarray
    ) -> tuple[slice | np.ndarray, np.ndarray] | None:
        """The rows and sample numbers of a block's samples that go to the viewers' topics."""
        if self.view_stride == self.stride:
            return rows, samples
        pick = np.flatnonzero(samples % self.view_stride == 0)
        if not len(pick):
            return None
        if isinstance(rows, slice):
            return rows.start + pick, samples[pick]
        return rows[pick], samples[pick]

    def _assemble_columns(
        self, result: Result, rows: slice | np.ndarray, samples: np.ndarray
    ) -> tuple[np.ndarray, dict]:
        """The chunk pinwind reads back: the ``/pinwind/columns`` records of a block.

        The first record's payload holds every array but the poses for the ``rows`` of a block
        (sample numbers ``samples``): the m values of each series that varies, the one value
        of each series that is the same (bit for bit) at every sample of the block, and a bit
        per series saying which; then the times and poses of the samples that have one (every
        ``pose_stride``-th). A closing record without samples, at the block's last sample
        time, makes the chunk's time span (its log times, in the chunk index) that of the
        block. The copy turns the block's sample-major arrays into runs of one series, which
        zstd compresses twice as fast, and the varying series' values into byte planes
        (``byte_planes.hpp``), which it compresses to 0.6 of the size 1.6 times as fast and
        decompresses twice as fast; a constant series (a rigid mesh's deflection, a fixed
        gear's pitch point, a bearing without moment) is neither compressed nor decompressed
        nor copied.
        One record per block, poses included, so that no other tool's rechunking can part a
        block's values.
        """
        m = len(samples)
        k = self._column_width
        flags = mask_bytes(k)
        time = result.time[rows]
        log_time = np.rint(time[:1] * 1e9).astype(np.uint64)
        posed = np.flatnonzero(samples % self.pose_stride == 0)
        p = len(posed)
        bodies = len(result.body_names)
        pose_width = self._pose_width
        # room for every series varying, and the closing record
        most = (2 * _COLUMNS_AT + 2 * flags) // 8 + k * m + pose_width * p
        if self._column_buffer.size < most:
            self._column_buffer = np.empty(most)
        first = (_COLUMNS_AT + flags) // 8
        if self._column_scratch.size < k * m:
            self._column_scratch = np.empty(k * m)
        values = self._column_scratch[: k * m].reshape(k, m)
        at = 0
        for key, width in self._columns:
            if key.startswith("energy/"):
                source = result.energy[key[len("energy/") :]]
            else:
                source = getattr(result, key)
            values[at : at + width] = source[rows].reshape(m, width).T
            at += width
        bits = values.view(np.uint64)
        same = bits.max(axis=1) == bits.min(axis=1)  # bit for bit: -0.0 and NaN too
        count = int(np.count_nonzero(same))
        vary = k - count
        end = first + vary * m
        shuffle_series(values, np.flatnonzero(~same), self._column_buffer[first:end].view(np.uint8))
        self._column_buffer[end : end + count] = values[same, 0]
        end += count
        if p:
            poses = self._column_buffer[end : end + pose_width * p].reshape(pose_width, p)
            poses[0] = time[posed]
            poses[1 : 1 + 3 * bodies] = result.body_position[rows][posed].reshape(p, -1).T
            poses[1 + 3 * bodies :] = result.body_quaternion[rows][posed].reshape(p, -1).T
        end += pose_width * p
        size = 8 * end
        data = self._column_buffer.view(np.uint8)[: size + _COLUMNS_AT + flags]
        last_time = np.rint(time[-1:] * 1e9).astype(np.uint64)
        self._column_head(data, 0, samples[0], log_time, m, p, size - _COLUMNS_AT)
        data[_COLUMNS_AT : _COLUMNS_AT + flags] = 0
        data[_COLUMNS_AT : _COLUMNS_AT + (k + 7) // 8] = np.packbits(same, bitorder="little")
        # the closing record: no samples, no series constant, at the last sample's time
        self._column_head(data, size, samples[-1], last_time, 0, 0, flags)
        data[size + _COLUMNS_AT :] = 0
        index = np.array([[log_time[0], 0], [last_time[0], size]], dtype=np.uint64)
        return data, {self._columns_channel: index}

    def _column_head(
        self,
        data: np.ndarray,
        at: int,
        sample: int,
        log_time: np.ndarray,
        m: int,
        p: int,
        after: int,
    ) -> None:
        """Header, layout byte and counts of a columns record of m samples and p poses.

        ``after``: the bytes after them (constant-series bits and values).
        """
        head = data[at : at + RECORD_HEADER.itemsize].view(RECORD_HEADER)
        head["op"] = Opcode.MESSAGE
        head["length"] = _COLUMNS_AT - 9 + after
        head["channel"] = self._columns_channel
        head["sequence"] = int(sample) & 0xFFFFFFFF  # the sample's number (mod 2^32)
        head["log_time"] = log_time
        head["publish_time"] = log_time
        counts = data[at + RECORD_HEADER.itemsize : at + _COLUMNS_AT]
        counts[0] = COLUMNS_LAYOUT
        counts[1:].view("<u4")[:] = (m, p)

    def _assemble(
        self, result: Result, rows: slice | np.ndarray, samples: np.ndarray
    ) -> tuple[np.ndarray, dict]:
        """Message records of ``rows`` of a block (bytes), and each channel's index.

        ``samples`` are the rows' sample indices in the run (the messages' sequence numbers).

        Each sample is one row of records of fixed length, a record per channel but /tf, in
        ``array_topics()`` order after /joints; the /tf records of the samples that have a pose
        follow all the rows, in time order (their payloads grow with the stamp's varint).
        """
        m = len(samples)
        layout = self._rows
        log_time = np.rint(result.time[rows] * 1e9).astype(np.uint64)
        posed = np.flatnonzero(samples % self.pose_stride == 0)
        tf_runs = self._tf_codec.encode_runs(
            log_time[posed],
            result.body_position[rows][posed],
            result.body_quaternion[rows][posed],
        )
        width = RECORD_HEADER.itemsize
        tf_bytes = sum((b - a) * (width + tf.shape[1]) for a, b, tf in tf_runs)
        size = m * layout.size + tf_bytes
        if self._buffer.size < size:
            self._buffer = np.empty(size, dtype=np.uint8)
        # One buffer for every chunk: the writer thread compresses a chunk before it assembles
        # the next, and fresh pages cost a fault per 4 kB (a fifth of the logger's time).
        data = self._buffer[:size]
        flat = data[: m * layout.size].reshape(m, layout.size)
        flat[:] = layout.template
        row = flat.reshape(-1).view(self._row_dtype)
        times = np.empty(m, dtype=_TIMES)
        times["sequence"] = samples
        times["log_time"] = log_time
        times["publish_time"] = log_time
        times = times.view("V20")
        for i in range(len(layout.columns)):
            row[f"h{i}"] = times
        row["stamp"] = messages._stamp_columns(log_time).reshape(-1).view("V8")
        for j, (field, _, size) in enumerate(self._sources):
            if field == "energy":
                values = np.stack([result.energy[t][rows] for t in self._terms], axis=1)
            else:
                values = np.ascontiguousarray(getattr(result, field)[rows], dtype="<f8")
            row[f"v{j}"] = values.reshape(m, -1).view(f"V{size}")[:, 0]
        offsets = np.arange(m, dtype=np.uint64) * np.uint64(layout.size)
        index = {
            channel: np.stack([log_time, offsets + np.uint64(column)], axis=1)
            for channel, column in zip(layout.channels, layout.columns, strict=True)
        }
        at = m * layout.size
        tf_index = []
        for a, b, tf in tf_runs:
            records = message_records(
                self._tf_channel, samples[posed[a:b]], log_time[posed[a:b]], tf
            )
            data[at : at + records.size] = records.reshape(-1)
            length = records.shape[1]
            starts = at + np.arange(b - a, dtype=np.uint64) * np.uint64(length)
            tf_index.append(np.stack([log_time[posed[a:b]], starts], axis=1))
            at += records.size
        if tf_index:
            index[self._tf_channel] = np.concatenate(tf_index)
        return data, index
