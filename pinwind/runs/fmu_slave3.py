"""The FMI 3.0 co-simulation slave of a pinwind gearbox (packed into the FMU by ``fmu_export``).

PythonFMU3 (``pythonfmu3`` 0.3) runs this class inside the FMU's binary, which embeds the Python
interpreter of the process that loads it: that environment must have pinwind installed
(docs/coupling.md). The variables and the session are ``fmu_unit.GearboxUnit``'s, the same as
the FMI 2.0 slave's (``fmu_slave``); this class only maps PythonFMU3's calls onto it. FMI 3.0
adds ``time``, the independent variable [s] (FMI 3.0 §2.4.7: every unit declares one), and
the units go into ``UnitDefinitions`` through PythonFMU3 itself.

Statuses (PythonFMU3 0.3.4, ``PySlaveInstance.cpp`` and ``fmi_functions.cpp``): do_step's
False is fmi3Discard (lastSuccessfulTime = the step's start); a returned ``Fmi3StepResult``
gives its own status (fmi3Error among them); a Python exception is fmi3Fatal (its
``handle_py_exception`` throws ``cppfmu::FatalError``). A pinwind error in a step returns
False: the step is refused, the session stays at the last communication point and the unit
goes on (fmi3Error would tell the master the unit's state is unusable, which it is not); the
message goes to the FMU's log with category logStatusError.
fmi3EnterInitializationMode of PythonFMU3 0.3.4 passes neither start nor stop time to Python:
the session's duration is the FMU's own (``--duration`` of a model file, the scenario's),
declared as the DefaultExperiment's stopTime. fmi3GetFMUState/SetFMUState
(``canGetAndSetFMUState``) save and restore the session's state (``Session.state``, a copy of
the compiled run's); it does not serialize (``canSerializeFMUState`` false).
"""

from __future__ import annotations

from typing import Any

from pythonfmu3 import Float64, Fmi3Causality, Fmi3Slave, Fmi3Status, Fmi3Variability
from pythonfmu3.default_experiment import DefaultExperiment
from pythonfmu3.unit import Unit

from pinwind.runs.fmu_unit import GearboxUnit, Variable


class PinwindGearbox(Fmi3Slave):
    """A gearbox session: inputs held over each communication step, outputs at its end."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.author = "pinwind"
        self.description = "pinwind gearbox (multibody drivetrain) as an FMI 3.0 co-simulation unit"
        self.unit = GearboxUnit(kwargs.get("resources"))
        self.default_experiment = DefaultExperiment(start_time=0.0, stop_time=self.unit.duration)
        self.register_units([Unit(name, **base) for name, base in self.unit.units().items()])
        if "s" not in self.units:
            self.register_units([Unit("s", s=1)])
        self.register_variable(
            Float64(
                "time",
                causality=Fmi3Causality.independent,
                variability=Fmi3Variability.continuous,
                unit="s",
                description="time: the last communication point [s]",
                getter=lambda: self.unit.time,
            )
        )
        for variable in self.unit.variables():
            self.register_variable(self._float(variable))

    def _float(self, variable: Variable) -> Float64:
        name = variable.name

        def get() -> float:
            return self.unit.get(name)

        def put(value: float) -> None:
            self.unit.set(name, value)

        return Float64(
            name,
            causality=Fmi3Causality.input if variable.is_input else Fmi3Causality.output,
            variability=Fmi3Variability.continuous,
            description=variable.description,
            unit=variable.unit,
            getter=get,
            setter=put if variable.is_input else None,
        )

    def exit_initialization_mode(self):
        """Opens the session: the scenario's run prepared, sample 0 recorded."""
        try:
            self.unit.open(None)
        except Exception as err:  # fmi3Fatal for the master, with this message in the log
            self.log(f"pinwind: {type(err).__name__}: {err}", Fmi3Status.error)
            raise

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advances the session to current_time + step_size with the inputs held."""
        message = self.unit.step(current_time, step_size)
        if message is not None:  # fmi3Discard: refused, the session where it was
            self.log(message, Fmi3Status.error)
            return False
        return True

    def _get_fmu_state(self) -> dict[str, Any]:
        """fmi3GetFMUState: the session's state (a copy of its compiled run's) and the values."""
        return self.unit.save()

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """fmi3SetFMUState: the session and the values back where ``_get_fmu_state`` found them.

        A pinwind error (a state beyond the session's log) is fmi3Fatal.
        """
        self.unit.load(state)

    def terminate(self):
        """Closes the session (and its log)."""
        self.unit.close()
