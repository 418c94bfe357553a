"""A case reduced as it runs, block by block, is the case reduced after the run.

The invariant of a streamed reduction (``life/cycles.CycleStream``, ``life/tooth_damage.GearTeeth``,
``life/life_sums.HistoryStream``, ``runs/kept_blocks.KeptBlocks``): the reversals of a history
given in parts are those of the whole history (checked against the ``rainflow`` package's own
``reversals`` and ``extract_cycles``), so the rainflow cycles of every tooth flank are the same
cycles, exactly, and the bearing sums are the same sums, to rounding, whatever the blocks: of a
few samples, so that block ends fall inside tooth passes, or of random sizes.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import pinwind
from pinwind.life.bearing_life import load_power_sum, sample_weights
from pinwind.life.life_sums import HistoryStream, RunLoadSums, history_sums, run_load_sums
from pinwind.life.root_stress import ISO_ROOT_STRESS
from pinwind.life.sn_curve import SNCurve
from pinwind.life.tooth_damage import GearTeeth, gear_tooth_damage
from pinwind.model.bearing import bearing_rating
from pinwind.model.bearing_life_data import BearingLifeData
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.runs.case_runner import CASE_SERIES, case_reduction, reduce_case, run_case
from pinwind.runs.fatigue_set_file import load_fatigue_set
from pinwind.runs.kept_blocks import KeptBlocks
from tests.conftest import fatigue_toml, two_gear_urdf
from tests.life.test_helical_tooth_stress import helical_pair_urdf

#: N(s) = (1000 MPa / s)³ (any curve: the cycles are compared).
CURVE = SNCurve(reference_stress=1000e6, slope_exponent=3.0)


def random_cuts(rng: np.random.Generator, n: int, largest: int) -> list[tuple[int, int]]:
    """Consecutive (start, stop) parts of 0..n, each of 1 to ``largest`` samples."""
    cuts = [0]
    while cuts[-1] < n:
        cuts.append(min(n, cuts[-1] + int(rng.integers(1, largest + 1))))
    return list(zip(cuts[:-1], cuts[1:], strict=True))


def assert_same_damage(blocks: tuple, whole: tuple) -> None:
    """The flanks rated from blocks are those of the whole run: cycles exactly, 1e-9 else."""
    assert [d.flank for d in blocks] == [d.flank for d in whole]
    for b, w in zip(blocks, whole, strict=True):
        assert len(b.cycles) == len(w.cycles)
        for cb, cw in zip(b.cycles, w.cycles, strict=True):
            assert_array_equal(cb.counts, cw.counts)
            assert_allclose(cb.ranges, cw.ranges, rtol=1e-9, atol=0)
            assert_allclose(cb.means, cw.means, rtol=1e-9, atol=0)
        assert_allclose(b.peak_stress, w.peak_stress, rtol=1e-9, atol=0)
        assert_allclose(b.damage, w.damage, rtol=1e-9, atol=0)


def blocks_damage(result, gearbox, gear: str, cuts, **kwargs) -> tuple:
    counter = GearTeeth(gearbox, gear, root_stress=kwargs.get("root_stress"))
    for start, stop in cuts:
        counter.add(result.rows(start, stop))
    return counter.damage(curve=CURVE, time_factor=1.0)


@pytest.mark.parametrize("urdf", [two_gear_urdf, helical_pair_urdf], ids=["spur", "helical"])
def test_teeth_counted_in_blocks_give_the_cycles_of_the_whole_run(urdf):
    """The 20/40 pair, spur and helical (ε_β = 1.59: a pass is one cycle, of its largest
    stress), driven at a 200 Hz mesh frequency: a tooth pass spans about 25 (spur) samples, so
    blocks of 1 to 7 samples cut passes, helical passes included, and random blocks of up to
    400 samples cut some; contact and root, each gear, every flank: the same cycles."""
    gearbox = loads(urdf(), "pair.urdf")
    result = pinwind.simulate(
        gearbox,
        duration=0.04,
        dt=2e-5,
        speeds={"a": 2 * math.pi * 200 / 20},
        torques={"b": 10.0},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=1e9, damping_ratio=0.1)},
    )
    rng = np.random.default_rng(5)
    n = len(result)
    for gear in ("g1", "g2"):
        for root in (None, ISO_ROOT_STRESS):
            whole = gear_tooth_damage(
                result, gearbox, gear, curve=CURVE, time_factor=1.0, root_stress=root
            )
            # 200 Hz · 0.04 s = 8 tooth pairs enter, each pass at least one cycle (but the
            # passes cut at the run's ends): the passes were counted
            assert sum(c.total for d in whole for c in d.cycles) >= 6
            for largest in (7, 400):
                cuts = random_cuts(rng, n, largest)
                assert_same_damage(
                    blocks_damage(result, gearbox, gear, cuts, root_stress=root), whole
                )


def test_bearing_sums_of_parts_are_the_sums_of_the_whole_history():
    """A tapered roller row whose mean axial load is negative (it faces the other way: its
    cells are turned at the end), the same with an axial load at times below its induced
    thrust (no equilibrium there: no reference life, the same samples counted), a cylindrical
    roller row with a clearance (its cells depend on the largest load: its loads are kept)
    and one without (direction cells): the sums of parts of 1 to 9 samples and of random
    parts are those of the whole history, to 1e-9, and so are the notes. The whole history's
    reference sum is Σ P_ref,i^p n_i of each sample's own P_ref (ISO/TS 16281,
    `sample_distribution`), to 1e-9."""
    rng = np.random.default_rng(16281)
    n = 600
    time = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, n))
    speed = 10.0 + rng.normal(0.0, 2.0, n)

    def loads_of(axial: float) -> np.ndarray:
        return np.column_stack([
            60e3 + rng.normal(0, 8e3, n), rng.normal(0, 8e3, n), axial + rng.normal(0, 4e3, n),
            rng.normal(0, 300, n), rng.normal(0, 300, n),
        ])  # fmt: skip

    tapered = bearing_rating("row", "tapered_roller", dynamic_load_rating=500e3)
    cylinder = bearing_rating("row", "cylindrical_roller", dynamic_load_rating=500e3)
    size = (0.30, 0.20, 0.06)
    # (name, rating, data, W, a reference life)
    cases = [
        ("tapered", tapered, BearingLifeData(size=size, fatigue_limit=50e3), loads_of(-40e3), True),
        ("thrust", tapered, BearingLifeData(size=size), loads_of(-15e3), False),
        ("clearance", cylinder, BearingLifeData(size=size, clearance=20e-6), loads_of(0.0), True),
        ("cylinder", cylinder, BearingLifeData(size=size, fatigue_limit=50e3), loads_of(0.0), True),
    ]  # fmt: skip
    for name, rating, data, load, referenced in cases:
        whole = history_sums(name, rating, data=data, size=None, time=time, speed=speed,
                             load=load)  # fmt: skip
        assert whole.distribution is not None
        assert math.isnan(whole.sums.reference_sum) != referenced, whole.notes
        assert referenced or any("below the single angular row's" in t for t in whole.notes)
        if referenced:
            turns = sample_weights(time) * np.abs(speed) / (2 * math.pi)
            assert_allclose(
                whole.sums.reference_sum,
                load_power_sum(whole.distribution.reference_load, turns, rating.exponent),
                rtol=1e-9,
            )
        for largest in (9, 200):
            stream = HistoryStream(name, rating, data=data, size=None)
            for start, stop in random_cuts(rng, n, largest):
                stream.add(time=time[start:stop], speed=speed[start:stop], load=load[start:stop])
            parts = stream.sums()
            assert parts.notes == whole.notes
            for key, value in dataclasses.asdict(whole.sums).items():
                if isinstance(value, float) and not math.isnan(value):
                    assert_allclose(getattr(parts.sums, key), value, rtol=1e-9, err_msg=key)
                else:
                    assert getattr(parts.sums, key) == value or math.isnan(value), key


def test_a_fatigue_case_reduced_as_it_runs_is_the_case_reduced_after_its_run(tmp_path):
    """A case of the DTU 500 kW stage (sun, three planets on both flanks, ring; planet
    bearings), run with its reduction fed as it runs (`run_case`) and again keeping every
    sample at the set's rate in its Result, reduced after the run (`reduce_case`): the same
    cycles, exactly, and the same bearing sums. Fed by a `KeptBlocks` of 5-sample blocks, the
    reduction is the same too."""
    import warnings

    from pinwind.runs.case_runner import case_scenario
    from pinwind.runs.scenario import run

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    case = fset.cases()[0]
    streamed = run_case(case, fset)
    scenario = case_scenario(case, fset)
    gearbox = pinwind.load(scenario.model_path())
    reduction = case_reduction(fset, gearbox)
    stride = int(fset.case_values(case)["keep"])
    small = KeptBlocks([reduction], series=CASE_SERIES, stride=stride,
                       skip_start=fset.skip_start, block=5)  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run(scenario, gearbox=gearbox, progress=False, statistics=False,
                     keep_series=CASE_SERIES, observer=small)  # fmt: skip
    after = reduce_case(case, fset, result, gearbox)
    assert result.metadata["keep_stride"] == stride
    counted = int(np.sum(result.time >= fset.skip_start - 1e-12))
    assert small.samples_handed == counted > 1000
    for flanks, roots, bearings in (
        (streamed.flanks, streamed.roots, streamed.bearings),
        reduction.reduced(),
    ):
        assert len(flanks) == len(after.flanks) > 5 and len(bearings) == len(after.bearings) > 0
        for got, want in zip((*flanks, *roots), (*after.flanks, *after.roots), strict=True):
            assert (got.gear, got.flank, got.teeth) == (want.gear, want.flank, want.teeth)
            assert_array_equal(got.tooth, want.tooth)
            assert_array_equal(got.counts, want.counts)
            assert_allclose(got.ranges, want.ranges, rtol=1e-9, atol=0)
            assert_allclose(got.peaks, want.peaks, rtol=1e-9, atol=0)
        for got, want in zip(bearings, after.bearings, strict=True):
            for key, value in dataclasses.asdict(want).items():
                if isinstance(value, float):
                    assert_allclose(getattr(got, key), value, rtol=1e-9, err_msg=key)
                else:
                    assert getattr(got, key) == value


def test_run_load_sums_of_blocks_are_those_of_the_whole_run(tmp_path):
    """The bearings and rows of a fatigue case's run, summed over blocks of 1 to 50 samples
    (`RunLoadSums`), are `run_load_sums` of the whole run."""
    import warnings

    from pinwind.runs.case_runner import case_scenario
    from pinwind.runs.scenario import run

    fset = load_fatigue_set(fatigue_toml(tmp_path))
    scenario = case_scenario(fset.cases()[0], fset)
    gearbox = pinwind.load(scenario.model_path())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run(scenario, gearbox=gearbox, progress=False, statistics=False,
                     keep_series=CASE_SERIES)  # fmt: skip
    whole = run_load_sums(result, gearbox)
    sums = RunLoadSums(gearbox)
    for start, stop in random_cuts(np.random.default_rng(2), len(result), 50):
        sums.add(result.rows(start, stop))
    parts = sums.sums()
    assert [s.joint for s in parts] == [s.joint for s in whole] and whole
    for got, want in zip(parts, whole, strict=True):
        for key, value in dataclasses.asdict(want).items():
            if isinstance(value, float):
                assert_allclose(getattr(got, key), value, rtol=1e-9, err_msg=key)
