"""The compiled step loop: its copy of the model, and runs cut into chunks."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.result import Result
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from tests.conftest import MODELS

SHIPPED = sorted(p.name for p in MODELS.glob("*.urdf"))


@pytest.mark.parametrize("name", SHIPPED)
def test_compiled_model_has_pinocchios_mass_matrix(name):
    """The C++ side rebuilds the joint tree from arrays: its M must be Pinocchio's own."""
    gb = pinwind.load(MODELS / name)
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
    gb = pinwind.load(MODELS / "cai_spur_pair.urdf")
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
