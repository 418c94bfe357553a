"""Analysis of results: statistics, summaries and planet load sharing."""

from pinwind.analysis.load_sharing import LoadSharing, load_sharing
from pinwind.analysis.run_statistics import RunningStatistics
from pinwind.analysis.summary import statistics, summary_tables

__all__ = ["LoadSharing", "RunningStatistics", "load_sharing", "statistics", "summary_tables"]
