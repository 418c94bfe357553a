"""A helical mesh's axial thrust in the step's dynamics: its row has the tooth force's direction.

The 20/40-tooth helical pair of ``test_helical_pair`` (gear 1 right hand β = 15°, gear 2 left
hand, m_n 2 mm, α_n 20°), compliant, with gear 2 in a compliant bearing that has an axial slide
(stiffness k_a) and tilt hinges (k_t). A torque T on gear 1 against gear 2 held: gear 1 turns
on its fixed axis, so its moment balance about that axis gives the transverse force along the
line of action, F_bt = T / r_b1 (r_b1 = r_1 cos α_t; the thrust is parallel to the axis and
has no moment about it), and the thrust F_a = F_bt tan β_b = T tan β / r_1
(tan β_b = tan β cos α_t). A right-hand driver pushes the driven gear towards −z
(test_helical_pair's docstring), so at equilibrium the axial spring holds
k_a z = −F_a, and the tilt hinge about y holds the thrust's moment about gear 2's centre,
(P − O_2) × (−F_a z) with P − O_2 = (−r_2, 0, 0): M_y = −r_2 F_a, θ_y = −r_2 F_a / k_t.
The same pair with a rigid mesh and with a compliant one cut into slices; the row and its bias
against finite differences; the overlap's rate against the row; the energy ledger.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.mesh import MeshSet
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import energy_scale, ledger_residual
from tests.dynamics.test_helical_pair import ALPHA_T, BETA, R1, R2, pair_urdf

K_RADIAL, K_AXIAL, K_TILT = 2e9, 5e7, 4e6
TORQUE = 10.0


def thrust_pair(
    *,
    backlash_mm: float = 0.0,
    damping: float = 0.0,
    offset: float = 0.0,
    radial: float = K_RADIAL,
    kind: str = "compliant",
) -> pinwind.Gearbox:
    """The compliant helical pair with gear 2 ("b") on a bearing with axial and tilt slides,
    gear 2's mass centre ``offset`` [m] along its axis from its centre."""
    if kind == "rigid":
        mesh = '<mesh name="m" gear1="g1" gear2="g2"/>'
    else:
        slices = ' slices="4"' if kind == "sliced" else ""
        mesh = (
            f'<mesh name="m" gear1="g1" gear2="g2" type="compliant" backlash_mm="{backlash_mm!r}"'
            f' damping="{damping!r}"{slices}/>'
        )
    bearing = (
        f'<bearing joint="b" radial_stiffness="{radial!r}" axial_stiffness="{K_AXIAL!r}" '
        f'tilt_stiffness="{K_TILT!r}"/>'
    )
    text = pair_urdf(R1 + R2, name="thrust", mesh=mesh).replace(
        "</gearbox>", f"  {bearing}\n  </gearbox>"
    )
    text = text.replace(
        '<link name="b"><inertial>', f'<link name="b"><inertial><origin xyz="0 0 {offset!r}"/>'
    )
    return loads(text, path="thrust.urdf")


@pytest.mark.parametrize(("kind", "rtol"), [("compliant", 1e-9), ("sliced", 1e-9), ("rigid", 1e-5)])
def test_the_thrust_pushes_the_driven_gear_along_its_axial_slide_and_tilts_it_by_its_moment(
    kind, rtol
):
    # A rigid mesh keeps the working pressure angle of the reference centre distance, from which
    # the radial slide moves gear 2 by F / k_r ≈ 3e-7 m of a = 62 mm: F_bt = T / r_b1 to ~1e-5.
    gb = thrust_pair(damping=50.0, kind=kind)
    res = pinwind.simulate(
        gb, duration=2e-4, dt=1e-5, torques={"a": TORQUE}, speeds={"b": 0.0}
    )  # the static start, held there
    f_a = TORQUE * math.tan(BETA) / R1
    assert_allclose(TORQUE / (R1 * math.cos(ALPHA_T)) * math.tan(BETA) * math.cos(ALPHA_T), f_a)
    mesh = res.mesh("m")
    assert_allclose(mesh.axial, f_a, rtol=rtol)
    bearing = res.bearing("b")
    # The axial slide: k_a z = −F_a exactly (the slide runs along gear 1's axis, which the
    # thrust is parallel to); the spring holds +F_a on gear 2, and so does the bearing's
    # reaction (RNEA).
    assert_allclose(bearing.displacement[:, 2], -f_a / K_AXIAL, rtol=rtol)
    assert_allclose(bearing.elastic_force[:, 2], f_a, rtol=rtol)
    assert_allclose(bearing.force[:, 2], f_a, rtol=rtol)  # world axes
    # The tilt about y: θ_y = −r_2 F_a / k_t, to first order in the slides' displacements
    # (the radial slide moves P by F / k_r ≈ 3e-7 m of r_2 = 41 mm; the tilt by 1e-4 rad).
    if kind == "sliced":
        return  # the slices resist gear 2's tilt about k × n too: the hinge holds a part only
    theta = res.joint("b_tilt_y").angle
    assert_allclose(theta, -R2 * f_a / K_TILT, rtol=1e-4)
    # About x only the transverse force F_t at P, z = F_a / k_a below the hinge: 1e-3 of θ_y.
    np.testing.assert_array_less(np.abs(res.joint("b_tilt_x").angle), 1e-3 * abs(theta[0]))


def test_with_the_slide_s_axial_motion_the_overlap_s_rate_is_minus_the_row_times_v():
    # A free run with backlash wide enough that the teeth never touch: the gears turn under
    # balanced torques, and gear 2, released undeflected under gravity along its axis, rings on
    # its axial slide (ω_a = √(k_a / m_2)). The front flank's overlap δ (transmission_error,
    # computed from positions) then changes with the axial motion by tan β_b ż; its central
    # difference between samples must be −J v of the front flank's row (f = n − tan β_b k),
    # J and v at the middle sample by the rows' own kinematics (MeshSet). The step's speeds are
    # the trapezoidal rule's, (x_{n+1} − x_n)/h = (v_n + v_{n+1})/2, so the central difference
    # is (v_{n−1} + 2 v_n + v_{n+1})/4 = v_n (1 − (ω_a h)²/4) for the ringing slide: the
    # tolerance, twice that of the largest rate (the turning part, at constant acceleration, has
    # no such error).
    gb = thrust_pair(backlash_mm=1.0)
    dt = 1e-6
    res = pinwind.simulate(
        gb,
        duration=800 * dt,
        dt=dt,
        initial_speeds={"a": 3.0},
        torques={"a": 0.025, "b": 0.05},  # balanced through the ratio; the teeth never touch
        gravity=[0.0, 0.0, -100.0],
        initial_deflection="none",
    )
    model = gb.model
    delta = res.mesh("m").transmission_error
    ms = MeshSet(gb)
    tan_bb = math.tan(BETA) * math.cos(ALPHA_T)
    omega_h = math.sqrt(K_AXIAL / 2.0) * dt  # gear 2's mass: 2 kg
    samples = range(100, 800, 100)
    rates, rows_v, axial = [], [], []
    for i in samples:
        q = np.zeros(model.nq)
        v = np.zeros(model.nv)
        for j in range(1, model.njoints):
            joint = res.joint(model.names[j])
            angle, speed = float(joint.angle[i]), float(joint.speed[i])
            if model.joints[j].shortname().startswith("JointModelRUB"):  # (cos, sin)
                q[model.idx_qs[j] : model.idx_qs[j] + 2] = (math.cos(angle), math.sin(angle))
            else:
                q[model.idx_qs[j]] = angle
            v[model.idx_vs[j]] = speed
        data = model.createData()
        pin.computeJointJacobiansTimeVariation(model, data, q, v)
        rows = ms.evaluate(model, data)
        jac, _ = ms.combine(rows, np.array([1.0]))
        rates.append((delta[i + 1] - delta[i - 1]) / (2 * dt))
        rows_v.append(-(jac[0] @ v))
        axial.append(tan_bb * float(rows.jac_k[0] @ v))
    scale = max(abs(r) for r in rates)
    assert_allclose(rates, rows_v, rtol=0.0, atol=0.5 * omega_h**2 * scale)
    # the axial part is the real term here (gear 2's axial speed at P, times tan β_b)
    assert max(abs(a) for a in axial) > 0.5 * scale


@pytest.mark.parametrize("flank", [1.0, -1.0])
def test_the_row_is_the_transverse_line_of_action_plus_the_rate_of_the_flanks_axial_offset(flank):
    # The row of flank s is n·(v_B(P) − v_A(P)) − s tan β_b Ż, Ż the rate at fixed P of the
    # axial offset Z of gear B's mid-plane from gear A's at P, (C_B − P)·k_B / (k·k_B) +
    # (P − C_A)·k: k_B·v_B(P) / (k·k_B) − k·v_A(P) (a body's mid-plane through C turns and
    # moves with it, and P − C_B lies in it when Z = 0). Both by central differences of the
    # material points of both gears at P and of the axes, over random states with the axial
    # slide and the tilts moving.
    gb = thrust_pair()
    model = gb.model
    rng = np.random.default_rng(3)
    ms = MeshSet(gb)
    tan_bb = math.tan(BETA) * math.cos(ALPHA_T)
    a_id, b_id = model.getJointId("a"), model.getJointId("b")
    for _ in range(4):
        q = pin.integrate(model, pin.neutral(model), rng.uniform(-1e-2, 1e-2, model.nv))
        v = rng.uniform(-1.0, 1.0, model.nv)
        data = model.createData()
        pin.computeJointJacobiansTimeVariation(model, data, q, v)
        rows = ms.evaluate(model, data)
        jac, _ = ms.combine(rows, np.array([flank]))
        p, k = rows.pitch_point[0], rows.axis[0]
        k_b = data.oMi[b_id].rotation[:, 2]  # gear 2's axis: its joint's z
        n = ms.line_of_action(rows, np.array([flank]))[0]
        h = 1e-6

        def point(joint_id, qq, data=data, p=p):
            d = model.createData()
            pin.forwardKinematics(model, d, qq)
            return d.oMi[joint_id].act(data.oMi[joint_id].actInv(p))

        plus, minus = pin.integrate(model, q, v * h), pin.integrate(model, q, -v * h)
        v_a = (point(a_id, plus) - point(a_id, minus)) / (2 * h)
        v_b = (point(b_id, plus) - point(b_id, minus)) / (2 * h)
        z_rate = k_b @ v_b / (k @ k_b) - k @ v_a
        assert_allclose(jac[0] @ v, n @ (v_b - v_a) - flank * tan_bb * z_rate, rtol=1e-7)
        assert abs(z_rate) > 1e-2 * abs(jac[0] @ v)  # the axial part is a real term here


def test_a_tilted_gear_s_spin_is_no_axial_motion_of_its_flank():
    # Gear 2 tilted on its hinges turns about its own (tilted) axis: its mid-plane stays where
    # it is, so the row's axial part has no entry in gear 2's spin column; the material point
    # at P does move along k, by ω (P − C_B)·(k × k_B) (here ω r_2 θ_x with the tilt θ_x about
    # the centre line x), which a row along k·v_B(P) would count.
    gb = thrust_pair()
    model = gb.model
    q = pin.neutral(model)
    theta = 1e-3
    q[model.idx_qs[model.getJointId("b_tilt_x")]] = theta
    data = model.createData()
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    rows = MeshSet(gb).evaluate(model, data)
    spin = model.idx_vs[model.getJointId("b")]
    assert abs(rows.jac_k[0, spin]) <= 1e-15
    b_id = model.getJointId("b")
    k_b = data.oMi[b_id].rotation[:, 2]
    lever = rows.pitch_point[0] - data.oMi[b_id].translation
    material = float(rows.axis[0] @ np.cross(k_b, lever))
    assert_allclose(abs(material), R2 * math.sin(theta), rtol=1e-3)


@pytest.mark.parametrize("kind", ["compliant", "sliced"])
def test_the_ledger_closes_with_the_driven_gear_ringing_on_its_axial_slide_and_tilt(kind):
    # Released undeflected under the torque (no static start): the mesh loads, gear 2 rings on
    # its axial and tilt springs through the thrust, and the trapezoidal step (ρ∞ = 1) keeps the
    # energy of the linear springs; the mesh's overlap is a potential whose gradient is its row
    # only if both carry the axial part with the same sign.
    gb = thrust_pair(kind=kind)
    res = pinwind.simulate(
        gb,
        duration=2e-3,
        dt=2e-6,
        torques={"a": TORQUE},
        speeds={"b": 0.0},
        initial_deflection="none",
    )
    z = res.bearing("b").displacement[:, 2]
    f_a = TORQUE * math.tan(BETA) / R1
    # the slide rings about −F_a / k_a, reaching about twice it
    assert z.min() < -1.5 * f_a / K_AXIAL
    residual = ledger_residual(res)
    assert np.max(np.abs(residual)) <= 1e-6 * energy_scale(res)


@pytest.mark.parametrize("flank", [1.0, -1.0])
def test_the_row_s_bias_is_its_time_derivative_at_zero_acceleration_with_the_slides_moving(flank):
    # A rigid helical mesh's constraint ċ = J q̈ + γ: γ (with the axial part's k̇·Δv + k·Δa_s(P) +
    # k·((ω_B − ω_A) × Ṗ)) by central differences of J(q(t)) v(t) along q̈ = a.
    gb = thrust_pair()
    model = gb.model
    rng = np.random.default_rng(5)
    ms = MeshSet(gb)
    f = np.array([flank])

    def row_and_bias(q, v):
        data = model.createData()
        pin.computeJointJacobiansTimeVariation(model, data, q, v)
        ms.set_velocity(v)
        rows = ms.evaluate(model, data)
        jac, bias = ms.combine(rows, f)
        return jac[0], bias[0], rows

    for _ in range(4):
        q = pin.integrate(model, pin.neutral(model), rng.uniform(-0.05, 0.05, model.nv))
        v = rng.uniform(-3.0, 3.0, model.nv)
        a = rng.uniform(-5.0, 5.0, model.nv)
        jac, bias, rows = row_and_bias(q, v)
        h = 1e-6  # the difference's error, O(h²), ~1e-9 of c̈ here; rounding ~1e-8

        def c(s, q=q, v=v, a=a):
            js, _, rs = row_and_bias(pin.integrate(model, q, v * s + 0.5 * a * s * s), v + a * s)
            return js @ (v + a * s), rs.jac_k[0] @ (v + a * s)

        (plus, plus_k), (minus, minus_k) = c(h), c(-h)
        assert_allclose(jac @ a + bias, (plus - minus) / (2 * h), rtol=1e-7, atol=1e-7)
        # the axial part alone, k·(v_B(P) − v_A(P)) and its bias
        axial = rows.jac_k[0] @ a + rows.bias_k[0]
        assert_allclose(axial, (plus_k - minus_k) / (2 * h), rtol=1e-7, atol=1e-8)
        assert abs(rows.bias_k[0]) > 1e-3  # the tilts make the axial part's bias a real term
