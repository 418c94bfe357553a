"""Analysis of results: statistics, summaries and planet load sharing."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.analysis.load_sharing import LoadSharing, load_sharing
    from pinwind.analysis.run_statistics import RunningStatistics
    from pinwind.analysis.summary import statistics, summary_tables
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = ["LoadSharing", "RunningStatistics", "load_sharing", "statistics", "summary_tables"]
