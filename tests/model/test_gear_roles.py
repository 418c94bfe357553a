"""Sun, planet and ring come from the train's topology (``model/gear_roles.py``), not the names.

Saleh's and the DTU 500 kW stage are read with their gears renamed, once neutrally (``a``, ``b1``
… ``b3``, ``c``) and once misleadingly (the sun called ``ring``, the ring ``sun``, the planets
``sun1`` …); the ring is still the internal gear, the planets what meshes with it, the sun what
meshes with the planets. Life, the design sweep's columns and the modes read the same roles.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest

import pinwind
from pinwind.analysis.rating import rate
from pinwind.analysis.sweep_planetary import _rating_columns
from pinwind.dynamics.coordinates import coordinates
from pinwind.life.sn_curve import jorgensen_2014_curve
from pinwind.model.gear_roles import (
    PlanetaryGears,
    gear_roles,
    gearbox_planetary_gears,
    planetary_gears,
)
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from pinwind.modes.planetary_modes import planetary_stages
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import FATIGUE_MODEL, MODELS, fatigue_toml

NEUTRAL = {"sun": "a", "planet1": "b1", "planet2": "b2", "planet3": "b3", "ring": "c"}
MISLEADING = {"sun": "ring", "planet1": "sun1", "planet2": "sun2", "planet3": "sun3", "ring": "sun"}
ROLES = {"sun": "sun", "ring": "ring"} | {f"planet{i}": "planet" for i in (1, 2, 3)}
#: Carrier torque in at speed, the sun holding T/i (i = 1 + 120/24 for Saleh's stage).
RUN = {
    "duration": 0.01,
    "dt": 1e-3,
    "torques": {"carrier": 1e6, "sun": -1e6 / 6},
    "initial_speeds": {"carrier": 14.2},
}


def renamed(path: Path, names: dict[str, str]) -> str:
    """The model file's text with its gears renamed (links, joints and bodies keep theirs)."""
    text = path.read_text()

    def gear(match: re.Match[str]) -> str:
        return f'{match[1]}="{names.get(match[2], match[2])}"'

    text = re.sub(r'(<gear name|gear1|gear2)="([^"]+)"', gear, text)
    count = iter(range(1, 100))
    return re.sub(r'<mesh name="[^"]+"', lambda _: f'<mesh name="m{next(count)}"', text)


@pytest.mark.parametrize("names", [NEUTRAL, MISLEADING])
def test_roles_follow_the_meshes_not_the_names(names):
    gearbox = loads(renamed(MODELS / "saleh2017_planetary.urdf", names), "renamed.urdf")
    (stage,) = gearbox_planetary_gears(gearbox)
    assert stage == PlanetaryGears(
        ring=names["ring"],
        planets=(names["planet1"], names["planet2"], names["planet3"]),
        suns=(names["sun"],),
    )
    assert gear_roles([stage]) == {names[g]: role for g, role in ROLES.items()}


def test_a_parallel_pair_named_sun_and_ring_has_no_roles():
    assert planetary_gears({"sun": False, "ring": False}, [("sun", "ring")]) == []


def test_both_gears_of_a_stepped_planet_are_planets():
    internal = {"s": False, "p_big": False, "p_small": False, "r": True}
    body = {"s": 0, "p_big": 1, "p_small": 1, "r": 2}
    (stage,) = planetary_gears(internal, [("s", "p_big"), ("p_small", "r")], body)
    assert stage == PlanetaryGears(ring="r", planets=("p_big", "p_small"), suns=("s",))


@pytest.mark.parametrize("names", [NEUTRAL, MISLEADING])
def test_the_modes_find_the_same_stage_under_any_gear_names(names):
    original = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    gearbox = loads(renamed(MODELS / "saleh2017_planetary.urdf", names), "renamed.urdf")
    (stage,) = planetary_stages(gearbox, coordinates(gearbox))
    (reference,) = planetary_stages(original, coordinates(original))
    assert stage.ring == names["ring"]
    assert stage.central == reference.central
    assert stage.planet_names == reference.planet_names
    kinds = Counter(m.kind for m in linearise(gearbox, meshes={"all": "compliant"}).modes())
    assert kinds == {"rotational": 3, "planet": 2}


@pytest.mark.parametrize("names", [NEUTRAL, MISLEADING])
def test_the_sweep_columns_read_the_roles_under_any_gear_names(names):
    original = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    gearbox = loads(renamed(MODELS / "saleh2017_planetary.urdf", names), "renamed.urdf")
    columns = [_rating_columns(rate(gb, pinwind.simulate(gb, **RUN))) for gb in (original, gearbox)]
    assert columns[1] == columns[0]


@pytest.mark.parametrize("names", [NEUTRAL, MISLEADING])
def test_a_fatigue_set_rates_each_gear_by_its_role_under_any_gear_names(tmp_path, names):
    model = tmp_path / "renamed.urdf"
    model.write_text(renamed(Path(FATIGUE_MODEL), names))
    path = fatigue_toml(tmp_path, fatigue='materials = { ring = "42CrMo4" }')
    text = path.read_text().replace(FATIGUE_MODEL, model.as_posix())
    sn_curve = r"s0_mpa = 1000.0\s+m = 3.0\s+endurance_limit_mpa = 0.0"
    path.write_text(re.sub(sn_curve, 'preset = "jorgensen2014"', text))
    fatigue = load_fatigue_set(path)
    roles = {names[g]: role for g, role in ROLES.items()}
    assert fatigue.roles == roles
    gearbox = pinwind.load(model)
    (stage,) = planetary_stages(gearbox, coordinates(gearbox))  # the modes' stage: the same ring
    assert fatigue.roles[stage.ring] == "ring"
    joint = {g: gearbox.model.names[gearbox.gears[g].joint_id] for g in roles}
    assert set(stage.planet_names) == {joint[g] for g, role in roles.items() if role == "planet"}
    assert fatigue.curves == {g: jorgensen_2014_curve(role) for g, role in roles.items()}
    # The table's "ring" is every gear whose role is ring, and a gear named "ring" (its own
    # name comes before its role).
    assert fatigue.materials == {
        g: "42CrMo4" if "ring" in (role, g) else "18CrNiMo7-6" for g, role in roles.items()
    }
