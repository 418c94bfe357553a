"""Sliced compliant meshes: the load across the face width in the run, against the spring bed.

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm, face width b = 20 mm) on
shafts that do not tilt, with a constant mesh stiffness K: each of N slices is a spring K/N at
z_s from the face centre behind the lead gap e_s of both gears. Held still with a brake on B, the
mesh carries F = T_B / r_b,B and the slices share it as the spring bed
(Σ_s (K/N) max(0, δ − e_s) = F): with a linear gap f_Hβ z/b (z from side I) the loaded slices
and δ follow by hand, and ISO 6336-1's closed forms K_Hβ = 1 + F_β c b/(2F) (the whole face
carries) and √(2 F_β c b/F) (part lifts) are their limits (c = K/b).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.integrator import Integrator
from pinwind.errors import MalformedModel
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import held_still, two_gear_urdf

K = 1e8  # mesh stiffness [N/m]
B = 0.020  # face width [m]
TORQUE_B = 8.0  # brake on B [N·m]
R_BB = 40 * 0.002 * math.cos(math.radians(20.0)) / 2  # base radius of B [m]
F = TORQUE_B / R_BB  # the mesh force [N], 212.8


def pair(**modification_um: float) -> pinwind.Gearbox:
    """The pair, gear g1 carrying the given lead modifications [µm] (model-file names)."""
    attributes = "".join(f'{name}_um="{value!r}" ' for name, value in modification_um.items())
    text = two_gear_urdf().replace('<gear name="g1" ', f'<gear name="g1" {attributes}')
    return loads(text, "pair.urdf")


def held(gearbox: pinwind.Gearbox, slices: int, **kwargs):
    """A held by a speed driver at rest, B braked, from the static deflection: 20 steps."""
    return held_still(
        gearbox,
        TORQUE_B,
        meshes={
            "m": MeshCompliance(
                mean_stiffness=K, variation="constant", damping_ratio=0.5, slices=slices
            )
        },
        **kwargs,
    )


def spring_bed(gap: np.ndarray, force: float) -> tuple[float, np.ndarray]:
    """δ and the slice forces of N springs K/N behind gaps e_s pressed by F, by hand.

    The m slices with the smallest gaps carry: δ = (F N/K + Σ_{s<m} e_s)/m, the largest m whose
    slices all overlap.
    """
    n = gap.size
    order = np.sort(gap)
    for m in range(n, 0, -1):
        delta = (force * n / K + order[:m].sum()) / m
        if delta > order[m - 1]:
            return delta, K / n * np.maximum(0.0, delta - gap)
    raise AssertionError("no slice carries")


def test_slices_without_misalignment_step_as_one_contact_line():
    """N = 5 with no tilt and no modification: every slice carries F/5, and the run is N = 1's
    (equal to 1e-12 over the first 2 ms; later a contact change decided at a force of rounding
    size may take another settle iteration, and the runs stay within 1e-10)."""
    common = dict(
        duration=0.02,
        dt=2e-5,
        initial_speeds={"a": 20.0},
        torques={"b": TORQUE_B, "a": TORQUE_B / 2},
        gravity=np.zeros(3),
    )
    runs = [
        pinwind.simulate(
            pair(),
            meshes={"m": MeshCompliance(stiffness=K, damping_ratio=0.05, slices=n)},
            **common,
        )
        for n in (1, 5)
    ]
    one, five = (r.mesh("m") for r in runs)
    scale = np.max(np.abs(one.normal))
    defl = np.max(np.abs(one.deflection))
    assert scale > 0.5 * F
    for samples, tol in ((101, 1e-12), (None, 1e-10)):
        cut = slice(0, samples)
        for name in ("normal", "normal_front", "normal_back"):
            assert_allclose(
                getattr(five, name)[cut], getattr(one, name)[cut], rtol=0, atol=tol * scale
            )
        assert_allclose(five.deflection[cut], one.deflection[cut], rtol=0, atol=tol * defl)
        for term in ("potential_spring", "kinetic", "work_parametric", "dissipated"):
            e1, e5 = runs[0].energy[term][cut], runs[1].energy[term][cut]
            assert_allclose(e5, e1, rtol=0, atol=tol * max(np.max(np.abs(e1)), 1e-30))
    loaded = five.normal > 0
    assert_allclose(five.face_load_factor[loaded], 1.0, rtol=1e-12)
    assert_allclose(five.load_centre[loaded], 0.0, atol=1e-12 * B)


def test_a_small_helix_slope_deviation_loads_the_face_linearly_as_iso():
    """F_β c b/(2F) = 0.47 ≤ 1: the whole face carries, w linear; K_Hβ of N slices is ISO's
    closed form less (K_Hβ − 1)/N (the peak half a slice in), the centre the sampled
    trapezoid's."""
    f_hb, n = 2e-6, 8
    res = held(pair(helix_slope_deviation=f_hb * 1e6), n)
    mesh = res.mesh("m")
    c = K / B
    closed = 1 + f_hb * c * B / (2 * F)
    assert closed < 2.0
    assert_allclose(mesh.normal, F, rtol=1e-9)
    assert_allclose(mesh.face_load_factor, closed - (closed - 1) / n, rtol=1e-6)
    # The line load w(z) = c (δ − f_Hβ z/b), δ = F/(cb) + f_Hβ/2, at the slice centres.
    z = (np.arange(n) + 0.5) * B / n
    w = c * (F / (c * B) + f_hb / 2 - f_hb * z / B)
    assert_allclose(mesh.load_centre, np.sum(w * (z - B / 2)) / np.sum(w), rtol=1e-6)
    assert mesh.load_centre[0] < 0  # towards side I, where the gap is closed
    assert_allclose(mesh.deflection, F / K + f_hb / 2, rtol=1e-6)


def test_a_large_helix_slope_deviation_lifts_part_of_the_face_as_iso():
    """F_β c b/(2F) = 4.7 > 1: a loaded length ℓ = √(2 F b/(c F_β)) < b; the slices by hand,
    and ISO's K_Hβ = √(2 F_β c b / F) as their limit (within 1/N)."""
    f_hb, n = 20e-6, 40
    res = held(pair(helix_slope_deviation=f_hb * 1e6), n)
    mesh = res.mesh("m")
    z = (np.arange(n) + 0.5) * B / n
    delta, slice_force = spring_bed(f_hb * z / B, F)
    assert np.count_nonzero(slice_force) < n // 2
    assert_allclose(mesh.normal, F, rtol=1e-9)
    assert_allclose(mesh.face_load_factor, n * slice_force.max() / F, rtol=1e-6)
    assert_allclose(mesh.load_centre, slice_force @ (z - B / 2) / F, rtol=1e-6)
    assert_allclose(mesh.deflection, delta, rtol=1e-6)
    # ISO's closed form is the limit: within a slice's share of the loaded length ℓ.
    closed = math.sqrt(2 * f_hb * (K / B) * B / F)
    loaded = math.sqrt(2 * F * B / ((K / B) * f_hb))
    assert_allclose(mesh.face_load_factor, closed, rtol=B / n / loaded)
    # The closed form's resultant sits a third of ℓ in from side I.
    assert_allclose(mesh.load_centre, loaded / 3 - B / 2, atol=B / n)


def test_the_slices_load_the_bearings_with_their_moment_across_the_face():
    """The slices' forces, all along one direction, tilt gear B's bearing by F times the lever of
    their resultant from the gear's centre plane: by hand from the spring bed, the lifted part of
    the face included (the tilting moment is the reaction's part normal to the axis)."""
    f_hb, n = 20e-6, 40
    res = held(pair(helix_slope_deviation=f_hb * 1e6), n)
    z = (np.arange(n) + 0.5) * B / n
    _, slice_force = spring_bed(f_hb * z / B, F)
    lever = slice_force @ (z - B / 2) / F  # [m] from the face centre, towards side II positive
    assert abs(lever) > B / 4  # far off the centre: a moment the single line would not have
    bearing = res.bearing("b")
    axis = np.array([0.0, 0.0, 1.0])  # the joints turn about z (tests/conftest.two_gear_urdf)
    tilting = bearing.moment_local - np.outer(bearing.moment_local @ axis, axis)
    assert_allclose(np.linalg.norm(tilting, axis=1), F * abs(lever), rtol=1e-6)
    # and the same on gear A's bearing, whose mesh force is the opposite one at the same point
    tilting_a = res.bearing("a").moment_local - np.outer(res.bearing("a").moment_local @ axis, axis)
    assert_allclose(np.linalg.norm(tilting_a, axis=1), F * abs(lever), rtol=1e-6)


def test_lead_crowning_loads_the_face_as_the_parabola_it_leaves():
    """Crowning C_β (2z/b − 1)² on g1, the whole face carrying: w = c (δ − e), δ = F/(cb) +
    mean e over the slice centres; symmetric, so the centre stays at the face centre."""
    crown, n = 1e-6, 10
    res = held(pair(crowning=crown * 1e6), n)
    mesh = res.mesh("m")
    z = (np.arange(n) + 0.5) * B / n
    gap = crown * (2 * z / B - 1) ** 2
    delta = F / K + gap.mean()
    assert delta > gap.max()  # every slice carries
    assert_allclose(mesh.deflection, delta, rtol=1e-6)
    assert_allclose(mesh.face_load_factor, (delta - gap.min()) / (delta - gap.mean()), rtol=1e-6)
    assert_allclose(mesh.load_centre, 0.0, atol=1e-9 * B)


def undamped_run(f_hb_um: float):
    """The pair turning, balanced torques, from the undeflected pose (the mesh rings), ρ∞ = 1,
    an undamped 6-slice mesh with backlash (only the front flank touches)."""
    return pinwind.simulate(
        pair(helix_slope_deviation=f_hb_um),
        duration=0.05,
        dt=1e-5,
        integrator=Integrator(rho_infinity=1.0),
        initial_speeds={"a": 20.0},
        torques={"b": TORQUE_B, "a": TORQUE_B / 2},
        gravity=np.zeros(3),
        initial_deflection="none",
        meshes={
            "m": MeshCompliance(
                mean_stiffness=K, variation="constant", damping=0.0, slices=6, backlash=5e-5
            )
        },
    )


def test_the_sliced_step_at_rho_one_keeps_an_undamped_pairs_energy():
    """f_Hβ = −4 µm: every slice overlaps by at least 2/6 µm at the undeflected start and stays
    in contact while the mesh rings (its load 200-226 N) and its K_Hβ moves: a quadratic
    potential with constant rows, which the trapezoidal rule keeps to rounding."""
    res = undamped_run(-4.0)
    mesh, energy = res.mesh("m"), res.energy
    assert np.ptp(mesh.face_load_factor) > 0.05  # the load across the face moves
    assert mesh.normal.min() > 0.5 * F
    scale = np.max(energy["potential_spring"])
    assert np.max(np.abs(energy["numerical"])) < 1e-9 * scale  # measured 2.9e-11


def test_the_energy_ledger_closes_as_slices_lift_off_and_land():
    """f_Hβ = +6 µm from the undeflected start: the slices lift and land every period; each
    change within a step is held over the step (as a flank's), the ledger's numerical term is
    what those changes cost (measured 1.4e-4 of the peak potential)."""
    res = undamped_run(6.0)
    mesh, energy = res.mesh("m"), res.energy
    loaded = mesh.normal > 0
    assert np.ptp(mesh.face_load_factor[loaded]) > 1.0
    scale = np.max(energy["potential_spring"])
    assert np.max(np.abs(energy["numerical"])) < 5e-4 * scale


def test_the_model_file_sets_slices_and_refuses_a_bad_count():
    text = two_gear_urdf().replace('<mesh name="m" ', '<mesh name="m" type="compliant" slices="7" ')
    assert loads(text, "p.urdf").meshes[0].compliance.slices == 7
    with pytest.raises(MalformedModel, match="slices"):
        loads(text.replace('slices="7"', 'slices="0"'), "p.urdf")
    with pytest.raises(MalformedModel, match="slices"):
        loads(text.replace('slices="7"', 'slices="two"'), "p.urdf")


def test_a_tilting_bearing_moves_the_load_centre_to_the_side_the_tilt_closes():
    """Gear B on a bearing with tilt stiffness k_t, both gears' face centres L along the axis
    from it. Statics by hand, N slices at z_s, B tilted by θ about e = k × n: the slices carry
    F_s = (K/N)(δ − z_s θ) (B's flank at +z_s moves θ z_s along n, away from A), Σ F_s = F gives
    δ = F/K (Σ z_s = 0), and B's moments about e at the bearing centre, k_t θ = Σ (L + z_s) F_s,
    give θ = L F / (k_t + (K/N) Σ z_s²) > 0: the tilt closes side −z, where the load centre
    −(K/N) θ Σ z_s² / F goes."""
    length, k_tilt, n = 0.05, 1e5, 5
    text = (
        two_gear_urdf()
        .replace('<gear name="g1" ', f'<gear name="g1" xyz="0 0 {length!r}" ')
        .replace('<gear name="g2" ', f'<gear name="g2" xyz="0 0 {length!r}" ')
        .replace(
            "</gearbox>",
            f'<bearing joint="b" radial_stiffness="1e9" tilt_stiffness="{k_tilt!r}"/></gearbox>',
        )
    )
    res = held(loads(text, "tilting.urdf"), n)
    mesh = res.mesh("m")
    z = (np.arange(n) + 0.5) * B / n - B / 2
    theta = length * F / (k_tilt + K / n * np.sum(z**2))
    slice_force = K / n * (F / K - z * theta)
    assert slice_force.min() > 0  # every slice carries
    centre = slice_force @ z / F
    assert centre < -1e-3  # a millimetre and a half towards −z
    assert_allclose(mesh.normal, F, rtol=1e-6)
    assert_allclose(mesh.load_centre, centre, rtol=1e-4)
    assert_allclose(mesh.face_load_factor, n * slice_force.max() / F, rtol=1e-4)
