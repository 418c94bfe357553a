"""Row loads (the row series): a shaft's rows share its load by lever rule, beam statics, tilt."""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.testing import assert_allclose

import pinwind
from pinwind.analysis.bearing_rows import row_loads
from pinwind.errors import PinwindWarning
from pinwind.loads.hub_loads import constant_hub_load
from pinwind.model.bearing_rows import BearingRow, equivalent_bearing
from pinwind.model.gearbox import loads

#: Rows A and B [m from the joint], k_A a_A + k_B a_B = 0: the joint is their stiffness centre.
A, B, K = -0.3, 0.1, 1e9


def _rows(k: float = K, axial_b: float = 5e8) -> list[BearingRow]:
    damping = (100.0, 1e3, 1e3, 0.0, 0.0)
    return [
        BearingRow("A", "spherical_roller", A, 1e6, (0.0, k, k, 0.0, 0.0), damping),
        BearingRow("B", "cylindrical_roller", B, 1e6, (axial_b, 3 * k, 3 * k, 0.0, 0.0), damping),
    ]


def shaft_on_rows(rows: list[BearingRow], radial: float | None = None) -> str:
    """A shaft (axis world z) on bearing "shaft", its rows given; no gravity."""
    eq = equivalent_bearing(rows)
    k = eq.radial_stiffness if radial is None else radial
    lines = "".join(
        f'      <row name="{r.name}" type="{r.kind}" position_mm="{r.position * 1e3!r}" '
        f'stiffness="{" ".join(repr(x) for x in r.stiffness)}" '
        f'damping="{" ".join(repr(x) for x in r.damping)}" rating_c_kN="1000"/>\n'
        for r in rows
    )
    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="100"/>
    <inertia ixx="10" iyy="10" izz="5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <bearing joint="shaft" radial_stiffness="{k!r}" radial_damping="{eq.radial_damping!r}"
      axial_stiffness="{eq.axial_stiffness!r}" axial_damping="{eq.axial_damping!r}"
      tilt_stiffness="{eq.tilt_stiffness!r}" tilt_damping="{eq.tilt_damping!r}">
{lines}    </bearing>
  </gearbox>
</robot>"""


def _run(text: str, load) -> tuple:
    gb = loads(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(gb, duration=0.01, dt=1e-3, hub_loads=[load])
    return res, gb


def test_two_rows_share_a_radial_load_beyond_them_by_the_lever_rule():
    # F along w (world y) at p = 0.5 m: moments about A give R_B (B − A) + F (p − A) = 0.
    force, p = -1.0e4, 0.5
    load = constant_hub_load("shaft", [0, 0, force, 0, 0, 0], point=(0, 0, p), up=(0, 1, 0))
    res, gb = _run(shaft_on_rows(_rows()), load)
    rows = {r.name: r for r in row_loads(res, gb)}
    r_b = -force * (p - A) / (B - A)
    r_a = -force - r_b
    assert_allclose(rows["A"].radial[-1], [0.0, r_a], rtol=1e-9, atol=1e-9 * abs(force))
    assert_allclose(rows["B"].radial[-1], [0.0, r_b], rtol=1e-9, atol=1e-9 * abs(force))
    # the rows add up to the bearing's reaction
    total = rows["A"].radial[-1] + rows["B"].radial[-1]
    assert_allclose(total, res.bearing("shaft").force_local[-1, :2], rtol=1e-9, atol=1e-6)


def test_a_main_shaft_s_rows_carry_weight_thrust_and_bending_as_beam_statics_says():
    # Weight W down at the overhang p, thrust T along the axis, bending moment M about the
    # hub's y (world x, the joint's u): radial statics of a beam on two pin supports; the
    # thrust goes to the only row with axial stiffness (B).
    weight, thrust, moment, p = 1.1e6, 8.0e5, 2.5e6, -1.5
    load = constant_hub_load("shaft", [thrust, 0, -weight, 0, moment, 0], point=(0, 0, p),
                             up=(0, 1, 0))  # fmt: skip
    res, gb = _run(shaft_on_rows(_rows(k=1e11)), load)  # main-bearing stiffness
    rows = {r.name: r for r in row_loads(res, gb)}
    # In the joint frame (u, w, k = world x, y, z): the force is −W along w at p k, the moment
    # M about u (the hub's y = z × x = w × k = u). A force F w at a k has the moment
    # (a k) × (F w) = −a F u, so about u: −(A R_A + B R_B) + p W + M = 0, and R_A + R_B = W.
    r_b = (moment + p * weight - A * weight) / (B - A)
    r_a = weight - r_b
    # The shaft tilts by θ under the load, so the thrust's line moves by p θ off the rows'
    # axis: beam statics in the undeflected pose holds to about T |p| θ over the reactions.
    theta = np.max(np.abs(res.joint("shaft_tilt_x").angle))
    tolerance = 10 * thrust * abs(p) * theta / min(abs(r_a), abs(r_b)) + 1e-9
    assert_allclose(rows["A"].radial[-1, 1], r_a, rtol=tolerance)
    assert_allclose(rows["B"].radial[-1, 1], r_b, rtol=tolerance)
    assert_allclose(rows["A"].axial[-1], 0.0, atol=1e-9 * thrust)
    assert_allclose(rows["B"].axial[-1], -thrust, rtol=1e-9)


def test_the_5mw_planet_rows_share_a_planet_s_load_by_its_tilt():
    # A stage-1 planet on its two rows (PL-A, PL-B at ∓136 mm; K_y = 9.4e9 N/m radially, K_z =
    # 3.2e9 N/m tangentially, Nejad et al. 2016 Table VI) tilts under its meshes and weight: the
    # rows carry different radial loads, and they add up to the bearing's reaction, its force
    # and its moment about the centre on the tilt hinges (Newton: Σ F_i, Σ (M_i + a_i k × F_i)),
    # in the planet's slide axes u, w, k (its radial_axis u points away from the carrier's
    # axis): the joint frame's components along them (axes_in_joint), turned by the tilts and
    # the planet's angle, rotations about u, w and k.
    from tests.conftest import MODELS
    from tests.dynamics.test_row_springs import slides_from_joint

    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        # rated: 5 MW at 12.1 rpm (Jonkman et al. 2009 Table 1-1), the generator at the ratio
        # of the teeth (Nejad et al. 2016 Table V)
        speed, ratio = 12.1 * math.pi / 30.0, (1 + 56 / 19) * (1 + 93 / 18) * 95 / 24
        res = pinwind.simulate(gb, duration=2e-3, dt=1e-4, torques={"rotor": 5e6 / speed},
                               speeds={"generator": -speed * ratio},
                               initial_speeds={"rotor": speed})  # fmt: skip
    assert len(res) >= 10
    planet = "stage1_planet3"
    rows = {r.name: r for r in row_loads(res, gb) if r.bearing == planet}
    assert sorted(rows) == ["PL-A", "PL-B"]
    force = sum(np.column_stack([r.radial, r.axial]) for r in rows.values())
    moment = sum(
        r.tilting + r.position * np.column_stack([-r.radial[:, 1], r.radial[:, 0]])
        for r in rows.values()
    )
    rotation = slides_from_joint(res, planet) @ gb.compliant_bearings[planet].axes_in_joint
    reaction = res.bearing(planet)
    f_slides = np.einsum("nij,nj->ni", rotation, reaction.force_local)
    m_slides = np.einsum("nij,nj->ni", rotation, reaction.moment_local)
    tilt_u = res.joint(f"{planet}_tilt_x").angle  # the w hinge turned by it: R_u(θ_u) w
    hinge_w = np.column_stack([np.zeros(len(res)), np.cos(tilt_u), np.sin(tilt_u)])
    on_hinges = np.column_stack([m_slides[:, 0], np.einsum("ni,ni->n", m_slides, hinge_w)])
    # The reaction takes each mesh's force at its pitch point (compliant_mesh.hpp
    # add_body_forces), the step its generalised force along the mesh's row: they differ by
    # ~6e-6 of the load here (a shaft without meshes closes to 1e-9: test_row_springs.py).
    load = float(np.max(np.linalg.norm(f_slides, axis=1)))
    assert_allclose(force, f_slides, atol=1e-4 * load)
    assert_allclose(moment, on_hinges, atol=1e-4 * load * 0.136)
    # the tilt shares the load unequally: the rows do not carry equal halves
    a, b = rows["PL-A"], rows["PL-B"]
    difference = np.linalg.norm(a.radial[-1] - b.radial[-1])
    assert difference > 1e-3 * np.linalg.norm(a.radial[-1] + b.radial[-1])


def test_simulate_prints_every_row_of_the_5mw_gearbox_with_its_bearing():
    from tests.conftest import MODELS
    from tests.test_cli import run as run_cli

    out = run_cli("simulate", str(MODELS / "nrel5mw_gearbox.urdf"), "--torque",
                  "rotor=3945990.3245924464", "--speed", "generator=-1165.8854166666667",
                  "--initial-speed", "rotor=12.1", "--duration", "0.005", "--dt", "1e-4",
                  "--no-log")  # fmt: skip
    assert out.returncode == 0, out.stderr
    table = out.stdout[out.stdout.index("Bearing rows at t") :]
    # Nejad et al. 2016 Tables VI and IX: sixteen bearings, the planets' rows once per planet
    names = ["INP-A", "INP-B", "PLC-A", "PLC-B", "IMS-PLC-A", "IMS-PLC-B", "IMS-A", "IMS-B",
             "IMS-C", "HS-A", "HS-B", "HS-C"]  # fmt: skip
    for name in names:
        assert f" {name} " in table
    assert table.count(" PL-A ") == 3 and table.count(" IMS-PL-A ") == 3
