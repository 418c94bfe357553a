"""``pinwind build planetary --parallel``: each parallel stage its own module, width and helix."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import pinwind

#: Saleh's planetary stage (Saleh 2017 Table 2) and its two parallel stages.
PLANETARY = ["--sun", "24", "--planet", "48", "--ring", "120", "--planets", "3"]
PLANETARY += ["--module", "15", "--pressure-angle", "24.5", "--face-width", "380"]
STAGES = [(83, 23), (103, 26)]
PARALLEL = [flag for wheel, pinion in STAGES for flag in ("--parallel", f"{wheel}/{pinion}")]


def build(tmp_path, *options: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", "build", "planetary", *PLANETARY, *PARALLEL, *options,
         "-o", str(tmp_path / "built.urdf")],
        capture_output=True, text=True, timeout=120, env=os.environ,
    )  # fmt: skip


def test_each_parallel_stage_sits_at_m_z1_plus_z2_over_2_cos_beta_of_its_own_module(tmp_path):
    done = build(
        tmp_path,
        *("--parallel-module-mm", "12", "--parallel-module-mm", "8"),
        *("--parallel-face-width-mm", "250", "--parallel-face-width-mm", "150"),
        *("--parallel-helix-deg", "10"),
    )
    assert done.returncode == 0, done.stderr
    gearbox = pinwind.load(tmp_path / "built.urdf")
    beta = math.radians(10.0)
    for k, ((wheel, pinion), module, width) in enumerate(
        zip(STAGES, (12e-3, 8e-3), (0.250, 0.150), strict=True), start=1
    ):
        # No profile shift: the working centre distance is the reference one, m_n (z1+z2)/(2 cos β).
        np.testing.assert_allclose(
            gearbox.mesh(f"stage{k}").centre_distance,
            module * (wheel + pinion) / (2.0 * math.cos(beta)),
            rtol=1e-9,  # β in degrees in the file, radians inside: rounding
        )
        wheel_spec = gearbox.gears[f"stage{k}_wheel"].spec
        pinion_spec = gearbox.gears[f"stage{k}_pinion"].spec
        np.testing.assert_allclose([wheel_spec.module, pinion_spec.module], module, rtol=1e-12)
        np.testing.assert_allclose([wheel_spec.face_width, pinion_spec.face_width], width)
        # An external helical pair: opposite hands.
        np.testing.assert_allclose([wheel_spec.helix_angle, pinion_spec.helix_angle], [beta, -beta])
    # The planetary keeps its own module: a = 15 mm (24 + 48)/2.
    np.testing.assert_allclose(gearbox.mesh("sun_planet1").centre_distance, 0.540, rtol=1e-12)


def test_default_parallel_modules_carry_no_more_tooth_load_than_the_planetary(tmp_path):
    done = build(tmp_path)
    assert done.returncode == 0, done.stderr
    gearbox = pinwind.load(tmp_path / "built.urdf")
    m, b, z_sun, planets = 15e-3, 0.380, 24, 3
    # Unit sun torque: each of the 3 sun–planet meshes carries F_t = 2 T / (planets m z_sun).
    planetary_load = 2.0 / (planets * m * z_sun) / (b * m)
    torque = 1.0
    for k, (wheel, pinion) in enumerate(STAGES, start=1):
        spec = gearbox.gears[f"stage{k}_wheel"].spec
        m_k, b_k = spec.module, spec.face_width
        # As many modules wide as the planetary's face.
        np.testing.assert_allclose(b_k / m_k, b / m, rtol=1e-12)
        load = 2.0 * torque / (m_k * wheel) / (b_k * m_k)
        assert load <= planetary_load * (1 + 1e-12), k
        # The smallest module of 0.5 mm steps that does so: 0.5 mm less would exceed it.
        smaller = m_k - 0.5e-3
        assert 2.0 * torque / (smaller * wheel) / (smaller * b / m * smaller) > planetary_load, k
        torque *= pinion / wheel  # the next wheel turns with this stage's pinion
    # Not the planetary's module any more (the 795 mm centre distance of 15 mm teeth).
    assert gearbox.mesh("stage1").centre_distance < 15e-3 * (83 + 23) / 2


def test_a_per_stage_option_given_a_wrong_number_of_times_is_refused_naming_it(tmp_path):
    done = build(tmp_path, *("--parallel-module-mm", "12") * 3)
    assert done.returncode == 2
    assert "--parallel-module-mm given 3 times for 2" in done.stderr
    assert not (tmp_path / "built.urdf").exists()


@pytest.mark.parametrize("degrees", ["45", "-50"])
def test_a_parallel_helix_of_45_degrees_or_more_is_refused(tmp_path, degrees):
    done = build(tmp_path, "--parallel-helix-deg", degrees)
    assert done.returncode == 2
    assert "parallel_helix_angle" in done.stderr and "|β| < 45°" in done.stderr
