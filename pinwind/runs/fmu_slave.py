"""The FMI 2.0 co-simulation slave of a pinwind gearbox (packed into the FMU by ``fmu_export``).

PythonFMU (``pythonfmu``) runs this class inside the FMU's binary: it needs the Python
environment pinwind is installed in (the master's process imports ``pinwind``; docs/coupling.md).
The variables and the session are ``fmu_unit.GearboxUnit``'s (shared with the FMI 3.0 slave,
``fmu_slave3``); this class only maps PythonFMU's calls onto it. Each ``do_step`` is one
``Session.advance``; a pinwind error refuses the step (fmi2Discard: PythonFMU's do_step returns
a bool) with its message in the FMU's log (category logStatusError), and the unit goes on.
fmi2Error cannot be returned from a Python slave: PythonFMU (0.7, ``fmi2.cpp``) maps do_step's
False to fmi2Discard and any Python exception to fmi2Fatal (``handle_py_exception`` throws
``pythonfmu::fatal_error``); fmi2Error is left to C++ exceptions of its own.
fmi2GetFMUstate/SetFMUstate (``canGetAndSetFMUstate``) save and restore the session's state
(``Session.state``: a copy of the compiled run's, the same cost at any time); the state does
not serialize (``canSerializeFMUstate`` stays false).
"""

from __future__ import annotations

from typing import Any

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Status

from pinwind.runs.fmu_unit import GearboxUnit, Variable


class PinwindGearbox(Fmi2Slave):
    """A gearbox session: inputs held over each communication step, outputs at its end."""

    author = "pinwind"
    description = "pinwind gearbox (multibody drivetrain) as an FMI 2.0 co-simulation unit"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.unit = GearboxUnit(kwargs.get("resources"))
        self.stop_time: float | None = None
        for variable in self.unit.variables():
            self.register_variable(self._real(variable))

    def _real(self, variable: Variable) -> Real:
        name = variable.name

        def get() -> float:
            return self.unit.get(name)

        def put(value: float) -> None:
            self.unit.set(name, value)

        return Real(
            name,
            causality=Fmi2Causality.input if variable.is_input else Fmi2Causality.output,
            variability=Fmi2Variability.continuous,
            description=variable.description,
            getter=get,
            setter=put if variable.is_input else None,
        )

    def setup_experiment(self, start_time: float, stop_time: float | None, tolerance: Any) -> None:
        """Keeps the master's stop time [s]: the session's duration (the FMU's own without)."""
        self.stop_time = stop_time

    def exit_initialization_mode(self):
        """Opens the session: the scenario's run prepared, sample 0 recorded."""
        try:
            self.unit.open(self.stop_time)
        except Exception as err:  # the master gets FMI's error status and this message
            self.log(f"pinwind: {type(err).__name__}: {err}", Fmi2Status.error)
            raise

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advances the session to current_time + step_size with the inputs held."""
        message = self.unit.step(current_time, step_size)
        if message is not None:
            # PythonFMU returns fmi2Discard for False (and fmi2Fatal, the unit unusable, for an
            # exception): the step is refused, the message logged with fmi2Error's category, and
            # the session stays where it was, so that the master may go on.
            self.log(message, Fmi2Status.error)
            return False
        return True

    def _get_fmu_state(self) -> dict[str, Any]:
        """fmi2GetFMUstate: the session's state (a copy of its compiled run's) and the values."""
        return self.unit.save()

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """fmi2SetFMUstate: the session and the values back where ``_get_fmu_state`` found them.

        A pinwind error (a state beyond the session's log) is PythonFMU's fmi2Fatal, as any
        exception the slave raises (its C++ side turns each into ``pythonfmu::fatal_error``).
        """
        self.unit.load(state)

    def terminate(self):
        """Closes the session (and its log)."""
        self.unit.close()
