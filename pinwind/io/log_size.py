"""How large a run's log will be, and whether it fits: the estimate made before a run starts.

``McapLogger`` (``io/log_writer.py``) checks the estimate against a limit (``MAX_LOG_BYTES``, or
``max_bytes``) and the free space of the log's disk before it writes anything, and refuses a log
that would not fit with a log rate that would (``LogTooLargeToWrite``).
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.errors import LogTooLargeToWrite
from pinwind.io.log_format import NAMES_OF, array_topics

#: Largest log a run writes without ``allow_large_log`` (``--allow-large-log``) [bytes].
MAX_LOG_BYTES = 20e9

#: What a log takes per value, record and file, measured on the Saleh, Cai and CART models
#: (docs/log_format.md, "Size and cost"): the values compress to 0.2-0.35 of their 8 bytes, so
#: counting half of them keeps the estimate on the high side; a record's header and CDR layout
#: compress to a few bytes, and each has a 16-byte message-index entry (not compressed); a file
#: has schemas, metadata and the summary, and the model text twice.
_VALUE_FRACTION = 0.5
_RECORD_BYTES = 6
_FILE_BYTES = 24_000


@dataclass(frozen=True)
class LogEstimate:
    """How large a log will be (an estimate on the high side).

    Attributes:
        samples: samples logged.
        posed: samples with link poses (/tf).
        bytes: size of the file [bytes].
        per_sample: bytes per logged sample, poses included.
    """

    samples: int
    posed: int
    bytes: int
    per_sample: float


def estimate_log_size(
    result: Result,
    *,
    samples: int,
    stride: int,
    pose_stride: int,
    view_stride: int | None = None,
    model_bytes: int = 0,
) -> LogEstimate:
    """Size of the log of a run of ``samples`` samples, estimated on the high side [bytes].

    Every ``stride``-th sample is logged (``/pinwind/columns``), every ``view_stride``-th also on
    the viewers' topics (default: every logged one), with its link poses every
    ``pose_stride``-th; ``result`` gives the shapes (names) of the arrays, ``model_bytes`` the
    length of the model file (stored twice). Every float64 counts ``_VALUE_FRACTION`` of its 8
    bytes, every viewers' record its message-index entry (16 bytes, uncompressed) and
    ``_RECORD_BYTES`` of compressed framing.
    """
    view_stride = stride if view_stride is None else view_stride
    doubles = len(result.energy)
    records = 1  # /joints
    for name in result.ARRAYS:  # the run's own schema
        if name in POSE_ARRAYS:
            continue
        doubles += int(np.prod(getattr(result, name).shape[1:], dtype=int))
    for topic in array_topics():
        names = getattr(result, NAMES_OF[topic.element], None) if topic.element else None
        if topic.element in ("", "term") or names:  # topics of an empty family are left out
            records += 1
    logged = -(-samples // stride)
    viewed = -(-samples // view_stride)
    posed = -(-samples // pose_stride)
    bodies = len(result.body_names)
    per_sample = 8 * _VALUE_FRACTION * doubles
    per_view = 8 * _VALUE_FRACTION * doubles + records * (16 + _RECORD_BYTES)
    # /tf for the viewers, and the same poses with their time on /pinwind/poses
    per_pose = 8 * _VALUE_FRACTION * (15 * bodies + 1) + 16 + _RECORD_BYTES * (1 + bodies)
    total = logged * per_sample + viewed * per_view + posed * per_pose
    total += _FILE_BYTES + 2 * model_bytes
    return LogEstimate(
        samples=logged,
        posed=posed,
        bytes=int(total),
        per_sample=(total - _FILE_BYTES - 2 * model_bytes) / max(logged, 1),
    )


def result_bytes(result: Result) -> int:
    """Memory of a Result's arrays [bytes]."""
    return sum(getattr(result, name).nbytes for name in result.ARRAYS) + sum(
        values.nbytes for values in result.energy.values()
    )


def _free_space(folder: Path) -> int | None:
    """Free bytes on the file system that holds ``folder`` (or its nearest existing parent)."""
    folder = folder.absolute()
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    try:
        return shutil.disk_usage(folder).free
    except OSError:
        return None


def _fitting_rate(estimate: LogEstimate, limit: float, rate: float) -> float:
    """A log rate [Hz] whose log fits in 90 % of ``limit``, from the estimate at ``rate`` [Hz].

    Two significant digits, rounded down.
    """
    fixed = estimate.bytes - estimate.samples * estimate.per_sample
    wanted = 0.9 * rate * (limit - fixed) / max(estimate.bytes - fixed, 1)
    if wanted <= 0:
        return 0.0
    digits = 10.0 ** (math.floor(math.log10(wanted)) - 1)
    return math.floor(wanted / digits) * digits


def check_log_fits(
    path: Path, estimate: LogEstimate, result: Result, *, rate: float, max_bytes: float
) -> None:
    """Refuse a log larger than ``max_bytes`` or the free space of its file system.

    ``estimate``: the log's size at log rate ``rate`` [Hz]; ``path``: the file to write.

    Raises:
        LogTooLargeToWrite: it is larger, with a log rate whose log would fit.
    """
    free = _free_space(path.parent)
    limits = [(float(max_bytes), "the limit for one log")]
    if free is not None:
        limits.append((float(free), "the free space on its disk"))
    limit, what = min(limits)
    if estimate.bytes <= limit:
        return
    raise LogTooLargeToWrite(
        str(path),
        log_bytes=estimate.bytes,
        limit_bytes=limit,
        limit=what,
        result_bytes=result_bytes(result),
        samples=estimate.samples,
        fitting_rate=_fitting_rate(estimate, limit, rate),
    )
