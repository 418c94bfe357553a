"""Efficiency from the losses the step took: per mesh, bearing and stage, against the ledger.

Expectations, each derived apart from the code under test:

- the heat the components give to the oil, integrated over the run, is the energy ledger's
  ``friction_loss`` (the step's own booking of the friction forces' work);
- P_in − P_out − Σ losses is what the dampers take and the stored energy gains (the ledger);
- the overall efficiency is the product of the stages' (each stage receives what the one before
  passes on);
- the NREL 5 MW gearbox (Nejad et al. 2016) has three stages: two planetary, one parallel.
"""

from __future__ import annotations

import math
import re
from functools import cache

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.efficiency import (
    efficiency,
    mesh_friction_coefficients,
    train_stages,
)
from pinwind.errors import InvalidLossInput
from pinwind.losses.oil import Lubricant
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

RPM = 2.0 * math.pi / 60.0
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # Nejad et al. 2016: 97.0
OIL = Lubricant(320, 343.15)  # VG 320 at 70 °C


def _rated(gb, meshes=None, duration=0.02, dt=5e-5):
    return pinwind.simulate(
        gb, duration=duration, dt=dt, torques={"rotor": 5e6 / (12.1 * RPM)},
        speeds={"generator": -12.1 * RPM * RATIO}, initial_speeds={"rotor": 12.1 * RPM},
        meshes=meshes,
    )  # fmt: skip


@cache
def rated_with_friction():
    """The NREL 5 MW gearbox at rated, μ_mz on every (compliant) mesh, Palmgren on every bearing.

    μ_mz per mesh: ISO/TR 14179-2 at the mesh's rated load and speed (from a rigid run's
    forces), VG 320 at 70 °C, Ra 0.5 µm.
    """
    rigid = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    first = _rated(rigid, duration=0.01, dt=1e-4)
    mu = mesh_friction_coefficients(first, rigid, oil=OIL, start=1e-3)
    text = (MODELS / "nrel5mw_gearbox.urdf").read_text()
    text = re.sub(
        r"<bearing joint=",
        '<bearing friction_model="iso_tr_14179_2" lubricant_vg="320" temperature_C="70" joint=',
        text,
    )
    gb = loads(text, path=str(MODELS / "nrel5mw_gearbox.urdf"))
    meshes = {name: MeshCompliance(friction_coefficient=value) for name, value in mu.items()}
    return gb, _rated(gb, meshes=meshes), mu


def test_the_nrel_5mw_train_has_two_planetary_stages_and_a_parallel_one():
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    stages = train_stages(gb, {"lss": 1.0, "iss": 5.0, "ims": 20.0, "hss": 100.0})
    assert [s.kind for s in stages] == ["planetary", "planetary", "parallel"]
    # each stage: its carrier (the main shaft, then the sun shaft iss), planets and ring support
    planets = {f"stage{i}_planet{j}" for i in (1, 2) for j in (1, 2, 3)}
    assert set(stages[0].bearings) == {"lss", "stage1_ring"} | {p for p in planets if "1_" in p}
    assert set(stages[1].bearings) == {"iss", "stage2_ring"} | {p for p in planets if "2_" in p}
    assert set(stages[2].bearings) == {"ims", "hss"}
    assert len(stages[0].meshes) == 6 and len(stages[1].meshes) == 6
    assert stages[2].meshes == ("stage3",)


def test_losses_in_the_step_close_the_ledger_and_multiply_to_the_overall_efficiency():
    gb, res, _ = rated_with_friction()
    e = efficiency(res, gb, oil=OIL)
    assert e.source == "run"
    t = np.asarray(res.time)
    # the heat to the oil over the run is the ledger's friction_loss (trapezoid of the samples)
    heat = np.sum(0.5 * (e.loss[1:] + e.loss[:-1]) * np.diff(t))
    booked = res.energy["friction_loss"][-1] - res.energy["friction_loss"][0]
    assert_allclose(heat, booked, rtol=2e-3)
    # P_in − P_out − Σ losses = what the dampers take + what the stored energy gains − the
    # meshes' parametric work (the ledger's terms; here mostly kinetic energy, ~0.33 MW over
    # the second half: the compliant train's start-up, the same without friction)
    window = slice(len(t) // 2, None)
    span = t[-1] - t[len(t) // 2]
    energy = res.energy
    kept = (
        energy["dissipated"] + energy["kinetic"] + energy["potential_spring"]
        - energy["work_parametric"]
    )  # fmt: skip
    expected = (kept[-1] - kept[len(t) // 2]) / span
    balance = e.input_power - e.output_power - e.loss
    assert abs(np.mean(balance[window]) - expected) < 1e-3 * 5e6
    # the stages: all the losses are theirs, and their efficiencies multiply to the overall
    assert len(e.stages) == 3
    assert_allclose(sum(s.loss for s in e.stages), e.loss, rtol=1e-12, atol=1e-9)
    product = math.prod(s.mean_efficiency for s in e.stages)
    assert_allclose(product, e.mean_efficiency, rtol=1e-12)


def test_an_unknown_source_is_refused():
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    with pytest.raises(InvalidLossInput, match="source"):
        efficiency(None, gb, oil=OIL, source="nonsense")
