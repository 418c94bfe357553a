"""``pinwind view MODEL``: the model at rest in Rerun, without a run; refused at once headless."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import pinwind
from pinwind.io.model_view import lines_of_action
from tests.conftest import MODELS
from tests.io.conftest import rrd_columns

PLANETARY = MODELS / "saleh2017_planetary.urdf"
DRIVETRAIN = MODELS / "saleh2017_drivetrain.urdf"
#: Saleh's stage: sun 24, planets 48, module 15 mm, no profile shift.
SUN_TEETH, PLANET_TEETH, MODULE = 24, 48, 15e-3
#: The issue's bound for a refusal on a headless machine [s].
WITHIN_S = 15.0


def pinwind_cli(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pinwind", *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={**(env or os.environ), "RERUN_ANALYTICS": "0"},
    )


@pytest.fixture(scope="module")
def viewed(tmp_path_factory) -> dict[str, dict[str, list]]:
    rrd = tmp_path_factory.mktemp("view") / "planetary.rrd"
    out = pinwind_cli("view", str(PLANETARY), "--save", str(rrd))
    assert out.returncode == 0, out.stderr
    assert f"wrote {rrd}" in out.stdout.replace("\n", "")
    return rrd_columns(rrd)


def test_view_save_writes_every_body_gear_and_mesh_line_of_action(viewed):
    for body in ("carrier", "sun", "planet1", "planet2", "planet3", "ring"):
        assert "Transform3D:translation" in viewed[f"/gearbox/{body}"], body
    for gear in ("sun", "planet1", "ring"):
        assert "Mesh3D:vertex_positions" in viewed[f"/gearbox/{gear}/{gear}/body"]
        assert "LineStrips3D:strips" in viewed[f"/gearbox/{gear}/{gear}/teeth"]
    assert "LineStrips3D:strips" in viewed["/gearbox/lines_of_action"]
    labels = viewed["/gearbox/lines_of_action"]["Points3D:labels"][0].to_pylist()[0]
    meshes = [f"sun_planet{k}" for k in (1, 2, 3)] + [f"planet{k}_ring" for k in (1, 2, 3)]
    assert sorted(labels) == sorted(meshes)


def test_view_places_the_planets_at_the_centre_distance_from_the_sun(viewed):
    def origin(body: str) -> np.ndarray:
        return np.array(viewed[f"/gearbox/{body}"]["Transform3D:translation"][0].to_pylist()[0][0])

    a = MODULE * (SUN_TEETH + PLANET_TEETH) / 2.0  # no profile shift: a = m (z1 + z2) / 2
    for planet in ("planet1", "planet2", "planet3"):
        distance = np.linalg.norm(origin(planet) - origin("sun"))
        np.testing.assert_allclose(distance, a, rtol=1e-6)  # Rerun keeps float32


def test_parallel_stage_gears_are_translucent_and_the_planetary_stage_opaque(tmp_path):
    rrd = tmp_path / "drivetrain.rrd"
    out = pinwind_cli("view", str(DRIVETRAIN), "--save", str(rrd))
    assert out.returncode == 0, out.stderr
    viewed = rrd_columns(rrd)
    gearbox = pinwind.load(DRIVETRAIN)
    # The planetary stage: the ring, the gears meshing with it (planets), and theirs (the sun).
    partners: dict[str, set[str]] = {name: set() for name in gearbox.gears}
    for mesh in gearbox.meshes:
        partners[mesh.gear_a.name].add(mesh.gear_b.name)
        partners[mesh.gear_b.name].add(mesh.gear_a.name)
    rings = {name for name, gear in gearbox.gears.items() if gear.spec.internal}
    planets = set().union(*(partners[ring] for ring in rings))
    planetary = rings | planets | set().union(*(partners[p] for p in planets))
    parallel = set(gearbox.gears) - planetary
    assert parallel and planetary  # the drivetrain has both
    for name, gear in gearbox.gears.items():
        (packed,) = viewed[f"/gearbox/{gear.spec.link}/{name}/body"]["Mesh3D:albedo_factor"][0]
        alpha = packed.as_py()[0] & 0xFF  # Rerun packs a colour as 0xRRGGBBAA
        if name in parallel:
            assert alpha < 255, name
        else:
            assert alpha == 255, name


def test_a_machine_without_a_planetary_stage_has_no_translucent_gear():
    from pinwind.io.log_model import model_geometry
    from pinwind.io.replay_scene import parallel_stage_gears

    planetary = model_geometry(pinwind.load(PLANETARY))
    assert parallel_stage_gears(planetary) == set()  # one stage, planetary: nothing in front
    parallel = {
        "gears": {name: {"internal": False} for name in ("wheel", "pinion")},
        "meshes": {"stage": {"gear_a": "wheel", "gear_b": "pinion"}},
    }
    assert parallel_stage_gears(parallel) == set()  # no planetary stage to show behind it


@pytest.mark.parametrize("path", [PLANETARY, DRIVETRAIN], ids=lambda p: p.stem)
def test_lines_of_action_touch_both_base_circles_and_pass_the_pitch_point(path):
    import pinocchio as pin

    gearbox = pinwind.load(path)
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    lines = lines_of_action(gearbox)
    assert sorted(lines) == sorted(m.name for m in gearbox.meshes)
    for mesh in gearbox.meshes:
        found = lines[mesh.name]
        for flank in ("front", "back"):
            segment = found[flank]
            direction = segment[1] - segment[0]
            direction /= np.linalg.norm(direction)
            # The pitch point lies on the line.
            offset = found["pitch_point"] - segment[0]
            np.testing.assert_allclose(
                np.linalg.norm(offset - (offset @ direction) * direction), 0.0, atol=1e-9
            )
            for gear, end in ((mesh.gear_a, segment[0]), (mesh.gear_b, segment[1])):
                spec = gear.spec
                placement = data.oMi[gear.joint_id]
                centre = placement.act(gear.centre_in_joint)
                axis = placement.rotation @ gear.axis_in_joint
                radial = end - centre - ((end - centre) @ axis) * axis
                # r_b = m_n z cos α_t / (2 cos β), tan α_t = tan α_n / cos β.
                beta = spec.helix_angle
                alpha_t = math.atan(math.tan(spec.pressure_angle) / math.cos(beta))
                base = spec.module * spec.teeth * math.cos(alpha_t) / (2.0 * math.cos(beta))
                np.testing.assert_allclose(np.linalg.norm(radial), base, rtol=1e-9)
                # Tangent there: the line is perpendicular to the radius.
                np.testing.assert_allclose(radial @ direction, 0.0, atol=1e-9)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="displays are X11/Wayland here")
def test_view_without_a_display_ends_at_once_with_one_line_naming_save_and_serve():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    started = time.monotonic()
    out = pinwind_cli("view", str(PLANETARY), env=env)
    assert time.monotonic() - started < WITHIN_S
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert "--save" in out.stderr and "--serve" in out.stderr and "display" in out.stderr
