"""A run is prepare → step blocks → finish, each usable alone, with its settings in one object."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.dynamics import RunSettings, drivetrain, prepare
from pinwind.dynamics.simulate import simulate
from pinwind.errors import ConflictingInputs, InputError, StepTooCoarse, TorquesUnbalanced
from tests.conftest import MODELS

#: The Saleh stage at rated load: the sun brakes the carrier's torque at the ratio 6.
TORQUES = {"carrier": 1e6, "sun": -1e6 / 6}
SPEEDS = {"carrier": 14.2 * 2 * math.pi / 60}


@pytest.fixture(scope="module")
def stage() -> pinwind.Gearbox:
    return pinwind.load(MODELS / "saleh2017_planetary.urdf")


def _arrays(res: pinwind.Result) -> dict[str, np.ndarray]:
    return {
        name: np.asarray(getattr(res, name))
        for name in ("time", "angle", "speed", "mesh_normal", "bearing_force")
    } | {f"energy_{k}": v for k, v in res.energy.items()}


def test_a_prepared_run_stepped_block_by_block_gives_the_bits_of_simulate(stage):
    kwargs = dict(duration=0.05, dt=1e-3, meshes={"all": "compliant"})
    # 1 ms does not resolve the compliant meshes' modes (a test of blocks, not of the physics):
    # the run and the prepared run both say so
    with pytest.warns(StepTooCoarse, match="highest mesh mode"):
        whole = simulate(stage, torques=TORQUES, initial_speeds=SPEEDS, keep="all", **kwargs)
    train = drivetrain(stage, torques=TORQUES, initial_speeds=SPEEDS, meshes=kwargs["meshes"])
    with pytest.warns(StepTooCoarse, match="highest mesh mode"):
        run = prepare(train, duration=0.05, dt=1e-3, settings=RunSettings(keep="all", chunk=7))
    done = 0
    for start in range(0, run.samples, run.chunk):
        stop = min(start + run.chunk, run.samples)
        outcome = run.step_block(start, stop, run.result.rows(start, stop))
        assert outcome.error is None
        done = outcome.done
    # The energy ledger's numerical term is folded over the blocks by run(); compare the rest.
    res = run.finish(done, "completed")
    assert done == run.samples == 51
    for name, values in _arrays(whole).items():
        if name != "energy_numerical":
            np.testing.assert_array_equal(_arrays(res)[name], values, err_msg=name)


def test_prepare_takes_the_static_start_and_steps_nothing(stage):
    """The sun meshes of the compliant stage carry (1e6/6 N·m) / (3 r_b,sun) from sample 0."""
    train = drivetrain(stage, torques=TORQUES, meshes={"all": "compliant"})
    with pytest.warns(StepTooCoarse, match="highest mesh mode"):  # no step is taken
        run = prepare(train, duration=0.01, dt=1e-4)
    start = run.result.metadata["initial_deflection"]
    assert start["mode"] == "static" and start["converged"]
    assert run.result.metadata["samples_simulated"] == run.samples  # what it will simulate
    block = run.result.rows(0, 1)
    assert run.step_block(0, 1, block).done == 1
    sun_base_radius = 0.18 * math.cos(math.radians(24.5))  # Saleh 2017: r 180 mm, α 24.5°
    expected = 1e6 / 6 / (3 * sun_base_radius)
    np.testing.assert_allclose(block.mesh("sun_planet1").normal[0], expected, rtol=1e-6)


def test_finish_keeps_the_samples_before_where_the_run_stopped(stage):
    train = drivetrain(stage, torques=TORQUES)
    run = prepare(train, duration=0.1, dt=1e-3, settings=RunSettings(keep="all"))
    outcome = run.step_block(0, 10, run.result.rows(0, 10))
    res = run.finish(outcome.done, "interrupted at step 10")
    assert len(res) == 10 and res.status == "interrupted at step 10"
    np.testing.assert_allclose(res.time, np.arange(10) * 1e-3, rtol=0, atol=1e-15)


def test_run_settings_given_twice_are_refused_naming_both(stage):
    with pytest.raises(ConflictingInputs, match=r"keep='all'"):
        simulate(stage, duration=0.01, dt=1e-3, settings=RunSettings(), keep="all")


@pytest.mark.parametrize(
    ("field", "value", "named"),
    [
        ("keep", 0, "keep is 0"),
        ("chunk", 2.5, "chunk=2.5"),
        ("initial_deflection", "sagged", "initial_deflection='sagged'"),
        ("integrator", 0.8, "integrator=0.8"),
        ("progress", "yes", "progress='yes'"),
    ],
)
def test_run_settings_refuse_a_value_of_the_wrong_kind_naming_it(field, value, named):
    with pytest.raises(InputError, match=re_escape(named)):
        RunSettings(**{field: value})


def re_escape(text: str) -> str:
    import re

    return re.escape(text)


def test_a_run_s_warning_names_the_line_that_called_it(stage):
    for call in (pinwind.simulate, simulate):
        with pytest.warns(TorquesUnbalanced) as caught:
            call(stage, duration=0.01, dt=1e-3, torques={"carrier": 1e6})
        (warning,) = [w for w in caught if w.category is TorquesUnbalanced]
        assert warning.filename == __file__, call
