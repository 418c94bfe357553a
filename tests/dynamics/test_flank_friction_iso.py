"""μ at the operating point in the step: ``friction_coefficient="iso14179"`` (issue 41 item 2).

ISO/TR 14179-2:2001's mean coefficient of friction (Schlenk 1994, Michaelis), in the standard's
units (F_bt N, b mm, v_Σc m/s, ρ_redC mm, η mPa·s, Ra µm):

    μ_mz = 0.048 (F_bt/b / (v_Σc ρ_redC))^0.2 η^(−0.05) Ra^0.25 X_L.

The step evaluates it from the flank's force and the gears' spins; the Python function
(``losses.mesh_friction.mean_friction_coefficient``) is the reference it restates.

The pair is ``tests/conftest.two_gear_urdf``: 20/40 teeth, module 2 mm, 20°, b = 20 mm, at the
reference centre distance, so r_w = r: v_Σc = 2 ω_A r_A sin α and ρ_redC = r_A r_B sin α /
(r_A + r_B).
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import pinwind
from pinwind.cli import main
from pinwind.dynamics import _native
from pinwind.errors import InputError, MalformedModel
from pinwind.losses.mesh_friction import mean_friction_coefficient
from pinwind.losses.oil import Lubricant
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import ledger_residual
from tests.conftest import two_gear_urdf

MODULE, ALPHA, B = 0.002, math.radians(20.0), 0.020
R_A, R_B = 0.020, 0.040
R_BA, R_BB = R_A * math.cos(ALPHA), R_B * math.cos(ALPHA)
OMEGA_A = 10.0  # [rad/s]
LOAD = 5.0  # T_L on B [N·m]
OIL = Lubricant(320, 343.15)  # VG 320 at 70 °C
RA = 0.5e-6  # [m]
MESH_PERIOD = 2 * math.pi / (20 * OMEGA_A)


def iso(damping_ratio: float = 0.3) -> MeshCompliance:
    return MeshCompliance(
        stiffness=1e8,
        variation="constant",
        damping_ratio=damping_ratio,
        friction_coefficient="iso14179",
        oil=OIL,
        roughness=RA,
    )


@pytest.mark.parametrize(
    ("force", "width", "speed", "radius", "eta", "ra", "x_l", "by_hand"),
    [
        # 100 N/mm over (5 m/s · 5 mm) = 4; 4^0.2 = 1.319508, 50^−0.05 = 0.822467, 0.5^0.25 =
        # 0.840896: μ = 0.048 · 1.319508 · 0.822467 · 0.840896 = 0.043804
        (2000.0, 0.020, 5.0, 0.005, 0.050, 0.5e-6, 1.0, 0.048 * 4**0.2 * 50**-0.05 * 0.5**0.25),
        # 5000 N/mm over (1 m/s · 100 mm) = 50, η 200 mPa·s, Ra 1.2 µm, polyalphaolefin X_L 0.8
        (2.5e6, 0.5, 1.0, 0.1, 0.2, 1.2e-6, 0.8, 0.048 * 50**0.2 * 200**-0.05 * 1.2**0.25 * 0.8),
    ],
)
def test_mu_mz_by_hand_in_the_standards_units(force, width, speed, radius, eta, ra, x_l, by_hand):
    args = (force, width, speed, radius, eta, ra, x_l)
    python = mean_friction_coefficient(
        transverse_force=force, face_width=width, sum_velocity=speed, reduced_radius=radius,
        dynamic_viscosity=eta, roughness=ra, lubricant_factor=x_l,
    )  # fmt: skip
    np.testing.assert_allclose(python, by_hand, rtol=1e-12)
    np.testing.assert_allclose(_native.iso14179_friction_coefficient(*args), by_hand, rtol=1e-12)


def test_the_steps_mu_mz_is_the_python_function_at_many_operating_points():
    rng = np.random.default_rng(41)
    for _ in range(50):
        force = 10 ** rng.uniform(0, 7)
        width, speed = 10 ** rng.uniform(-2.5, 0), 10 ** rng.uniform(-2, 2)
        radius, eta = 10 ** rng.uniform(-3, -0.5), 10 ** rng.uniform(-3, 0)
        ra, x_l = 10 ** rng.uniform(-7, -5.5), rng.uniform(0.5, 1.5)
        python = mean_friction_coefficient(
            transverse_force=force, face_width=width, sum_velocity=speed, reduced_radius=radius,
            dynamic_viscosity=eta, roughness=ra, lubricant_factor=x_l,
        )  # fmt: skip
        compiled = _native.iso14179_friction_coefficient(force, width, speed, radius, eta, ra, x_l)
        np.testing.assert_allclose(compiled, python, rtol=1e-12)


def _run(compliance: MeshCompliance, *, load=LOAD, per_period=4000, periods=2.25, **kw):
    period = MESH_PERIOD
    return pinwind.simulate(
        loads(two_gear_urdf(), "pair.urdf"),
        duration=round(periods * per_period) * (period / per_period),
        dt=period / per_period,
        speeds={"a": OMEGA_A},
        torques={"b": load},
        gravity=np.zeros(3),
        meshes={"m": compliance},
        **kw,
    )


def test_the_step_takes_mu_mz_at_its_force_and_speed():
    res = _run(iso())
    mesh = res.mesh("m")
    d = mesh.contact_position - R_BA * math.tan(ALPHA)
    single = (mesh.pairs == 1) & (res.time > 0.5 * MESH_PERIOD) & (np.abs(d) > 1e-4)
    assert single.sum() > 50
    # μ_mz at the run's own force and speed, from the standard's variables by hand
    omega_b = np.abs(res.joint("b").speed)
    sum_velocity = 2 * OMEGA_A * R_A * math.sin(ALPHA)
    np.testing.assert_allclose(omega_b[single], OMEGA_A / 2, rtol=1e-3)  # rolling
    rho = R_A * R_B * math.sin(ALPHA) / (R_A + R_B)
    eta = OIL.dynamic_viscosity()
    line_load = mesh.normal / (B * 1e3)
    mu = (
        0.048
        * (line_load / (sum_velocity * rho * 1e3)) ** 0.2
        * (eta * 1e3) ** -0.05
        * (RA * 1e6) ** 0.25
    )
    assert 0.03 < mu[single].min() and mu[single].max() < 0.08
    recorded = res.metadata["meshes"]["m"]
    assert recorded["friction_coefficient"] == "iso14179"
    assert recorded["friction_data"]["oil_grade"] == 320
    # one pair in contact: the friction on A along e is −μ F sgn(d) (F predicted at the step's
    # start: within 1e-3 of the step's F, as for a constant μ)
    np.testing.assert_allclose(
        mesh.friction_force[single], -(mu * mesh.normal * np.sign(d))[single], rtol=1.5e-3
    )


def test_mu_mz_is_held_at_0_2_where_the_flanks_barely_slide():
    # ω_A = 0.05 rad/s under 100 N·m: μ_mz from the fit exceeds 0.2; the step holds 0.2. The
    # pair at the pitch point at the start rolls 0.19 mm either side of it in 0.2 s.
    omega, load = 0.05, 100.0
    res = pinwind.simulate(
        loads(two_gear_urdf(), "pair.urdf"), duration=0.2, dt=2e-5, speeds={"a": omega},
        torques={"b": load}, gravity=np.zeros(3), meshes={"m": iso()},
    )  # fmt: skip
    mesh = res.mesh("m")
    d = mesh.contact_position - R_BA * math.tan(ALPHA)
    single = (mesh.pairs == 1) & (res.time > 0.05) & (np.abs(d) > 2e-5)
    assert single.sum() > 1000
    rho = R_A * R_B * math.sin(ALPHA) / (R_A + R_B)
    group = mesh.normal / (B * 1e3) / (2 * omega * R_A * math.sin(ALPHA) * rho * 1e3)
    fit = 0.048 * group**0.2 * (OIL.dynamic_viscosity() * 1e3) ** -0.05 * (RA * 1e6) ** 0.25
    assert fit[single].min() > 0.25
    np.testing.assert_allclose(
        mesh.friction_force[single], -(0.2 * mesh.normal * np.sign(d))[single], rtol=1e-3
    )


def test_no_load_gives_no_friction_and_the_ledger_closes():
    # T_L = 0: the flanks part after the start (F → 0, μ_mz ∝ F^0.2 → 0 and μ F → 0); with a
    # load the friction takes its share and the ledger closes either way.
    for load in (0.0, LOAD):
        # (no load: no static start to solve, the train starts undeflected)
        start = {"initial_deflection": "none"} if load == 0.0 else {}
        res = _run(iso(damping_ratio=0.05), load=load, per_period=1000, periods=3.0, **start)
        power = res.mesh("m").friction_power
        assert np.all(np.isfinite(power)) and np.all(np.isfinite(res.mesh("m").normal))
        work_in = max(abs(res.energy["work_drivers"][-1]), 1e-12)
        scale = max(work_in, np.max(np.abs(res.energy["kinetic"])))
        assert np.abs(ledger_residual(res)).max() <= 1e-9 * scale
        if load == 0.0:
            assert power[len(power) // 2 :].max() <= 1e-6 * OMEGA_A * LOAD * 0.05
        else:
            assert res.energy["friction_loss"][-1] > 5e-3 * work_in  # μ H_V ≈ 0.052 · 0.166


def _model_text(**attrs: str) -> str:
    extra = " ".join(f'{k}="{v}"' for k, v in attrs.items())
    return two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        f'<mesh name="m" gear1="g1" gear2="g2" type="compliant" {extra}/>',
    )


def test_the_model_file_sets_the_law_and_its_oil():
    gb = loads(
        _model_text(
            friction_coefficient="iso14179", lubricant_vg="220", temperature_C="60",
            roughness_um="0.4", base_oil="polyalphaolefin",
        ),
        "pair.urdf",
    )  # fmt: skip
    c = gb.meshes[0].compliance
    assert c.friction_coefficient == "iso14179"
    assert c.oil == Lubricant(220, 333.15)
    np.testing.assert_allclose(c.roughness, 0.4e-6, rtol=1e-15)
    assert c.base_oil == "polyalphaolefin"


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"friction_coefficient": "coulomb"}, 'friction_coefficient "coulomb" is not a law'),
        ({"friction_coefficient": "iso14179", "roughness_um": "0.5"}, "needs the oil"),
        (
            {"friction_coefficient": "iso14179", "lubricant_vg": "320", "temperature_C": "70"},
            "needs the flanks' roughness",
        ),
        (
            {
                "friction_coefficient": "iso14179",
                "lubricant_vg": "300",
                "temperature_C": "70",
                "roughness_um": "0.5",
            },
            "VG 300 is not an ISO 3448 grade",
        ),
        (
            {
                "friction_coefficient": "iso14179",
                "lubricant_vg": "320",
                "temperature_C": "70",
                "roughness_um": "0.5",
                "base_oil": "olive",
            },
            'base_oil "olive" is unknown',
        ),
    ],
)
def test_bad_friction_input_is_one_message_naming_the_mesh_and_exit_2(
    attrs, message, tmp_path, monkeypatch, capsys
):
    with pytest.raises(MalformedModel, match=r'<mesh name="m">.*' + message):
        loads(_model_text(**attrs), "pair.urdf")
    path = tmp_path / "pair.urdf"
    path.write_text(_model_text(**attrs))
    monkeypatch.setattr(sys, "argv", ["pinwind", "info", str(path)])
    with pytest.raises(SystemExit) as caught:
        main()
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert message in err and '"m"' in err, err
    assert err.strip().count("\n") == 0, err


def test_bad_friction_input_in_python_names_the_mesh():
    gb = loads(two_gear_urdf(), "pair.urdf")
    for compliance, message in (
        (MeshCompliance(friction_coefficient="iso"), '"iso" is not a law'),
        (MeshCompliance(friction_coefficient="iso14179", roughness=RA), "needs the oil"),
        (MeshCompliance(friction_coefficient="iso14179", oil=OIL), "needs the flanks' roughness"),
    ):
        with pytest.raises(InputError, match=r'meshes\["m"\]: .*' + message):
            pinwind.simulate(gb, duration=0.01, dt=1e-3, meshes={"m": compliance})
