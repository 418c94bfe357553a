"""The slices of a tilting helical mesh carry the spring bed at the tilt θ of the gears' axes.

``benchmarks/independent_face_load.py`` recodes the load across the face from a logged run and
the model file alone (docs/validation.md, "Independent recoding of the load across the face").
Here its tilting case: the NREL 5 MW stage 3 on its shipped compliant bearings, θ = (k × k_B)·
(k × n) taken from the logged link poses. A gear turning about its own axis does not move that
axis, so the slices' forces follow θ alone; the step once counted B's spin as a tilt rate, ω_B
(k × n)·k_B, and its line loads then left the spring bed by 8e-3 of the mean line load.
"""

from __future__ import annotations

import math

import numpy as np

from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_face_load.py", "independent_face_load")


def test_a_tilting_helical_mesh_s_slices_carry_the_spring_bed_at_the_tilt_of_the_axes(tmp_path):
    r = recoding
    g1, g2 = "stage3_wheel", "stage3_pinion"
    geo = r.pair(*(r.read_gears(r.HELICAL_MODEL)[g] for g in (g1, g2)))
    b, n = geo["b"], r.HELICAL_SLICES
    z = (np.arange(n) + 0.5) * b / n - b / 2
    res, text = r.helical_run(tmp_path / "tilting.mcap", tilting=True)
    leads = r.read_leads(text)
    e = res.mesh("stage3")
    y = e.contact_position - geo["rho1_a"] + b / 2 * math.tan(geo["beta_b"])
    stiffness = r.helical_stiffness(geo, r.HELICAL_STIFFNESS, b, n, y)
    theta, _, _ = r.tilt_of(res, text, g1, g2, e.flank, geo)
    assert np.max(np.abs(theta)) > 1e-5  # the gears do tilt
    # a sample's force is the step's mean of its forces at both ends (ρ∞ = 1): θ midway; the
    # last sample's θ would need the next sample
    mid = np.append(0.5 * (theta[:-1] + theta[1:]), theta[-1])
    keep = slice(0, len(theta) - 1)
    recoded = r.recode(e.normal, e.flank, b, n, stiffness, [leads[g1], leads[g2]], z, mid)
    _, line_loads = res.slice_line_loads("stage3")
    scale = float(np.max(recoded.mean[keep]))
    assert r.rel(line_loads[keep], recoded.w[keep], scale) < 1e-4
