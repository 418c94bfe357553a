"""Bearing rows in the step: each row its own spring-damper at its position (cpp/bearing_rows.hpp).

Expectations are hand statics of a rigid shaft on linear springs: per radial plane the shaft's
displacement at the bearing centre and its tilt solve the 2x2 stiffness matrix of the rows,

    u plane (x, θ_w):  [[Σ k_u, Σ k_u a], [Σ k_u a, Σ (k_u a² + k_γ)]] [x, θ_w] = [F_u, p F_u]
    w plane (y, θ_u):  [[Σ k_w, −Σ k_w a], [−Σ k_w a, Σ (k_w a² + k_β)]] [y, θ_u] = [F_w, −p F_w]

for a force F at p along the axis (p k × F_u u = p F_u w, p k × F_w w = −p F_w u), and each row
carries −k (x + a θ_w, y − a θ_u): for two rows without tilt stiffness, the lever rule.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import MalformedModel, PinwindWarning
from pinwind.loads.hub_loads import HubLoad, constant_hub_load
from pinwind.loads.signals import Constant, Sine
from pinwind.model.bearing_rows import BearingRow, equivalent_bearing
from pinwind.model.gearbox import loads

#: Rows A and B [m along the axis from the bearing centre].
A, B = -0.3, 0.1


def _row(name: str, at: float, stiffness, damping=(0.0,) * 5) -> BearingRow:
    return BearingRow(name, "cylindrical_roller", at, 1e6, tuple(stiffness), tuple(damping))


def shaft_on_rows(rows: list[BearingRow], bearing: str | None = None) -> str:
    """A shaft (axis world z: u = world x, w = world y) on bearing "shaft"; no gravity.

    ``bearing``: the bearing's own attributes (default: slides for every row direction).
    """
    if bearing is None:
        bearing = 'radial_stiffness="1" axial_stiffness="1" tilt_stiffness="1"'
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
    <bearing joint="shaft" {bearing}>
{lines}    </bearing>
  </gearbox>
</robot>"""


def _run(text: str, load: HubLoad, duration: float = 0.01, dt: float = 1e-3):
    gb = loads(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(gb, duration=duration, dt=dt, hub_loads=[load])
    return res, gb


def _radial_load(force: float, angle: float, p: float, thrust: float = 0.0) -> HubLoad:
    """F at angle from u towards w, at p on the axis (hub: x the axis, y = world x, z = world y)."""
    f_u, f_w = force * math.cos(angle), force * math.sin(angle)
    return constant_hub_load("shaft", [thrust, f_u, f_w, 0, 0, 0], point=(0, 0, p), up=(0, 1, 0))


def _planes(rows: list[BearingRow], f_u: float, f_w: float, p: float) -> tuple:
    """(x, θ_w), (y, θ_u) of the module docstring's 2x2 statics."""
    a = np.array([r.position for r in rows])
    k = np.array([r.stiffness for r in rows])
    k_u, k_w, k_beta, k_gamma = k[:, 1], k[:, 2], k[:, 3], k[:, 4]
    u_plane = np.array(
        [[k_u.sum(), (k_u * a).sum()], [(k_u * a).sum(), (k_u * a**2 + k_gamma).sum()]]
    )
    w_plane = np.array(
        [[k_w.sum(), -(k_w * a).sum()], [-(k_w * a).sum(), (k_w * a**2 + k_beta).sum()]]
    )
    x, theta_w = np.linalg.solve(u_plane, [f_u, p * f_u])
    y, theta_u = np.linalg.solve(w_plane, [f_w, -p * f_w])
    return x, y, theta_u, theta_w


def test_two_anisotropic_rows_share_a_load_at_30_degrees_by_the_lever_rule():
    # k_u ≠ k_w on each row, in different ratios: the shaft deflects off the load's direction
    # (the 2x2 statics), while two rows without tilt stiffness carry the lever rule's shares.
    rows = [_row("A", A, (0.0, 1e9, 2e9, 0.0, 0.0)), _row("B", B, (5e8, 3e9, 1.5e9, 0.0, 0.0))]
    force, angle, p = 1.0e3, math.radians(30.0), 0.5
    res, gb = _run(shaft_on_rows(rows), _radial_load(force, angle, p))
    f = force * np.array([math.cos(angle), math.sin(angle)])
    r_b = -f * (p - A) / (B - A)  # moments about A: R_B (B − A) + F (p − A) = 0
    r_a = -f - r_b
    scale = 1e-9 * force
    for name, expected in (("A", r_a), ("B", r_b)):
        row = res.row(f"shaft.{name}")
        assert_allclose(row.force[:, :2], np.tile(expected, (len(res), 1)), rtol=1e-9, atol=scale)
        assert_allclose(row.moment, 0.0, atol=scale)
        # the radial force a bearing engineer reads (and the plots draw): the lever rule's length
        assert_allclose(row.radial, np.linalg.norm(expected), rtol=1e-9)
        assert_allclose(row.axial, 0.0, atol=scale)  # no thrust on the shaft
    x, y, theta_u, theta_w = _planes(rows, f[0], f[1], p)
    moved = np.array([res.joint("shaft_radial_x").angle[-1], res.joint("shaft_radial_y").angle[-1]])
    assert_allclose(moved, [x, y], rtol=1e-9)
    assert_allclose(res.joint("shaft_tilt_x").angle[-1], theta_u, rtol=1e-9)
    assert_allclose(res.joint("shaft_tilt_y").angle[-1], theta_w, rtol=1e-9)
    # the deflection is not along the load: 2x2 anisotropy, several degrees off 30°
    assert abs(math.degrees(math.atan2(moved[1], moved[0])) - 30.0) > 5.0
    # at rest the bearing's elastic force (joint frame: u, w, k = x, y, z) is the rows' sum
    total = res.row("shaft.A").force + res.row("shaft.B").force
    assert_allclose(res.bearing("shaft").elastic_force, total, rtol=1e-9, atol=scale)


def test_rows_off_the_stiffness_centre_couple_a_radial_load_into_tilt():
    # Σ k a ≠ 0 and tilt springs on the rows: a radial load at the bearing centre tilts the
    # shaft, θ from the 2x2 statics; the thrust goes to the rows by their axial stiffness.
    rows = [
        _row("A", A, (2e8, 2e9, 1e9, 4e6, 6e6)),
        _row("B", 0.25, (6e8, 1e9, 3e9, 1e6, 2e6)),
    ]
    force, angle, thrust = 2.0e3, math.radians(30.0), 800.0
    res, gb = _run(shaft_on_rows(rows), _radial_load(force, angle, 0.0, thrust))
    f_u, f_w = force * math.cos(angle), force * math.sin(angle)
    x, y, theta_u, theta_w = _planes(rows, f_u, f_w, 0.0)
    assert abs(theta_w) > 1e-3 * abs(x) and abs(theta_u) > 1e-3 * abs(y)  # it does tilt
    scale = 1e-9 * force
    k_axial = sum(r.stiffness[0] for r in rows)
    for r in rows:
        k = r.stiffness
        row = res.row(f"shaft.{r.name}")
        expected = [-k[1] * (x + r.position * theta_w), -k[2] * (y - r.position * theta_u)]
        assert_allclose(row.force[-1, :2], expected, rtol=1e-9, atol=scale)
        assert_allclose(row.force[-1, 2], -thrust * k[0] / k_axial, rtol=1e-9)
        assert_allclose(row.moment[-1, :2], [-k[3] * theta_u, -k[4] * theta_w], rtol=1e-9,
                        atol=1e-9 * force * 0.3)  # fmt: skip


def test_isotropic_rows_at_the_stiffness_centre_act_as_the_old_equivalent_bearing():
    # Rows with K_y = K_z about their stiffness centre (k_A A + k_B B = 0) and the one bearing
    # that stands for them (model/bearing_rows.equivalent_bearing): the same shaft motion and
    # reaction under a varying load; and the rows add up to the reaction at every sample.
    # (the dampers likewise: c_A A + c_B B = 0)
    k, c = 1e9, 1e3
    rows = [
        _row("A", A, (0.0, k, k, 2e6, 2e6), (0.0, c, c, 5.0, 5.0)),
        _row("B", B, (5e8, 3 * k, 3 * k, 1e6, 1e6), (100.0, 3 * c, 3 * c, 2.0, 2.0)),
    ]
    eq = equivalent_bearing(rows)
    own = " ".join(
        f'{name}="{getattr(eq, name)!r}"'
        for name in ("radial_stiffness", "radial_damping", "axial_stiffness", "axial_damping",
                     "tilt_stiffness", "tilt_damping")
    )  # fmt: skip
    components = (Sine(500.0, 200.0, 30.0), Sine(1e3, 400.0, 23.0), Sine(-2e3, 1e3, 41.0, 0.4),
                  Constant(0.0), Sine(0.0, 300.0, 17.0), Constant(0.0))  # fmt: skip
    load = HubLoad("shaft", components, "fixed", (0.0, 0.0, 0.4), (0.0, 1.0, 0.0))
    with_rows, _ = _run(shaft_on_rows(rows, own), load, duration=0.05, dt=2e-4)
    lumped, _ = _run(shaft_on_rows([], own), load, duration=0.05, dt=2e-4)
    assert lumped.row_names == [] and with_rows.row_names == ["shaft.A", "shaft.B"]
    scale = np.max(np.abs(lumped.bearing("shaft").force_local))
    for quantity in ("force_local", "moment_local"):
        assert_allclose(getattr(with_rows.bearing("shaft"), quantity),
                        getattr(lumped.bearing("shaft"), quantity), atol=1e-7 * scale)  # fmt: skip
    # Newton, at every sample: Σ F_i is the bearing's force, Σ (M_i + a_i k × F_i) its moment
    # about the centre (k × u = w, k × w = −u) on the tilt hinges, in the slides' axes: the
    # joint frame (its reaction's) is the slides' turned by R_u(θ_u) R_w(θ_w) R_k(φ).
    rotation = slides_from_joint(with_rows, "shaft")
    reaction = with_rows.bearing("shaft")
    force_in_slides = np.einsum("nij,nj->ni", rotation, reaction.force_local)
    moment_in_slides = np.einsum("nij,nj->ni", rotation, reaction.moment_local)
    hinge_w = _turn(with_rows.joint("shaft_tilt_x").angle, 0)[:, :, 1]  # R_u(θ_u) w
    on_hinges = np.column_stack(
        [moment_in_slides[:, 0], np.einsum("ni,ni->n", moment_in_slides, hinge_w)]
    )
    loads = [with_rows.row(f"shaft.{r.name}") for r in rows]
    force = sum(load.force for load in loads)
    moment = sum(
        load.moment[:, :2] + r.position * np.column_stack([-load.force[:, 1], load.force[:, 0]])
        for r, load in zip(rows, loads, strict=True)
    )
    assert_allclose(force, force_in_slides, atol=1e-9 * scale)
    assert_allclose(moment, on_hinges, atol=1e-9 * scale)


def _turn(angle: np.ndarray, axis: int) -> np.ndarray:
    """Rotations (n, 3, 3) by angle [rad] about the coordinate axis (0 x, 1 y, 2 z)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((len(angle), 3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out[:, axis, axis] = 1.0
    out[:, i, i], out[:, j, j] = c, c
    out[:, i, j], out[:, j, i] = -s, s
    return out


def slides_from_joint(res, joint: str) -> np.ndarray:
    """R_u(θ_u) R_w(θ_w) R_k(φ) (n, 3, 3): a bearing's joint frame in its slides' axes (u, w, k).

    The tilt hinges, then the bearing's own turn (``model/gearbox.py`` puts them in this order).
    """
    return (
        _turn(res.joint(f"{joint}_tilt_x").angle, 0)
        @ _turn(res.joint(f"{joint}_tilt_y").angle, 1)
        @ _turn(res.joint(joint).angle, 2)
    )


@pytest.mark.parametrize("damped", [False, True])
def test_the_energy_ledger_closes_on_rows_under_a_varying_load(damped):
    from pinwind.testing import ledger_closure

    c = (50.0, 2e3, 3e3, 10.0, 20.0) if damped else (0.0,) * 5
    rows = [_row("A", A, (2e7, 1e8, 2e8, 1e5, 3e5), c), _row("B", 0.2, (1e7, 3e8, 1e8, 0, 0), c)]
    components = (Sine(0.0, 300.0, 9.0), Sine(0.0, 1e3, 7.0), Sine(0.0, 2e3, 13.0, 0.3),
                  Constant(0.0), Sine(0.0, 200.0, 11.0), Constant(0.0))  # fmt: skip
    load = HubLoad("shaft", components, "fixed", (0.0, 0.0, 0.5), (0.0, 1.0, 0.0))
    res, _ = _run(shaft_on_rows(rows), load, duration=0.3, dt=1e-4)
    assert abs(res.energy["work_applied"][-1]) > 1e-6  # the load did work
    assert (res.energy["dissipated"][-1] > 0.0) == damped
    ledger_closure(res, rtol=1e-9)


def test_rows_with_a_clearance_are_refused_naming_the_bearing():
    rows = [_row("A", A, (0.0, 1e9, 1e9, 0.0, 0.0)), _row("B", B, (0.0, 3e9, 3e9, 0.0, 0.0))]
    text = shaft_on_rows(rows, 'radial_stiffness="4e9" radial_clearance_mm="0.05"')
    with pytest.raises(MalformedModel, match=r'<bearing joint="shaft">.*radial_clearance_mm=0\.05'):
        loads(text)


def test_rows_reach_the_log_and_read_back(tmp_path):
    rows = [_row("A", A, (0.0, 1e9, 2e9, 0.0, 0.0)), _row("B", B, (5e8, 3e9, 1.5e9, 0.0, 0.0))]
    gb = loads(shaft_on_rows(rows))
    path = tmp_path / "rows.mcap"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(gb, duration=0.01, dt=1e-3, hub_loads=[_radial_load(1e3, 0.5, 0.5)],
                               log=path)  # fmt: skip
    back = pinwind.read_log(path)
    assert back.row_names == ["shaft.A", "shaft.B"]
    assert_allclose(back.row_force, res.row_force, rtol=0, atol=0)
    assert_allclose(back.row_moment, res.row_moment, rtol=0, atol=0)


def test_a_radial_axis_turns_the_rows_directions_with_it():
    # u along (cos 60°, sin 60°): the stiff K_y = 3e9 acts there. A load along u is carried by
    # K_y alone, F_u = −Σ K_y x_u: the shaft moves by F / Σ K_y along u, not F / Σ K_z.
    rows = [_row("A", A, (0.0, 1e9, 1e8, 0.0, 0.0)), _row("B", B, (0.0, 3e9, 3e8, 0.0, 0.0))]
    axis = (math.cos(math.pi / 3), math.sin(math.pi / 3), 0.0)
    bearing = ('radial_stiffness="1" axial_stiffness="1" tilt_stiffness="1" '
               f'radial_axis="{axis[0]!r} {axis[1]!r} 0"')  # fmt: skip
    force = 1e3
    res, gb = _run(shaft_on_rows(rows, bearing), _radial_load(force, math.pi / 3, 0.0))
    assert_allclose(gb.compliant_bearings["shaft"].axes_in_joint[0], axis, atol=1e-15)
    x_u = res.joint("shaft_radial_x").angle[-1]  # the slide along u
    assert_allclose(x_u, force / 4e9, rtol=1e-9)
    assert_allclose(res.joint("shaft_radial_y").angle[-1], 0.0, atol=1e-9 * force / 4e9)


def test_a_radial_axis_along_the_bearing_axis_is_refused():
    bearing = 'radial_stiffness="1e9" radial_axis="0 0 2"'
    with pytest.raises(MalformedModel, match=r'radial_axis="0 0 2" must be .* not along'):
        loads(shaft_on_rows([], bearing))


def test_the_5mw_planets_rows_point_u_away_from_their_carrier_s_axis():
    from tests.conftest import MODELS

    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    for stage in ("stage1", "stage2"):
        for i in (1, 2, 3):
            name = f"{stage}_planet{i}"
            # the planet's centre in its carrier's frame: its first slide's placement
            slide = gb.model.getJointId(f"{name}_radial_x")
            centre = gb.model.jointPlacements[slide].translation[:2]
            u = gb.compliant_bearings[name].axes_in_joint[0]
            assert_allclose(u[:2], centre / np.linalg.norm(centre), atol=1e-12)
