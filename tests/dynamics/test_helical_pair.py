"""A held helical pair: tooth force components and the bearings' thrust by hand statics.

Gear 1 (20 teeth, right hand β = 15°) at the origin, gear 2 (40 teeth, left hand) at +x, normal
module 2 mm, α_n = 20°. Transverse module m_t = m / cos β, so the centre distance is
m_t (z1 + z2)/2 and r_1 = m_t z1/2. A torque T on gear 1 against a driver holding gear 2 gives

    F_t = T / r_1,   F_r = F_t tan α_t,   F_a = F_t tan β,   tan α_t = tan α_n / cos β

and on gear 2 (centre O_2, pitch point P = (r_1, 0, 0)) the tooth force (F_r, F_t, −F_a): a right-
hand driver pushes the driven gear towards −z. Its bearing carries the opposite force and the
moment −(P − O_2) × F, which includes the tilting moment r_2 F_a of the thrust.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.compliant import mesh_setup
from pinwind.errors import StepTooCoarse
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import single_pair_stiffness
from pinwind.model.gearbox import loads

BETA, ALPHA, M_N = math.radians(15.0), math.radians(20.0), 0.002
M_T = M_N / math.cos(BETA)
R1, R2 = M_T * 20 / 2, M_T * 40 / 2
ALPHA_T = math.atan(math.tan(ALPHA) / math.cos(BETA))


def pair_urdf(
    centre_distance: float,
    *,
    name: str = "helical",
    face_width_mm: float = 20,
    shifts: tuple[float, float] = (0.0, 0.0),
    mesh: str = '<mesh name="m" gear1="g1" gear2="g2"/>',
) -> str:
    """The 20/40-tooth helical pair (m_n 2 mm, β ±15°) at ``centre_distance`` [m]."""
    x1, x2 = shifts
    return f"""<robot name="{name}"><link name="housing"/>
  <link name="a"><inertial><mass value="1"/>
    <inertia ixx="1e-3" iyy="1e-3" izz="1.5e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="2"/>
    <inertia ixx="4e-3" iyy="4e-3" izz="6e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="a" type="continuous"><parent link="housing"/><child link="a"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="b" type="continuous"><parent link="housing"/><child link="b"/>
    <origin xyz="{centre_distance!r} 0 0"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <gear name="g1" link="a" teeth="20" module_mm="2" face_width_mm="{face_width_mm}"
          helix_angle_deg="15" profile_shift="{x1}"/>
    <gear name="g2" link="b" teeth="40" module_mm="2" face_width_mm="{face_width_mm}"
          helix_angle_deg="-15" profile_shift="{x2}"/>
    {mesh}
  </gearbox>
</robot>"""


HELICAL = pair_urdf(R1 + R2)


def test_helical_tooth_force_has_the_transverse_components_and_the_axial_thrust():
    gb = loads(HELICAL, path="helical.urdf")
    assert_allclose(gb.mesh("m").centre_distance, R1 + R2, rtol=1e-12)
    torque = 10.0
    with pytest.warns(StepTooCoarse):
        res = pinwind.simulate(
            gb, duration=0.003, dt=1e-3, torques={"a": torque}, speeds={"b": 0.0}
        )
    f_t = torque / R1
    mesh = res.mesh("m")
    assert_allclose(mesh.tangential, f_t, rtol=1e-9)
    assert_allclose(mesh.radial, f_t * math.tan(ALPHA_T), rtol=1e-9)
    assert_allclose(mesh.axial, f_t * math.tan(BETA), rtol=1e-9)
    force = np.array([f_t * math.tan(ALPHA_T), f_t, -f_t * math.tan(BETA)])
    assert_allclose(mesh.force_on_b[-1], force, rtol=1e-9)
    assert_allclose(res.bearing("b").force[-1], -force, rtol=1e-9, atol=1e-9)
    lever = np.array([-R2, 0.0, 0.0])  # P − O_2
    assert_allclose(res.bearing("b").moment[-1], -np.cross(lever, force), rtol=1e-9, atol=1e-9)
    # Gear 1's bearing takes the opposite thrust, at its own pitch radius.
    assert_allclose(res.bearing("a").force[-1], force, rtol=1e-9, atol=1e-9)


def inverse_involute(value: float) -> float:
    """α with tan α − α = value, by Newton's method from α = 0.5 rad."""
    alpha = 0.5
    for _ in range(50):
        alpha -= (math.tan(alpha) - alpha - value) / math.tan(alpha) ** 2
    return alpha


def helical_pair(*, shifts: tuple[float, float], face_width_mm: float, mesh: str) -> tuple:
    """The pair above with profile shifts, at its working centre distance (ISO 21771):

        inv α_wt = inv α_t + 2 tan α_n (x1 + x2) / (z1 + z2),   a_w = a cos α_t / cos α_wt

    Returns the model text, α_wt and a_w [m].
    """
    x1, x2 = shifts
    inv = math.tan(ALPHA_T) - ALPHA_T + 2.0 * math.tan(ALPHA) * (x1 + x2) / 60.0
    alpha_wt = inverse_involute(inv)
    a_w = (R1 + R2) * math.cos(ALPHA_T) / math.cos(alpha_wt)
    text = pair_urdf(a_w, name="shifted", face_width_mm=face_width_mm, shifts=shifts, mesh=mesh)
    return text, alpha_wt, a_w


def test_shifted_helical_axial_force_is_base_tangential_force_times_tan_base_helix():
    # The contact force is normal to the flanks, in the plane of action and perpendicular to the
    # contact lines (inclined at β_b): its transverse part along the line of action is
    # F_bt = T / r_b1 and its axial part F_bt tan β_b, tan β_b = tan β cos α_t, whatever the
    # centre distance. With shift α_wt ≠ α_t, so F_tw tan β (F_tw = T / r_w1) would differ.
    text, alpha_wt, a_w = helical_pair(
        shifts=(0.4, 0.3), face_width_mm=20, mesh='<mesh name="m" gear1="g1" gear2="g2"/>'
    )
    gb = loads(text, path="shifted.urdf")
    torque = 10.0
    with pytest.warns(StepTooCoarse):
        res = pinwind.simulate(
            gb, duration=0.003, dt=1e-3, torques={"a": torque}, speeds={"b": 0.0}
        )
    r_b1 = R1 * math.cos(ALPHA_T)
    r_w1, r_w2 = a_w / 3.0, 2.0 * a_w / 3.0
    f_bt = torque / r_b1
    f_a = f_bt * math.tan(BETA) * math.cos(ALPHA_T)
    assert abs(alpha_wt - ALPHA_T) > math.radians(1.0)  # the shift moves the working angle
    mesh = res.mesh("m")
    assert_allclose(mesh.normal, f_bt, rtol=1e-9)
    assert_allclose(mesh.tangential, torque / r_w1, rtol=1e-9)
    assert_allclose(mesh.axial, f_a, rtol=1e-9)
    force = np.array([f_bt * math.sin(alpha_wt), f_bt * math.cos(alpha_wt), -f_a])
    assert_allclose(mesh.force_on_b[-1], force, rtol=1e-9)
    # The tilting moment on gear 2's bearing: the thrust at the working pitch radius r_w2.
    lever = np.array([-r_w2, 0.0, 0.0])  # P − O_2
    assert_allclose(res.bearing("b").moment[-1], -np.cross(lever, force), rtol=1e-9, atol=1e-9)
    assert_allclose(res.bearing("a").force[-1], force, rtol=1e-9, atol=1e-9)


def test_helical_path_stiffness_follows_the_contact_line_length():
    # b = 30 mm: ε_β = b sin β / (π m_n) = 1.236. ε_α by hand (ISO 21771, no shift): tip radii
    # r + m_n, g_α = Σ √(r_a² − r_b²) − a sin α_t, p_bt = π m_t cos α_t. The summed pair stiffness
    # the step loop uses (cpp/mesh_path.hpp path_state: pairs at x + j p_bt up to the path
    # length) over its mean c′b (0.75 ε_α + 0.25) must span the contact-line length's range
    # 1 + [max(0, n_α + n_β − 1) − n_α n_β] / (ε_α ε_β) … 1 + [min(n_α, n_β) − n_α n_β] / (ε_α ε_β)
    # (n the fractional parts), not the spur 1 … 1.75 c′b.
    width = 0.030
    text, _, _ = helical_pair(
        shifts=(0.0, 0.0),
        face_width_mm=30,
        mesh='<mesh name="m" gear1="g1" gear2="g2" type="compliant"/>',
    )
    gb = loads(text, path="helical_compliant.urdf")
    r_b1, r_b2 = R1 * math.cos(ALPHA_T), R2 * math.cos(ALPHA_T)
    g = (
        math.sqrt((R1 + M_N) ** 2 - r_b1**2)
        + math.sqrt((R2 + M_N) ** 2 - r_b2**2)
        - (R1 + R2) * math.sin(ALPHA_T)
    )
    p_bt = math.pi * M_T * math.cos(ALPHA_T)
    eps_a, eps_b = g / p_bt, width * math.sin(BETA) / (math.pi * M_N)
    assert eps_b >= 1.0
    pair = GearPair.from_gears(gb.gears["g1"].spec, gb.gears["g2"].spec)
    mean = single_pair_stiffness(pair) * (0.75 * eps_a + 0.25)

    setup = mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-5)
    path = setup.paths[0]
    assert_allclose(path.path_length, g + eps_b * p_bt, rtol=1e-9)  # ε_γ p_bt
    x = np.linspace(0.0, p_bt, 20_001)
    summed = sum(
        np.where(x + j * p_bt <= path.path_length, 1.0, 0.0)
        * np.interp(x + j * p_bt, path.pair_position, path.pair_stiffness)
        for j in range(4)
    )
    n_a, n_b = eps_a % 1.0, eps_b % 1.0
    low = 1.0 + (max(0.0, n_a + n_b - 1.0) - n_a * n_b) / (eps_a * eps_b)
    high = 1.0 + (min(n_a, n_b) - n_a * n_b) / (eps_a * eps_b)
    assert_allclose([summed.min(), summed.max()], [low * mean, high * mean], rtol=1e-9)
    assert_allclose(setup.compliant[0].stiffness, mean, rtol=1e-6)
    assert high / low < 1.2  # a spur mesh steps 1 : 1.75


def test_compliant_helical_pair_counts_the_pairs_of_the_total_contact_ratio():
    # A helical pair touches while its inclined contact line crosses any part of the face: the
    # step loop counts ⌊ε_γ⌋ or ⌈ε_γ⌉ pairs, ε_γ = ε_α + ε_β (ε_α from the path, ε_β by hand).
    text, _, _ = helical_pair(
        shifts=(0.0, 0.0),
        face_width_mm=30,
        mesh='<mesh name="m" gear1="g1" gear2="g2" type="compliant"/>',
    )
    gb = loads(text, path="helical_compliant.urdf")
    eps_g = gb.mesh("m").path.contact_ratio + 0.030 * math.sin(BETA) / (math.pi * M_N)
    res = pinwind.simulate(
        gb, duration=0.04, dt=2e-5, torques={"b": -20.0}, speeds={"a": 10.0}
    )  # gear A turns 0.4 rad, more than a base pitch (0.32 rad)
    pairs = set(np.unique(res.mesh("m").pairs).tolist())
    assert pairs == {math.floor(eps_g), math.ceil(eps_g)}
