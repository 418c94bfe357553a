"""Logs of runs: MCAP writer and reader, Rerun replay, reports and exports."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.io.export import export_log
    from pinwind.io.log_channels import CHANNELS, UnknownChannel
    from pinwind.io.log_reader import (
        LogDamaged,
        LogFile,
        LogReader,
        LogTooLarge,
        iter_log,
        open_log,
        read_log,
    )
    from pinwind.io.log_writer import McapLogger
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "CHANNELS",
    "LogDamaged",
    "LogFile",
    "LogReader",
    "LogTooLarge",
    "McapLogger",
    "UnknownChannel",
    "export_log",
    "iter_log",
    "open_log",
    "read_log",
]
