"""Every example runs briefly and gives the closed-form numbers it prints."""

from __future__ import annotations

import importlib.util
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import ImplausibleGear
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import single_pair_stiffness
from pinwind.gears.rating_iso import form_factors
from pinwind.modes.linearisation import linearise

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: Cai's gear 2 warns on purpose: its source's inertia is below its teeth's (models/README.md).
CAI_GEAR_2 = '<link name="gear2">'


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_saleh_rated_load_reaches_the_rated_sun_mesh_force(tmp_path):
    res = _load("saleh_rated_load").main(["--duration", "0.2", "--figures", str(tmp_path)])
    # --figures logs the run and writes pinwind plot's figures of it.
    assert (tmp_path / "saleh_rated_load.mcap").exists()
    assert (tmp_path / "04_mesh_forces.png").stat().st_size > 10_000
    # Rated rotor torque at constant speed: 1e6/6 N·m on the sun, shared by 3 planets at
    # r_b = 0.18 m · cos 24.5°.
    expected = 1e6 / 6 / (3 * 0.18 * math.cos(math.radians(24.5)))
    assert_allclose(res.mesh("sun_planet1").normal[-1], expected, rtol=1e-9)


def test_cai_quasi_steady_contact_force_is_the_brake_torque_over_the_base_radius(capsys):
    with pytest.warns(ImplausibleGear, match=CAI_GEAR_2):
        rows = _load("cai_quasi_steady").main(["--duration", "1", "--runs", "1", "--dt", "2e-4"])
    printed = capsys.readouterr().out
    assert "A [rpm]" in printed and "f [Hz]" in printed  # units not eaten as rich markup
    static = 49.0 / (0.120 * math.cos(math.radians(20.0)))
    assert_allclose(rows[0]["force"]["mean"], static, rtol=1e-3)
    assert_allclose(rows[0]["t_in"]["mean"], 49.0 * 40 / 80, rtol=1e-3)


def test_kelso_cai_pair_starts_with_its_shafts_twisted_by_the_brake_and_keeps_them_so():
    with pytest.warns(ImplausibleGear, match=CAI_GEAR_2):
        results = _load("kelso2011_cai_spur_pair").main(["--duration", "0.2", "--runs", "1"])
    accel, force, t_in, t_out = results["200 rpm"]
    # Started in equilibrium under the brake: the shafts carry 49 N·m · 40/80 and 49 N·m from the
    # first sample and their torsional modes are not rung; the teeth carry the static
    # 49 N·m / r_b2 on average, the mesh stiffness's variation vibrating about it.
    static = 49.0 / (0.120 * math.cos(math.radians(20.0)))
    assert_allclose([t_in["min"], t_in["max"]], 49.0 * 40 / 80, rtol=0.01)
    assert_allclose([t_out["min"], t_out["max"]], 49.0, rtol=0.01)
    assert_allclose(force["mean"], static, rtol=0.02)
    assert force["max"] > static > force["min"] > 0.0


def test_dtu500_planetary_balances_the_rotor_torque_at_the_generator(tmp_path):
    module = _load("dtu500_planetary")
    log = tmp_path / "dtu.mcap"
    res = module.main(["--duration", "0.3", "--out", str(log), "--keep", "1"])
    # Ring fixed: the sun's driver holds the carrier torque over the ratio 1 + 91/20 (mean over
    # the run, the inertia of the stage at constant speed doing no work on average).
    late = res.time >= 0.1
    expected = -np.mean(module.ROTOR_TORQUE.values(res.time[late])) / (1 + 91 / 20)
    assert_allclose(res.joint("sun").torque[late].mean(), expected, rtol=2e-3)
    assert pinwind.read_log(log).mesh_names == res.mesh_names


def test_saleh2017_case_study_turns_the_carrier_at_14_2_rpm_and_the_sun_six_times_faster(
    tmp_path, monkeypatch
):
    from tests.io.test_figures_layout import checked_pages, on_the_page_with_units

    pages = checked_pages(monkeypatch)
    out = _load("saleh2017_case_study").main(["--duration", "2", "--out", str(tmp_path)])
    rpm = 2 * math.pi / 60
    planetary, drivetrain = out["planetary"], out["drivetrain"]
    assert_allclose(planetary.joint("carrier").speed[-1], 14.2 * rpm, rtol=1e-4)
    assert_allclose(planetary.joint("sun").speed[-1], 85.2 * rpm, rtol=1e-4)
    # Rigid train: the sun turns 6 times as fast as the carrier at every sample, in wind too.
    assert_allclose(drivetrain.joint("sun").speed, 6 * drivetrain.joint("carrier").speed,
                    rtol=1e-9)  # fmt: skip
    assert len(out["figures"]) == 5 and all(p.stat().st_size > 10_000 for p in out["figures"])
    on_the_page_with_units(pages, 5)  # legends beside the curves, nothing cut, units on axes


def test_dtu500_single_tooth_force_at_the_example_dt_is_within_one_percent_of_dt_over_8():
    # Issue 22's check: at rated torque, the single-tooth force's standard deviation and maximum
    # at the example's dt agree with a run at dt/8 within 1 % (the tooth-pass vibration that
    # fatigue raises to the power m), over 0.25 s after a start in equilibrium.
    module = _load("dtu500_planetary")
    gb = pinwind.load(Path(__file__).resolve().parents[1] / "models" / "dtu500_planetary.urdf")
    dt = module.DT

    def run(step: float) -> dict[str, tuple[float, float]]:
        res = pinwind.simulate(gb, duration=0.3, dt=step, torques={"carrier": module.RATED_TORQUE},
                               speeds={"sun": module.RATIO * module.ROTOR_SPEED},
                               initial_speeds={"carrier": module.ROTOR_SPEED},
                               meshes={"all": module.MESH})  # fmt: skip
        late = res.time >= 0.05
        out = {}
        for mesh in gb.meshes:
            force = res.mesh(mesh.name).single_tooth_force[late]
            out[mesh.name] = (float(force.std()), float(force.max()))
        return out

    coarse, fine = run(dt), run(dt / 8)
    for name, (std, peak) in coarse.items():
        assert_allclose(std, fine[name][0], rtol=0.01, err_msg=f"{name} standard deviation")
        assert_allclose(peak, fine[name][1], rtol=0.01, err_msg=f"{name} maximum")


def _fall_in_one_step(omega: float, zeta: float, dt: float) -> float:
    """Fraction of a force step ΔF that a damped mode's response loses over one step after it.

    Released from a static deflection ΔF/k with no speed, the mode's force above its new
    static value is ΔF e^{−ζωt} (cos ω_d t − ζ/√(1 − ζ²) sin ω_d t) (spring plus dashpot
    c = 2ζωm): a peak sampled up to one step after the step lies this far below it.
    """
    omega_d = omega * math.sqrt(1 - zeta**2)
    left = math.exp(-zeta * omega * dt) * (
        math.cos(omega_d * dt) - zeta / math.sqrt(1 - zeta**2) * math.sin(omega_d * dt)
    )
    return 1.0 - left


def test_kelso_cai_pair_maxima_converge_with_dt_to_the_second_pair_s_engagement():
    module = _load("kelso2011_cai_spur_pair")
    dts = (5e-6, 2.5e-6)  # the example's dt and its half
    with pytest.warns(ImplausibleGear, match=CAI_GEAR_2):
        stats = [
            module.main(["--duration", "0.2", "--runs", "1", "--dt", str(dt)])["200 rpm"]
            for dt in dts
        ]
    # When a second tooth pair comes into contact the mesh stiffness jumps from c′b to 1.75 c′b
    # (ISO 6336-1) at the same deflection: the force jumps from the static F_s = 49 N·m / r_b2
    # to 1.75 F_s, and gear 1's pitch point takes 0.75 F_s r_b1 r_1 / J_1 (its shaft spring
    # still holds F_s r_b1). The damped mesh mode then settles before the next step.
    r_b1 = 0.060 * math.cos(math.radians(20.0))
    r_b2, inertia = 2 * r_b1, 0.003  # J_1 = J_2, Table 3-1: gear 0.002 + half shaft 0.001
    static = 49.0 / r_b2
    jump, kick = 1.75 * static, 0.75 * static * r_b1 * 0.060 / inertia
    # The mesh mode with two pairs in contact, ω² = 1.75 c′b (r_b1²/J_1 + r_b2²/J_2); the
    # damping ratio 0.068 of the mean stiffness is a bound on the two-pair one.
    pair = GearPair(teeth_1=40, teeth_2=80, module=0.003, pressure_angle=math.radians(20.0),
                    face_width=0.015)  # fmt: skip
    omega = math.sqrt(1.75 * single_pair_stiffness(pair) * (r_b1**2 + r_b2**2) / inertia)
    fall = [_fall_in_one_step(omega, module.MESH_DAMPING_RATIO, dt) for dt in dts]
    for (accel, force, _, _), lag in zip(stats, fall, strict=True):
        assert force["min"] > 0.0  # the teeth never separate: no rattle through the backlash
        assert_allclose(force["max"], jump, atol=lag * (jump - static))
        assert_allclose(accel["max"], kick, atol=lag * kick)
    # So the maxima at dt and dt/2 agree within what one step at dt can lag the peak.
    (accel, force, _, _), (accel_half, force_half, _, _) = stats
    assert abs(force["max"] - force_half["max"]) <= fall[0] * (jump - static)
    assert abs(accel["max"] - accel_half["max"]) <= fall[0] * kick


def test_cart600_support_starts_sagged_and_carries_the_power_s_load_from_the_first_sample(
    tmp_path, monkeypatch
):
    from tests.io.test_figures_layout import checked_pages, on_the_page_with_units

    pages = checked_pages(monkeypatch)
    module = _load("cart600_support")
    duration = 1.0
    results = module.main(["--duration", str(duration), "--figures", str(tmp_path)])
    assert (tmp_path / "cart600_support_psd.png").stat().st_size > 10_000
    on_the_page_with_units(pages, 2)
    flexible = module.model(flexible=True)
    gearbox_mass = module.gearbox_mass(module.model(flexible=False))
    m = module.TOWER_MASS
    # The tower alone at f √((m + M)/m) carries the gearbox at f = 7.3 Hz (an input, tuned):
    # k = m (2π f_alone)², and the mode of the combined mass is at f, lowered by the bodies'
    # own compliance in series with it (their modes are 15 times higher: ~(1/15)² ≈ 4e-3).
    k = m * (2 * math.pi * module.TOWER_FREQUENCY) ** 2 * (m + gearbox_mass) / m
    modes = [x.frequency for x in linearise(flexible, meshes={"all": module.MESH}).modes()]
    assert min(abs(f - module.TOWER_FREQUENCY) for f in modes) < 4e-3 * module.TOWER_FREQUENCY
    # The bedplate starts sagged under the weight on the tower, (m + M) g / k, and stays.
    sag = (m + gearbox_mass) * 9.81 / k
    carrier = {}
    for key, pair in results.items():
        assert_allclose(pair["flexible"].joint("support_tower_vertical").angle, -sag, rtol=1e-5)
        rigid, flex = (module.vertical_force(pair[n], "carrier") for n in ("rigid", "flexible"))
        # The first sample carries the run's load (no start-up release), on either support.
        for force in (rigid, flex):
            assert_allclose(force[0], force.mean(), rtol=1e-4)
            assert np.ptp(force) < 1e-2 * abs(force.mean())
        assert_allclose(flex.mean(), rigid.mean(), rtol=1e-4)
        carrier[key] = rigid.mean()
    # The power's effect, apart from any start: more load at 600 kW than at 270 kW.
    assert carrier["600 kW"] > 1.05 * carrier["270 kW"]


def _equivalent_circuit_generator_torque(speed: float) -> float:
    """001 Table 1's machine, steady state at shaft speed [rad/s]: T_gen [N·m], > 0 generating.

    Per phase R_s + jX_ls in series with jX_M ∥ (R_r'/s + jX_lr'), star on 575 V, 60 Hz, 4 poles;
    the air-gap power 3 |I_r'|² R_r'/s over the synchronous speed is the motor torque.
    """
    omega_e = 2 * math.pi * 60.0
    sync = omega_e / 2
    slip = (sync - speed) / sync
    stator = 0.00053 + 1j * omega_e * 0.0365e-3
    magnetizing = 1j * omega_e * 1.97e-3
    rotor = 0.00048 / slip + 1j * omega_e * 0.052e-3
    current = (575.0 / math.sqrt(3)) / (stator + magnetizing * rotor / (magnetizing + rotor))
    rotor_current = current * magnetizing / (magnetizing + rotor)
    return -3 * abs(rotor_current) ** 2 * 0.00048 / slip / sync


def test_cart600_support_dq_generator_follows_its_steady_curve_and_does_not_grow():
    module = _load("cart600_support")
    gearbox = module.model(flexible=True)
    duration = 2.0
    for power in module.POWERS:
        res = module.run(gearbox, power, duration=duration, dt=module.DT, dq=True)
        last = res.time >= duration / 2
        speed = res.joint("generator").speed[last]
        torque = res.generator("generator").torque[last]
        # The dq torque leaves the curve only by its fluxes' lag, within its ripple; the curve at
        # the mean speed lies within its slope times the speed's half range of its values.
        mean_speed = float(speed.mean())
        curve = _equivalent_circuit_generator_torque
        slope = (curve(mean_speed + 1e-3) - curve(mean_speed - 1e-3)) / 2e-3
        ripple = np.ptp(torque) / 2 + abs(slope) * np.ptp(speed) / 2
        assert_allclose(torque.mean(), curve(mean_speed), atol=ripple)
        # The torque takes the power: T ω = P within the same ripple.
        assert_allclose(torque.mean() * mean_speed, power, atol=ripple * mean_speed)
        # The oscillation of the generator's speed about its mean does not grow: its envelope,
        # the largest deviation in windows longer than the slowest period (the tower's 7.3 Hz),
        # has a log-slope ≤ 0 over the last half.
        window = 1.0 / module.TOWER_FREQUENCY
        time = res.time[last]
        starts = np.arange(time[0], time[-1] - window, window)
        envelope = [
            np.abs(speed - mean_speed)[(time >= a) & (time < a + window)].max() for a in starts
        ]
        growth = np.polyfit(starts + window / 2, np.log(envelope), 1)[0]
        assert growth <= 0.0


def test_the_users_test_file_checks_the_saleh_stage_and_passes(tmp_path):
    """examples/test_my_gearbox.py, run as a user runs it: its five checks pass."""
    out = subprocess.run(
        [sys.executable, str(EXAMPLES / "test_my_gearbox.py"), "-q", "-p", "no:cacheprovider"],
        capture_output=True, text=True, timeout=600, cwd=tmp_path,
    )  # fmt: skip
    assert out.returncode == 0, out.stdout + out.stderr
    assert "5 passed" in out.stdout


def test_nrel5mw_drivetrain_main_bearings_hold_thrust_and_weight_and_ranks_by_hand(tmp_path):
    """The 5 MW example on 0.1 s: its hub load by hand, its damage linear in the hours."""
    import dataclasses

    from scipy.interpolate import RegularGridInterpolator

    from pinwind.analysis.bearing_rows import row_loads
    from pinwind.life.set_bearing_life import set_bearing_lives
    from pinwind.life.set_damage import set_damage
    from pinwind.life.site import site_from_hours
    from pinwind.loads.rotor_performance import NREL5MW_PERFORMANCE, read_performance
    from pinwind.loads.wind import kaimal_series

    # The Result at the set's rate (1250 Hz), every counted sample, for the checks by hand.
    out = _load("nrel5mw_drivetrain").main(
        ["--duration", "0.1", "--out", str(tmp_path), "--no-progress", "--result-rate", "1250"]
    )
    res, gearbox, fset = out["result"], out["gearbox"], out["fatigue"]
    # The rotor's load along the main shaft by hand (Jonkman et al. 2009 Table 1-1: 110 t, 5°
    # tilt, R = 63 m): its thrust ½ ρ π R² v² C_t, v the disc-averaged Kaimal wind of seed 1 at
    # 13 m/s with class B's turbulence (IEC 61400-1 NTM: σ = 0.14 (0.75 v + 5.6 m/s)), and its
    # weight's component W sin 5°; the main shaft's rows hold it (stage 1 is spur, the model's
    # gravity is across the shaft), starting static. C_t is ROSCO's table (the shipped file,
    # scipy's bilinear interpolation) at the recorded λ and pitch; the pitch controller starts at
    # the scenario's 6.474° and moves little in 0.1 s.
    intensity = 0.14 * (0.75 * 13.0 + 5.6) / 13.0
    _, wind = kaimal_series(mean=13.0, turbulence_intensity=intensity, duration=600.0, seed=1,
                            sample_time=0.05, hub_height=90.0, rotor_radius=63.0)  # fmt: skip
    v = np.interp(res.time, np.arange(len(wind)) * 0.05, wind)
    rotor = res.rotor("rotor")
    assert_allclose(rotor.tip_speed_ratio, res.joint("rotor").speed * 63.0 / v, rtol=1e-9)
    assert np.all(np.abs(np.degrees(rotor.pitch) - 6.474160) < 0.5)
    grid = read_performance(NREL5MW_PERFORMANCE)
    ct = RegularGridInterpolator((grid.tsr, grid.pitch), grid.ct)
    expected_ct = ct(np.column_stack([rotor.tip_speed_ratio, rotor.pitch]))
    assert_allclose(rotor.thrust_coefficient, expected_ct, rtol=1e-12)
    thrust = 0.5 * 1.225 * math.pi * 63.0**2 * v**2 * expected_ct
    along = 110e3 * 9.81 * math.sin(math.radians(5)) + thrust
    axial = sum(row.axial for row in row_loads(res, gearbox) if row.bearing == "lss")
    # At the static start the rows hold it but for the stage-1 mesh forces' axial part, which
    # tilt with the carrier by the main bearing's tilt θ ≈ 1e-4 rad: at most θ Σ|F_n|, 1e-3 of
    # it at this torque (tests/runs/test_nrel5mw_rotor.py; 1.2e-5 measured).
    model, slides = gearbox.model, gearbox.compliant_bearings["lss"].v_index
    tilts = [model.names[j] for j in range(1, model.njoints)
             if model.joints[j].idx_v in (slides["tilt_x"], slides["tilt_y"])]  # fmt: skip
    theta = np.hypot(*(res.joint(name).angle[0] for name in tilts))
    stage1 = sum(abs(res.mesh(n).normal[0]) for n in res.mesh_names if n.startswith("stage1"))
    assert abs(-axial[0] - along[0]) <= theta * stage1
    assert_allclose(-axial, along, rtol=1e-2)
    # The ranking: every gear's flank and root (10 planetary, the helical stage 3's wheel and
    # pinion) and the 24 rated rows, most damaged first, and a figure of it.
    ranking = out["ranking"]
    assert len(ranking) == 2 * 12 + 24
    damages = [item.damage for item in ranking]
    assert damages == sorted(damages, reverse=True) and damages[-1] > 0.0
    assert out["figure"].stat().st_size > 20_000
    stage3 = [(i.name, i.kind) for i in ranking if i.name.startswith("stage3_")]
    assert sorted(stage3) == [
        (g, k) for g in ("stage3_pinion", "stage3_wheel") for k in ("flank", "root")
    ]
    # Stage 3 (β 10°, ε_β = 0.36 sin 10°/(π 0.014) = 1.42 ≥ 1) by ISO 6336-3 from the whole
    # mesh force: its largest root stress is F_t/(b m_n) Y_F Y_S Y_β of the largest counted
    # force, F_t = F_bt cos α_t (F_bt the logged transverse force), Y_β = 1 − 10°/120°.
    mesh = gearbox.mesh("stage3")
    pair = GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec)
    counted = res.time >= fset.skip_start - 1e-12
    f_bt = np.max(np.abs(res.mesh("stage3").normal[counted]))
    alpha_t = math.atan(math.tan(math.radians(20.0)) / math.cos(math.radians(10.0)))
    y_beta = 1.0 - 10.0 / 120.0
    roots = out["damage"].root_damage["iso 6336"][0]
    for gear, index in (("stage3_wheel", 1), ("stage3_pinion", 2)):
        y_f, y_s = form_factors(pair, index)
        assert_allclose(
            roots[gear].peak_stress,
            f_bt * math.cos(alpha_t) / (0.36 * 0.014) * y_f * y_s * y_beta,
            rtol=1e-9,
        )
    # Miner and ISO 281 are linear in the hours a history stands for: the same cycles over
    # twice the hours give twice every damage and life consumption.
    twice = dataclasses.replace(
        fset, site=site_from_hours(speeds=fset.site.speeds, hours=2 * fset.site.hours)
    )
    for variant in ("no limit", "iso 6336"):
        for table in ("damage", "root_damage"):
            one = getattr(out["damage"], table)[variant][0]
            two = getattr(set_damage(twice), table)[variant][0]
            for gear in one:
                assert_allclose(two[gear].total, 2 * one[gear].total, rtol=1e-12)
    lives = {life.joint: life for life in set_bearing_lives(twice)[0] if life.rated}
    for life in out["lives"][0]:
        if life.rated:
            assert_allclose(lives[life.joint].life_consumed, 2 * life.life_consumed, rtol=1e-12)
    # One row by ISO 281 from its forces: INP-B (spherical roller, e 0.28, Y1 2.4, X2 0.67,
    # Y2 3.6, C 16 518 kN; Nejad et al. 2016 Table VI) over the counted samples, standing for
    # the bin's hours.
    counted = res.time >= fset.skip_start - 1e-12
    row = next(r for r in row_loads(res, gearbox) if r.name == "INP-B")
    f_r, f_a = row.radial_magnitude[counted], np.abs(row.axial[counted])
    load = np.where(f_a <= 0.28 * f_r, f_r + 2.4 * f_a, 0.67 * f_r + 3.6 * f_a)
    t = res.time[counted]
    turns = np.abs(res.joint("lss").speed[counted]) / (2 * math.pi)
    step_turns = np.diff(t) * (turns[1:] + turns[:-1]) / 2  # trapezoid per interval
    step_load = (load[1:] ** (10 / 3) + load[:-1] ** (10 / 3)) / 2
    p_eq = (np.sum(step_turns * step_load) / np.sum(step_turns)) ** 0.3
    hours = float(fset.site.hours[0])
    revolutions = np.sum(step_turns) * hours * 3600.0 / (t[-1] - t[0])
    expected = revolutions * (p_eq / 16518e3) ** (10 / 3) / 1e6
    life = next(life for life in out["lives"][0] if life.joint == "lss.INP-B")
    assert_allclose(life.life_consumed, expected, rtol=1e-3)


def test_grc_planet_rows_share_each_planet_s_load_by_statics_and_carry_the_rotor_torque(tmp_path):
    """The GRC comparison on 5 ms: each planet's two rows, ±136 mm from the face centre where
    its meshes act, carry half its load each (statics of a rigid planet on two rows; the
    planet's inertia and the rows' tilt springs move it by under 1 %), in both runs; the three
    planets' tangential row loads times the carrier radius a are the rotor torque (the carrier
    turning steadily: torque balance)."""
    module = _load("grc_planet_rows")
    out = module.main(["--duration", "0.005", "--figures", str(tmp_path)])
    assert out["figure"].stat().st_size > 10_000
    for name, (res, gearbox) in out["results"].items():
        slide = gearbox.model.getJointId("stage1_planet1_radial_x")
        a = float(np.linalg.norm(gearbox.model.jointPlacements[slide].translation[:2]))
        tangential = sum(
            res.row(f"{planet}.{row}").force[:, 1]
            for planet in module.PLANETS
            for row in module.ROWS
        )
        assert_allclose(np.abs(tangential) * a, module.ROTOR_TORQUE, rtol=1e-3)
        for planet in module.PLANETS:
            loads = [np.hypot(*res.row(f"{planet}.{row}").force[:, :2].T) for row in module.ROWS]
            assert_allclose(loads[0] / (loads[0] + loads[1]), 0.5, atol=0.01)
        shares = [r.share for r in out["runs"][name]]
        assert_allclose(shares, 0.5, atol=0.01)
    # The preloaded rows' every roller carries load: their reference life is the longer one.
    assert out["life_ratio"] > 1.0


def test_fmu_closed_loop_settles_at_the_torque_balance_in_closed_form():
    pytest.importorskip("fmpy")
    pytest.importorskip("pythonfmu")
    example = _load("fmu_closed_loop")
    final = example.main(["--duration", "4"])
    # T_aero(ω) = T_r (2 − ω/ω_r) = 6 k (6 ω)², k = T_r / (6 (6 ω_r)²): ω = ω_r (14.2 rpm).
    rated = 14.2 * 2 * math.pi / 60
    assert_allclose(final["rotor_speed"], rated, rtol=1e-6)
    assert_allclose(final["sun_speed"], 6.0 * final["rotor_speed"], rtol=1e-6)
    assert_allclose(final["shaft_torque"], 6.0 * final["generator_torque"], rtol=1e-6)
    assert_allclose(final["shaft_torque"], 1e6, rtol=1e-5)
