"""The FMI 2.0 co-simulation slave of a pinwind gearbox (packed into the FMU by ``fmu_export``).

PythonFMU (``pythonfmu``) runs this class inside the FMU's binary: it needs the Python
environment pinwind is installed in (the master's process imports ``pinwind``; docs/coupling.md).
The FMU's resources hold ``pinwind_fmu.json`` (the model file, the scenario file, the inputs and
outputs with their units) written by ``fmu_export.export_fmu``. Each ``do_step`` is one
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

import json
from pathlib import Path
from typing import Any

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Status

#: The configuration file in the FMU's resources.
CONFIG = "pinwind_fmu.json"


class PinwindGearbox(Fmi2Slave):
    """A gearbox session: inputs held over each communication step, outputs at its end."""

    author = "pinwind"
    description = "pinwind gearbox (multibody drivetrain) as an FMI 2.0 co-simulation unit"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        resources = Path(kwargs.get("resources") or ".")
        self.config = json.loads((resources / CONFIG).read_text())
        self.resources = resources
        self.session: Any = None
        self.stop_time: float | None = None
        self.values: dict[str, float] = {}
        for name, spec in self.config["inputs"].items():
            self.values[name] = float(spec["start"])
            self.register_variable(self._real(name, Fmi2Causality.input, spec))
        for name, spec in self.config["outputs"].items():
            self.values[name] = 0.0
            self.register_variable(self._real(name, Fmi2Causality.output, spec))

    def _real(self, name: str, causality: Fmi2Causality, spec: dict) -> Real:
        def get() -> float:
            return self.values[name]

        def put(value: float) -> None:
            self.values[name] = float(value)

        return Real(
            name,
            causality=causality,
            variability=Fmi2Variability.continuous,
            description=f"{spec['description']} [{spec['unit']}]",
            getter=get,
            setter=put if causality == Fmi2Causality.input else None,
        )

    def setup_experiment(self, start_time: float, stop_time: float | None, tolerance: Any) -> None:
        """Keeps the master's stop time [s]: the session's duration (the FMU's own without)."""
        self.stop_time = stop_time

    def exit_initialization_mode(self):
        """Opens the session: the scenario's run prepared, sample 0 recorded."""
        try:
            from pinwind.runs.fmu_export import open_session

            self.session = open_session(
                self.resources, self.config, self.values, duration=self.stop_time
            )
            self.values.update(self.session.outputs())
        except Exception as err:  # the master gets FMI's error status and this message
            self.log(f"pinwind: {type(err).__name__}: {err}", Fmi2Status.error)
            raise

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advances the session to current_time + step_size with the inputs held."""
        try:
            inputs = {n: self.values[n] for n in self.config["inputs"]}
            self.values.update(self.session.advance(current_time + step_size, inputs))
        except Exception as err:
            # PythonFMU returns fmi2Discard for False (and fmi2Fatal, the unit unusable, for an
            # exception): the step is refused, the message logged with fmi2Error's category, and
            # the session stays where it was, so that the master may go on.
            self.log(f"pinwind: {type(err).__name__}: {err}", Fmi2Status.error)
            return False
        return True

    def _get_fmu_state(self) -> dict[str, Any]:
        """fmi2GetFMUstate: the session's state (a copy of its compiled run's) and the values."""
        saved = self.session.state() if self.session is not None else None
        return {"session": saved, "values": dict(self.values)}

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """fmi2SetFMUstate: the session and the values back where ``_get_fmu_state`` found them.

        A pinwind error (a state beyond the session's log) is PythonFMU's fmi2Fatal, as any
        exception the slave raises (its C++ side turns each into ``pythonfmu::fatal_error``).
        """
        if state["session"] is not None:
            self.session.restore(state["session"])
        self.values = dict(state["values"])

    def terminate(self):
        """Closes the session (and its log)."""
        if self.session is not None:
            self.session.close()
            self.session = None  # the compiled stepper freed with the instance
