"""Logs of runs: MCAP writer and reader, Rerun replay and reports."""

from pinwind.io.mcap_log import LogFile, McapLogger, open_log, read_log

__all__ = ["LogFile", "McapLogger", "open_log", "read_log"]
