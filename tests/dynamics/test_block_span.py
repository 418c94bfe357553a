"""A run nobody watches steps in the fewest blocks: the same bits as in a log's blocks."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.simulate import CHUNK, simulate
from tests.conftest import MODELS

#: The Saleh stage at rated load: the sun brakes the carrier's torque at the ratio 6.
TORQUES = {"carrier": 1e6, "sun": -1e6 / 6}
SPEEDS = {"carrier": 14.2 * 2 * math.pi / 60}
#: Samples of the runs: more than two of the blocks nobody watches, the last one shorter.
SAMPLES = 2 * CHUNK + 1001


def test_blocks_nobody_watches_are_the_longest_and_give_the_bits_of_short_ones(monkeypatch):
    stage = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    module = importlib.import_module("pinwind.dynamics.simulate")
    spans: list[int] = []
    step_block = module.PreparedRun.step_block

    def counted(self, start, stop, block, **kwargs):
        spans.append(stop - start)
        return step_block(self, start, stop, block, **kwargs)

    monkeypatch.setattr(module.PreparedRun, "step_block", counted)
    kwargs = dict(duration=(SAMPLES - 1) * 1e-3, dt=1e-3, torques=TORQUES, initial_speeds=SPEEDS)
    long = simulate(stage, **kwargs)
    assert spans == [CHUNK, CHUNK, 1001]
    spans.clear()
    short = simulate(stage, chunk=1000, **kwargs)  # the blocks a log of this run would get
    assert spans == [1000] * 11 + [1]
    derived = [s.name for s in long.schema.derived()]
    assert {"bearing_radial", "bearing_tilting", "bearing_torque"} <= set(derived)
    for name in long.ARRAYS:
        a, b = np.asarray(getattr(long, name)), np.asarray(getattr(short, name))
        assert np.array_equal(a.view(np.uint8), b.view(np.uint8)), name
    for term, values in long.energy.items():
        assert np.array_equal(values.view(np.uint8), short.energy[term].view(np.uint8)), term
    # and the derived series are those of the step's own: the radial force of every sample is
    # |F − (F·k) k| of its reaction in the joint frame, recomputed here with a cross product
    k = np.array([stage.joint_axis(name) for name in long.bearing_names])
    radial = np.linalg.norm(np.cross(long.bearing_force_local, k), axis=-1)
    np.testing.assert_allclose(long.bearing_radial, radial, rtol=1e-13, atol=1e-9 * radial.max())


@pytest.mark.parametrize("keep", ["last", 7])
def test_a_strided_or_last_run_keeps_the_same_samples_whatever_its_blocks(keep):
    # keep=7 records the kept samples alone, in the longest blocks; keep="last" steps into
    # buffers of the observers' block size (their memory), whatever the run's length
    stage = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    kwargs = dict(duration=(SAMPLES - 1) * 1e-3, dt=1e-3, torques=TORQUES, keep=keep)
    long, short = simulate(stage, **kwargs), simulate(stage, chunk=1000, **kwargs)
    assert len(long) == len(short) == (1 if keep == "last" else math.ceil(SAMPLES / 7) + 1)
    for name in long.ARRAYS:
        a, b = np.asarray(getattr(long, name)), np.asarray(getattr(short, name))
        assert np.array_equal(a.view(np.uint8), b.view(np.uint8)), name
