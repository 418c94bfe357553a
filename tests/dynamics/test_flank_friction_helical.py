"""Flank friction of a helical pair, integrated along its inclined contact lines (issue 41 item 1).

The pair is ``tests/conftest.two_gear_urdf`` made helical: 20/40 teeth, normal module 2 mm, 20°,
face width b = 20 mm, β = ±asin(π m_n / b) = 18.2°, so that the overlap ratio ε_β = b sin β /
(π m_n) is exactly 1, at the reference centre distance m_n (z1 + z2) / (2 cos β). A (joint
``a``) turns at a constant ω_A; B carries a constant load torque T_L; μ is small (1e-4) so that
the friction's own moments move the mesh force by ~1e-5 of itself.

Hand integral. In the plane of action a pair touches along a line inclined at β_b: the section
ζ from the front face touches at y = x − ζ tan β_b on the transverse path [0, g_α] (x the front
section's position), so the line covers [x − Δ, x] ∩ [0, g_α], Δ = b tan β_b = ε_β p_bt. A point
at u = y − y_P from the pitch point slides at ω_rel |u| (ω_rel = ω_A + |ω_B|) under the flanks'
normal load, F_n = F_bt / cos β_b in all. Where the stiffness per unit contact length is uniform
(ISO 6336-1's, the mesh's ``"path"`` law) so is the load, w = F_n / L with L the total length of
the lines in contact, and the loss is μ w ω_rel Σ_j ∫ |u| dℓ. Over a mesh cycle the lines sweep
the field [0, g_α] × [0, b] once, so the cycle's mean of Σ_j ∫ |u| du is (Δ/p_bt) ∫ |y − y_P| dy
= (Δ/p_bt) p_bt² (ε_1² + ε_2²)/2, and with ε_β whole L = ε_α Δ throughout. Hence

    P_loss / (μ P) = π (u + 1) / (z1 u cos β_b) · (ε_1² + ε_2²) / ε_α      (P = F_bt r_b,A ω_A).

For an ε_β that is not whole L varies over the cycle and the mean is a quadrature over it of
Σ_j ∫ |u| du / L (``contact_line_quadrature``; β = 10°, ε_β = 0.553).

Ohlendorf's H_V (ISO/TR 14179-2) has (1 − ε_α + ε_1² + ε_2²) in its place: each transverse section
a spur pair whose teeth share the load equally where two are in contact. That is exact for the
mesh's ``"constant"`` stiffness (every section's pairs sharing the section's load equally), single
line or sliced, and the tests check both.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.gears.gear_pair import GearPair
from pinwind.losses.mesh_friction import tooth_loss_factor
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import ledger_residual
from tests.conftest import two_gear_urdf

M_N, ALPHA_N, B = 0.002, math.radians(20.0), 0.020
Z_A, Z_B = 20, 40
U = Z_B / Z_A
BETA = math.asin(math.pi * M_N / B)  # ε_β = 1
ALPHA_T = math.atan(math.tan(ALPHA_N) / math.cos(BETA))
M_T = M_N / math.cos(BETA)
R_A, R_B = Z_A * M_T / 2, Z_B * M_T / 2
R_BA, R_BB = R_A * math.cos(ALPHA_T), R_B * math.cos(ALPHA_T)
BASE_PITCH = math.pi * M_T * math.cos(ALPHA_T)
BETA_B = math.atan(math.tan(BETA) * math.cos(ALPHA_T))
SPAN = B * math.tan(BETA_B)  # Δ = ε_β p_bt
OMEGA_A = 10.0  # [rad/s]
LOAD = 5.0  # T_L on B [N·m]
MU = 1e-4
MESH_PERIOD = 2 * math.pi / (Z_A * OMEGA_A)  # [s]


def _contact_ratios() -> tuple[float, float]:
    """(ε_1, ε_2): the path on B's addendum (approach) and on A's (recess), over p_bt."""
    approach = math.sqrt((R_B + M_N) ** 2 - R_BB**2) - R_BB * math.tan(ALPHA_T)
    recess = math.sqrt((R_A + M_N) ** 2 - R_BA**2) - R_BA * math.tan(ALPHA_T)
    return approach / BASE_PITCH, recess / BASE_PITCH


EPS_1, EPS_2 = _contact_ratios()
EPS = EPS_1 + EPS_2
SPEED_FACTOR = math.pi * (U + 1) / (Z_A * U * math.cos(BETA_B))


def contact_line_factor() -> float:
    """P_loss/(μ P) with the load uniform along the contact lines (module docstring)."""
    return SPEED_FACTOR * (EPS_1**2 + EPS_2**2) / EPS


def ohlendorf_factor() -> float:
    """Ohlendorf's H_V: each transverse section a spur pair sharing its load equally."""
    return SPEED_FACTOR * (1 - EPS + EPS_1**2 + EPS_2**2)


def sliced_contact_line_factor(slices: int) -> float:
    """P_loss/(μ P) of N slices under the ``"path"`` law, by quadrature over a mesh cycle.

    Slice s is the section ζ_s = (s + ½) b/N; its pairs sit at y = φ − ζ_s tan β_b + j p_bt in
    [0, g_α] and each pair of every slice carries the same stiffness k_ℓ/N, so at one deflection
    the same force: F_bt / n(φ), n the count of (slice, pair) points in contact.
    """
    phi = (np.arange(20000) + 0.5) / 20000 * BASE_PITCH
    length, pitch = EPS * BASE_PITCH, EPS_1 * BASE_PITCH
    count = np.zeros_like(phi)
    moment = np.zeros_like(phi)
    for s in range(slices):
        q = phi - (s + 0.5) * B / slices * math.tan(BETA_B)
        for j in range(-3, 4):
            y = q + j * BASE_PITCH
            on = (y >= 0.0) & (y <= length)
            count += on
            moment += np.where(on, np.abs(y - pitch), 0.0)
    mean = np.mean(moment / count)
    return (1 + 1 / U) * mean / (R_BA * math.cos(BETA_B))


def helical_pair() -> pinwind.Gearbox:
    text = (
        two_gear_urdf(centre_distance=M_T * (Z_A + Z_B) / 2)
        .replace('<gear name="g1" ', f'<gear name="g1" helix_angle_deg="{math.degrees(BETA)!r}" ')
        .replace('<gear name="g2" ', f'<gear name="g2" helix_angle_deg="{-math.degrees(BETA)!r}" ')
    )
    return loads(text, "helical.urdf")


def _run(*, variation: str, slices: int, per_period: int, periods: float, mu: float = MU):
    return pinwind.simulate(
        helical_pair(),
        duration=round(periods * per_period) * (MESH_PERIOD / per_period),
        dt=MESH_PERIOD / per_period,
        speeds={"a": OMEGA_A},
        torques={"b": LOAD},
        gravity=np.zeros(3),
        meshes={
            "m": MeshCompliance(
                stiffness=1e8,
                variation=variation,
                damping_ratio=0.3,
                friction_coefficient=mu,
                slices=slices,
            )
        },
    )


def _mean_loss_factor(res, periods: int) -> float:
    """Mean friction power over the last whole mesh periods over μ times the output power."""
    n = round(periods * MESH_PERIOD / (res.time[1] - res.time[0]))
    window = slice(len(res.time) - n, len(res.time))
    loss = res.mesh("m").friction_power[window].mean()
    power = (LOAD * np.abs(res.joint("b").speed[window])).mean()
    return loss / (MU * power)


def test_the_hand_geometry_is_the_packages():
    pair = GearPair.from_mesh(helical_pair().meshes[0])
    np.testing.assert_allclose(pair.path.overlap_ratio, 1.0, rtol=1e-12)
    np.testing.assert_allclose(pair.path.contact_ratio, EPS, rtol=1e-12)
    np.testing.assert_allclose(pair.path.base_pitch, BASE_PITCH, rtol=1e-12)
    np.testing.assert_allclose(tooth_loss_factor(pair), ohlendorf_factor(), rtol=1e-12)
    # The two laws differ by (ε_1² + ε_2²)/ε_α against 1 − ε_α + ε_1² + ε_2²: 19 % here.
    assert contact_line_factor() / ohlendorf_factor() - 1 > 0.15


def test_a_single_helical_line_loses_the_contact_line_integral():
    res = _run(variation="path", slices=1, per_period=4000, periods=2.0)
    np.testing.assert_allclose(_mean_loss_factor(res, 1), contact_line_factor(), rtol=1e-4)


@pytest.mark.parametrize("slices", [1, 5])
def test_equal_sharing_in_each_section_loses_ohlendorfs_h_v(slices):
    # "constant": each section (the single line's front section, or each slice) is a spur pair
    # whose pairs share its load equally: Ohlendorf's picture exactly.
    res = _run(variation="constant", slices=slices, per_period=20000, periods=2.0)
    np.testing.assert_allclose(_mean_loss_factor(res, 1), ohlendorf_factor(), rtol=1e-4)


def test_helical_slices_lose_the_midpoint_rule_of_the_contact_line_integral():
    slices = 8
    res = _run(variation="path", slices=slices, per_period=20000, periods=2.0)
    got = _mean_loss_factor(res, 1)
    np.testing.assert_allclose(got, sliced_contact_line_factor(slices), rtol=1e-4)
    # and that is the single line's integral to the midpoint rule's error across the face
    np.testing.assert_allclose(got, contact_line_factor(), rtol=2e-2)


@pytest.mark.parametrize("slices", [1, 5])
def test_helical_friction_closes_the_ledger(slices):
    res = _run(variation="path", slices=slices, per_period=1000, periods=3.0, mu=0.05)
    e = res.energy
    work_in = e["work_drivers"][-1]
    assert e["friction_loss"][-1] > 1e-3 * work_in
    assert np.abs(ledger_residual(res)).max() <= 1e-9 * work_in


def contact_line_quadrature(beta: float) -> tuple[float, float]:
    """(P_loss/(μ P) with the load uniform along the lines, ε_β) of the pair at helix angle β.

    For any ε_β (module docstring): at each instant the loss is μ F_bt/cos β_b ω_rel
    Σ_j ∫ |y − y_P| dy / Σ_j L_j over the lines [x_j − Δ, x_j] ∩ [0, g_α], x_j = φ + j p_bt;
    its mean over φ by the midpoint rule.
    """
    alpha_t = math.atan(math.tan(ALPHA_N) / math.cos(beta))
    m_t = M_N / math.cos(beta)
    r_a, r_b = Z_A * m_t / 2, Z_B * m_t / 2
    rb_a, rb_b = r_a * math.cos(alpha_t), r_b * math.cos(alpha_t)
    p = math.pi * m_t * math.cos(alpha_t)
    beta_b = math.atan(math.tan(beta) * math.cos(alpha_t))
    span = B * math.tan(beta_b)
    approach = math.sqrt((r_b + M_N) ** 2 - rb_b**2) - rb_b * math.tan(alpha_t)
    recess = math.sqrt((r_a + M_N) ** 2 - rb_a**2) - rb_a * math.tan(alpha_t)
    g = approach + recess
    phi = (np.arange(100_000) + 0.5) / 100_000 * p
    moment, length = np.zeros_like(phi), np.zeros_like(phi)
    for j in range(-2, int((g + span) / p) + 3):
        a, b = np.clip(phi + j * p - span, 0, g), np.clip(phi + j * p, 0, g)
        length += b - a
        moment += (
            (b - approach) * np.abs(b - approach) - (a - approach) * np.abs(a - approach)
        ) / 2
    factor = (1 + 1 / U) * np.mean(moment / length) / (rb_a * math.cos(beta_b))
    return factor, span / p


def test_a_helical_line_of_any_overlap_loses_the_quadrature_of_the_contact_line_integral():
    # β = 10°: ε_β = 0.553, the lines' total length varies over the cycle (and with it the mesh
    # stiffness: F varies by 0.9 %, which the mean sees at ~1e-4).
    factor, overlap = contact_line_quadrature(math.radians(10.0))
    assert 0.55 < overlap < 0.56
    whole, one = contact_line_quadrature(BETA)
    np.testing.assert_allclose([whole, one], [contact_line_factor(), 1.0], rtol=1e-9)
    text = (
        two_gear_urdf(centre_distance=M_N / math.cos(math.radians(10.0)) * (Z_A + Z_B) / 2)
        .replace('<gear name="g1" ', '<gear name="g1" helix_angle_deg="10" ')
        .replace('<gear name="g2" ', '<gear name="g2" helix_angle_deg="-10" ')
    )
    res = pinwind.simulate(
        loads(text, "helical10.urdf"),
        duration=12000 * (MESH_PERIOD / 4000),
        dt=MESH_PERIOD / 4000,
        speeds={"a": OMEGA_A},
        torques={"b": LOAD},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e8, damping_ratio=0.3, friction_coefficient=MU)},
    )
    np.testing.assert_allclose(_mean_loss_factor(res, 2), factor, rtol=3e-4)
