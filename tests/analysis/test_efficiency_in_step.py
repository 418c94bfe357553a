"""Efficiency from the losses the step took: per mesh, bearing and stage, against the ledger.

Expectations, each derived apart from the code under test:

- the heat the components give to the oil, integrated over the run, is the energy ledger's
  ``friction_loss`` (the step's own booking of the friction forces' work);
- P_in − P_out − Σ losses is what the dampers take and the stored energy gains (the ledger);
- the overall efficiency is the product of the stages' (each stage receives what the one before
  passes on);
- the NREL 5 MW gearbox (Nejad et al. 2016) has three stages: two planetary, one parallel;
- its helical stage loses μ P times the integral of the sliding along its inclined contact lines
  with the load uniform along them (a quadrature over a mesh cycle, docs/losses.md "Helical
  pairs").
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
from pinwind.gears.gear_pair import GearPair
from pinwind.losses.mesh_friction import addendum_contact_ratios, tooth_loss_factor
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


def contact_line_loss_factor(pair: GearPair) -> float:
    """P_loss/(μ P) of a helical pair with the load uniform along its contact lines [-].

    By quadrature over a mesh cycle (docs/losses.md "Helical pairs"): the front section at
    φ + j p_bt, each line over [x − Δ, x] ∩ [0, g_α], Δ = ε_β p_bt; at each instant the loss is
    μ F_bt/cos β_b ω_rel Σ_j ∫ |y − y_P| dy / Σ_j L_j, and P = F_bt r_b1 ω1.
    """
    approach, _ = addendum_contact_ratios(pair)
    p = pair.path.base_pitch
    g, pitch, span = pair.path.contact_ratio * p, approach * p, pair.path.overlap_ratio * p
    phi = (np.arange(100_000) + 0.5) / 100_000 * p
    moment, length = np.zeros_like(phi), np.zeros_like(phi)
    for j in range(-2, int((g + span) / p) + 3):
        a, b = np.clip(phi + j * p - span, 0, g), np.clip(phi + j * p, 0, g)
        length += b - a
        moment += ((b - pitch) * np.abs(b - pitch) - (a - pitch) * np.abs(a - pitch)) / 2
    base_radius_1 = pair.teeth_1 * p / (2 * math.pi)
    u = pair.gear_ratio
    return (
        (1 + 1 / u) * np.mean(moment / length) / (base_radius_1 * math.cos(pair.base_helix_angle))
    )


def test_the_helical_stage_loses_the_contact_line_integral_not_ohlendorfs_h_v():
    # Stage 3 (24/95, ε_α = 1.46, ε_β = 1.42): the step integrates the friction along the
    # inclined lines, 1.174 × H_V here; the friction at one point of each line gave 1.52 × H_V.
    gb, res, mu = rated_with_friction()
    mesh = next(m for m in gb.meshes if m.name == "stage3")
    pair = GearPair.from_mesh(mesh)
    assert pair.teeth_1 == 24  # the pinion, on the high-speed shaft
    keep = np.asarray(res.time) >= 5e-3
    power = res.mesh("stage3").normal * (pair.teeth_1 * pair.path.base_pitch / (2 * math.pi))
    power = power * np.abs(res.joint("hss").speed)
    loss = res.mesh("stage3").friction_power
    got = np.mean(loss[keep]) / (mu["stage3"] * np.mean(power[keep]))
    expected = contact_line_loss_factor(pair)
    assert_allclose(got, expected, rtol=1e-2)
    assert expected / tooth_loss_factor(pair) > 1.15
