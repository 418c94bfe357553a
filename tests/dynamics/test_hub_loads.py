"""Hub loads in a run: six components on a body carried by its bearing, turned with its shaft."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import InputError, PinwindWarning
from pinwind.loads.hub_loads import HubLoad, constant_hub_load, hub_load_from_openfast
from pinwind.model.gearbox import loads

#: The disc's bearing centre in the world [m] and its length to the rotor centre [m].
CENTRE, OVERHANG = (0.1, 0.2, 0.0), 1.5
#: F_x, F_y, F_z [N], M_x, M_y, M_z [N·m] in the hub frame: thrust, shears, no torque, bending.
COMPONENTS = np.array([8.0e5, -5.0e4, -1.1e6, 0.0, 2.5e6, -7.0e5])
INERTIA_ZZ = 0.2


def shaft_urdf(bearing: str = 'type="spherical_roller" rating_c_kN="2200"') -> str:
    """A shaft on bearing "shaft" (axis world z) at CENTRE, no gravity."""
    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="10"/>
    <inertia ixx="0.1" iyy="0.1" izz="{INERTIA_ZZ!r}" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <origin xyz="{CENTRE[0]!r} {CENTRE[1]!r} {CENTRE[2]!r}"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <bearing joint="shaft" {bearing}/>
  </gearbox>
</robot>"""


#: The hub axes in the world for this model with ``up`` = world y: x along the shaft axis
#: (world z), z up (world y), y = z × x (world x). Columns: the hub's x, y, z.
HUB_IN_WORLD = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def _expected_reaction(components: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bearing's reaction on the shaft at its centre: −f and −(m + r × f), r the overhang."""
    f = HUB_IN_WORLD @ components[:3]
    m = HUB_IN_WORLD @ components[3:]
    r = np.array([0.0, 0.0, OVERHANG])
    return -f, -(m + np.cross(r, f))


def test_a_fixed_frame_hub_load_at_the_overhang_is_carried_by_the_bearing_as_statics_says():
    load = constant_hub_load("shaft", COMPONENTS, point=(0.0, 0.0, OVERHANG), up=(0.0, 1.0, 0.0))
    res = _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, hub_loads=[load])
    force, moment = _expected_reaction(COMPONENTS)
    bearing = res.bearing("shaft")
    scale = np.max(np.abs(moment))
    assert_allclose(bearing.force, [force] * len(res.time), rtol=1e-12, atol=1e-9 * scale)
    assert_allclose(bearing.moment, [moment] * len(res.time), rtol=1e-12, atol=1e-9 * scale)
    assert_allclose(res.joint("shaft").speed, 0.0, atol=1e-12)  # no torque about the axis


def test_a_rotating_frame_load_equals_its_fixed_frame_form_turned_by_the_shaft_angle():
    # Driven at 20 rad/s, the shaft turns by θ = ω t; a load fixed in the shaft's turning frame
    # is, in the fixed frame, the same load turned by θ about x (loads/hub_loads.py):
    # F_y = cos θ F_ya − sin θ F_za, F_z = sin θ F_ya + cos θ F_za, and the moments alike.
    omega = 20.0
    rotating = constant_hub_load(
        "shaft", COMPONENTS, frame="rotating", point=(0.0, 0.0, OVERHANG), up=(0.0, 1.0, 0.0)
    )
    res = _run(loads(shaft_urdf()), duration=0.1, dt=1e-3, speeds={"shaft": omega},
               hub_loads=[rotating])  # fmt: skip
    theta = res.joint("shaft").angle
    assert_allclose(theta, omega * res.time, rtol=1e-12, atol=1e-12)
    c, s = np.cos(theta), np.sin(theta)
    turned = np.tile(COMPONENTS, (len(theta), 1))
    for y, z in ((1, 2), (4, 5)):
        turned[:, y] = c * COMPONENTS[y] - s * COMPONENTS[z]
        turned[:, z] = s * COMPONENTS[y] + c * COMPONENTS[z]
    expected = [_expected_reaction(row) for row in turned]
    bearing = res.bearing("shaft")
    scale = np.max(np.abs(COMPONENTS)) * OVERHANG
    assert_allclose(bearing.force, [f for f, _ in expected], rtol=0, atol=1e-9 * scale)
    assert_allclose(bearing.moment[:, :2], [m[:2] for _, m in expected], rtol=0, atol=1e-9 * scale)


def test_a_hub_torque_spins_the_free_shaft_with_its_work_in_the_energy_ledger():
    # M_x alone on a free shaft: ω = M t / I, kinetic energy (M t)²/(2 I), all of it applied work.
    torque, duration = 3.0, 0.5
    load = constant_hub_load("shaft", [0, 0, 0, torque, 0, 0], up=(0.0, 1.0, 0.0))
    res = _run(loads(shaft_urdf()), duration=duration, dt=1e-3, hub_loads=[load])
    assert_allclose(res.joint("shaft").speed, torque * res.time / INERTIA_ZZ, rtol=1e-12,
                    atol=1e-12)  # fmt: skip
    kinetic = (torque * res.time) ** 2 / (2 * INERTIA_ZZ)
    assert_allclose(res.energy["work_applied"], kinetic, rtol=1e-9, atol=1e-12)


def test_an_openfast_output_drives_the_shaft_with_the_load_its_channels_give(tmp_path):
    # Two samples of the six fixed-frame channels in kN and kN·m, constant: the reaction is the
    # one statics gives for COMPONENTS (N, N·m).
    header = ["", "OpenFAST", "", "", "test", "",
              "Time\tRotThrust\tLSShftFys\tLSShftFzs\tRotTorq\tLSSTipMys\tLSSTipMzs",
              "(s)\t(kN)\t(kN)\t(kN)\t(kN-m)\t(kN-m)\t(kN-m)"]  # fmt: skip
    row = "\t".join(f"{x / 1e3:.10g}" for x in COMPONENTS)
    path = tmp_path / "loads.out"
    path.write_text("\n".join([*header, f"0.0\t{row}", f"1.0\t{row}"]) + "\n")
    load = hub_load_from_openfast(path, "shaft", point=(0.0, 0.0, OVERHANG), up=(0.0, 1.0, 0.0))
    res = _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, hub_loads=[load])
    force, moment = _expected_reaction(COMPONENTS)
    assert_allclose(res.bearing("shaft").force[-1], force, rtol=1e-9)
    assert_allclose(res.bearing("shaft").moment[-1], moment, rtol=1e-9)


def test_a_hub_load_on_a_body_the_model_does_not_have_is_one_message_naming_the_bodies():
    load = constant_hub_load("rotor", COMPONENTS, up=(0.0, 1.0, 0.0))
    message = r'hub load on "rotor": no such body; bodies are: ground, shaft'
    with pytest.raises(InputError, match=message):
        _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, hub_loads=[load])


def test_without_gravity_or_an_up_direction_the_hub_frame_is_refused_saying_how_to_give_it():
    load = HubLoad("shaft", tuple(COMPONENTS))
    with pytest.raises(InputError, match=r'hub load on "shaft": .*give up='):
        _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, hub_loads=[load])


def test_an_up_direction_along_the_shaft_axis_is_refused():
    load = constant_hub_load("shaft", COMPONENTS, up=(0.0, 0.0, 2.0))
    with pytest.raises(InputError, match=r"parallel to the shaft axis"):
        _run(loads(shaft_urdf()), duration=0.01, dt=1e-3, hub_loads=[load])


def test_the_hub_frame_is_right_handed_with_x_on_the_axis_and_z_up():
    assert_allclose(np.cross(HUB_IN_WORLD[:, 2], HUB_IN_WORLD[:, 0]), HUB_IN_WORLD[:, 1])
    assert math.isclose(np.linalg.det(HUB_IN_WORLD), 1.0)


@pytest.mark.parametrize("damping", ["0", "2e4"])
@pytest.mark.parametrize("frame", ["fixed", "rotating"])
def test_the_energy_ledger_closes_with_varying_hub_loads_on_a_compliant_bearing(damping, frame):
    # Thrust, a shear force and a bending moment that vary in time on a shaft whose bearing
    # slides and tilts in one plane: Δ(K + U) = W_applied − dissipated to rounding. (A shaft
    # that spins while it tilts, or tilts about both radial axes, which couples into its spin,
    # leaves the step's own error on the gyroscopic terms, which the bias forces' explicit
    # extrapolation carries: 3e-8 of the energy scale here at dt = 1e-4 s without damping.)
    from pinwind.loads.signals import Constant, Sine
    from pinwind.testing import ledger_closure

    bearing = (f'radial_stiffness="1e8" radial_damping="{damping}" axial_stiffness="5e7" '
               f'axial_damping="{damping}" tilt_stiffness="1e7" '
               f'tilt_damping="{damping}"')  # fmt: skip
    # in the plane of the shaft axis and the hub's z: F_x, F_z, M_y (the torque has its own test)
    components = (Sine(1e4, 3e3, 7.0), Constant(0.0), Sine(-5e3, 2e3, 13.0, 0.3),
                  Constant(0.0), Sine(1e3, 4e2, 11.0), Constant(0.0))  # fmt: skip
    load = HubLoad("shaft", components, frame, (0.0, 0.0, OVERHANG), (0.0, 1.0, 0.0))
    res = _run(loads(shaft_urdf(bearing)), duration=0.5, dt=1e-4, hub_loads=[load])
    assert abs(res.energy["work_applied"][-1]) > 1e-3  # the loads did work
    ledger_closure(res, rtol=1e-12)


def test_element_forces_without_a_sample_s_inputs_leave_the_hub_loads_out():
    # Stepper.element_forces (the tangent checks) has no sample: the loads are inputs of one.
    import pinocchio as pin

    from pinwind.dynamics.drivetrain import drivetrain
    from pinwind.testing.tangents import element_stepper

    gb = loads(shaft_urdf('radial_stiffness="1e8" tilt_stiffness="1e7"'))
    load = constant_hub_load("shaft", COMPONENTS, point=(0.0, 0.0, OVERHANG), up=(0.0, 1.0, 0.0))
    stepper = element_stepper(drivetrain(gb, hub_loads=[load]))
    forces = stepper.element_forces(pin.neutral(gb.model), np.zeros(gb.model.nv))
    assert_allclose(forces.force, 0.0, atol=0.0)
