"""The tooth phase of a ring gear (``model/phasing.py``), derived by hand.

A profile-shifted internal pair (DTU 500 kW planet–ring, Jørgensen 2014: z 35/91,
x 0.419/−0.840, module 10 mm, 20°) with the ring first in the file, so that the ring starts the
train and keeps the phase its file gives: ``tooth_phase_deg`` φ is where its front flank crosses
its working pitch circle, here two tooth pitches from the ring's zero direction (+x), so that a
front flank stands at the pitch point P, which lies along +x from both centres.

By hand (ISO 21771, signed tooth numbers, internal gear negative):

- working pressure angle: inv α_w = inv α + 2 tan α (x_p + x_r) / (z_p − z_r); working radii
  r_w = z m cos α / (2 cos α_w), centre distance r_w,r − r_w,p;
- half tooth angle of the ring on its working circle (its teeth thicken outwards, away from its
  tip): ψ_r = (π/2 + 2 x_r tan α)/z_r − inv α + inv α_w; of the planet (thinning outwards):
  ψ_p = (π/2 + 2 x_p tan α)/z_p + inv α − inv α_w;
- the ring's tooth 0 centre is at φ − ψ_r about its axis;
- without backlash the planet's flank touches the ring's at P. The ring's tooth there lies on
  the clockwise side of P (its front flank, facing its positive turn about +z, is at P), so
  the planet's tooth lies on the anticlockwise side: a planet tooth centre at +ψ_p from P
  about the planet's axis (+z too).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from pinwind.model.gearbox import loads

Z_P, Z_R = 35, 91
X_P, X_R = 0.419, -0.840
MODULE, ALPHA = 0.010, math.radians(20.0)
#: Two tooth pitches: the ring's front flank crosses its working circle at P, on +x.
PHI = 2 * 2 * math.pi / Z_R


def inv(angle: float) -> float:
    return math.tan(angle) - angle


INV_W = inv(ALPHA) + 2 * math.tan(ALPHA) * (X_P + X_R) / (Z_P - Z_R)
ALPHA_W = brentq(lambda a: inv(a) - INV_W, 1e-3, 1.2)
R_WP = Z_P * MODULE * math.cos(ALPHA) / (2 * math.cos(ALPHA_W))
R_WR = Z_R * MODULE * math.cos(ALPHA) / (2 * math.cos(ALPHA_W))
PSI_R = (math.pi / 2 + 2 * X_R * math.tan(ALPHA)) / Z_R - inv(ALPHA) + INV_W
PSI_P = (math.pi / 2 + 2 * X_P * math.tan(ALPHA)) / Z_P + inv(ALPHA) - INV_W


def _pair_urdf() -> str:
    gear = 'module_mm="10" pressure_angle_deg="20" face_width_mm="210"'
    links = "".join(
        f"""
  <link name="{name}">
    <inertial><mass value="{mass}"/>
      <inertia ixx="{izz / 2}" iyy="{izz / 2}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="{name}" type="continuous">
    <parent link="housing"/><child link="{name}"/>
    <origin xyz="{x!r} 0 0"/><axis xyz="0 0 1"/>
  </joint>"""
        for name, mass, izz, x in (("ring", 900.0, 200.0, 0.0), ("planet", 400.0, 6.0, R_WR - R_WP))
    )
    return f"""<?xml version="1.0"?>
<robot name="internal_pair">
  <link name="housing"/>{links}
  <gearbox>
    <gear name="ring" link="ring" teeth="{Z_R}" {gear} profile_shift="{X_R!r}" internal="true"
          tooth_phase_deg="{math.degrees(PHI)!r}"/>
    <gear name="planet" link="planet" teeth="{Z_P}" {gear} profile_shift="{X_P!r}"/>
    <mesh name="ring_planet" gear1="ring" gear2="planet"/>
  </gearbox>
</robot>
"""


def _off_pitch(angle: float, teeth: int) -> float:
    """Distance of ``angle`` from the nearest whole tooth pitch 2π/z [rad]."""
    pitch = 2 * math.pi / teeth
    return abs((angle + pitch / 2) % pitch - pitch / 2)


def test_ring_tooth_centre_is_its_flank_phase_less_its_half_tooth_on_the_working_circle():
    """Guards the internal gear's sign in the half tooth angle (``gears/involute.py``
    ``half_tooth_angle``, through ``GearSpec.half_tooth_angle`` with ``internal``) where it
    places a ring's teeth (``phasing.tooth_phases``): the external sign moves them by
    2 (inv α_w − inv α)."""
    gearbox = loads(_pair_urdf(), "internal_pair.urdf")
    mesh = gearbox.mesh("ring_planet")
    np.testing.assert_allclose(mesh.working_radius_a, R_WR, rtol=1e-12)
    assert abs(INV_W - inv(ALPHA)) > 1e-4  # the shifts move the working circle off the reference
    np.testing.assert_allclose(
        _off_pitch(gearbox.tooth_phases["ring"] - (PHI - PSI_R), Z_R), 0.0, atol=1e-12
    )


def test_planet_tooth_stands_beside_the_ring_tooth_at_the_pitch_point_where_the_flanks_touch():
    """Guards the interlock of an internal pair (``phasing.mating_fraction``, f_B = ½ + f_A
    when both pitch circles move the same way at P): with the external rule's ½ − f_A the
    planet's tooth would stand on the ring's side of P."""
    gearbox = loads(_pair_urdf(), "internal_pair.urdf")
    centre = gearbox.tooth_phases["planet"]
    np.testing.assert_allclose(_off_pitch(centre - PSI_P, Z_P), 0.0, atol=1e-12)
