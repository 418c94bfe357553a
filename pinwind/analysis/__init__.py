"""Analysis of results: statistics and summaries."""

from pinwind.analysis.summary import statistics, summary_tables

__all__ = ["statistics", "summary_tables"]
