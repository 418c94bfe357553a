"""Checks of a gearbox model with ``pinwind.testing``: copy this file next to your model.

Each test runs one check of docs/testing.md on the model ``MODEL`` (here Saleh 2017's planetary
stage, shipped in ``models/``) and fails with ``CheckFailed``, naming the measured value, the
tolerance and where, when the model or pinwind is wrong:

- the energy ledger of a run closes (nothing is created or lost but by the forces);
- the bearings on the ground hold the whole gearbox's weight and torques (free-body balance);
- every joint turns at its tooth ratio times the input's speed;
- each element's tangent equals finite differences of its force, and its force at rest is the
  gradient of its stored energy (the meshes made compliant with a constant stiffness);
- the lowest natural modes ring at their frequencies in a free vibration.

Run it with pytest (``pytest examples/test_my_gearbox.py``) or as a script:

    python examples/test_my_gearbox.py -q
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import pytest

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.model.compliance import MeshCompliance
from pinwind.testing import (
    conservative_forces,
    element_tangents,
    free_body_balance,
    ledger_closure,
    modes_in_spectrum,
    speed_ratios,
)

#: Your model, its input joint, and the load of a run at its rated point.
MODEL = Path(__file__).resolve().parent.parent / "models" / "saleh2017_planetary.urdf"
INPUT = "carrier"
RATED_TORQUE = 1e6  # N·m on the carrier (Saleh 2017: 1 MN·m at 14.2 rpm)
OUTPUT_SPEED = 85.2 * 2 * math.pi / 60  # rad/s of the sun, held by a speed driver
#: Compliant meshes of a constant stiffness (ISO's mean c_γα b): linear, so that their
#: tangents and modes are exact and the free vibration rings at the linearised frequencies.
COMPLIANT = {"all": MeshCompliance(variation="constant", damping=0.0)}


@pytest.fixture(scope="module")
def gearbox() -> pinwind.Gearbox:
    return pinwind.load(MODEL)


@pytest.fixture(scope="module")
def rated_run(gearbox: pinwind.Gearbox) -> pinwind.Result:
    """0.05 s at the rated point, started in equilibrium (the static start)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(
            gearbox, duration=0.05, dt=1e-4, torques={INPUT: RATED_TORQUE},
            speeds={"sun": OUTPUT_SPEED}, meshes=COMPLIANT,
        )  # fmt: skip


def test_the_energy_ledger_closes(rated_run):
    ledger_closure(rated_run, rtol=1e-6)


def test_the_ground_bearings_hold_the_gearbox(rated_run, gearbox):
    free_body_balance(rated_run, gearbox, rtol=1e-6)


def test_every_joint_turns_at_its_tooth_ratio(rated_run, gearbox):
    # Started in equilibrium, the compliant train turns at its ratios to rounding; a run with a
    # transient vibrates about them by the meshes' deflection rate (give a looser rtol).
    speed_ratios(rated_run, gearbox, input_joint=INPUT, rtol=1e-9)


def test_every_element_has_the_tangent_of_its_force(gearbox):
    element_tangents(gearbox, states=4, meshes=COMPLIANT, rtol=1e-6)
    conservative_forces(gearbox, states=4, meshes=COMPLIANT, rtol=1e-6)


def test_the_lowest_modes_ring_in_a_free_vibration(gearbox):
    modes_in_spectrum(gearbox, meshes=COMPLIANT, held=["sun"], count=2, rtol=0.01)


def main(argv: list[str] | None = None) -> int:
    """Run these tests with pytest; the arguments are pytest's (``-q``, ``-k ledger``)."""
    return int(pytest.main([__file__, *(sys.argv[1:] if argv is None else argv)]))


if __name__ == "__main__":
    sys.exit(main())
