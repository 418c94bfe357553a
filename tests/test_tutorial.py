"""docs/tutorial.md runs as written, and its output shows the numbers it derives by hand.

Every ```bash block runs in order in one empty folder (``pinwind`` is ``python -m pinwind``), then
every ```python block; each must exit 0. The checks take the tooth counts, torques and speeds
from the tutorial's own commands, so the page and the test cannot drift apart.
"""

from __future__ import annotations

import csv
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from numpy.testing import assert_allclose

ROOT = Path(__file__).resolve().parent.parent
TUTORIAL = ROOT / "docs" / "tutorial.md"
BLOCK = re.compile(r"^```(bash|python)\n(.*?)^```$", re.MULTILINE | re.DOTALL)


def flag(command: str, name: str) -> float:
    """The number after ``--name`` (``--name 18``) or ``--name JOINT=`` in a command."""
    (value,) = re.findall(rf"--{name}[ =](-?[0-9.]+(?:e[-+]?[0-9]+)?)", command)
    return float(value)


def row(output: str, name: str) -> list[str]:
    """The cells of the first table row of ``name`` in a command's output (in any column)."""
    return next(line.split() for line in output.splitlines() if line.split()[:1] == [name])


@pytest.fixture(scope="module")
def tutorial(tmp_path_factory) -> dict[str, str]:
    """Run the tutorial; each block's output keyed by its code."""
    folder = tmp_path_factory.mktemp("tutorial")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHON": sys.executable}
    prelude = 'set -euo pipefail\npinwind() { "$PYTHON" -m pinwind "$@"; }\n'
    outputs: dict[str, str] = {}
    blocks = BLOCK.findall(TUTORIAL.read_text(encoding="utf-8"))
    for language, code in sorted(blocks, key=lambda block: block[0] != "bash"):
        command = (
            ["bash", "-c", prelude + code] if language == "bash" else [sys.executable, "-c", code]
        )
        out = subprocess.run(
            command, capture_output=True, text=True, timeout=300, cwd=folder, env=env
        )
        assert out.returncode == 0, f"{code}\n{out.stdout}\n{out.stderr}"
        outputs[code] = out.stdout
    outputs["folder"] = str(folder)
    return outputs


def output_of(tutorial: dict[str, str], start: str) -> tuple[str, str]:
    """The block that starts with ``start``: (its code, its output)."""
    (key,) = [key for key in tutorial if key.startswith(start)]
    return key, tutorial[key]


def test_tutorial_commands_all_run(tutorial):
    assert len(tutorial) - 1 == len(BLOCK.findall(TUTORIAL.read_text(encoding="utf-8")))


def test_hand_written_pair_turns_at_the_tooth_ratio_and_carries_torque_over_radius(tutorial):
    text = TUTORIAL.read_text(encoding="utf-8")
    wheel, pinion = (int(z) for z in re.findall(r'teeth="([0-9]+)"', text)[:2])
    module = 10e-3  # module_mm="10" of both gears
    _, info = output_of(tutorial, "cat > pair.urdf")
    assert f"output {-wheel / pinion:.4f}" in info
    assert f"a_w = {module * (wheel + pinion) / 2 * 1e3:.4f} mm" in info
    command, out = output_of(tutorial, "pinwind simulate pair.urdf")
    speed_in, torque_in = flag(command, "initial-speed input"), flag(command, "torque input")
    # Power balance: T_out = -T_in ω_in / ω_out = T_in z_pinion / z_wheel.
    assert_allclose(flag(command, "torque output"), torque_in * pinion / wheel, rtol=1e-12)
    assert f"{-speed_in * wheel / pinion:.4f}" in row(out, "output")
    tangential = torque_in / (module * wheel / 2)
    cells = row(out, "wheel_pinion")
    alpha = math.radians(20)  # the default pressure angle; no profile shift
    for force in (tangential / math.cos(alpha), tangential, tangential * math.tan(alpha)):
        assert f"{force / 1e3:.4f}" in cells, force


def bearing_loads(output: str) -> dict[str, list[float]]:
    """Bearing → (radial, axial, tilting, torque) of the run summary's bearing-load table."""
    lines = output.splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip().startswith("Bearing loads on"))
    rows: dict[str, list[float]] = {}
    for line in lines[start + 3 :]:  # title, header, rule
        if not line.strip():
            break
        name, *cells = line.split()
        rows[name] = [float(cell) for cell in cells]
    return rows


def test_pair_bearings_carry_tooth_force_and_weight_radially_and_the_shaft_torque_apart(tutorial):
    text = TUTORIAL.read_text(encoding="utf-8")
    wheel = int(re.findall(r'teeth="([0-9]+)"', text)[0])
    wheel_mass, pinion_mass = (float(m) for m in re.findall(r'mass value="([0-9.]+)"', text)[:2])
    command, out = output_of(tutorial, "pinwind simulate pair.urdf")
    torque_in, torque_out = flag(command, "torque input"), flag(command, "torque output")
    tangential = torque_in / (10e-3 * wheel / 2)  # module 10 mm
    radial = tangential * math.tan(math.radians(20))
    g = 9.81  # gravity="0 -9.81 0", across both shafts (axes along z)
    # The pinion sits on +x of the wheel: the tangential force is vertical, the radial along x.
    # The wheel's bearing holds its weight and the pinion's push F_t up; the pinion's holds its
    # weight against the wheel's push down.
    loads = bearing_loads(out)
    expected = {
        "input": [math.hypot(tangential + wheel_mass * g, radial), 0.0, 0.0, torque_in],
        "output": [math.hypot(-tangential + pinion_mass * g, radial), 0.0, 0.0, torque_out],
    }
    for name, values in expected.items():
        # the table prints kN and kN·m to 4 decimals
        assert_allclose(loads[name], [v / 1e3 for v in values], atol=6e-5, err_msg=name)


def test_built_stage_has_the_ratio_of_its_tooth_counts(tutorial):
    command, info = output_of(tutorial, "pinwind build planetary")
    sun, planet, ring = (flag(command, name) for name in ("sun", "planet", "ring"))
    assert f"sun {1 + ring / sun:g}" in info
    assert f"planet1 {-ring / planet:g}" in info
    assert f"a_w = {flag(command, 'module') * (sun + planet) / 2:.4f} mm" in info


def test_stage_run_balances_torques_and_shares_the_sun_torque_equally(tutorial):
    build, _ = output_of(tutorial, "pinwind build planetary")
    sun, ring, module = (flag(build, name) for name in ("sun", "ring", "module"))
    command, out = output_of(tutorial, "pinwind simulate stage.urdf")
    carrier_rpm = flag(command, "initial-speed carrier")
    torque_carrier, torque_sun = flag(command, "torque carrier"), flag(command, "torque sun")
    assert_allclose(torque_sun, -torque_carrier / (1 + ring / sun), rtol=1e-12)
    assert f"{carrier_rpm * (1 + ring / sun):.4f}" in row(out, "sun")
    # The ring holds what the carrier and sun torques leave: -(T_c + T_s).
    assert f"{-(torque_carrier + torque_sun) / 1e3:.4f}" in row(out, "ring")
    tangential = -torque_sun / (3 * module * 1e-3 * sun / 2)
    for mesh in ("sun_planet1", "sun_planet2", "sun_planet3", "planet1_ring"):
        assert f"{tangential / 1e3:.4f}" in row(out, mesh), mesh


def test_exported_table_holds_every_sample_of_the_normal_force(tutorial):
    build, _ = output_of(tutorial, "pinwind build planetary")
    sun, module = flag(build, "sun"), flag(build, "module")
    command, _ = output_of(tutorial, "pinwind simulate stage.urdf")
    normal = (
        -flag(command, "torque sun") / (3 * module * 1e-3 * sun / 2) / math.cos(math.radians(20))
    )
    with open(Path(tutorial["folder"]) / "mesh_forces.csv", newline="") as file:
        rows = list(csv.DictReader(file))
    assert len(rows) == round(flag(command, "duration") / flag(command, "dt")) + 1
    forces = [float(value) for r in rows for key, value in r.items() if key != "time_s"]
    assert len(forces) == 6 * len(rows)
    assert_allclose(forces, normal, rtol=1e-9)


def test_python_block_prints_ratio_force_ratio_and_equal_sharing(tutorial):
    _, out = output_of(tutorial, "import math")
    values = [float(line.rsplit(" ", 1)[1]) for line in out.splitlines()]
    assert_allclose(values, [5.0, 1.0, 1.0], rtol=1e-9)


def report_rows(output: str) -> dict[tuple[str, str], list[float]]:
    """``pinwind report``'s rows: (element, quantity) -> [min, max, mean, final]."""
    rows: dict[tuple[str, str], list[float]] = {}
    element = ""
    for line in output.splitlines():
        cells = line.split()
        if len(cells) == 1 and not line.startswith(" "):
            element = cells[0]
        elif line.startswith("  ") and element and len(cells) >= 5:
            try:
                numbers = [float(cell) for cell in cells[-4:]]
            except ValueError:
                continue
            rows[(element, " ".join(cells[:-4]))] = numbers
    return rows


def test_report_is_steady_but_for_single_tooth_force_and_planet_weight(tutorial):
    build, _ = output_of(tutorial, "pinwind build planetary")
    sun, planet, module = (flag(build, name) for name in ("sun", "planet", "module"))
    width = flag(build, "face-width")
    command, _ = output_of(tutorial, "pinwind simulate stage.urdf")
    _, out = output_of(tutorial, "pinwind report logs/run.mcap")
    rows = report_rows(out)
    steady = [key for key in rows if key[1].split()[0] in ("speed", "torque", "T", "normal")]
    # six speeds, three applied torques (carrier, sun, ring lock), six shaft torques, six meshes
    assert len(steady) == 6 + 3 + 6 + 6, steady
    for key in steady:
        low, high, _, _ = rows[key]
        assert low == high, key
    # Single-tooth force: F_n while one pair carries the mesh, F_n / 2 while two do.
    normal = rows[("sun_planet1", "normal [kN]")][0]
    low, high, _, _ = rows[("sun_planet1", "F 1 tooth [kN]")]
    assert_allclose([low, high], [normal / 2, normal], atol=1e-4)
    # A planet bearing: 2 F_t ± the weight of a steel disc of the pitch diameter (7850 kg/m³).
    tangential = -flag(command, "torque sun") / (3 * module * 1e-3 * sun / 2)
    weight = 7850 * math.pi * (module * 1e-3 * planet / 2) ** 2 * width * 1e-3 * 9.81
    lows, highs = zip(*(rows[(f"planet{i}", "F radial [kN]")][:2] for i in (1, 2, 3)), strict=True)
    assert (2 * tangential - weight) / 1e3 - 1e-3 <= min(lows) < max(highs)
    assert max(highs) <= (2 * tangential + weight) / 1e3 + 1e-3
    assert max(highs) - min(lows) > weight / 1e3  # the carrier turns a third of a turn
