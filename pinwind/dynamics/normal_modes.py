"""Natural modes of a linear gear train: (K − ω² M) φ = 0 over the motions the rigid rows allow.

A gear train linearised about its reference pose is M q̈ + C q̇ + K q = 0 on the joint
coordinates, with the rigid meshes, speed drivers and locks as rows J q̇ = 0. Over a basis B of
the motions the rows allow (q = B y), the generalised eigenproblem Bᵀ K B y = ω² Bᵀ M B y gives
the undamped natural frequencies and, with φ = B y mass-normalised (φᵀ M φ = 1), the modal
damping ratio ζ = φᵀ C φ / (2ω) (proportional damping assumed; the dashpots' share of each mode).
Each mode's kinetic energy splits over the joints as φⱼ (M φ)ⱼ and its strain energy over the
elements as ½ kₑ (Jₑ φ)² / (½ ω²), the shares every modal report gives (which body moves, which
spring works). Motions no spring resists (the train turning as a whole) have ω = 0: rigid modes.

This module holds the eigenproblem only; ``dynamics/linear_model.py`` builds M, K, C and the
rows of a model at rest, ``modes/linearisation.py`` at an operating speed; a run asks it for its
highest mesh mode (``dynamics/compliant.py``), its highest torsional-spring mode
(``dynamics/torsional_modes.py``) and the motions nothing holds (``linear_model.check_held``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: ω² below this fraction of the largest one is a rigid mode (no spring resists it).
RIGID_TOLERANCE = 1e-9
#: Frequencies this close (relative) are one repeated (degenerate) frequency.
REPEATED_TOLERANCE = 1e-6


@dataclass(frozen=True)
class SpringElement:
    """One linear spring-damper of the train: force −k (J q) − c (J q̇) along its row.

    Attributes:
        name: the mesh or spring name.
        kind: ``"mesh"``, ``"spring"``, ``"bearing"`` (a compliant bearing's slide) or
            ``"support"`` (a support slide: a tower mode or a mount).
        stiffness: k [N/m or N·m/rad].
        damping: c [N·s/m or N·m·s/rad].
        row: J (nv,): the deflection (or twist) per joint coordinate [m or rad per rad].
    """

    name: str
    kind: str
    stiffness: float
    damping: float
    row: np.ndarray


@dataclass(frozen=True)
class Mode:
    """One natural mode.

    Attributes:
        frequency: undamped natural frequency [Hz] (0 for a rigid mode); at speed |λ|/2π.
        damping_ratio: ζ from the dashpots [-]; at speed −Re λ/|λ|.
        shape: φ (nv,), mass-normalised (φᵀ M φ = 1 kg·m²), joint coordinates.
        kinetic_share: joint name → share of the mode's kinetic energy [-] (sums to 1).
        strain_share: element name → share of the mode's strain energy [-] (sums to 1 when
            the elements hold all the stiffness).
        kind: for a train with planetary stages, the class of mode Lin & Parker give
            (``rotational``, ``translational``, ``planet`` or ``unclassified``;
            ``modes/planetary_modes.py``); ``""`` without a stage.
        whirl: ``forward`` or ``backward`` when a spinning body orbits in its bearing with or
            against its spin (``modes/gyroscopic_modes.py``); ``""`` otherwise.
        complex_shape: φ (nv,) complex, φᴴ M φ = 1, the motion Re(φ e^{λt}) of a mode at speed
            (``modes/gyroscopic_modes.py``); ``None`` for the real modes of the symmetric solve.
    """

    frequency: float
    damping_ratio: float
    shape: np.ndarray
    kinetic_share: dict[str, float]
    strain_share: dict[str, float]
    kind: str = ""
    whirl: str = ""
    complex_shape: np.ndarray | None = None

    @property
    def rigid(self) -> bool:
        """No spring resists the motion (the train turning as a whole)."""
        return self.frequency == 0.0


def free_motions(constraints: np.ndarray, nv: int) -> np.ndarray:
    """Basis (nv, f) of the motions the rows J (r, nv) allow: the null space of J."""
    if constraints.shape[0] == 0:
        return np.eye(nv)
    _, sv, vt = np.linalg.svd(constraints)
    rank = int(np.sum(sv > 1e-10 * sv[0]))
    return vt[rank:].T


def element_matrices(elements: list[SpringElement], nv: int) -> tuple[np.ndarray, np.ndarray]:
    """K = Σ kₑ JₑᵀJₑ and C = Σ cₑ JₑᵀJₑ of the elements (nv, nv)."""
    stiffness, damping = np.zeros((nv, nv)), np.zeros((nv, nv))
    for e in elements:
        stiffness += e.stiffness * np.outer(e.row, e.row)
        damping += e.damping * np.outer(e.row, e.row)
    return stiffness, damping


def _generalised_eigh(k: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and eigenvectors of K y = λ M y, M symmetric positive definite.

    With M = L Lᵀ (Cholesky), the symmetric problem L⁻¹ K L⁻ᵀ z = λ z and y = L⁻ᵀ z; numpy's, as
    scipy.linalg's import alone costs more than the modes of a gearbox.
    """
    lower = np.linalg.cholesky(m)
    half = np.linalg.solve(lower, k)
    reduced = np.linalg.solve(lower, half.T)
    values, z = np.linalg.eigh(0.5 * (reduced + reduced.T))
    return values, np.linalg.solve(lower.T, z)


def natural_modes(
    mass: np.ndarray,
    stiffness: np.ndarray,
    damping: np.ndarray,
    constraints: np.ndarray,
    *,
    joint_names: list[str] | None = None,
    elements: list[SpringElement] | None = None,
) -> list[Mode]:
    """The natural modes of M q̈ + C q̇ + K q = 0 under J q̇ = 0, lowest first (module docstring).

    Args:
        mass, stiffness, damping: M, K, C (nv, nv) on the joint coordinates.
        constraints: J (r, nv), the rigid rows (meshes, drivers, locks).
        joint_names: names of the nv coordinates, for the kinetic-energy shares.
        elements: the springs K is made of, for the strain-energy shares.
    """
    nv = mass.shape[0]
    basis = free_motions(constraints, nv)
    if basis.shape[1] == 0:
        return []
    m = basis.T @ mass @ basis
    omega2, vectors = _generalised_eigh(basis.T @ stiffness @ basis, m)
    largest = max(float(omega2[-1]), 0.0)
    names = joint_names or [str(i) for i in range(nv)]
    out = []
    for value, y in zip(omega2, vectors.T, strict=True):
        phi = basis @ y / math.sqrt(float(y @ m @ y))
        rigid = value <= RIGID_TOLERANCE * largest
        omega = 0.0 if rigid else math.sqrt(float(value))
        ratio = float(phi @ damping @ phi) / (2.0 * omega) if omega > 0.0 else 0.0
        kinetic = phi * (mass @ phi)
        strain = {}
        if elements and omega > 0.0:
            strain = {e.name: e.stiffness * float(e.row @ phi) ** 2 / omega**2 for e in elements}
        out.append(
            Mode(
                frequency=omega / (2.0 * math.pi),
                damping_ratio=ratio,
                shape=phi,
                kinetic_share={n: float(x) for n, x in zip(names, kinetic, strict=True)},
                strain_share=strain,
            )
        )
    return out


def repeated_groups(modes: list[Mode]) -> list[list[Mode]]:
    """The modes grouped by repeated frequency (``REPEATED_TOLERANCE``), lowest first.

    A repeated frequency's shapes are any basis of its eigenspace, so only what the group shares
    (its frequency, its multiplicity, the sum of its energy shares) describes it.
    """
    groups: list[list[Mode]] = []
    for mode in sorted(modes, key=lambda m: m.frequency):
        if groups and math.isclose(
            groups[-1][0].frequency, mode.frequency, rel_tol=REPEATED_TOLERANCE
        ):
            groups[-1].append(mode)
        else:
            groups.append([mode])
    return groups
