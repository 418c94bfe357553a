"""Compliant and floating bearings: a disc on a linear bearing, clearance, a floating sun."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.analysis import load_sharing
from pinwind.dynamics.compliant import mesh_choices, mesh_setup
from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import InvalidBearingCompliance, PinwindWarning, UnheldMember
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from pinwind.testing.tangents import element_stepper
from tests.conftest import MODELS
from tests.test_cli import run

MASS, STIFFNESS, G = 10.0, 1e6, 9.81


def disc_urdf(bearing: str) -> str:
    """A 10 kg disc on bearing "disc" (axis z) at the ground, gravity along −y."""
    return f"""<robot name="disc">
  <link name="ground"/>
  <link name="disc"><inertial><mass value="{MASS!r}"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.2" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="disc" type="continuous"><parent link="ground"/><child link="disc"/>
    <origin xyz="0.1 0.2 0"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 {-G!r} 0">
    <bearing joint="disc" {bearing}/>
  </gearbox>
</robot>"""


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def _crossing_period(t: np.ndarray, x: np.ndarray) -> float:
    """Mean period of x(t) from its upward zero crossings, linearly interpolated [s]."""
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    times = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    return float(np.mean(np.diff(times)))


def test_a_disc_on_a_linear_bearing_has_its_translational_mode_at_sqrt_k_over_m():
    gb = loads(disc_urdf(f'radial_stiffness="{STIFFNESS!r}"'))
    modes = [m for m in linearise(gb).modes() if not m.rigid]
    expected = math.sqrt(STIFFNESS / MASS) / (2 * math.pi)
    np.testing.assert_allclose([m.frequency for m in modes], [expected, expected], rtol=1e-12)
    for m in modes:  # all the mode's strain energy is in the bearing's radial springs
        np.testing.assert_allclose(
            m.strain_share["disc_radial_x"] + m.strain_share["disc_radial_y"], 1.0, rtol=1e-12
        )


def test_axial_and_tilt_springs_give_sqrt_ka_over_m_and_sqrt_kt_over_i_and_the_damper_its_ratio():
    axial, tilt, damping = 4e6, 1e4, 100.0
    gb = loads(
        disc_urdf(
            f'radial_stiffness="{STIFFNESS!r}" radial_damping="{damping!r}" '
            f'axial_stiffness="{axial!r}" tilt_stiffness="{tilt!r}"'
        )
    )
    modes = {
        max(m.kinetic_share, key=m.kinetic_share.get): m
        for m in linearise(gb).modes()
        if not m.rigid
    }
    hz = 1 / (2 * math.pi)
    i_radial = 0.1  # the disc's Ixx = Iyy [kg·m²] about its centre, the bearing centre
    expected = {
        "disc_radial_x": math.sqrt(STIFFNESS / MASS) * hz,
        "disc_radial_y": math.sqrt(STIFFNESS / MASS) * hz,
        "disc_axial": math.sqrt(axial / MASS) * hz,
        "disc_tilt_x": math.sqrt(tilt / i_radial) * hz,
        "disc_tilt_y": math.sqrt(tilt / i_radial) * hz,
    }
    assert set(modes) == set(expected)
    for name, frequency in expected.items():
        np.testing.assert_allclose(modes[name].frequency, frequency, rtol=1e-9, err_msg=name)
    ratio = damping / (2 * math.sqrt(STIFFNESS * MASS))  # ζ = c / (2 √(k m))
    np.testing.assert_allclose(modes["disc_radial_x"].damping_ratio, ratio, rtol=1e-9)
    np.testing.assert_allclose(modes["disc_axial"].damping_ratio, 0.0, atol=0.0)


def test_a_disc_released_under_gravity_swings_at_sqrt_k_over_m_about_its_sag():
    gb = loads(disc_urdf(f'radial_stiffness="{STIFFNESS!r}"'))
    res = _run(gb, duration=0.4, dt=1e-4, initial_deflection="none")
    sag = MASS * G / STIFFNESS
    y = res.bearing("disc").displacement[:, 1]
    omega = math.sqrt(STIFFNESS / MASS)
    np.testing.assert_allclose(_crossing_period(res.time, y + sag), 2 * math.pi / omega, rtol=2e-4)
    # Released at rest from the bearing centre: y = −sag (1 − cos ω̃t), down to twice the sag,
    # with the trapezoidal step's frequency ω̃ = (2/h) atan(ωh/2) (its only error: the period).
    h = res.time[1]
    discrete = 2.0 / h * math.atan(omega * h / 2.0)
    np.testing.assert_allclose(y, -sag * (1 - np.cos(discrete * res.time)), atol=1e-6 * sag)
    np.testing.assert_allclose(res.bearing("disc").displacement[:, [0, 2]], 0.0, atol=1e-15)


def test_the_static_start_puts_the_disc_at_its_sag_m_g_over_k_carried_by_the_bearing():
    gb = loads(disc_urdf(f'radial_stiffness="{STIFFNESS!r}" radial_damping="500"'))
    res = _run(gb, duration=0.01, dt=1e-4)
    bearing = res.bearing("disc")
    np.testing.assert_allclose(bearing.displacement[:, 1], -MASS * G / STIFFNESS, rtol=1e-9)
    # The spring holds the weight, and the bearing's reaction on the disc is that force.
    np.testing.assert_allclose(bearing.elastic_force[:, 1], MASS * G, rtol=1e-9)
    np.testing.assert_allclose(bearing.force_local[:, 1], MASS * G, rtol=1e-9)
    np.testing.assert_allclose(bearing.force_local[:, [0, 2]], 0.0, atol=1e-9)


def test_a_disc_on_an_axis_along_x_reads_its_radial_and_axial_sag_in_its_joint_frame():
    # The bearing's axis along x: its slides run along world y, z (radial) and x (axial), none
    # of them the joint frame's x, y, z in order. Gravity (−1, −g, 0) m/s² sags the disc by
    # m g / k along −y and by m · 1 / k_a along −x; the springs carry (1, g, 0) m.
    axial = 4e6
    text = disc_urdf(
        f'radial_stiffness="{STIFFNESS!r}" radial_damping="500" '
        f'axial_stiffness="{axial!r}" axial_damping="500"'
    )
    text = text.replace('<axis xyz="0 0 1"/>', '<axis xyz="1 0 0"/>')
    text = text.replace(f'gravity="0 {-G!r} 0"', f'gravity="-1.0 {-G!r} 0"')
    res = _run(loads(text), duration=0.001, dt=1e-4)
    bearing = res.bearing("disc")
    sag = [-MASS * 1.0 / axial, -MASS * G / STIFFNESS, 0.0]
    np.testing.assert_allclose(bearing.displacement, [sag] * len(res.time), rtol=1e-9, atol=1e-15)
    weight = [MASS * 1.0, MASS * G, 0.0]
    np.testing.assert_allclose(bearing.elastic_force, [weight] * len(res.time), rtol=1e-9,
                               atol=1e-9)  # fmt: skip


def test_the_slides_are_joints_not_bearings_or_bodies_and_the_disc_pose_holds_its_sag():
    gb = loads(disc_urdf(f'radial_stiffness="{STIFFNESS!r}" radial_damping="500"'))
    res = _run(gb, duration=0.001, dt=1e-4)
    assert res.joint_names == ["disc_radial_x", "disc_radial_y", "disc"]
    # The slides' links are massless and their reaction is the bearing's: one bearing, the
    # file's two links.
    assert res.bearing_names == ["disc"]
    assert res.body_names == ["ground", "disc"]
    # The disc's recorded pose is its joint origin (0.1, 0.2, 0) lowered by its sag m g / k.
    disc = res.body_names.index("disc")
    np.testing.assert_allclose(
        res.body_position[:, disc], [[0.1, 0.2 - MASS * G / STIFFNESS, 0.0]] * len(res.time),
        rtol=0.0, atol=1e-12,
    )  # fmt: skip


def test_a_turning_disc_reads_its_weight_in_its_own_turning_frame():
    # Driven at 20 rad/s from its sag, the disc's bearing carries its weight m g (up, world y)
    # in the disc's joint frame, which turns by θ about z: (m g sin θ, m g cos θ, 0).
    gb = loads(disc_urdf(f'radial_stiffness="{STIFFNESS!r}" radial_damping="500"'))
    res = _run(gb, duration=0.05, dt=1e-4, speeds={"disc": 20.0})
    theta = res.joint("disc").angle
    assert theta[-1] > 0.9  # about 1 rad turned
    expected = MASS * G * np.stack([np.sin(theta), np.cos(theta), 0.0 * theta], axis=1)
    np.testing.assert_allclose(res.bearing("disc").force_local, expected, rtol=0, atol=1e-6)
    np.testing.assert_allclose(res.bearing("disc").force[:, 1], MASS * G, rtol=1e-9)


def test_inside_its_clearance_the_disc_falls_freely_then_rests_at_clearance_plus_sag():
    clearance = 50e-6
    gb = loads(
        disc_urdf(
            f'radial_stiffness="{STIFFNESS!r}" radial_damping="1500" '
            f'radial_clearance_mm="{clearance * 1e3!r}"'
        )
    )
    res = _run(gb, duration=0.3, dt=1e-5, initial_deflection="none")
    bearing = res.bearing("disc")
    radius = np.hypot(bearing.displacement[:, 0], bearing.displacement[:, 1])
    inside = radius < clearance
    assert inside.sum() > 100
    # No force while |r| < c: the disc falls as a free body, y = −g t²/2.
    np.testing.assert_allclose(bearing.elastic_force[inside], 0.0, atol=0.0)
    t = res.time[inside]
    np.testing.assert_allclose(bearing.displacement[inside, 1], -0.5 * G * t**2, atol=1e-10)
    # At rest it presses on the bearing with its weight: |r| = c + m g / k.
    np.testing.assert_allclose(radius[-1], clearance + MASS * G / STIFFNESS, rtol=1e-6)
    np.testing.assert_allclose(bearing.force_local[-1, 1], MASS * G, rtol=1e-6)


def test_an_ideal_bearing_has_no_displacement_and_no_elastic_force():
    gb = loads(disc_urdf('type="deep_groove_ball" rating_c_kN="100"'))
    res = _run(gb, duration=0.001, dt=1e-4)
    assert res.joint_names == ["disc"]
    np.testing.assert_allclose(res.bearing_displacement, 0.0, atol=0.0)
    np.testing.assert_allclose(res.bearing_elastic_force, 0.0, atol=0.0)
    np.testing.assert_allclose(res.bearing("disc").force_local[:, 1], MASS * G, rtol=1e-12)


@pytest.mark.parametrize(
    ("attributes", "attribute"),
    [
        ('radial_stiffness="-1e6"', "radial_stiffness"),
        ('radial_stiffness="nan"', "radial_stiffness"),
        ('radial_stiffness="1e6" radial_clearance_mm="-0.01"', "radial_clearance_mm"),
        ('radial_stiffness="1e6" radial_clearance_mm="nan"', "radial_clearance_mm"),
        ('radial_stiffness="1e6" axial_stiffness="-5"', "axial_stiffness"),
    ],
)
def test_a_negative_or_nan_bearing_stiffness_or_clearance_is_refused_with_its_value(
    attributes, attribute
):
    with pytest.raises(InvalidBearingCompliance, match=attribute) as err:
        loads(disc_urdf(attributes))
    assert err.value.bearing == "disc"
    assert err.value.attribute == attribute
    assert not err.value.value >= 0.0  # negative or NaN, kept


def test_a_floating_disc_with_nothing_to_hold_it_is_refused_naming_its_free_motion():
    gb = loads(disc_urdf('floating="true"'))
    with pytest.raises(UnheldMember, match="disc_radial_") as err:
        linearise(gb)
    assert err.value.bearing == "disc"
    assert set(err.value.motion) <= {"disc_radial_x", "disc_radial_y"}
    with pytest.raises(UnheldMember):
        _run(gb, duration=0.001, dt=1e-4)


# --- a floating sun in a planetary stage ----------------------------------------------------------

K_PAIR, SUN_TORQUE = 5e9, 1e5


def _saleh(floating: bool):
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    if floating:
        text = text.replace("</gearbox>", '  <bearing joint="sun" floating="true"/>\n</gearbox>')
    return loads(text, "saleh.urdf")


def _stage_run(gb, errors):
    compliance = MeshCompliance(stiffness=K_PAIR, variation="constant", damping_ratio=0.3)
    return _run(
        gb,
        duration=0.03,
        dt=1e-5,
        torques={"sun": SUN_TORQUE},
        speeds={"carrier": 0.0},
        gravity=np.zeros(3),
        meshes={"all": compliance},
        position_errors=errors,
    )


def _network_forces(gb, errors) -> np.ndarray:
    """Mesh forces of the stage's linear stiffness network at rest (carrier held).

    Each mesh a spring k_m = c_γα b along its row J_m (front flank for the sun meshes, back for
    the ring meshes); a pin error e of a planet shifts its meshes' deflections by n_m·e. The
    free coordinates are the sun's and planets' angles and, for a floating sun, its two radial
    slides: Jᵀ K (J dq − offsets) = τ, F = K (offsets − J dq).
    """
    model = gb.model
    data = model.createData()
    pin.computeJointJacobiansTimeVariation(model, data, gb.neutral(), np.zeros(model.nv))
    ms = MeshSet(gb)
    rows = ms.evaluate(model, data)
    flank = np.array([1.0 if m.name.startswith("sun") else -1.0 for m in gb.meshes])
    jac, _ = ms.combine(rows, flank)
    normal = ms.line_of_action(rows, flank)
    axis = np.array([0.0, 0.0, 1.0])
    offsets = np.zeros(len(gb.meshes))
    for i, m in enumerate(gb.meshes):
        for gear, sign in ((m.gear_a, 1.0), (m.gear_b, -1.0)):
            if gear.name in errors:
                centre = data.oMi[gear.joint_id].translation
                radial = centre / np.linalg.norm(centre)
                tangential, radial_error = errors[gear.name]
                e = tangential * np.cross(axis, radial) + radial_error * radial
                offsets[i] += sign * normal[i] @ e
    free = [gb.v_index(j) for j in ("sun", "planet1", "planet2", "planet3", *gb.slide_joints)]
    k = np.array([K_PAIR * (0.75 * m.path.contact_ratio + 0.25) for m in gb.meshes])
    jf = jac[:, free]
    tau = np.zeros(len(free))
    tau[0] = SUN_TORQUE
    dq = np.linalg.solve(jf.T @ (k[:, None] * jf), tau + jf.T @ (k * offsets))
    return k * (offsets - jf @ dq)


def test_a_floating_sun_in_a_perfect_stage_shares_the_load_equally():
    gb = _saleh(floating=True)
    res = _stage_run(gb, {})
    sun = {s.gear: s for s in load_sharing(res, gb)}["sun"]
    np.testing.assert_allclose(sun.factor[-1], 1.0, atol=1e-9)
    np.testing.assert_allclose(res.bearing("sun").displacement[-1], 0.0, atol=1e-12)
    np.testing.assert_allclose(res.mesh_normal[-1], _network_forces(gb, {}), rtol=1e-7)


def test_a_floating_sun_shares_a_pin_error_better_than_a_fixed_one_as_the_network_says():
    errors = {"planet1": (10e-6, 0.0)}
    factors = {}
    for floating in (False, True):
        gb = _saleh(floating)
        res = _stage_run(gb, errors)
        expected = _network_forces(gb, errors)
        # The network is linear about the reference pose; the run's geometry follows the sun's
        # and planets' displacements (µm on a 180 mm sun): agreement to 1e-4.
        np.testing.assert_allclose(res.mesh_normal[-1], expected, rtol=1e-4)
        sun = {s.gear: s for s in load_sharing(res, gb)}["sun"]
        np.testing.assert_allclose(
            sun.factor[-1], expected[:3].max() / expected[:3].mean(), rtol=1e-4
        )
        factors[floating] = sun.factor[-1]
    assert factors[True] < factors[False]
    assert factors[False] > 1.01
    # Three planets and a sun free to move in its plane: three meshes, three sun coordinates,
    # so the floating sun takes up the pin error and the planets share alike.
    np.testing.assert_allclose(factors[True], 1.0, atol=1e-4)


@pytest.mark.parametrize(
    ("bearing", "command", "message"),
    [
        ('radial_stiffness="-1e6"', "simulate", "radial_stiffness is -1e+06 N/m; give a finite"),
        ('radial_stiffness="1e6" radial_clearance_mm="nan"', "simulate", "radial_clearance_mm"),
        ('floating="true"', "simulate", 'the floating bearing "disc" lets its body move freely'),
        ('floating="true"', "modes", "disc_radial_"),
    ],
)
def test_bad_bearing_compliance_exits_2_in_one_line(tmp_path, bearing, command, message):
    model = tmp_path / "disc.urdf"
    model.write_text(disc_urdf(bearing))
    args = ["--duration", "0.01", "--dt", "1e-3", "--no-log"] if command == "simulate" else []
    out = run(command, str(model), *args, cwd=tmp_path)
    assert out.returncode == 2, out.stderr
    assert message in out.stderr
    assert out.stderr.count("\n") == 1, out.stderr


def test_a_disc_in_a_bearing_with_clearance_starts_sagged_across_its_clearance():
    """The static start carries the disc across its radial clearance c to the wall its weight
    pushes it to, then deflects the bearing by m g / k: y = −(c + m g / k), and the run starts at
    rest there."""
    clearance = 20e-6
    gb = loads(
        disc_urdf(f'radial_stiffness="{STIFFNESS!r}" radial_clearance_mm="{clearance * 1e3!r}"')
    )
    res = _run(gb, duration=1e-3, dt=1e-4)
    sag = clearance + MASS * G / STIFFNESS
    np.testing.assert_allclose(res.joint("disc_radial_y").angle, -sag, rtol=1e-9)
    np.testing.assert_allclose(res.joint("disc_radial_x").angle, 0.0, atol=1e-15)
    np.testing.assert_allclose(res.joint("disc_radial_y").speed, 0.0, atol=1e-9)


def _saleh_in_radial_bearings():
    """Saleh 2017's stage with sun, carrier and planets each in a radial bearing of 2e9 N/m (two
    slides), undamped: the elements' damping is then the meshes' alone."""
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    turning = [j for j in gb.joint_names if j not in gb.locked_joints]
    bearings = "".join(f'<bearing joint="{j}" radial_stiffness="2e9"/>' for j in turning)
    return loads(gb.source_text.replace("</gearbox>", bearings + "</gearbox>"), "saleh.urdf")


def _flank_overlaps(gb, setup, data: pin.Data, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each compliant mesh's flank overlaps (δ_f, δ_b) [m] and cos α' [-] at q, from the poses.

    The overlap of two involute flanks along the line of action (IFToMM 2018 eqs. 2-6,
    Jørgensen 2014 eqs. 14-19), recomputed here with Pinocchio's placements: ψ_A, ψ_B the gears'
    angles about A's axis k from the centre line (their tooth-0 directions, ``reference_a`` and
    ``reference_b``), T = r_A ψ_A − r_B ψ_B with signed base radii, wrapped into one base pitch
    p_b about the middle of the backlash gap, and the radial part of the centre distance a
    perpendicular to k, R = κ S (inv α'(a) − inv α'_ref) with cos α'(a) = S / a (ISO 21771's
    working pressure angle): δ_f = wrap(T − T_ref + e_T) + R + e_R, δ_b = −wrap(…) + R + e_R − j.
    """
    pin.forwardKinematics(gb.model, data, q)
    overlaps, cosines = [], []
    for spec in setup.compliant:
        mesh, path = setup.meshes[spec.mesh], setup.paths[spec.mesh]
        place_a, place_b = data.oMi[mesh.gear_a.joint_id], data.oMi[mesh.gear_b.joint_id]
        k = place_a.rotation @ mesh.gear_a.axis_in_joint
        d = place_b.act(mesh.gear_b.centre_in_joint) - place_a.act(mesh.gear_a.centre_in_joint)
        d -= (d @ k) * k
        a = np.linalg.norm(d)
        u = d / a

        def angle(e: np.ndarray, u: np.ndarray = u, k: np.ndarray = k) -> float:
            return math.atan2(k @ np.cross(u, e), u @ e)

        psi_a = angle(place_a.rotation @ np.asarray(path.reference_a))
        psi_b = angle(place_b.rotation @ np.asarray(spec.reference_b))
        rolling = spec.base_radius_a * psi_a - spec.base_radius_b * psi_b
        rolling += spec.tangential_offset - spec.tangential_ref
        rolling -= path.base_pitch * round((rolling + spec.backlash / 2) / path.base_pitch)
        cos_w = min(1.0, spec.base_radius_sum / a)
        involute = math.tan(math.acos(cos_w)) - math.acos(cos_w)
        radial = spec.radial_sign * spec.base_radius_sum * (involute - spec.involute_ref)
        radial += spec.radial_offset
        overlaps.append((rolling + radial, -rolling + radial - spec.backlash))
        cosines.append(cos_w)
    return np.array(overlaps), np.array(cosines)


def test_the_mesh_overlap_changes_at_minus_the_row_times_the_speeds_while_the_centres_move():
    """δ̇ = −J v for each flank of every compliant mesh of a stage whose centres vibrate.

    The stage starts undeflected under 1e6 N·m on the carrier with the sun held at 8.92 rad/s,
    and its members swing in their bearings. At seeded samples of the run, (1) the
    overlaps recomputed from the poses are the logged transmission error (the front flank's);
    (2) their central difference along the logged speeds, (δ(q + εv) − δ(q − εv)) / 2ε, is −J v
    with J the compiled flank row (``mesh_rows``, ``cpp/mesh_rows.hpp`` flank_row) at the
    working pressure angle of the current centre distance; (3) that row is the one the compliant
    mesh steps with: the elements' damping matrix is Σ c Jᵀ J over the flanks that overlap.

    The time series alone cannot settle (2) to better than the step's error: the central
    difference of the logged δ against J v at the samples differs by O(dt²) (0.29 %, 0.073 %,
    0.018 % at dt 2e-5, 1e-5, 5e-6 s on the run with damped bearings) and by O(dt) at the
    samples next to a change of the number of tooth pairs (a jump in the stiffness).
    """
    gb = _saleh_in_radial_bearings()
    damping = 1e4  # [N·s/m], each mesh's
    compliance = MeshCompliance(damping=damping)
    res = _run(
        gb, duration=2e-3, dt=2e-5, torques={"carrier": 1e6}, speeds={"sun": 8.92},
        meshes={"all": compliance}, initial_deflection="none",
    )  # fmt: skip
    stepper = element_stepper(gb, meshes={"all": compliance})
    setup = mesh_setup(gb, mesh_choices(gb, {"all": compliance}), driver_index=[], dt=None)
    assert [s.mesh for s in setup.compliant] == list(range(len(gb.meshes)))
    model = gb.model
    data = model.createData()
    mesh_set = MeshSet(gb, setup.meshes)
    slides = [gb.v_index(j) for j in gb.slide_joints]
    # [s]: q moved by up to 2e-5 m (slides) and 3e-4 rad; the truncation, ~(2e-5 m / a)², is
    # 1e-9 of the rate
    eps = 3e-5
    samples = np.random.default_rng(5).choice(np.arange(20, len(res.time)), 5, replace=False)
    for n in samples:
        q, v = res.angle[n], res.speed[n]
        assert np.abs(v[slides]).max() > 1e-3  # the centres move [m/s]
        overlaps, cos_w = _flank_overlaps(gb, setup, data, q)
        np.testing.assert_allclose(overlaps[:, 0], res.transmission_error[n], rtol=0, atol=1e-15)
        rate = (
            _flank_overlaps(gb, setup, data, q + eps * v)[0]
            - _flank_overlaps(gb, setup, data, q - eps * v)[0]
        ) / (2 * eps)
        mesh_set.constants.cos_a = cos_w
        mesh_set.constants.sin_a = np.sqrt(1.0 - cos_w**2)
        pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
        rows = mesh_set.evaluate(model, data)
        jv = np.stack([rows.row_front @ v, rows.row_back @ v], axis=1)
        # the centres' motion matters: the rows' radial part is 1e-3 of J v or more (1e4 times
        # the tolerance below)
        radial = np.abs(np.sqrt(1.0 - cos_w**2) * (rows.jac_r @ v))
        assert np.all(radial > 1e-3 * np.abs(jv[:, 0])), n
        np.testing.assert_allclose(rate, -jv, rtol=1e-7, err_msg=f"sample {n}")
        flanks = [*rows.row_front, *rows.row_back]
        overlapping = [*(overlaps[:, 0] >= 0.0), *(overlaps[:, 1] >= 0.0)]
        expected = damping * sum(
            np.outer(row, row) for row, on in zip(flanks, overlapping, strict=True) if on
        )
        np.testing.assert_allclose(
            stepper.element_forces(q, np.zeros(model.nv)).damping, expected, rtol=0,
            atol=1e-9 * np.abs(expected).max(),
        )  # fmt: skip
