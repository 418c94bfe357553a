"""Load inputs: time signals, generator laws, rotor aerodynamics, wind (docs/loads.md)."""

from typing import TYPE_CHECKING

from pinwind.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from pinwind.loads.generator import ConstantTorque, InductionMachine, LinearSlip, VariableSpeed
    from pinwind.loads.openfast import read_channel
    from pinwind.loads.rotor import CpTable, HeierCp, Rotor
    from pinwind.loads.signal_text import parse_signal
    from pinwind.loads.signals import (
        Constant,
        Ramp,
        Scaled,
        Signal,
        Sine,
        Step,
        Sum,
        Table,
        read_csv,
    )
    from pinwind.loads.wind import KaimalWind, kaimal_series
else:
    __getattr__, __dir__ = lazy_exports(__name__)

__all__ = [
    "Constant",
    "ConstantTorque",
    "CpTable",
    "HeierCp",
    "InductionMachine",
    "KaimalWind",
    "LinearSlip",
    "Ramp",
    "Rotor",
    "Scaled",
    "Signal",
    "Sine",
    "Step",
    "Sum",
    "Table",
    "VariableSpeed",
    "kaimal_series",
    "parse_signal",
    "read_channel",
    "read_csv",
]
