"""Shared small models for the test suite."""

from __future__ import annotations

import math
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

from pinwind.gears.checks import stage_pairs
from pinwind.gears.gear_pair import GearPair

#: The shipped models folder.
MODELS = Path(__file__).resolve().parent.parent / "models"


def load_model(path: str | Path):
    """A shipped model, loaded; Cai's pair warns for gear 2, asserted here.

    Its source's inertia of gear 2 is below its teeth's (models/README.md): loading it warns
    ``ImplausibleGear``, on purpose.
    """
    import pinwind
    from pinwind.errors import ImplausibleGear

    if Path(path).name == "cai_spur_pair.urdf":
        with pytest.warns(ImplausibleGear, match='<link name="gear2">'):
            return pinwind.load(path)
    return pinwind.load(path)


def dtu_pairs() -> tuple[GearPair, GearPair]:
    """Sun–planet and planet–ring pairs of the DTU stage of Jørgensen 2014.

    Module 10 mm, α 20°, z 20/35/91, ISO profile shifts 0.582/0.419/−0.840, face width 210 mm.
    """
    return stage_pairs(
        sun=20, planet=35, ring=91, module=10e-3, pressure_angle=math.radians(20.0),
        face_width=0.21, profile_shift=(0.582, 0.419, -0.840),
    )  # fmt: skip


def held_still(gearbox, torque_b: float, meshes=None, **kwargs):
    """A run of a gear pair with gear A held at rest by a speed driver and B braked by
    ``torque_b`` [N·m], from the static deflection, without gravity: 20 steps of 10 µs, so every
    sample is the static equilibrium the tests derive by hand."""
    import numpy as np

    import pinwind

    return pinwind.simulate(
        gearbox,
        duration=2e-4,
        dt=1e-5,
        speeds={"a": 0.0},
        torques={"b": torque_b},
        gravity=np.zeros(3),
        initial_deflection="static",
        meshes=meshes,
        **kwargs,
    )


def two_gear_urdf(
    *,
    teeth: tuple[str, str] = ("20", "40"),
    module_mm: tuple[str, str] = ("2", "2"),
    internal: tuple[str, str] = ("false", "false"),
    centre_distance: float = 0.060,
    axis_b: str = "0 0 1",
    mass_a: str = "1.0",
    inertia_a: tuple[str, str, str] = ("0.001", "0.001", "0.0015"),
    gear_link_a: str = "a",
    mesh: tuple[str, str] = ("g1", "g2"),
) -> str:
    """A housing with two parallel shafts ``a`` and ``b`` carrying gears ``g1`` and ``g2``.

    With the defaults: an external 20/40 pair of module 2 mm at its reference centre distance
    m (z1 + z2)/2 = 60 mm, which loads. Each argument is written into the file as given, so a
    test can break exactly one thing.
    """
    ixx, iyy, izz = inertia_a
    return f"""<?xml version="1.0"?>
<robot name="pair">
  <link name="housing"/>
  <link name="a">
    <inertial><mass value="{mass_a}"/>
      <inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="b">
    <inertial><mass value="2.0"/>
      <inertia ixx="0.004" iyy="0.004" izz="0.006" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="a" type="continuous">
    <parent link="housing"/><child link="a"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="b" type="continuous">
    <parent link="housing"/><child link="b"/>
    <origin xyz="{centre_distance!r} 0 0"/><axis xyz="{axis_b}"/>
  </joint>
  <gearbox>
    <gear name="g1" link="{gear_link_a}" teeth="{teeth[0]}" module_mm="{module_mm[0]}"
          face_width_mm="20" internal="{internal[0]}"/>
    <gear name="g2" link="b" teeth="{teeth[1]}" module_mm="{module_mm[1]}"
          face_width_mm="20" internal="{internal[1]}"/>
    <mesh name="m" gear1="{mesh[0]}" gear2="{mesh[1]}"/>
  </gearbox>
</robot>
"""


@pytest.fixture
def pair_urdf() -> Callable[..., str]:
    """Builder of a small two-gear model file text (see ``two_gear_urdf``)."""
    return two_gear_urdf


#: The DTU 500 kW planetary stage, the model of the fatigue sets of the tests.
FATIGUE_MODEL = (MODELS / "dtu500_planetary.urdf").as_posix()


def fatigue_toml(tmp_path: Path, fatigue: str = "", run: str = "", site: str = "") -> Path:
    """A fatigue set of the DTU 500 kW stage: two bins, one level, one seed, 0.04 s cases."""
    site = site or "speeds = [10, 16]\nhours = [1000, 250]"
    text = textwrap.dedent(
        f"""\
        model = "{FATIGUE_MODEL}"
        dt = 2e-5
        initial_speed = {{ carrier = 27.1 }}
        log_rate = 1000.0
        {run}
        [rotor.carrier]
        preset = "jorgensen2014"

        [generator.sun]
        law = "linear-slip"
        slope = 203568.04
        sync_rpm = 148.91584

        [fatigue]
        out = "cases"
        duration = 0.04
        sample_rate = 50000.0
        turbulence = 0.1
        seeds = [3]
        hub_height = 36.0
        {fatigue}
        [fatigue.site]
        {site}

        [fatigue.sn_curve]
        s0_mpa = 1000.0
        m = 3.0
        endurance_limit_mpa = 0.0
        """
    )
    path = tmp_path / "set.toml"
    path.write_text(text)
    return path
