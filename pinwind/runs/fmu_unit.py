"""What both gearbox FMUs do (FMI 2.0 and FMI 3.0): the variables and the session behind them.

``GearboxUnit`` holds one ``Session`` (``runs/session.py``) and the values of the unit's
variables; the FMI 2.0 slave (``fmu_slave``, PythonFMU) and the FMI 3.0 slave (``fmu_slave3``,
PythonFMU3) only translate their exporter's calls into its methods. The variables, their SI
units (``FMI_UNITS``: the unit names and base-unit exponents of FMI 2.0 §2.2.2 and FMI 3.0
§2.4.3, the same in both), their causality and their start values are declared here once,
from ``pinwind_fmu.json`` in the FMU's resources (written by ``fmu_export.export_fmu``).
This module does not import an exporter: the FMU's binary imports it from the pinwind
installed in the master's Python environment.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pinwind.runs.session import Session

#: The configuration file in the FMU's resources.
CONFIG = "pinwind_fmu.json"

#: FMI unit names of the series' units, with their SI base-unit exponents (FMI 2.0 §2.2.2,
#: FMI 3.0 §2.4.3: ``<Unit name><BaseUnit kg m s rad/></Unit>``).
FMI_UNITS: dict[str, tuple[str, dict[str, int]]] = {
    "N*m": ("N.m", {"kg": 1, "m": 2, "s": -2}),
    "N": ("N", {"kg": 1, "m": 1, "s": -2}),
    "rad": ("rad", {"rad": 1}),
    "rad/s": ("rad/s", {"rad": 1, "s": -1}),
    "rad/s^2": ("rad/s2", {"rad": 1, "s": -2}),
    "m": ("m", {"m": 1}),
    "m/s": ("m/s", {"m": 1, "s": -1}),
    "W": ("W", {"kg": 1, "m": 2, "s": -3}),
    "s": ("s", {"s": 1}),
    "1": ("1", {}),
}


@dataclass(frozen=True)
class Variable:
    """One variable of the unit: name, causality ("input" or "output"), unit, start, text.

    ``unit`` is the FMI unit name (``FMI_UNITS``), None for a unit the table lacks (the
    variable is then declared without one); ``description`` ends with pinwind's unit.
    """

    name: str
    causality: str
    unit: str | None
    start: float
    description: str

    @property
    def is_input(self) -> bool:
        """Whether the master sets it (causality input)."""
        return self.causality == "input"


def fmi_unit(unit: str) -> tuple[str, dict[str, int]] | None:
    """The FMI unit name and SI base-unit exponents of a pinwind unit (None if not tabled)."""
    return FMI_UNITS.get(unit)


def load_model(model: str | Path, scenario: str | Path | None, *, dt: float, duration: float):
    """The gearbox of ``model`` and its scenario.

    The scenario is ``scenario``'s (its model replaced by ``model``), else one of ``dt`` [s]
    and ``duration`` [s] with no loads.
    """
    from pinwind.model.gearbox import load
    from pinwind.runs.scenario import Scenario, load_scenario

    gearbox = load(model)
    if scenario is None:
        return gearbox, Scenario(dt=dt, duration=duration)
    scen = load_scenario(scenario, changes={"model": str(Path(model).resolve())})
    return gearbox, scen


def open_session(resources: Path, config: Mapping[str, Any], values: Mapping[str, float],
                 duration: float | None = None) -> Session:  # fmt: skip
    """The session of an FMU, from its resources and configuration (``pinwind_fmu.json``)."""
    model = resources / config["model"]
    scenario = resources / config["scenario"] if config["scenario"] else None
    gearbox, scen = load_model(model, scenario, dt=config["dt"],
                               duration=duration or config["duration"])  # fmt: skip
    if duration is not None:
        import dataclasses

        scen = dataclasses.replace(scen, duration=duration)
    return Session(gearbox, scen, inputs=list(config["inputs"]),
                   start={n: values[n] for n in config["inputs"]},
                   outputs=list(config["outputs"]))  # fmt: skip


class GearboxUnit:
    """A gearbox session behind an FMU: inputs held over a communication step, outputs at its end.

    Values in SI. The session opens at the end of initialization, when the inputs' start
    values are known; ``step`` advances it, ``save``/``load`` copy its state.
    """

    def __init__(self, resources: str | Path | None) -> None:
        self.resources = Path(resources or ".")
        self.config: dict[str, Any] = json.loads((self.resources / CONFIG).read_text())
        self.session: Any = None
        self.values: dict[str, float] = {}
        for variable in self.variables():
            self.values[variable.name] = variable.start

    def variables(self) -> Iterator[Variable]:
        """The unit's variables: the inputs, then the outputs, in the configuration's order."""
        for causality in ("input", "output"):
            for name, spec in self.config[f"{causality}s"].items():
                tabled = fmi_unit(spec["unit"])
                yield Variable(
                    name=name,
                    causality=causality,
                    unit=tabled[0] if tabled is not None else None,
                    start=float(spec.get("start", 0.0)),
                    description=f"{spec['description']} [{spec['unit']}]",
                )

    def units(self) -> dict[str, dict[str, int]]:
        """The FMI units the variables use: name → SI base-unit exponents."""
        used: dict[str, dict[str, int]] = {}
        for spec in [*self.config["inputs"].values(), *self.config["outputs"].values()]:
            tabled = fmi_unit(spec["unit"])
            if tabled is not None:
                used[tabled[0]] = dict(tabled[1])
        return used

    @property
    def duration(self) -> float:
        """The FMU's own longest run [s] (the model file's --duration, or the scenario's)."""
        return float(self.config["duration"])

    @property
    def dt(self) -> float:
        """The session's internal step [s]: a communication step is a whole number of them."""
        return float(self.config["dt"])

    @property
    def time(self) -> float:
        """The last communication point [s] (0 before the session opens)."""
        return self.session.time if self.session is not None else 0.0

    def get(self, name: str) -> float:
        """A variable's value (SI): an input as last set, an output at the last point."""
        return self.values[name]

    def set(self, name: str, value: float) -> None:
        """Sets an input (SI); it is held over the next communication step."""
        self.values[name] = float(value)

    def open(self, stop_time: float | None) -> None:
        """Opens the session: the scenario's run prepared, sample 0 recorded.

        The inputs' values are its start; ``stop_time`` [s], when the master gives one, is its
        duration (else the FMU's own). Raises whatever the session raises (a
        ``PinwindError`` for a bad start value).
        """
        self.session = open_session(self.resources, self.config, self.values, duration=stop_time)
        self.values.update(self.session.outputs())

    def step(self, current_time: float, step_size: float) -> str | None:
        """Advances the session to current_time + step_size [s] with the inputs held.

        Returns None, or the error's message when the session refuses the step (a
        non-finite input, a step off the dt grid or beyond the duration): the session and
        the outputs then stay at the last communication point, and the unit goes on.
        """
        try:
            inputs = {n: self.values[n] for n in self.config["inputs"]}
            self.values.update(self.session.advance(current_time + step_size, inputs))
        except Exception as err:
            return f"pinwind: {type(err).__name__}: {err}"
        return None

    def save(self) -> dict[str, Any]:
        """The session's state (``Session.state``: a copy of its compiled run's) and values."""
        saved = self.session.state() if self.session is not None else None
        return {"session": saved, "values": dict(self.values)}

    def load(self, state: dict[str, Any]) -> None:
        """The session and the values back where ``save`` found them.

        Raises a ``PinwindError`` for a state beyond the session's log.
        """
        if state["session"] is not None:
            self.session.restore(state["session"])
        self.values = dict(state["values"])

    def close(self) -> None:
        """Closes the session (and its log); the compiled stepper is freed with it."""
        if self.session is not None:
            self.session.close()
            self.session = None
