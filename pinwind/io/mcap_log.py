"""MCAP logs of runs: the documented topics, the writer (a ``RunObserver``) and the reader.

A log is one self-contained MCAP file (docs/log_format.md): the model file as an attachment and
on ``/robot_description``, metadata records (versions, model hash, solver settings, dt, loads, the
command, the gear geometry) and one message per logged sample on each topic, with log time =
simulation time. ``McapLogger`` writes it while ``simulate`` runs, one MCAP chunk per block of
samples, flushed to the OS as it goes, so a killed run leaves every block but the last; ``end``
writes the end-status record and the summary even when the run raised. ``read_log`` gives back
the ``Result``; it recovers the complete blocks of a file that was cut short.

Payloads are encoded a block of samples at a time (``io/messages.py``) and laid out as message
records with numpy, then written by ``io/mcap_file.py``: the ``mcap`` package's own writer spends
about 4 µs per message, which at 18 messages per sample would be 30 % of a drivetrain step.
"""

from __future__ import annotations

import json
import math
import os
import platform
import queue
import shlex
import signal
import sys
import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np
from mcap.opcode import Opcode

from pinwind.dynamics.result import Result
from pinwind.errors import InvalidLogRate, LogError, LogExists, LogRecovered
from pinwind.io import messages
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

#: Identity of the file format, in the ``pinwind`` metadata record.
FORMAT = "pinwind-log"
FORMAT_VERSION = 1

MODEL_TOPIC = "/robot_description"
JOINTS_TOPIC = "/joints"
TF_TOPIC = "/tf"
#: Parent frame of every link transform on ``/tf``.
WORLD_FRAME = "world"


@dataclass(frozen=True)
class ArrayTopic:
    """A topic of std_msgs/msg/Float64MultiArray messages holding one Result array per sample.

    Attributes:
        topic: MCAP topic (and Rerun entity path).
        field: Result attribute (``energy`` for the energy ledger).
        unit: SI unit of the values.
        description: what the values are.
        element: kind of the first dimension (``joint``, ``mesh``, ``bearing``, ``term``), or
            ``""`` for one value per sample.
        frame: ``world`` or ``joint`` for 3-vectors (second dimension x, y, z), else ``""``.
    """

    topic: str
    field: str
    unit: str
    description: str
    element: str = ""
    frame: str = ""


#: Every Result array except those on ``/joints`` (angle, speed, torque) and ``/tf`` (poses).
ARRAY_TOPICS: tuple[ArrayTopic, ...] = (
    ArrayTopic(
        "/joints/acceleration",
        "acceleration",
        "rad/s^2",
        "joint acceleration over the step that starts at the sample",
        "joint",
    ),
    ArrayTopic("/meshes/normal", "mesh_normal", "N", "tooth normal force F_n >= 0", "mesh"),
    ArrayTopic("/meshes/tangential", "mesh_tangential", "N", "F_t = F_n cos(alpha_w)", "mesh"),
    ArrayTopic("/meshes/radial", "mesh_radial", "N", "F_r = F_n sin(alpha_w)", "mesh"),
    ArrayTopic("/meshes/axial", "mesh_axial", "N", "F_a = F_t tan(beta)", "mesh"),
    ArrayTopic(
        "/meshes/flank",
        "mesh_flank",
        "1",
        "loaded flank s = +1 when A turning positively drives B, else -1",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/transmission_error",
        "transmission_error",
        "m",
        "position mismatch along the line of action",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/force_on_b", "mesh_force_on_b", "N", "tooth force on gear B", "mesh", "world"
    ),
    ArrayTopic("/meshes/pitch_point", "pitch_point", "m", "pitch point", "mesh", "world"),
    ArrayTopic(
        "/meshes/deflection",
        "mesh_deflection",
        "m",
        "compliant mesh: overlap of the loaded flank (negative: gap); rigid: 0",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/contact_position",
        "mesh_contact_position",
        "m",
        "roll position of the entering tooth pair from gear A's base tangency point",
        "mesh",
    ),
    ArrayTopic("/meshes/pairs", "mesh_pairs", "1", "tooth pairs in contact", "mesh"),
    ArrayTopic(
        "/meshes/single_tooth_force",
        "mesh_single_tooth_force",
        "N",
        "normal force on the entering tooth pair, F_n k1/k",
        "mesh",
    ),
    ArrayTopic(
        "/bearings/force",
        "bearing_force",
        "N",
        "force on the child body at the bearing centre",
        "bearing",
        "world",
    ),
    ArrayTopic(
        "/bearings/moment",
        "bearing_moment",
        "N*m",
        "moment on the child body about the bearing centre",
        "bearing",
        "world",
    ),
    ArrayTopic(
        "/bearings/force_local",
        "bearing_force_local",
        "N",
        "force on the child body at the bearing centre",
        "bearing",
        "joint",
    ),
    ArrayTopic(
        "/bearings/moment_local",
        "bearing_moment_local",
        "N*m",
        "moment on the child body about the bearing centre",
        "bearing",
        "joint",
    ),
    ArrayTopic("/run/time", "time", "s", "sample time (exact; log time is rounded to 1 ns)"),
    ArrayTopic(
        "/run/constraint_residual",
        "constraint_residual",
        "m/s or rad/s",
        "max |J v - target| after the step",
    ),
    ArrayTopic("/run/energy", "energy", "J", "energy ledger (docs/log_format.md)", "term"),
)

_NAMES_OF = {
    "joint": "joint_names",
    "mesh": "mesh_names",
    "bearing": "bearing_names",
    "term": "energy_terms",
}


def _utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def _plain(value: Any) -> Any:
    """JSON fallback: numpy scalars and arrays as numbers and lists, anything else as text."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def _json_record(values: dict[str, Any]) -> dict[str, str]:
    """MCAP metadata holds strings: every value is stored as JSON."""
    return {
        key: json.dumps(value, ensure_ascii=False, default=_plain) for key, value in values.items()
    }


def _versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version()}
    for dist in ("pinwind", "pin", "proxsuite", "numpy", "mcap", "protobuf", "rerun-sdk"):
        try:
            out[dist] = version(dist)
        except PackageNotFoundError:
            out[dist] = "not installed"
    return out


def _topic_values(result: Result, topic: ArrayTopic, rows: np.ndarray, terms: list[str]):
    if topic.field == "energy":
        return np.stack([result.energy[name][rows] for name in terms], axis=1)
    return getattr(result, topic.field)[rows]


@contextmanager
def _interrupts_deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM while a chunk and its bookkeeping are written.

    Ctrl-C raises between any two bytecodes; one landing between a write and the offsets that
    index it would leave a summary that does not match the file. Signals that arrive meanwhile
    are raised again, to their own handlers, once the block is done.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    held = (signal.SIGINT, signal.SIGTERM)
    previous = {s: signal.signal(s, lambda signum, frame: caught.append(signum)) for s in held}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        for s in caught:
            signal.raise_signal(s)


def _resolve_rate(dt: float | None, log_rate: float | None) -> tuple[int, float]:
    """(stride, logged rate [Hz]) for a wanted log rate at time step dt (None: check only)."""
    sample_rate = 1.0 / dt if dt is not None else math.inf
    if log_rate is None:
        return 1, sample_rate
    log_rate = float(log_rate)
    if not math.isfinite(log_rate) or log_rate <= 0.0:
        raise InvalidLogRate(f"the log rate must be a positive number [Hz]; got {log_rate}")
    if dt is None:
        return 1, log_rate
    if log_rate > sample_rate * (1.0 + 1e-9):
        raise InvalidLogRate(
            f"log rate {log_rate:g} Hz is above the sample rate 1/dt = {sample_rate:g} Hz "
            f"(dt = {dt:g} s): a run cannot log more samples than it computes; give at most "
            f"{sample_rate:g} Hz, or omit --log-rate to log every sample"
        )
    stride = max(1, round(sample_rate / log_rate))
    return stride, sample_rate / stride


class McapLogger:
    """Writes a run to one MCAP file while it is simulated (a ``RunObserver``).

    Args:
        path: the file to write; its folder is created.
        log_rate: logged samples per simulated second [Hz]; default every sample. The logger
            keeps every ``stride``-th sample, stride = round(1 / (dt · log_rate)) ≥ 1, counted from
            sample 0.
        overwrite: replace an existing file (otherwise ``LogExists`` before anything runs).
        command: the command line or call that started the run (default ``sys.argv``).
        compression_level: zstd level of the chunks.

    Raises:
        LogExists: the file exists and ``overwrite`` is false.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        *,
        log_rate: float | None = None,
        overwrite: bool = False,
        command: str | None = None,
        compression_level: int = 1,
    ):
        self.path = Path(path)
        if self.path.is_dir():
            raise LogError(str(self.path), "is a folder; give a file name such as run.mcap")
        if self.path.exists() and not overwrite:
            raise LogExists(str(self.path))
        if log_rate is not None:
            _resolve_rate(None, log_rate)  # check the value before the run starts
        self.log_rate = log_rate
        self.overwrite = overwrite
        self.command = command if command is not None else shlex.join(sys.argv)
        self.compression_level = compression_level
        self.stride = 1
        self.samples_logged = 0
        self._next_sample = 0
        self._stream: BinaryIO | None = None
        self._file: McapWriter | None = None
        self._failed: BaseException | None = None
        self._queued = 0
        self._jobs: queue.Queue = queue.Queue()
        self._writer: threading.Thread | None = None

    # --- RunObserver -----------------------------------------------------------------------

    def begin(self, gearbox, result: Result) -> None:
        """Open the file; write schemas, channels, the model, the metadata and the names."""
        meta = result.metadata
        self.stride, rate = _resolve_rate(float(meta["dt"]), self.log_rate)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise LogError(
                str(self.path),
                f"cannot create the folder {self.path.parent} for the log: "
                f"{err.strerror or err}; choose another --out (or log=) or fix its permissions",
            ) from err
        try:
            self._stream = open(self.path, "wb" if self.overwrite else "xb")  # noqa: SIM115
        except FileExistsError as err:
            raise LogExists(str(self.path)) from err
        except OSError as err:
            raise LogError(str(self.path), f"cannot write the log: {err.strerror}") from err
        try:
            self._start(gearbox, result, rate)
        except BaseException:
            self._stream.close()
            self._file = None
            self.path.unlink(missing_ok=True)
            raise
        # Chunks are encoded, compressed and written by a thread of their own, so that they
        # overlap the next samples' steps (the compiled step loop releases the GIL).
        self._writer = threading.Thread(target=self._write_chunks, name="pinwind-log", daemon=True)
        self._writer.start()

    def _start(self, gearbox, result: Result, rate: float) -> None:
        meta = result.metadata
        f = self._file = McapWriter(self._stream, compression_level=self.compression_level)
        versions = _versions()
        f.start(library=f"pinwind {versions['pinwind']} (mcap {versions['mcap']})")

        self._terms = list(result.energy)
        names = {
            "joint_names": list(result.joint_names),
            "mesh_names": list(result.mesh_names),
            "bearing_names": list(result.bearing_names),
            "body_names": list(result.body_names),
            "energy_terms": self._terms,
        }
        array_schema = f.schema(messages.FLOAT64_MULTI_ARRAY)
        joint_schema = f.schema(messages.JOINT_STATE)
        string_schema = f.schema(messages.STRING)
        tf_schema = f.schema(messages.frame_transforms_schema())
        model_channel = f.channel(
            MODEL_TOPIC, "cdr", string_schema, {"content": "model file (URDF with <gearbox>)"}
        )
        self._joint_codec = JointStateCodec(names["joint_names"], WORLD_FRAME)
        self._joint_channel = f.channel(
            JOINTS_TOPIC,
            "cdr",
            joint_schema,
            {
                "names": json.dumps(names["joint_names"]),
                "position": "joint angle [rad], unwrapped (Result.angle)",
                "velocity": "joint speed relative to the parent body [rad/s] (Result.speed)",
                "effort": "applied plus driver or lock torque [N*m] (Result.torque)",
            },
        )
        self._arrays = []
        for topic in ARRAY_TOPICS:
            dims = []
            channel_meta = {
                "field": topic.field,
                "unit": topic.unit,
                "description": topic.description,
            }
            if topic.element:
                element_names = names[_NAMES_OF[topic.element]]
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
            channel = f.channel(topic.topic, "cdr", array_schema, channel_meta)
            self._arrays.append((topic, Float64ArrayCodec(dims), channel))
        self._tf_codec = FrameTransformsCodec(WORLD_FRAME, names["body_names"])
        self._tf_channel = f.channel(
            TF_TOPIC,
            "protobuf",
            tf_schema,
            {"content": f"world pose of every link, parent frame '{WORLD_FRAME}'"},
        )

        source = gearbox.source_text.encode("utf-8")
        f.attachment(
            Path(str(gearbox.path)).name or f"{gearbox.name}.urdf",
            "application/xml",
            source,
            create_time=0,
        )
        f.metadata(
            "pinwind",
            {
                "format": FORMAT,
                "format_version": str(FORMAT_VERSION),
                "pinwind_version": versions["pinwind"],
                "created_utc": _utc_now(),
                "command": self.command,
                "versions": json.dumps(versions),
            },
        )
        run = {k: v for k, v in meta.items() if k not in ("status", "wall_time_s")}
        run.update(log_stride=self.stride, log_rate_hz=rate, sample_rate_hz=1.0 / meta["dt"])
        f.metadata("pinwind.run", _json_record(run))
        f.metadata("pinwind.model", _json_record({**names, **model_geometry(gearbox)}))
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
        into new arrays). Samples already queued are skipped, so a block handed over again after
        an interrupt is not logged twice.

        Raises:
            LogError: writing an earlier chunk failed (disk full, ...): the run stops.
        """
        if self._file is None:
            return
        self._raise_if_failed()
        stop = start + len(block)
        first = max(start, self._queued)
        rows = np.arange(first + (-first % self.stride), stop, self.stride)
        if not len(rows):
            return
        self._queued = int(rows[-1]) + 1
        self._jobs.put((block, rows - start, rows))

    def flush(self) -> None:
        """Wait until every queued chunk is in the file."""
        if self._writer is not None:
            self._jobs.join()
        self._raise_if_failed()

    def _raise_if_failed(self) -> None:
        if self._failed is not None:
            err = self._failed
            raise LogError(str(self.path), f"writing the log failed: {err}") from err

    def _write_chunks(self) -> None:
        """The writer thread: one chunk per queued block, in order, until None."""
        while True:
            job = self._jobs.get()
            try:
                if job is None:
                    return
                if self._failed is None:
                    block, rows, samples = job
                    data, index = self._assemble(block, rows, samples)
                    self._file.chunk(data, index)
                    self._next_sample = int(samples[-1]) + 1
                    self.samples_logged += len(samples)
            except Exception as err:  # disk full, ...: reported to the run by samples()
                self._failed = err
            finally:
                self._jobs.task_done()

    def _stop_writer(self) -> None:
        if self._writer is not None:
            self._jobs.put(None)
            self._writer.join()
            self._writer = None

    def end(self, result: Result, status: str) -> None:
        """Write the end-status record and the summary, close the file."""
        if self._file is None:
            return
        in_flight = sys.exc_info()[1]
        cause = f"{type(in_flight).__name__}: {in_flight}" if in_flight is not None else ""
        try:
            with _interrupts_deferred():
                self._stop_writer()
                self._finish(result, status, cause)
        except Exception as err:
            if in_flight is None and self._failed is None:
                raise LogError(str(self.path), f"finishing the log failed: {err}") from err
            warnings.warn(
                f"{self.path}: finishing the log failed: {err}", LogRecovered, stacklevel=2
            )
        finally:
            self._file = None
            if self._stream is not None:
                self._stream.close()
        if in_flight is None:
            self._raise_if_failed()

    def _finish(self, result: Result, status: str, cause: str) -> None:
        self._file.metadata(
            "pinwind.end",
            _json_record(
                {
                    "status": status,
                    "cause": cause,
                    "samples_simulated": result.metadata.get("samples_simulated", len(result)),
                    "samples_logged": self.samples_logged,
                    "log_error": str(self._failed) if self._failed else "",
                    "wall_time_s": result.metadata.get("wall_time_s"),
                    "ended_utc": _utc_now(),
                }
            ),
        )
        self._file.finish()

    # --- chunks ----------------------------------------------------------------------------

    def _assemble(
        self, result: Result, rows: np.ndarray, samples: np.ndarray
    ) -> tuple[np.ndarray, dict]:
        """Message records of ``rows`` of a block in time order (bytes), and each channel's index.

        ``samples`` are the rows' sample indices in the run (the messages' sequence numbers).

        Each sample is one row: a record per channel, /tf last. /tf payloads grow with the
        stamp's varint length, so rows are laid out run by run of equal /tf length.
        """
        log_time = np.rint(result.time[rows] * 1e9).astype(np.uint64)
        payloads = [
            (
                self._joint_channel,
                self._joint_codec.encode(
                    log_time, result.angle[rows], result.speed[rows], result.torque[rows]
                ),
            )
        ]
        for topic, codec, channel in self._arrays:
            values = _topic_values(result, topic, rows, self._terms)
            payloads.append((channel, codec.encode(values)))
        runs = self._tf_codec.encode_runs(
            log_time, result.body_position[rows], result.body_quaternion[rows]
        )
        width = RECORD_HEADER.itemsize
        columns = np.cumsum([0] + [width + p.shape[1] for _, p in payloads])
        fixed = int(columns[-1])
        row_length = np.empty(len(rows), dtype=np.int64)
        for a, b, tf in runs:
            row_length[a:b] = fixed + width + tf.shape[1]
        row_start = np.concatenate([[0], np.cumsum(row_length)[:-1]])
        data = np.empty(int(row_length.sum()), dtype=np.uint8)
        head = np.empty(len(rows), dtype=RECORD_HEADER)
        head["op"] = Opcode.MESSAGE
        head["sequence"] = samples
        head["log_time"] = log_time
        head["publish_time"] = log_time
        for a, b, tf in runs:
            channels = [*payloads, (self._tf_channel, tf)]
            starts = [*columns[:-1], fixed]
            # One row per sample; each record's header and payload is a field of raw bytes, so
            # filling a field copies a block per row.
            layout = np.dtype(
                {
                    "names": [f"{kind}{i}" for i in range(len(channels)) for kind in "hp"],
                    "formats": [
                        np.dtype(f"V{size}") for _, p in channels for size in (width, p.shape[1])
                    ],
                    "offsets": [int(c) + skip for c in starts for skip in (0, width)],
                    "itemsize": int(row_length[a]),
                }
            )
            block = data[row_start[a] : row_start[a] + (b - a) * row_length[a]].view(layout)
            for i, (channel, payload) in enumerate(channels):
                rows_ab = slice(a, b) if channel != self._tf_channel else slice(None)
                head["length"][a:b] = 22 + payload.shape[1]
                head["channel"][a:b] = channel
                block[f"h{i}"] = head[a:b].view(f"V{width}")
                block[f"p{i}"] = np.ascontiguousarray(payload[rows_ab]).view(
                    f"V{payload.shape[1]}"
                )[:, 0]
        offsets = row_start.astype(np.uint64)
        index = {
            channel: np.stack([log_time, offsets + np.uint64(column)], axis=1)
            for (channel, _), column in zip(payloads, columns[:-1], strict=True)
        }
        index[self._tf_channel] = np.stack([log_time, offsets + np.uint64(fixed)], axis=1)
        return data, index


def model_geometry(gearbox) -> dict[str, Any]:
    """Gears, meshes and bearings of a model, for the ``pinwind.model`` record (and replay).

    Gear centres and axes are in the frame of the link that carries the gear; radii, widths and
    distances in m, angles in rad.
    """
    import pinocchio as pin

    model = gearbox.model
    gears = {}
    for name, gear in gearbox.gears.items():
        spec = gear.spec
        frame = model.frames[model.getFrameId(spec.link, pin.BODY)]
        joint_from_link = frame.placement
        gears[name] = {
            "link": spec.link,
            "teeth": spec.teeth,
            "module": spec.module,
            "face_width": spec.face_width,
            "pressure_angle": spec.pressure_angle,
            "helix_angle": spec.helix_angle,
            "profile_shift": spec.profile_shift,
            "internal": spec.internal,
            "pitch_radius": spec.teeth * spec.module / (2.0 * math.cos(spec.helix_angle)),
            "centre_in_link": joint_from_link.actInv(gear.centre_in_joint).tolist(),
            "axis_in_link": (joint_from_link.rotation.T @ gear.axis_in_joint).tolist(),
        }
    meshes = {
        m.name: {
            "gear_a": m.gear_a.name,
            "gear_b": m.gear_b.name,
            "working_pressure_angle": m.working_pressure_angle,
            "centre_distance": m.centre_distance,
            "working_radius_a": m.working_radius_a,
            "working_radius_b": m.working_radius_b,
        }
        for m in gearbox.meshes
    }
    source_joints = getattr(getattr(gearbox, "source", None), "joints", {}) or {}
    bearings = {
        name: {
            "parent": source_joints.get(name, {}).get("parent", ""),
            "child": source_joints.get(name, {}).get("child", ""),
        }
        for name in gearbox.joint_names
    }
    return {
        "model_name": gearbox.name,
        "root_link": getattr(getattr(gearbox, "source", None), "root_link", ""),
        "locked_joints": list(gearbox.locked_joints),
        "gears": gears,
        "meshes": meshes,
        "bearings": bearings,
    }


# --- reading (pinwind/io/log_reader.py) ---------------------------------------------------------


def __getattr__(name: str):
    """``read_log``, ``open_log`` and ``LogFile`` live in ``log_reader`` (which imports this)."""
    if name in ("LogFile", "open_log", "read_log"):
        from pinwind.io import log_reader

        return getattr(log_reader, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
