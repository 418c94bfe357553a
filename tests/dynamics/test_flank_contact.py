"""Compliant-mesh contact is a potential: each flank pushes where it overlaps, both at once.

The test pair (issue 36's): an undamped 20/40 spur pair of module 5 mm at its reference centre
distance, constant mesh stiffness, zero backlash, the pinion in a radial bearing of 1e8 N/m.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from pinwind.errors import PinwindWarning, StepTooCoarse
from pinwind.model.builders import planetary_urdf
from pinwind.model.gearbox import loads

MODULE, Z1, Z2 = 5e-3, 20, 40
CENTRE_DISTANCE = MODULE * (Z1 + Z2) / 2
ALPHA = math.radians(20.0)  # the working pressure angle at the reference centre distance
PINION_MASS, GEAR_MASS = 5.0, 20.0
BEARING_STIFFNESS = 1e8


def pair_urdf(
    *,
    bearing: str = f'<bearing joint="a" radial_stiffness="{BEARING_STIFFNESS!r}"/>',
    mesh: str = 'stiffness_variation="constant" damping="0" backlash_mm="0"',
    gravity: str = "0 0 0",
) -> str:
    """The test pair: pinion "a" at the origin, gear "b" at the centre distance along x."""
    return f"""<robot name="pair">
  <link name="housing"/>
  <link name="a"><inertial><mass value="{PINION_MASS!r}"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="{GEAR_MASS!r}"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.16" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="a" type="continuous"><parent link="housing"/><child link="a"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="b" type="continuous"><parent link="housing"/><child link="b"/>
    <origin xyz="{CENTRE_DISTANCE!r} 0 0"/><axis xyz="0 0 1"/></joint>
  <gearbox gravity="{gravity}">
    <gear name="g1" link="a" teeth="{Z1}" module_mm="{MODULE * 1e3!r}" face_width_mm="40"/>
    <gear name="g2" link="b" teeth="{Z2}" module_mm="{MODULE * 1e3!r}" face_width_mm="40"/>
    <mesh name="m" gear1="g1" gear2="g2" type="compliant" {mesh}/>
    {bearing}
  </gearbox>
</robot>"""


def _simulate(gb: pinwind.Gearbox, **kwargs) -> pinwind.Result:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def _released(t: float, value: float) -> float:
    """A torque that deflects the start (t = 0) and is gone after it [N·m]."""
    return value if t <= 0.0 else 0.0


def _swinging_pair(dt: float, rho_infinity: float = 1.0) -> pinwind.Result:
    """The pair deflected by 500 N·m on the pinion and let go: it swings through zero load."""
    gb = loads(pair_urdf())
    return _simulate(
        gb,
        duration=0.05,
        dt=dt,
        torques={"a": lambda t: _released(t, 500.0), "b": lambda t: _released(t, -1000.0)},
        integrator=Integrator(rho_infinity=rho_infinity),
    )


def _energy(res: pinwind.Result) -> np.ndarray:
    """Kinetic + stored energy less the work the torques put in (the first step's) [J]."""
    return res.energy["kinetic"] + res.energy["potential_spring"] - res.energy["work_applied"]


def test_an_undamped_pair_in_a_compliant_bearing_keeps_its_energy_through_every_flank_change():
    res = _swinging_pair(dt=1e-5)
    energy = _energy(res)
    mesh = res.mesh("m")
    # It does swing through zero load, and the centres come close enough for both flanks to push.
    assert np.count_nonzero(np.diff(mesh.flank)) > 100
    both = (mesh.normal_front > 0.0) & (mesh.normal_back > 0.0)
    assert np.count_nonzero(both) > 100
    np.testing.assert_allclose(energy, energy[0], rtol=0.01)


def test_the_energy_error_of_the_swinging_pair_falls_at_second_order_with_the_step():
    """The flanks open and close within steps; the error of those steps is O(dt²) (ρ∞ = 1)."""
    errors = []
    for dt in (1e-5, 5e-6):
        energy = _energy(_swinging_pair(dt=dt))
        errors.append(np.abs(energy / energy[0] - 1.0).max())
    assert errors[1] < errors[0] / 4


def test_numerical_damping_leaves_the_swinging_pair_bounded_and_losing_energy():
    """ρ∞ = 0.8 damps the unresolved modes; the flank changes may not pump energy back in."""
    energy = _energy(_swinging_pair(dt=1e-5, rho_infinity=0.8))
    assert energy.max() <= energy[0] * 1.01
    assert energy[-1] < energy[0]


def test_a_pinion_pressed_into_its_mate_loads_both_flanks_alike():
    """Gravity g along the centre line pushes the pinion towards the gear with m g.

    Moving the centres closer by x overlaps each flank by x sin α' (the radial part of the line
    of action, d inv α'/da (r_b1 + r_b2) = sin α'), so each pushes k x sin α' and both together
    hold 2 k x sin² α' of the weight, the bearing k_b x: x = m g / (k_b + 2 k sin² α').
    The flanks' tangential parts cancel, so neither gear turns.
    """
    g = 9.81
    gb = loads(pair_urdf(gravity=f"{g!r} 0 0"))
    with pytest.warns(StepTooCoarse):
        k = mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-4).compliant[0].stiffness
    res = _simulate(gb, duration=1e-4, dt=1e-4)
    x = PINION_MASS * g / (BEARING_STIFFNESS + 2 * k * math.sin(ALPHA) ** 2)
    flank_force = k * x * math.sin(ALPHA)
    mesh = res.mesh("m")
    # The overlap is linear in x to x / (a tan α') ≈ 1e-7 relative.
    np.testing.assert_allclose(mesh.normal_front[0], flank_force, rtol=1e-5)
    np.testing.assert_allclose(mesh.normal_back[0], flank_force, rtol=1e-5)
    np.testing.assert_allclose(res.joint("a").speed, 0.0, atol=1e-9)
    # The resultant on the gear is along the centre line: the pinion's weight less its bearing's.
    np.testing.assert_allclose(
        mesh.force_on_b[0], [2 * flank_force * math.sin(ALPHA), 0.0, 0.0], rtol=1e-5, atol=1e-6
    )


def _stepper(gb: pinwind.Gearbox) -> CompiledStepper:
    # dt is the assembly's, never stepped: that it does not resolve the mesh mode is said
    with pytest.warns(StepTooCoarse, match="highest mesh mode"):
        meshes = mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-4)
    return CompiledStepper(
        gb,
        2,
        gb.neutral(),
        np.zeros(gb.model.nv),
        dt=1e-4,
        gravity=gb.gravity,
        driver_index=[],
        driver_names=[],
        settings=SolverSettings(),
        meshes=meshes,
    )


def _states(gb: pinwind.Gearbox, seed: int, count: int) -> list[np.ndarray]:
    """Seeded states of the pair: the gears turned by up to ±10 µm at the pitch circle, the
    pinion's centre moved by up to ±10 µm: one flank, both or none overlapping."""
    rng = np.random.default_rng(seed)
    states = []
    for _ in range(count):
        spans = [10e-6 if kind == "prismatic" else 10e-6 / 0.05 for kind in gb.joint_kinds]
        states.append(gb.neutral() + rng.uniform(-1.0, 1.0, len(spans)) * spans)
    return states


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_mesh_force_is_the_gradient_of_its_flanks_potential(seed):
    """f = −∂U/∂q, U = Σ_flanks ½ k δ₊², by central differences at seeded states."""
    gb = loads(pair_urdf())
    stepper = _stepper(gb)
    nv = gb.model.nv
    overlapping = set()
    for q in _states(gb, seed, 8):
        at = stepper.element_forces(q, np.zeros(nv))
        h = 1e-8  # [rad or m]: 1e-3 of the states' spread, 1e-8 relative truncation
        gradient = np.array(
            [
                (
                    stepper.element_forces(q + h * e, np.zeros(nv)).potential
                    - stepper.element_forces(q - h * e, np.zeros(nv)).potential
                )
                / (2 * h)
                for e in np.eye(nv)
            ]
        )
        scale = max(abs(at.force).max(), 1e-3)
        np.testing.assert_allclose(at.force, -gradient, rtol=0, atol=1e-6 * scale)
        overlapping.add(at.potential > 0)
    assert overlapping == {True, False} or overlapping == {True}


def _floating_stage() -> pinwind.Gearbox:
    """Lin & Parker 1999's four-planet stage (z 24/24/72, module 10 mm, 20°) with sun, carrier
    and planets in radial bearings of 1e9 N/m, zero backlash, no gravity (whose sag would
    wedge the floating sun into the lower planets and preload their flanks)."""
    text = planetary_urdf(
        sun=24, planet=24, ring=72, planets=4, module=0.01, pressure_angle=ALPHA,
        face_width=0.1, name="stage4",
    )  # fmt: skip
    text = text.replace('gravity="0 -9.81 0"', 'gravity="0 0 0"')
    members = ["sun", "carrier", *(f"planet{i}" for i in range(1, 5))]
    bearings = "".join(f'<bearing joint="{m}" radial_stiffness="1e9"/>' for m in members)
    return loads(text.replace("</gearbox>", bearings + "</gearbox>"), "stage4.urdf")


#: The sun's base radius of the floating stage [m] and its quasi-static sun-planet force per
#: N·m of sun torque, shared by four planets [N/(N·m)].
SUN_BASE_RADIUS = 0.12 * math.cos(ALPHA)
FORCE_PER_TORQUE = 1.0 / (4 * SUN_BASE_RADIUS)


def test_a_torque_reversal_on_a_floating_stage_follows_the_quasi_static_forces():
    """A sun torque 100 cos(2π 50 t) N·m, the carrier held: 50 Hz is far below the stage's
    modes, so every sun-planet flank carries |T| / (4 r_b,s), changing flank at each reversal."""
    gb = _floating_stage()
    torque = lambda t: 100.0 * np.cos(2 * np.pi * 50.0 * t)  # noqa: E731
    res = _simulate(
        gb, duration=0.04, dt=1e-5, torques={"sun": torque}, speeds={"carrier": 0.0},
        meshes={"all": "compliant"},
    )  # fmt: skip
    quasi_static = np.abs(torque(res.time)) * FORCE_PER_TORQUE
    for name in (m.name for m in gb.meshes):
        mesh = res.mesh(name)
        assert np.count_nonzero(np.diff(mesh.flank)) >= 3, name  # four reversals in 0.04 s
        np.testing.assert_allclose(
            mesh.normal, quasi_static, rtol=0, atol=0.05 * quasi_static.max(), err_msg=name
        )


def test_a_floating_stage_loaded_from_an_undeflected_start_stays_bounded():
    """A step of 100 N·m on the sun from the undeflected pose. A linear system's response to a
    step peaks at twice the static force; flanks that open and close make this one piecewise
    linear, so the bound is three times (before the flanks were a potential it diverged: planets
    at 1e5 rad/s within 9 ms)."""
    gb = _floating_stage()
    res = _simulate(
        gb, duration=0.01, dt=1e-5, torques={"sun": 100.0}, speeds={"carrier": 0.0},
        meshes={"all": "compliant"}, initial_deflection="none",
    )  # fmt: skip
    static = 100.0 * FORCE_PER_TORQUE
    for name in (m.name for m in gb.meshes):
        assert res.mesh(name).normal.max() < 3.0 * static, name
    # What the torque put in is stored, moving, or lost to the mesh dampers, but for the step's
    # error where flanks open and close between moving centres: 1.8e-4, 0.5e-4 and 1.5e-4 of
    # the work at dt 1e-5, 5e-6 and 2.5e-6 s (the planets wedge between sun and ring on both
    # flanks, a motion sensitive to its start).
    e = res.energy
    balance = e["kinetic"] + e["potential_spring"] + e["dissipated"] - e["work_applied"]
    np.testing.assert_allclose(balance, 0.0, atol=5e-4 * e["work_applied"].max())


def test_the_ledger_of_a_damped_mesh_closes_to_rounding_while_one_flank_stays_loaded():
    """On fixed axes with constant stiffness and no flank change, the step's force is linear in
    the step (k and c both implicit, trapezoidal): the work of the torque is the kinetic and
    stored energy plus what the mesh damper took, to rounding."""
    gb = loads(pair_urdf(bearing="", mesh='stiffness_variation="constant" damping="2000"'))
    res = _simulate(
        gb, duration=0.02, dt=1e-5,
        torques={"a": lambda t: 50.0 + 20.0 * np.sin(2 * np.pi * 300.0 * t)},
        speeds={"b": 0.0},
    )  # fmt: skip
    assert np.all(res.mesh("m").flank == 1.0)
    e = res.energy
    assert e["dissipated"][-1] > 1e-3 * e["work_applied"].max()  # the damper does work
    balance = (
        e["kinetic"] + e["potential_spring"] + e["dissipated"] - e["work_applied"]
        - e["work_drivers"]
    )  # fmt: skip
    # (the static start's stored energy is there from the first sample)
    np.testing.assert_allclose(
        balance - balance[0], 0.0, atol=1e-9 * np.abs(e["work_applied"]).max()
    )


def test_flank_changes_on_step_boundaries_leave_the_ledger_closed_to_rounding():
    """A pinion bouncing in its backlash against a held gear, every contact change on a step.

    The pinion starts at rest, its front flank pressed by δ₀ under a torque k δ₀ r_b that is
    gone after the first step; it rings on that flank at its mesh mode, ω_n = r_b √(k/J), until
    the flank opens, flies through the gap j at δ₀ ω_n (its energy ½ k δ₀² all kinetic), rings
    on the back flank for half a period, and so on. The trapezoidal rule turns the mode by
    exactly θ = 2 atan(ω_n h/2) a step: with h = (2/ω_n) tan(π/(4N)) a quarter period is N
    steps, and with δ₀ = j / (ω_n M h) a flight M steps, so each flank opens and closes on a
    sample. The step's error is then only rounding: the ledger's numerical term is 1e-9 of
    the energy.
    """
    import pinocchio as pin

    backlash = 50e-6
    gb = loads(
        pair_urdf(
            bearing="",
            mesh=f'stiffness_variation="constant" damping="0" backlash_mm="{backlash * 1e3!r}"',
        )
    )
    k = mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-5).compliant[0].stiffness
    inertia = pin.crba(gb.model, gb.model.createData(), gb.neutral())[0, 0]  # J of joint a
    base_radius = MODULE * Z1 * math.cos(ALPHA) / 2
    omega_n = base_radius * math.sqrt(k / inertia)
    quarter_steps, flight_steps = 20, 30
    h = 2 / omega_n * math.tan(math.pi / (4 * quarter_steps))
    pressed = backlash / (omega_n * flight_steps * h)
    torque = k * pressed * base_radius
    res = _simulate(
        gb, duration=500 * h, dt=h, speeds={"b": 0.0},
        torques={"a": lambda t: _released(t, torque)},
    )  # fmt: skip
    mesh = res.mesh("m")
    np.testing.assert_allclose(mesh.normal_front[0], k * pressed, rtol=1e-9)
    loaded = (mesh.normal_front > 0) | (mesh.normal_back > 0)
    assert np.count_nonzero(np.diff(loaded.astype(int))) >= 8  # four bounces, in and out
    energy = 0.5 * k * pressed**2
    np.testing.assert_allclose(res.energy["numerical"], 0.0, atol=1e-9 * energy)
    np.testing.assert_allclose(
        res.energy["kinetic"] + res.energy["potential_spring"], energy, rtol=1e-9
    )
