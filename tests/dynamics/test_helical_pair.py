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
from numpy.testing import assert_allclose

import pinwind
from pinwind.model.gearbox import loads

BETA, ALPHA, M_N = math.radians(15.0), math.radians(20.0), 0.002
M_T = M_N / math.cos(BETA)
R1, R2 = M_T * 20 / 2, M_T * 40 / 2
ALPHA_T = math.atan(math.tan(ALPHA) / math.cos(BETA))

HELICAL = f"""<robot name="helical"><link name="housing"/>
  <link name="a"><inertial><mass value="1"/>
    <inertia ixx="1e-3" iyy="1e-3" izz="1.5e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="2"/>
    <inertia ixx="4e-3" iyy="4e-3" izz="6e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="a" type="continuous"><parent link="housing"/><child link="a"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="b" type="continuous"><parent link="housing"/><child link="b"/>
    <origin xyz="{R1 + R2!r} 0 0"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <gear name="g1" link="a" teeth="20" module_mm="2" face_width_mm="20" helix_angle_deg="15"/>
    <gear name="g2" link="b" teeth="40" module_mm="2" face_width_mm="20" helix_angle_deg="-15"/>
    <mesh name="m" gear1="g1" gear2="g2"/>
  </gearbox>
</robot>"""


def test_helical_tooth_force_has_the_transverse_components_and_the_axial_thrust():
    gb = loads(HELICAL, path="helical.urdf")
    assert_allclose(gb.mesh("m").centre_distance, R1 + R2, rtol=1e-12)
    torque = 10.0
    res = pinwind.simulate(gb, duration=0.003, dt=1e-3, torques={"a": torque}, speeds={"b": 0.0})
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
