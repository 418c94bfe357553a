"""``pinwind.simulate`` with a log: run a gearbox and write the run to an MCAP file as it goes.

This thin layer builds the ``McapLogger`` (``io/log_writer.py``) and hands it to
``pinwind.dynamics.simulate.simulate`` as its observer, so the physics stays unaware of files.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pinwind.analysis.run_statistics import StatisticsObserver
from pinwind.dynamics.result import Result
from pinwind.dynamics.simulate import observers_of
from pinwind.dynamics.simulate import simulate as _simulate
from pinwind.io.log_size import MAX_LOG_BYTES
from pinwind.io.log_writer import POSE_RATE, VIEW_RATE, McapLogger
from pinwind.model.gearbox import Gearbox

#: Folder of logs given without one (``log=True`` or a bare file name).
DEFAULT_LOG_FOLDER = Path("logs")


def log_path(log: str | os.PathLike | bool, model_name: str) -> Path:
    """Where a log goes.

    ``True`` gives a new ``logs/<model>_<UTC time to the ms>.mcap`` (with ``_2``, ``_3``, ... if
    that name is taken); a bare file name goes in ``logs/``; a path with a folder is used as given.
    """
    if log is True:
        now = datetime.now(UTC)
        stem = f"{model_name}_{now:%Y%m%dT%H%M%S}.{now.microsecond // 1000:03d}Z"
        path = DEFAULT_LOG_FOLDER / f"{stem}.mcap"
        count = 1
        while path.exists():
            count += 1
            path = DEFAULT_LOG_FOLDER / f"{stem}_{count}.mcap"
        return path
    if log is False:
        raise TypeError("log_path needs a path or True, not False (False means no log)")
    path = Path(log)
    if path.parent == Path("."):
        return DEFAULT_LOG_FOLDER / path
    return path


def describe_call(gearbox: Gearbox, kwargs: Mapping[str, Any]) -> str:
    """The call as text, for the log's metadata (callables by their description or name)."""

    def show(value: Any) -> str:
        if callable(value):
            name = getattr(value, "description", None) or getattr(value, "__name__", repr(value))
            return str(name)
        if isinstance(value, Mapping):
            return "{" + ", ".join(f"{k!r}: {show(v)}" for k, v in value.items()) + "}"
        return repr(value)

    args = ", ".join(f"{key}={show(value)}" for key, value in kwargs.items())
    return f"pinwind.simulate(pinwind.load({str(gearbox.path)!r}), {args})"


def simulate(
    gearbox: Gearbox,
    *,
    log: str | os.PathLike | bool | None = None,
    log_rate: float | None = None,
    pose_rate: float | None = POSE_RATE,
    view_rate: float | None = VIEW_RATE,
    overwrite: bool = False,
    command: str | None = None,
    allow_large_log: bool = False,
    **kwargs: Any,
) -> Result:
    """Simulate a gearbox (``pinwind.dynamics.simulate.simulate``) and log it to an MCAP file.

    Args:
        gearbox: the model (``pinwind.load``).
        log: MCAP file to write: a path, a bare file name (written in ``logs/``), ``True`` for
            ``logs/<model>_<UTC time>.mcap``, or ``None`` for no log.
        log_rate: logged samples per simulated second [Hz]; default every sample. Every array
            is in the log at this rate (``/pinwind/columns``, what ``read_log`` reads).
        view_rate: samples per simulated second on the ROS 2 topics that Rerun and Foxglove
            plot when they open the log [Hz], a display rate (default 100 Hz); None for every
            logged sample.
        pose_rate: link poses per simulated second [Hz], for display (default 100 Hz, at most
            the view rate); None for a pose with every viewed sample.
        overwrite: replace an existing log file; otherwise ``LogExists`` is raised before the run.
        command: the command line to record in the log (default: this call, as text).
        allow_large_log: write the log even when its estimated size is above ``MAX_LOG_BYTES``
            (20 GB) or the free disk space.
        **kwargs: ``duration``, ``dt``, ``torques``, ``speeds``, ... as for
            ``pinwind.dynamics.simulate.simulate``, and these two for the statistics:

            - ``statistics``: fold every simulated sample into ``result.statistics``: min, max,
              mean, RMS and final value of every series (``analysis/run_statistics``), on a
              thread of its own while the loop steps. Default: when the Result does not keep
              every sample (``keep``), so that the peaks between kept samples count. With
              ``keep="last"`` the Result holds the last sample and these statistics only.
            - ``skip_start``: leave the samples before this time [s] out of
              ``result.statistics`` (a start-up span: a compliant run starts undeflected, and
              its start-up impact would set the maxima); the statistics are then folded
              whatever ``keep``, and ``metadata["statistics_from_s"]`` records it for the
              summary and the load sharing.

    Returns:
        The Result; ``result.metadata["log_path"]`` names the log when one was written.

    Raises:
        LogExists: the log file exists and ``overwrite`` is false.
        LogTooLargeToWrite: the log would be larger than 20 GB or the free disk space (before
            the run starts; the message gives the sizes and the fixes).
        LogWriteFailed: writing the log failed during the run (disk full, file deleted): the
            run stops; the file keeps the samples of its complete chunks.
        InputError, SolverFailed, Diverged: as for the simulation; the log is still complete up
            to the failure, with an end-status record saying why the run stopped.
    """
    # the statistics last: the observers' ends run in order (a log is closed first)
    observers = [*observers_of(kwargs.pop("observer", None))]
    skip_start = kwargs.pop("skip_start", 0.0)
    observers.append(StatisticsObserver(kwargs.pop("statistics", None), skip_start=skip_start))
    if log is None or log is False:
        return _simulate(gearbox, observer=observers, **kwargs)
    path = log_path(log, gearbox.name)
    logger = McapLogger(
        path,
        log_rate=log_rate,
        pose_rate=pose_rate,
        view_rate=view_rate,
        overwrite=overwrite,
        max_bytes=None if allow_large_log else MAX_LOG_BYTES,
        command=command
        or describe_call(
            gearbox,
            {
                **kwargs,
                "log": str(path),
                "log_rate": log_rate,
                "pose_rate": pose_rate,
                "view_rate": view_rate,
            },
        ),
    )
    result = _simulate(gearbox, observer=[logger, *observers], **kwargs)
    result.metadata["log_path"] = str(path)
    return result
