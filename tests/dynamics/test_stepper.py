"""The compiled step loop: its copy of the model, its assembly, its series, runs in chunks."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.dynamics import _native
from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.result import Result
from pinwind.dynamics.series import schema
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper, series_array
from pinwind.errors import StepTooCoarse, TorquesUnbalanced
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, load_model
from tests.dynamics.test_mesh_rows import SWING_ARM

SHIPPED = sorted(p.name for p in MODELS.glob("*.urdf"))


@pytest.mark.parametrize("name", SHIPPED)
def test_compiled_model_has_pinocchios_mass_matrix(name):
    """The C++ side rebuilds the joint tree from arrays: its M must be Pinocchio's own."""
    gb = load_model(MODELS / name)
    model = gb.model
    stepper = CompiledStepper(
        gb,
        2,
        gb.neutral(),
        np.zeros(model.nv),
        dt=1e-3,
        gravity=gb.gravity,
        driver_index=[],
        driver_names=[],
        settings=SolverSettings(),
        meshes=mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-3),
    )
    rng = np.random.default_rng(7)
    data = model.createData()
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        expected = pin.crba(model, data, q)
        expected = np.triu(expected) + np.triu(expected, 1).T
        np.testing.assert_allclose(
            stepper.mass_matrix(q), expected, rtol=0, atol=1e-12 * abs(expected).max()
        )


def _fields(res: Result) -> dict[str, np.ndarray]:
    out = {name: getattr(res, name) for name in Result.ARRAYS}
    out.update({f"energy.{k}": v for k, v in res.energy.items()})
    return out


def test_chunk_size_does_not_change_a_run():
    """The state carries over between chunks: 7-sample chunks give the same bits as one chunk."""
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    kwargs = dict(
        duration=0.05,
        dt=1e-4,
        torques={"input_shaft": lambda t: 20.0 + 5.0 * np.sin(300.0 * t)},
        speeds={"output_shaft": lambda t: 10.0 * t},
    )
    whole = pinwind.simulate(gb, chunk=100_000, **kwargs)
    pieces = pinwind.simulate(gb, chunk=7, **kwargs)
    for name, value in _fields(whole).items():
        np.testing.assert_array_equal(_fields(pieces)[name], value, err_msg=name)


def _stepper(gb: pinwind.Gearbox, driver_index: list[int]) -> CompiledStepper:
    return CompiledStepper(
        gb,
        2,
        gb.neutral(),
        np.zeros(gb.model.nv),
        dt=1e-3,
        gravity=gb.gravity,
        driver_index=driver_index,
        driver_names=[gb.joint_names[i] for i in driver_index],
        settings=SolverSettings(),
        meshes=mesh_setup(gb, gb.meshes, driver_index=driver_index, dt=1e-3),
    )


def _assert_assembly_is_pinocchios(
    gb: pinwind.Gearbox, seed: int, slides: Sequence[str] = ()
) -> None:
    """M is Pinocchio's CRBA and b = C(q, v) v + g(q) its RNEA at zero acceleration, at three
    random states; ``slides`` moved by up to 1 mm at up to 1 m/s, as a loose bearing's."""
    model = gb.model.copy()
    model.gravity = pin.Motion(np.asarray(gb.gravity, dtype=float), np.zeros(3))
    data = model.createData()
    stepper = _stepper(gb, [])
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        v = rng.uniform(-30.0, 30.0, model.nv)
        for slide in slides:
            q[gb.v_index(slide)] = rng.uniform(-1e-3, 1e-3)
            v[gb.v_index(slide)] = rng.uniform(-1.0, 1.0)
        assembly = stepper.assemble(q, v)
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        atol = 1e-12 * abs(mass).max()
        np.testing.assert_allclose(assembly.mass, mass, rtol=0, atol=atol)
        np.testing.assert_allclose(stepper.mass_matrix(q), mass, rtol=0, atol=atol)
        bias = pin.rnea(model, data, q, v, np.zeros(model.nv))
        # Coaxial gears under axial gravity have b ≈ 0: an absolute floor of 1e-10 N·m.
        scale = max(1.0, abs(bias).max())
        np.testing.assert_allclose(assembly.bias, bias, rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("name", SHIPPED)
def test_assembly_has_pinocchios_mass_matrix_and_bias_forces(name):
    """M is Pinocchio's CRBA and b = C(q, v) v + g(q) its RNEA at zero acceleration."""
    _assert_assembly_is_pinocchios(load_model(MODELS / name), seed=11)


def _all_bearings_compliant(name: str) -> pinwind.Gearbox:
    """The model with every turning bearing compliant radially, axially and in tilt: slides
    along x, y and z and tilt joints under every body (nv 6 -> 36 for the planetary stage)."""
    gb = load_model(MODELS / name)
    bearing = (
        'radial_stiffness="2e9" axial_stiffness="1e9" tilt_stiffness="1e8" radial_damping="1e4"'
    )
    text, lines = gb.source_text, ""
    for joint in (j for j in gb.joint_names if j not in gb.locked_joints):
        if joint in gb.source.bearings:  # a rated bearing keeps its rating
            text = text.replace(
                f'<bearing joint="{joint}"', f'<bearing joint="{joint}" {bearing}', 1
            )
        else:
            lines += f'  <bearing joint="{joint}" {bearing}/>\n'
    return loads(text.replace("</gearbox>", lines + "</gearbox>"), str(gb.path))


@pytest.mark.parametrize("name", ["saleh2017_planetary.urdf", "dtu500_planetary.urdf"])
def test_compliant_bearings_keep_pinocchios_mass_matrix_and_bias_forces(name):
    """The step places a compliant bearing's slides itself (joint_jacobians.cpp) and takes their
    rows of M and of J̇ v as pure translations (stepper_run.cpp): M must still be Pinocchio's
    CRBA and b its RNEA at zero acceleration, with every slide moved off its rest."""
    gb = _all_bearings_compliant(name)
    slides = [j for j in gb.joint_names if gb.model.joints[gb.model.getJointId(j)].shortname()
              in ("JointModelPX", "JointModelPY", "JointModelPZ")]  # fmt: skip
    assert len(slides) == 15  # three per turning bearing
    _assert_assembly_is_pinocchios(gb, seed=13, slides=slides)


def test_spur_mesh_row_is_base_radii_and_driver_row_is_unit():
    """Fixed axes: the mesh row is (r_b,A, r_b,B) with r_b = m z cos α / 2, γ = 0; J v = 0 at
    the gear ratio; a speed driver's row is e_i."""
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    nv = gb.model.nv
    a, b = gb.v_index("gear1"), gb.v_index("gear2")
    out = gb.v_index("output_shaft")
    stepper = _stepper(gb, [out])
    base_a = 0.5 * 3e-3 * 40 * np.cos(np.radians(20.0))
    base_b = 0.5 * 3e-3 * 80 * np.cos(np.radians(20.0))
    rng = np.random.default_rng(3)
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, gb.model.nq)
        v = rng.uniform(-10.0, 10.0, nv)
        assembly = stepper.assemble(q, v)
        assert assembly.jac.shape == (2, nv)
        mesh = assembly.jac[0]
        expected = np.zeros(nv)
        expected[a], expected[b] = base_a, base_b
        np.testing.assert_allclose(abs(mesh), expected, rtol=1e-12, atol=1e-15)
        assert mesh[a] * mesh[b] > 0.0  # external pair: the gears turn opposite ways
        driver = np.zeros(nv)
        driver[out] = 1.0
        np.testing.assert_array_equal(assembly.jac[1], driver)
        np.testing.assert_allclose(assembly.gamma, 0.0, rtol=0, atol=1e-9)
        on_manifold = v.copy()
        on_manifold[b] = -v[a] * 40 / 80
        np.testing.assert_allclose(mesh @ on_manifold, 0.0, rtol=0, atol=1e-12 * abs(v).max())


def test_every_compiled_series_has_a_result_array_of_its_layout():
    """The compiled table of series (cpp/series.hpp) names each Result array or ledger term,
    with the shape of its family's count and its components."""
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    # three steps of an accelerating pair: all the layout needs, and the run says both
    with pytest.warns(TorquesUnbalanced), pytest.warns(StepTooCoarse):
        res = pinwind.simulate(gb, duration=3e-3, dt=1e-3, torques={"input_shaft": 10.0})
    counts = {
        _native.Family.run: 1,
        _native.Family.joint: len(res.joint_names),
        _native.Family.mesh: len(res.mesh_names),
        _native.Family.bearing: len(res.bearing_names),
        _native.Family.body: len(res.body_names),
        _native.Family.generator: len(res.generator_names),
        _native.Family.rotor: len(res.rotor_names),
        _native.Family.row: len(res.row_names),
        _native.Family.slice: len(res.slice_names),
    }
    names = [series.name for series in _native.Series]
    derived = {s.name for s in schema() if s.derive is not None}  # computed in Python
    assert set(Result.ARRAYS) - derived <= set(names)
    for series in _native.Series:
        family, components = _native.series_layout(series)
        values = series_array(res, series.name)
        assert values.size == len(res) * counts[family] * components, series.name


def test_assembled_mesh_bias_is_the_time_derivative_of_its_row():
    """γ = J̇ v: central differences of the assembled row along q̇ = v, on the swing arm whose
    gear centre moves (its row changes with the angles)."""
    gb = loads(SWING_ARM, path="swing_arm.urdf")
    model = gb.model
    stepper = _stepper(gb, [])
    rng = np.random.default_rng(5)
    h = 1e-6
    for _ in range(3):
        q = rng.uniform(-0.3, 0.3, model.nq)
        v = rng.uniform(-2.0, 2.0, model.nv)
        ahead = stepper.assemble(pin.integrate(model, q, v * h), v).jac
        behind = stepper.assemble(pin.integrate(model, q, -v * h), v).jac
        gamma = stepper.assemble(q, v).gamma
        assert abs(gamma).max() > 1e-3  # the row does change
        np.testing.assert_allclose(gamma, (ahead - behind) / (2 * h) @ v, rtol=1e-6, atol=1e-9)
