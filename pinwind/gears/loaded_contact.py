"""Springs in parallel behind gaps, pressed by one force: tooth contact in a static mesh.

A loaded mesh at rest is a bed of linear springs (tooth pairs, slices of their face width),
each behind its own gap e_i (the material its modifications removed, a misalignment), all moved
by one approach δ along the line of action. A spring carries k_i (δ − e_i) while δ > e_i and
nothing otherwise, so the force is

    F(δ) = Σ_i k_i max(0, δ − e_i),

piecewise linear and increasing in δ. `approach` inverts it exactly: with the springs sorted by
gap, the first m engaged give δ_m = (F + Σ_{i<m} k_i e_i) / Σ_{i<m} k_i, the answer where it
lies between the m-th and the (m+1)-th gap. The same law is each slice of ISO 6336-1's face load
distribution (its spring bed) and each pair of a loaded transmission-error calculation.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError


def approach(stiffness: npt.ArrayLike, gap: npt.ArrayLike, force: float) -> float:
    """The approach δ [m] at which springs ``stiffness`` [N/m] behind ``gap`` [m] carry ``force``.

    ``force`` [N]. Springs of zero stiffness take no part. With ``force`` 0 the approach is the
    smallest gap (the flanks just touch).

    Raises:
        InputError: a negative or non-finite force, stiffness or gap, or no spring to carry it.
    """
    k = np.asarray(stiffness, dtype=float).ravel()
    e = np.asarray(gap, dtype=float).ravel()
    if k.shape != e.shape:
        raise InputError(f"{k.size} stiffnesses for {e.size} gaps; give one gap per spring")
    if not (np.isfinite(force) and force >= 0.0):
        raise InputError(f"contact force {force!r} N; it must be finite and ≥ 0 (compression)")
    if not (np.all(np.isfinite(k)) and np.all(np.isfinite(e))) or np.any(k < 0.0):
        raise InputError("contact springs need finite stiffnesses ≥ 0 and finite gaps")
    live = k > 0.0
    if not np.any(live):
        raise InputError("no tooth pair in contact carries stiffness: nothing carries the load")
    k, e = k[live], e[live]
    order = np.argsort(e, kind="stable")
    k, e = k[order], e[order]
    engaged = np.cumsum(k)
    # δ_m with the first m + 1 springs engaged; valid where it does not pass the next gap.
    delta = (force + np.cumsum(k * e)) / engaged
    upper = np.append(e[1:], np.inf)
    m = int(np.argmax(delta <= upper))
    return float(max(delta[m], e[0]))


def spring_forces(stiffness: npt.ArrayLike, gap: npt.ArrayLike, delta: float) -> np.ndarray:
    """Each spring's force k_i max(0, δ − e_i) [N] at approach δ [m], shaped like ``gap``."""
    k = np.asarray(stiffness, dtype=float)
    return k * np.maximum(0.0, delta - np.asarray(gap, dtype=float))
