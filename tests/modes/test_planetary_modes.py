"""Mode classes of a planetary stage (``modes/planetary_modes.py``, Lin & Parker 1999).

Expectations derived here for the torsional model of a stage with the ring fixed, sun and
carrier free and N identical, equally spaced planets (one rotation each): N + 2 coordinates.

- Planet modes: sun and carrier still. Each planet is then a disc on its two mesh springs, the
  sun-planet k_sp and the planet-ring k_rp, both at the planet's base radius r_b,p, so it rings
  alone at ω² = (k_sp + k_rp) r_b,p² / J_p; the sun's and the carrier's torque balances ask only
  Σ θ_p = 0 (each mesh force is k r_b,p θ_p on the sun, and the carrier sees their sum too):
  N − 1 independent shapes at one frequency.
- Rotational modes: the N + 2 − (N − 1) = 3 others (the rigid rotation among them), single,
  every planet turning alike.

With compliant bearings on sun, carrier, ring and planets every body also translates (and, with
axial and tilt springs, moves axially and tilts). Turning the stage by one planet spacing 2π/N
splits the motions by their wave number k about the stage (Lin & Parker 1999): each central
member's rotation and axial motion are unchanged by the turn (k = 0), its radial translation and
its tilt each a pair turning with it (k = ±1); the N planets' p coordinates (each in its own
bearing) take every k = 0 … N − 1. The central members couple only to k = 0 and ±1, so

- rotational modes (k = 0): c₀ + p, single, c₀ the central members' invariant coordinates;
- translational modes (k = ±1): c₁ + p pairs, double, c₁ the central members' pairs;
- planet modes (k = 2 … N − 2, central members still, the same p equations for every k): p
  frequencies of multiplicity N − 3 (none for N = 3).

They add up to c₀ + 2 c₁ + N p, the coordinates the rows leave free.
"""

from __future__ import annotations

import math
from collections import Counter
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import pinwind
from pinwind.dynamics.coordinates import coordinates
from pinwind.model.builders import planetary_urdf
from pinwind.model.gearbox import Gearbox, loads
from pinwind.modes.linearisation import linearise
from tests.conftest import MODELS, load_model

MODULE = 0.01
ALPHA = math.radians(20.0)
#: (sun, planet, ring) teeth that assemble with N equally spaced planets: (z_s + z_r) / N whole,
#: z_r = z_s + 2 z_p, and neighbouring planets clear of each other.
TEETH = {4: (24, 24, 72), 5: (30, 20, 70)}


def _stage(planets: int) -> Gearbox:
    if planets == 3:
        return pinwind.load("models/saleh2017_planetary.urdf")
    sun, planet, ring = TEETH[planets]
    text = planetary_urdf(
        sun=sun,
        planet=planet,
        ring=ring,
        planets=planets,
        module=MODULE,
        pressure_angle=ALPHA,
        face_width=0.1,
        name=f"stage{planets}",
    )
    return loads(text, f"stage{planets}.urdf")


def _groups(frequencies: list[float]) -> list[list[int]]:
    """Indices of equal frequencies (relative 1e-6), lowest first."""
    groups: list[list[int]] = []
    for i, f in enumerate(frequencies):
        if groups and math.isclose(frequencies[groups[-1][0]], f, rel_tol=1e-6, abs_tol=1e-9):
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


def _axial_inertia(gearbox: Gearbox, joint: str) -> float:
    """J about the joint axis from the model's own inertia (centre of mass on the axis)."""
    inertia = gearbox.model.inertias[gearbox.model.getJointId(joint)]
    k = gearbox.joint_axis(joint)
    c = np.asarray(inertia.lever)
    about_origin = inertia.inertia + inertia.mass * ((c @ c) * np.eye(3) - np.outer(c, c))
    return float(k @ about_origin @ k)


@pytest.mark.parametrize("planets", [3, 4, 5])
def test_planet_modes_are_n_minus_one_fold_and_rotational_modes_single(planets):
    gb = _stage(planets)
    modes = linearise(gb, meshes={"all": "compliant"}).modes()
    assert len(modes) == planets + 2
    multiplicity = {
        modes[g[0]].kind: len(g) for g in _groups([m.frequency for m in modes]) if len(g) > 1
    }
    assert multiplicity == {"planet": planets - 1}
    assert Counter(m.kind for m in modes) == {"rotational": 3, "planet": planets - 1}


@pytest.mark.parametrize("planets", [3, 4, 5])
def test_rotational_modes_turn_every_planet_alike_and_planet_modes_hold_sun_and_carrier(planets):
    gb = _stage(planets)
    lin = linearise(gb, meshes={"all": "compliant"})
    index = {name: gb.v_index(name) for name in gb.joint_names}
    planet_index = [index[f"planet{i}"] for i in range(1, planets + 1)]
    for mode in lin.modes():
        phi = mode.shape
        scale = np.abs(phi).max()
        if mode.kind == "rotational":
            np.testing.assert_allclose(phi[planet_index], phi[planet_index[0]], atol=1e-9 * scale)
        else:
            assert mode.kind == "planet"
            central = [index["sun"], index["carrier"]]
            np.testing.assert_allclose(phi[central], 0.0, atol=1e-9 * scale)
            np.testing.assert_allclose(phi[planet_index].sum(), 0.0, atol=1e-9 * scale)


@pytest.mark.parametrize("planets", [3, 4, 5])
def test_the_planet_mode_rings_at_the_planet_on_its_two_mesh_springs(planets):
    gb = _stage(planets)
    lin = linearise(gb, meshes={"all": "compliant"})
    k = {e.name: e.stiffness for e in lin.elements}
    planet = gb.mesh("sun_planet1").gear_b
    r_b = planet.spec.teeth * planet.spec.module * math.cos(planet.spec.pressure_angle) / 2
    omega2 = (k["sun_planet1"] + k["planet1_ring"]) * r_b**2 / _axial_inertia(gb, "planet1")
    (frequency,) = {round(m.frequency, 6) for m in lin.modes() if m.kind == "planet"}
    np.testing.assert_allclose(frequency, math.sqrt(omega2) / (2 * math.pi), rtol=1e-6)


def test_a_stage_with_one_planet_held_is_unclassified():
    gb = _stage(3)
    modes = linearise(gb, meshes={"all": "compliant"}, held=["planet1"]).modes()
    assert {m.kind for m in modes} == {"unclassified"}


def test_a_train_without_a_planetary_stage_has_no_mode_class():
    gb = load_model(MODELS / "cai_spur_pair.urdf")
    assert {m.kind for m in linearise(gb).modes()} == {""}


def test_a_planet_moved_off_its_place_leaves_the_stage_unclassified():
    gb = _stage(4)
    # Turn planet 1's bearing 1 mrad about the stage axis: the planets are no longer equally
    # spaced (the centre distances still hold, so the model loads).
    jid = gb.model.getJointId("planet1")
    gb.model.jointPlacements[jid] = (
        pin.SE3(pin.AngleAxis(1e-3, np.array([0.0, 0.0, 1.0])).matrix(), np.zeros(3))
        * gb.model.jointPlacements[jid]
    )
    modes = linearise(gb, meshes={"all": "compliant"}).modes()
    assert {m.kind for m in modes} == {"unclassified"}


def test_every_bearing_of_a_stage_is_a_rotation_about_the_stage_axis():
    gb = _stage(3)  # every joint of the builder's stage turns about z, with rpy = 0
    coords = coordinates(gb)
    assert [c.kind for c in coords] == ["rotation"] * gb.model.nv
    np.testing.assert_allclose(np.abs([c.axis for c in coords]), [[0, 0, 1]] * gb.model.nv)


def _compliant_stage(planets: int) -> Gearbox:
    """The stage with every body in a compliant radial bearing (Lin & Parker's planar model).

    The ring turns on a continuous joint (fixed in the model file) so that it can take a bearing;
    the linearisation holds its rotation (``held``), the stiff torque support Lin & Parker's ring
    has.
    """
    if planets == 3:
        text = Path("models/saleh2017_planetary.urdf").read_text()
    else:
        sun, planet, ring = TEETH[planets]
        text = planetary_urdf(
            sun=sun, planet=planet, ring=ring, planets=planets, module=MODULE,
            pressure_angle=ALPHA, face_width=0.1, name=f"stage{planets}",
        )  # fmt: skip
    text = text.replace(
        '<joint name="ring" type="fixed">',
        '<joint name="ring" type="continuous"><axis xyz="0 0 1"/>',
    )
    members = ["sun", "carrier", "ring", *(f"planet{i}" for i in range(1, planets + 1))]
    bearings = "".join(f'<bearing joint="{m}" radial_stiffness="1e9"/>' for m in members)
    return loads(text.replace("</gearbox>", bearings + "</gearbox>"), f"stage{planets}.urdf")


@pytest.mark.parametrize("planets", [3, 4, 5])
def test_with_compliant_bearings_the_mode_classes_have_lin_and_parker_s_counts_and_multiplicities(
    planets,
):
    gb = _compliant_stage(planets)
    modes = linearise(gb, meshes={"all": "compliant"}, held=["ring"]).modes()
    # Module docstring: sun and carrier turn (the ring's rotation held), each body translates in
    # its bearing's plane (one pair), a planet also turns.
    invariant, central_pairs, planet = 2, 3, 3
    expected = {
        "rotational": invariant + planet,
        "translational": 2 * (central_pairs + planet),
        "planet": (planets - 3) * planet,
    }
    assert len(modes) == invariant + 2 * central_pairs + planets * planet
    assert Counter(m.kind for m in modes) == {k: n for k, n in expected.items() if n}
    multiplicity = {"rotational": 1, "translational": 2, "planet": planets - 3}
    for group in _groups([m.frequency for m in modes]):
        kinds = {modes[i].kind for i in group}
        assert len(kinds) == 1
        assert len(group) == multiplicity[kinds.pop()]


def test_translational_modes_keep_the_central_members_from_turning_and_planet_modes_still():
    gb = _compliant_stage(4)
    lin = linearise(gb, meshes={"all": "compliant"}, held=["ring"])
    central = [gb.v_index(n) for n in ("sun", "carrier")]
    translations = [gb.v_index(f"{n}_radial_{a}") for n in ("sun", "carrier", "ring") for a in "xy"]
    for mode in lin.modes():
        phi = mode.shape * np.sqrt(np.diag(lin.mass))  # √J and √m: one unit
        scale = np.abs(phi).max()
        if mode.kind == "translational":
            np.testing.assert_allclose(phi[central], 0.0, atol=1e-6 * scale)
            assert np.abs(phi[translations]).max() > 1e-3 * scale
        elif mode.kind == "planet":
            np.testing.assert_allclose(phi[central + translations], 0.0, atol=1e-6 * scale)
