"""Modes at speed: the quadratic eigenproblem (M λ² + (C + G) λ + K) φ = 0, and an orbit's whirl.

A train linearised at an operating speed whose velocity terms act (a body spinning while it tilts
in a compliant bearing) has a gyroscopic matrix G = ∂(C(q, v) v)/∂v, skew for a conservative
spin, and a centrifugal stiffness K_Ω = ∂(C(q, v) v)/∂q (``modes/linearisation.py``). Over the
basis B of the motions the rigid rows allow (q = B y), the quadratic eigenproblem

    (M_r λ² + D_r λ + K_r) y = 0,   M_r = Bᵀ M B, D_r = Bᵀ (C + G) B, K_r = Bᵀ (K + K_Ω) B,

is solved in first-order (state-space) form on the 2f pencil

    [ 0     s I ] [y]       [ I  0  ] [y]
    [ −K_r/s −D_r] [w] = λ  [ 0  M_r] [w],    w = λ y / s,

(s = √(|K_r| / |M_r|), the frequency scale, keeps both rows of one size) with
``scipy.linalg.eig``. The eigenvalues come in conjugate pairs; each pair λ, λ̄ with Im λ > 0 is a
mode whose motion is Re(φ e^{λt}): natural frequency |λ|/2π (the undamped one when C = 0, since λ
is then imaginary; the damped one is |Im λ|/2π = f √(1 − ζ²)) and damping ratio ζ = −Re λ/|λ|.
Real eigenvalues pair up, by size, into overdamped modes (f = √(λ₁λ₂)/2π, ζ ≥ 1), zero ones into
rigid modes (0 Hz), and a positive with a negative one into a divergence (f = √|λ₁λ₂|/2π, ζ = −1: a
centrifugal softening beyond the stiffness). Energy shares as in ``dynamics/normal_modes.py``,
time-averaged over the complex shape: joint j's kinetic share Re(φ̄ⱼ (M φ)ⱼ) / φᴴ M φ, element e's
strain share kₑ |Jₑ φ|² / φᴴ K φ.

The orbit of a body translating (or tilting) in a bearing on its two radial coordinates u, w
(``radial_x``, ``radial_y``; or the tilts about them, whose axis tip traces (θ_w, −θ_u), turned a
quarter turn but with the same sense) is (Re(φ_u e^{iωt}), Re(φ_w e^{iωt})): its mean angular
momentum about k = u × w is ∝ ω Im(φ_u φ̄_w). Its sign against the body's spin about k is the
whirl: **forward** when the orbit turns with the spin, **backward** against it (a disc's tilt
modes split so under its polar inertia's gyroscopic moment, Jeffcott/Stodola-Green).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.normal_modes import (
    RIGID_TOLERANCE,
    Mode,
    SpringElement,
    free_motions,
)

#: |Re λ| below this fraction of the largest |λ| is the eigensolver's rounding: ζ = 0.
DAMPING_ROUNDING = 1e-10
#: An orbit of semi-axes a ≥ b with 2ab/(a² + b²) below this (b < 2.5 % of a: the slight
#: ellipse Coriolis forces give a planet's near-straight orbit on a turning carrier) is a line,
#: without whirl; a circular whirl has 1.
LINE_TOLERANCE = 0.05
#: A pair with less than this share of the mode's kinetic energy does not move in it.
MOVING_SHARE = 1e-6
FORWARD, BACKWARD = "forward", "backward"


@dataclass(frozen=True)
class WhirlPair:
    """Two coordinates of a spinning body that orbit in a bearing's plane (module docstring).

    Attributes:
        body: the bearing's joint name.
        coordinates: (index of u, index of w) in the velocity vector: the radial slides, or the
            tilts about u and w.
        spin: the body's angular velocity about k = u × w at the operating speed [rad/s].
    """

    body: str
    coordinates: tuple[int, int]
    spin: float


def gyroscopic_modes(
    mass: np.ndarray,
    stiffness: np.ndarray,
    damping: np.ndarray,
    constraints: np.ndarray,
    *,
    gyroscopic: np.ndarray,
    centrifugal: np.ndarray,
    joint_names: list[str] | None = None,
    elements: list[SpringElement] | None = None,
) -> list[Mode]:
    """The modes of M q̈ + (C + G) q̇ + (K + K_Ω) q = 0 under J q̇ = 0, lowest first.

    Module docstring. Each mode's ``complex_shape`` is φ (nv,) with φᴴ M φ = 1; its ``shape`` is
    the real motion at the phase where φ is most nearly real, mass-normalised.

    Args:
        mass, stiffness, damping: M, K, C (nv, nv) on the joint coordinates.
        constraints: J (r, nv), the rigid rows (meshes, drivers, locks).
        gyroscopic: G (nv, nv) [N·m·s/rad].
        centrifugal: K_Ω (nv, nv) [N·m/rad].
        joint_names: names of the nv coordinates, for the kinetic-energy shares.
        elements: the springs K is made of, for the strain-energy shares.
    """
    # scipy's import costs more than a gearbox's modes at rest, which do not need it.
    import scipy.linalg

    nv = mass.shape[0]
    basis = free_motions(constraints, nv)
    f = basis.shape[1]
    if f == 0:
        return []
    m = basis.T @ mass @ basis
    d = basis.T @ (damping + gyroscopic) @ basis
    k = basis.T @ (stiffness + centrifugal) @ basis
    s = math.sqrt(float(np.abs(k).max()) / float(np.abs(m).max())) or 1.0
    eye, zero = np.eye(f), np.zeros((f, f))
    values, vectors = scipy.linalg.eig(
        np.block([[zero, s * eye], [-k / s, -d]]), np.block([[eye, zero], [zero, m]])
    )
    size = np.abs(values)
    rigid_below = math.sqrt(RIGID_TOLERANCE) * float(size.max())
    oscillating = [i for i in range(2 * f) if values[i].imag > rigid_below]
    # Real eigenvalues (|Im λ| small), zero ones first: pairs of them are the rigid and
    # overdamped modes.
    real = sorted(
        (i for i in range(2 * f) if abs(values[i].imag) <= rigid_below), key=lambda i: size[i]
    )
    names = joint_names or [str(i) for i in range(nv)]
    out = []
    for i in oscillating:
        lam = complex(values[i])
        # Below the eigensolver's rounding (relative to the largest |λ|) there is no damping.
        undamped = abs(lam.real) <= DAMPING_ROUNDING * float(size.max())
        ratio = 0.0 if undamped else -lam.real / abs(lam)
        out.append(_mode(basis @ vectors[:f, i], abs(lam), ratio, mass, stiffness, names, elements))
    for a, b in zip(real[0::2], real[1::2], strict=False):
        rigid = min(size[a], size[b]) <= rigid_below
        omega = 0.0 if rigid else math.sqrt(float(size[a] * size[b]))
        ratio = 0.0 if rigid else -float(values[a].real + values[b].real) / (2.0 * omega)
        if not rigid and values[a].real * values[b].real < 0.0:
            ratio = -1.0  # a divergence (K + K_Ω not positive): one root grows as e^{|λ|t}
        out.append(_mode(basis @ vectors[:f, a], omega, ratio, mass, stiffness, names, elements))
    return sorted(out, key=lambda mode: mode.frequency)


def _mode(
    phi: np.ndarray,
    omega: float,
    ratio: float,
    mass: np.ndarray,
    stiffness: np.ndarray,
    names: list[str],
    elements: list[SpringElement] | None,
) -> Mode:
    """One mode from its complex shape φ (nv,), |λ| [rad/s] and ζ (module docstring)."""
    phi = phi / math.sqrt(float(np.real(phi.conj() @ mass @ phi)))
    # The phase at which φ is most nearly real: e^{−iα} φ with α = ½ arg Σ φⱼ².
    real = np.real(phi * np.exp(-0.5j * np.angle(np.sum(phi * phi))))
    real_norm = float(real @ mass @ real)
    if real_norm > 0.0:
        real = real / math.sqrt(real_norm)
    kinetic = np.real(phi.conj() * (mass @ phi))
    strain = {}
    elastic = float(np.real(phi.conj() @ stiffness @ phi))
    if elements and omega > 0.0 and elastic > 0.0:
        strain = {e.name: e.stiffness * abs(complex(e.row @ phi)) ** 2 / elastic for e in elements}
    return Mode(
        frequency=omega / (2.0 * math.pi),
        damping_ratio=ratio,
        shape=real,
        kinetic_share={n: float(x) for n, x in zip(names, kinetic, strict=True)},
        strain_share=strain,
        complex_shape=phi,
    )


def whirl(mode: Mode, pairs: list[WhirlPair]) -> str:
    """``forward``, ``backward`` or ``""``: the whirl of the spinning pair that moves most.

    The pair of ``pairs`` with the largest kinetic-energy share in the mode decides; ``""`` when
    the mode has no complex shape, no spinning pair moves, or its orbit is a line. (A repeated
    frequency's shapes are any basis of its eigenspace, and so are their orbits:
    ``Linearisation.modes`` gives such modes none.)
    """
    phi = mode.complex_shape
    if phi is None:
        return ""
    names = list(mode.kinetic_share)
    moving = [p for p in pairs if p.spin != 0.0]
    if not moving:
        return ""

    def share(p: WhirlPair) -> float:
        return sum(abs(mode.kinetic_share[names[j]]) for j in p.coordinates)

    pair = max(moving, key=share)
    if share(pair) <= MOVING_SHARE:
        return ""
    u, w = (complex(phi[j]) for j in pair.coordinates)
    # 2 Im(u w̄) / (|u|² + |w|²) = 2ab/(a² + b²), signed by the orbit's sense about u × w.
    sense = (u * w.conjugate()).imag
    if abs(2.0 * sense) <= LINE_TOLERANCE * (abs(u) ** 2 + abs(w) ** 2):
        return ""
    return FORWARD if sense * pair.spin > 0.0 else BACKWARD
