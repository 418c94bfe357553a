"""How a run is stepped and what it keeps, apart from the machine it steps.

The machine (bodies, added inertias, elements, drivers, loads) is a ``Drivetrain``
(``dynamics/drivetrain.py``); ``RunSettings`` holds the rest of what a run needs: the solver and
the integrator, the start, which samples the Result keeps, how many samples go to the observers
at a time and whether a progress bar shows. ``pinwind.simulate`` builds one from its keywords;
a study that runs many cases (sweeps, fatigue sets) can build one and hand it to each.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.solver import SolverSettings
from pinwind.errors import InputError

#: The starts a run can take (``RunSettings.initial_deflection``).
INITIAL_DEFLECTIONS = {
    "static": "compliant meshes and springs deflected under the loads of t = 0",
    "none": "compliant meshes and springs undeflected, at the model's pose",
}

#: The named choices of ``RunSettings.keep`` (an integer N keeps every N-th sample).
KEEP_CHOICES = ("auto", "all", "last")


@dataclass(frozen=True)
class RunSettings:
    """The settings of one run (``pinwind.simulate``'s keywords of the same names).

    Attributes:
        solver: the QP's settings (``SolverSettings``).
        integrator: the time step and its numerical dissipation (``Integrator``; default
            generalized-α with ρ∞ = 1, the trapezoidal rule).
        keep: which samples the returned Result holds: ``"all"``, an integer N (every N-th
            sample from 0, and the last), ``"last"``, or ``"auto"`` (every sample while they
            fit in ``simulate.KEEP_BUDGET`` bytes, else every N-th with N the smallest that
            fits). The run itself streams every sample to its observers block by block.
        keep_series: the series the returned Result holds (names, ``docs/series.md``), or
            None: every series. The log and the other observers get every series whatever
            this says; a run that reduces a few series (a fatigue case) need not copy the
            others. The link poses are kept only when named (``body_position``).
        chunk: samples per observer call (a log holds a chunk of columns per call); None:
            ``simulate.block_samples`` (1000 to 5000, a twentieth of the run), and blocks of
            about ``simulate.UNWATCHED_BLOCK_S`` after the first when no observer reads them
            and the Result keeps their rows (the Python around each block then costs less).
        progress: show a progress bar; None: for runs over 20 000 steps on a terminal.
        initial_deflection: ``"static"``: the compliant meshes and springs start deflected
            under the loads of t = 0; ``"none"``: undeflected, at the model's pose
            (``INITIAL_DEFLECTIONS``).

    Raises:
        InputError: a setting of the wrong kind or out of its range, named with its value.
    """

    solver: SolverSettings = field(default_factory=SolverSettings)
    integrator: Integrator = field(default_factory=Integrator)
    keep: str | int = "auto"
    keep_series: tuple[str, ...] | None = None
    chunk: int | None = None
    progress: bool | None = None
    initial_deflection: str = "static"

    def __post_init__(self) -> None:
        if not isinstance(self.solver, SolverSettings):
            raise InputError(
                f"solver={self.solver!r}: give a pinwind.dynamics.SolverSettings, "
                "e.g. SolverSettings(eps_abs=1e-12)"
            )
        if not isinstance(self.integrator, Integrator):
            raise InputError(
                f"integrator={self.integrator!r}: give a pinwind.dynamics.Integrator, "
                "e.g. Integrator(rho_infinity=1.0)"
            )
        if self.initial_deflection not in INITIAL_DEFLECTIONS:
            raise InputError(
                f"initial_deflection={self.initial_deflection!r}: give one of "
                + ", ".join(repr(k) for k in INITIAL_DEFLECTIONS)
            )
        keep = self.keep
        if keep not in KEEP_CHOICES and (
            isinstance(keep, bool) or not isinstance(keep, int) or keep < 1
        ):
            raise InputError(
                f'keep is {keep!r}; give "all", "auto", "last" or a whole number N ≥ 1 '
                "(every N-th sample)"
            )
        if self.keep_series is not None:
            names = self.keep_series
            if isinstance(names, str) or not all(isinstance(n, str) for n in names):
                raise InputError(
                    f"keep_series={names!r}: give the names of the series to keep, e.g. "
                    '("mesh_normal", "speed")'
                )
            object.__setattr__(self, "keep_series", tuple(names))
        chunk = self.chunk
        if chunk is not None and (
            isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1
        ):
            raise InputError(
                f"chunk={chunk!r}: give a whole number of samples per block, at least 1"
            )
        if self.progress is not None and not isinstance(self.progress, bool):
            raise InputError(f"progress={self.progress!r}: give True, False or None (automatic)")
