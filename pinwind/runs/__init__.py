"""Runs: a simulation with its observers, scenarios, and the commands that run many of them.

The layer above the physics (``dynamics/``), the logs (``io/``), the analysis of a Result
(``analysis/``) and fatigue (``life/``), which it puts together: the run that ``pinwind.simulate``
is (``run``: the log writer and the run statistics as observers), a scenario and its run
(``scenario``), the executor of many runs on local processes or Dask (``executor``,
``dask_workers``), the design sweep (``sweep``), and a fatigue set read from its file
(``fatigue_set_file``), its cases run (``case_runner``) and its load spectra read from the cases'
logs (``set_load_spectra``), and a run held open and stepped from outside (``session``) with
its FMU (``fmu_export``). Nothing below imports it.
"""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.runs.run import simulate
    from pinwind.runs.scenario import Scenario, ScenarioError, load_scenario
    from pinwind.runs.session import Session
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = ["Scenario", "ScenarioError", "Session", "load_scenario", "simulate"]
