"""The tooth histories of `pinwind fatigue` at the run's peak line load (``face_load="run"``).

The run is ``tests/dynamics/test_sliced_mesh``'s held pair (20/40 teeth, module 2 mm, face
b = 20 mm, constant mesh stiffness K in N = 8 slices, a brake so that the mesh carries
F = T_B/r_b,B) with a helix slope deviation f_Hβ = 2 µm. The whole face carries, so by hand
ISO 6336-1's spring bed gives K_Hβ = 1 + f_Hβ c b/(2F) (c = K/b) and the sampled bed of N
slices peaks half a slice in: K_Hβ,N = K_Hβ − (K_Hβ − 1)/N, the same at every sample (the pair
is held). The Hertz contact stress goes as √(force) (Jørgensen 2014 eqs. 20-22), so at the
peak line load each counted stress is the even one times √K_Hβ,N; ISO 6336-3's root stress
goes as the force, times K_Fβ = K_Hβ,N^N_F with N_F = (b/h)²/(1 + b/h + (b/h)²),
h = 2.25 m_n (ISO 6336-1). Palmgren-Miner damage of the curve N = N0 (s0/s)^m then scales by
the stress ratio to the m-th power.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from pinwind.errors import FactorNotInRun, InputError
from pinwind.life.case_cycles import case_cycles
from pinwind.life.root_stress import ISO_ROOT_STRESS
from pinwind.life.sn_curve import SNCurve
from pinwind.life.tooth_damage import gear_tooth_damage
from tests.cli.test_fatigue import fatigue_exit
from tests.conftest import fatigue_toml
from tests.dynamics.test_sliced_mesh import B, F, K, held, pair

F_HB, SLICES = 2e-6, 8
CLOSED = 1 + F_HB * (K / B) * B / (2 * F)
K_HB = CLOSED - (CLOSED - 1) / SLICES
B_H = B / (2.25 * 0.002)
N_F = B_H**2 / (1 + B_H + B_H**2)
#: No endurance limit, so that every cycle counts: damage ∝ stress^m.
CURVE = SNCurve(reference_stress=2e9, slope_exponent=8.7, reference_cycles=1e6)


@pytest.fixture(scope="module")
def sliced():
    gearbox = pair(helix_slope_deviation=F_HB * 1e6)
    return gearbox, held(gearbox, SLICES)


def damage(gearbox, res, gear, **options):
    return gear_tooth_damage(res, gearbox, gear, curve=CURVE, time_factor=1.0, **options)


@pytest.mark.parametrize("gear", ["g1", "g2"])
@pytest.mark.parametrize(
    ("root", "ratio"),
    [(None, math.sqrt(K_HB)), (ISO_ROOT_STRESS, K_HB**N_F)],
    ids=["contact", "root"],
)
def test_each_counted_stress_and_the_damage_scale_by_the_peak_line_loads_factor(
    sliced, gear, root, ratio
):
    assert CLOSED < 2.0  # the whole face carries: the closed form holds
    even = damage(*sliced, gear, root_stress=root)
    peak = damage(*sliced, gear, root_stress=root, face_load="run")
    assert [d.flank for d in peak] == [d.flank for d in even]
    for e, p in zip(even, peak, strict=True):
        assert np.max(e.peak_stress) > 0.0
        assert_allclose(p.peak_stress, e.peak_stress * ratio, rtol=1e-9)
        for ce, cp in zip(e.cycles, p.cycles, strict=True):
            assert_allclose(cp.counts, ce.counts)
            # The held run's stress wiggles by ~1e-12 of itself: a cycle of that size is
            # rounding, compared to 1e-9 of the peak.
            atol = 1e-9 * np.max(p.peak_stress)
            assert_allclose(cp.ranges, ce.ranges * ratio, rtol=1e-9, atol=atol)
        assert np.max(e.damage) > 0.0
        assert_allclose(p.damage, e.damage * ratio**CURVE.slope_exponent, rtol=1e-9)


def test_the_default_spreads_the_force_evenly(sliced):
    """face_load="uniform" is the default, and a run's slices do not change it."""
    gearbox, res = sliced
    default = damage(gearbox, res, "g1")
    uniform = damage(gearbox, res, "g1", face_load="uniform")
    one_line = damage(gearbox, held(gearbox, 1), "g1")
    for d, u, o in zip(default, uniform, one_line, strict=True):
        np.testing.assert_array_equal(d.peak_stress, u.peak_stress)
        assert_allclose(d.peak_stress, o.peak_stress, rtol=1e-6)


def test_a_case_counts_its_cycles_at_the_peak_line_load(sliced):
    gearbox, res = sliced
    even = case_cycles(res, gearbox, ["g1"])
    peak = case_cycles(res, gearbox, ["g1"], face_load="run")
    for e, p in zip(even, peak, strict=True):
        atol = 1e-9 * np.max(p.peaks)
        assert_allclose(p.ranges, e.ranges * math.sqrt(K_HB), rtol=1e-9, atol=atol)
        assert_allclose(p.peaks, e.peaks * math.sqrt(K_HB), rtol=1e-9)


def test_a_mesh_with_one_contact_line_is_refused_when_asked_for_the_runs_face_load():
    gearbox = pair(helix_slope_deviation=F_HB * 1e6)
    with pytest.raises(FactorNotInRun, match=r'mesh "m".*one contact line.*slices'):
        damage(gearbox, held(gearbox, 1), "g1", face_load="run")


def test_an_unknown_face_load_is_refused(sliced):
    with pytest.raises(InputError, match='face_load = "peak".*"uniform".*"run"'):
        damage(*sliced, "g1", face_load="peak")


def test_the_fatigue_command_refuses_a_set_asked_for_the_peak_line_load_of_unsliced_meshes(
    tmp_path, monkeypatch, capsys
):
    """The DTU 500 kW stage's meshes have one contact line: refused before any step, exit 2."""
    monkeypatch.chdir(tmp_path)
    path = fatigue_toml(tmp_path, fatigue='face_load = "run"')
    code, err = fatigue_exit([str(path), "--workers", "1"], monkeypatch, capsys)
    assert code == 2, err
    assert err.strip().count("\n") == 0, err
    assert "one contact line" in err and 'face_load = "uniform"' in err and "slices" in err
    assert not list((tmp_path / "cases").glob("*.npz"))


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ('face_load = "peak"', "is 'peak'; give \"uniform\""),
        # [fatigue]'s mesh stiffness replaces each mesh's compliance by one of one line.
        ('face_load = "run"\nmesh_stiffness = 3.5e9', "mesh_stiffness or mesh_damping"),
    ],
)
def test_the_fatigue_file_refuses_a_face_load_it_cannot_give(
    tmp_path, monkeypatch, capsys, given, message
):
    path = fatigue_toml(tmp_path, fatigue=given)
    code, err = fatigue_exit([str(path)], monkeypatch, capsys)
    assert code == 2
    assert "fatigue.face_load" in err and message in err, err
    assert str(path) in err
    assert err.strip().count("\n") == 0, err
