"""Rolling-element loads of a radial bearing from its ring's displacement (ISO/TS 16281:2008).

The inner ring moves relative to the outer one by u = (u_x, u_y, u_z, θ_x, θ_y) in the bearing's
frame (u, w radial, z its axis; [m] and [rad]). Roller j of row r sits at ψ_j = 2πj/Z from u, in
contact at angle α with the raceways (row sign s_r = ±1: the two rows of a spherical roller
bearing lean opposite ways); its length L_we is cut into n_s slices at ξ_k along it (axial
position z_k = ξ_k cos α). Slice k of roller j is compressed by

    δ_jk = (ρ_jk − c) cos α + s_r a_jk sin α                       [m]
    ρ_jk = (u_x + θ_y z_k) cos ψ_j + (u_y − θ_x z_k) sin ψ_j        (radial approach)
    a_jk = u_z + R (θ_x sin ψ_j − θ_y cos ψ_j)                       (axial approach, R = d_m/2)

with the radial clearance c (negative: a preload), and carries (Palmgren's line contact,
ISO/TS 16281:2008 §5; Harris and Kotzalas 2007 eq. 7.1 for both raceways in series)

    q_jk = c_s max(δ_jk, 0)^(10/9),   c_s = (1/n_s) · L_we^(8/9) / (7.68·10⁻⁵)^(10/9)

in N, mm (Palmgren: δ = 3.84·10⁻⁵ Q^0.9 / L^0.8 at each raceway). A ball carries
Q_j = K max(δ_j, 0)^(3/2) (one slice, Hertz point contact, K = 1.0·10⁴ D_we^(1/2) [N, mm], Harris
and Kotzalas 2007 eq. 7.3 for steel-on-steel at typical conformity). The ring is in equilibrium
when the elements' loads balance the load W = (F_x, F_y, F_a, M_x, M_y) on it:

    W = Σ_jk q_jk ∂δ_jk/∂u,

solved for u by Newton's method (vectorised over the samples). Only cylindrical roller
bearings carry a tilting moment here (``InternalGeometry.carries_tilt``): self-aligning ones
(spherical, toroidal) carry none, and a single angular-contact row is held in tilt by its paired
row; for them θ is free and the moment is reported as not carried. A bearing at α = 0
(cylindrical, toroidal) carries no axial load on its raceways (ribs or nothing): u_z is free and
the axial load is reported as not carried.

Outputs: each element's load, the largest Q_max = max_j Σ_k q_jk [N], and the load-zone angle
2ψ_l of the widest row, cos ψ_l = (c − s_r u_z tan α)/ρ with the radial approach
ρ = |(u_x, u_y)| (``load_zone``; Harris and Kotzalas 2007 §7.3): 180° at zero clearance under
a radial load, less with clearance, more with a preload, and more in the row an axial load
presses (360° under a pure axial load).

**Reference rating life** (ISO/TS 16281:2008 §6, Lundberg-Palmgren's lamina summation): each
slice k of each raceway has an equivalent load over the rollers, the rotating ring's
q_e = (Σ_j q_jk^4 / Z)^(1/4) and the stationary one's q_e = (Σ_j q_jk^4.5 / Z)^(1/4.5) (balls: 3
and 10/3), and the raceways' dynamic ratings of a slice stand in the Lundberg-Palmgren ratio
q_ci/q_ce = ((1 − γ)/(1 + γ))^(143/108) (balls: ((1 − γ)/(1 + γ))^1.7233 times
((2f_i/(2f_i − 1))/(2f_e/(2f_e − 1)))^0.41 with f_i = 0.52, f_e = 0.53), γ = D_we cos α / d_m.
The bearing's "damage" D = Σ_k [(q_ei,k/q_ci)^(9/2) + (q_ee,k/q_ce)^(9/2)] (balls: exponent
10/3 over the two raceways) is homogeneous in the loads, of degree d = 9/2 (balls 10/3). pinwind
ties its level to ISO 281's rating C as the TS's calibration does: the **reference load**
P_ref is the radial load that gives the same D in the calibration case (no clearance, no tilt,
a continuum of rollers, pure radial load), P_ref = F (D/D_cal(F))^(1/d), and the reference life
is L_10r = (C/P_ref)^p with ISO 281's exponent p. In the calibration case P_ref = F_r exactly
in the continuum, and within the discretisation error (≈ 1 % at Z ≥ 12) with Z rollers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

LINE_EXPONENT = 10.0 / 9.0
POINT_EXPONENT = 1.5
#: Palmgren's line-contact deflection constant, both raceways in series [mm·N^-0.9·mm^0.8].
PALMGREN_LINE = 2 * 3.84e-5
#: Ball contact constant [N·mm^-2], Q = K √D_we δ^1.5 (module docstring).
BALL_CONTACT = 1.0e4
#: Conformities of ball raceways (groove radius / ball diameter) when not given.
BALL_CONFORMITY = (0.52, 0.53)


@dataclass(frozen=True)
class InternalGeometry:
    """What the load distribution needs of a bearing's inside (SI units).

    Attributes:
        kind: the type (a key of ``model.bearing.BEARING_TYPES``).
        rollers: Z, rolling elements per row.
        rows: 1, or 2 for a double-row bearing (its rows at ±α).
        contact_angle: α [rad].
        roller_diameter: D_we [m].
        roller_length: L_we [m] (0 for balls).
        pitch_diameter: d_m [m].
        clearance: radial clearance c [m] (negative: a preload).
        slices: n_s, slices of each roller (1 for balls).
        rotating: "inner" or "outer": the ring that turns relative to the load.
        estimated: the geometry was estimated from the bearing's size (``estimate_geometry``).
    """

    kind: str
    rollers: int
    rows: int
    contact_angle: float
    roller_diameter: float
    roller_length: float
    pitch_diameter: float
    clearance: float = 0.0
    slices: int = 10
    rotating: str = "inner"
    estimated: bool = False

    @property
    def ball(self) -> bool:
        """Point contact (a ball bearing)."""
        return self.kind.endswith("_ball")

    @property
    def self_aligning(self) -> bool:
        """The rings may tilt freely: the bearing carries no tilting moment."""
        return self.kind in ("spherical_roller", "toroidal_roller")

    @property
    def carries_tilt(self) -> bool:
        """A cylindrical roller bearing's rollers carry a tilting moment, loading one end.

        Self-aligning bearings carry none; a single angular-contact row (tapered roller,
        angular contact ball) is held in tilt by its paired row, and its moment about its own
        centre is left to that pair (not rated here); a deep groove ball bearing's is small.
        """
        return self.kind == "cylindrical_roller"

    @property
    def axially_free(self) -> bool:
        """α = 0: the raceways carry no axial load."""
        return self.contact_angle == 0.0

    @property
    def exponent(self) -> float:
        """Load-deflection exponent n: 10/9 line, 3/2 point contact."""
        return POINT_EXPONENT if self.ball else LINE_EXPONENT

    @property
    def slice_count(self) -> int:
        """Slices used: 1 unless the rollers carry tilt (uniform along the roller then)."""
        return self.slices if self.carries_tilt else 1

    @property
    def slice_stiffness(self) -> float:
        """c_s [N/m^n] of one slice (module docstring)."""
        if self.ball:
            k_mm = BALL_CONTACT * math.sqrt(self.roller_diameter * 1e3)
            return k_mm * 1e3**POINT_EXPONENT
        length_mm = self.roller_length * 1e3
        k_mm = length_mm ** (8.0 / 9.0) / PALMGREN_LINE ** (10.0 / 9.0)
        return k_mm * 1e3**LINE_EXPONENT / self.slice_count

    @property
    def gamma(self) -> float:
        """γ = D_we cos α / d_m [-]."""
        return self.roller_diameter * math.cos(self.contact_angle) / self.pitch_diameter

    @property
    def rating_ratio(self) -> float:
        """q_ci / q_ce of a slice (module docstring)."""
        g = (1.0 - self.gamma) / (1.0 + self.gamma)
        if not self.ball:
            return g ** (143.0 / 108.0)
        fi, fe = BALL_CONFORMITY
        return g**1.7233 * ((2 * fi / (2 * fi - 1)) / (2 * fe / (2 * fe - 1))) ** 0.41


#: Contact angles [deg] and rows of the types when a model does not give them (``BEARING_TYPES``).
TYPE_GEOMETRY = {
    "deep_groove_ball": (0.0, 1),
    "angular_contact_ball": (40.0, 1),
    "cylindrical_roller": (0.0, 1),
    "tapered_roller": (15.0, 1),
    "spherical_roller": (10.0, 2),
    "toroidal_roller": (0.0, 1),
}


def estimate_geometry(
    kind: str,
    size: tuple[float, float, float],
    *,
    clearance: float = 0.0,
    contact_angle: float | None = None,
    rotating: str = "inner",
) -> InternalGeometry:
    """An internal geometry estimated from the outer diameter D, bore d and width B [m].

    d_m = (D + d)/2; D_we = 0.25 (D − d) for rollers, 0.3 (D − d) for balls; L_we = 0.6 B
    (0.4 B per row of a double-row bearing); Z = ⌊0.85 π d_m / D_we⌋ (a cage filling 85 % of the
    pitch circle). Typical proportions of catalogue bearings, not any one bearing's: give
    ``rollers`` and ``roller_mm`` in the model for that (``estimated`` says it was estimated).
    """
    outer, bore, width = size
    alpha_deg, rows = TYPE_GEOMETRY[kind]
    alpha = math.radians(alpha_deg) if contact_angle is None else contact_angle
    ball = kind.endswith("_ball")
    dm = 0.5 * (outer + bore)
    dwe = (0.3 if ball else 0.25) * (outer - bore)
    length = 0.0 if ball else (0.4 if rows == 2 else 0.6) * width
    z = max(int(0.85 * math.pi * dm / dwe), 3)
    return InternalGeometry(
        kind, z, rows, alpha, dwe, length, dm, clearance, rotating=rotating, estimated=True
    )


@dataclass(frozen=True)
class Contacts:
    """The slices of every rolling element: their direction ∂δ/∂u and arrays of the geometry.

    Attributes:
        directions: g_m = ∂δ_m/∂u, (m, 5), m over rows × rollers × slices.
        element: the rolling element (row·Z + j) of each slice, (m,).
        slice_index: k of each slice, (m,).
        cos_alpha: cos α, the clearance's share of δ.
    """

    directions: np.ndarray
    element: np.ndarray
    slice_index: np.ndarray
    cos_alpha: float


def contacts(geometry: InternalGeometry) -> Contacts:
    """The slices of ``geometry``'s rolling elements (module docstring)."""
    z, ns = geometry.rollers, geometry.slice_count
    alpha = geometry.contact_angle
    psi = 2.0 * np.pi * np.arange(z) / z
    xi = ((np.arange(ns) + 0.5) / ns - 0.5) * geometry.roller_length
    zk = xi * math.cos(alpha)
    radius = 0.5 * geometry.pitch_diameter
    signs = (1.0, -1.0)[: geometry.rows]
    rows = []
    for r, s in enumerate(signs):
        c, sn = np.cos(psi)[:, None], np.sin(psi)[:, None]
        ca, sa = math.cos(alpha), s * math.sin(alpha)
        g = np.stack(
            np.broadcast_arrays(
                ca * c,
                ca * sn,
                sa + 0 * c,
                -zk[None, :] * ca * sn + sa * radius * sn,
                zk[None, :] * ca * c - sa * radius * c,
            ),
            axis=-1,
        )  # (Z, ns, 5)
        element = np.broadcast_to(r * z + np.arange(z)[:, None], (z, ns))
        index = np.broadcast_to(np.arange(ns)[None, :], (z, ns))
        rows.append((g.reshape(-1, 5), element.reshape(-1), index.reshape(-1)))
    return Contacts(
        np.concatenate([r[0] for r in rows]),
        np.concatenate([r[1] for r in rows]),
        np.concatenate([r[2] for r in rows]),
        math.cos(alpha),
    )


@dataclass(frozen=True)
class Distribution:
    """The internal load distribution of a bearing over samples.

    Attributes:
        displacement: u (n, 5) [m, rad]; NaN where no equilibrium was found.
        slice_loads: q (n, elements, slices) [N].
        max_element_load: Q_max (n,) [N].
        load_zone: 2ψ_l (n,) [rad].
        converged: (n,) bool.
        not_carried: the part of W the bearing cannot carry (tilt of a self-aligning bearing,
            axial of α = 0), (n, 5) [N, N·m].
    """

    displacement: np.ndarray
    slice_loads: np.ndarray
    max_element_load: np.ndarray
    load_zone: np.ndarray
    converged: np.ndarray
    not_carried: np.ndarray


def _free_axes(geometry: InternalGeometry) -> np.ndarray:
    carried = np.ones(5, dtype=bool)
    if geometry.axially_free:
        carried[2] = False
    if not geometry.carries_tilt:
        carried[3:] = False
    return carried


def _loads(
    u: np.ndarray, g: np.ndarray, c: float, cs: float, n: float
) -> tuple[np.ndarray, np.ndarray]:
    """(δ, q) (samples, m) of the slices at displacements u (samples, 5)."""
    delta = u @ g.T - c
    return delta, cs * np.maximum(delta, 0.0) ** n


def distribute(
    geometry: InternalGeometry,
    load: np.ndarray,
    *,
    tolerance: float = 1e-9,
    iterations: int = 80,
) -> Distribution:
    """The element loads that balance W (n, 5) = (F_x, F_y, F_a, M_x, M_y) on the inner ring.

    Newton's method on the carried axes (module docstring), from the displacement at which the
    most loaded element alone would carry the radial load; steps are halved until the residual
    falls. Samples that do not reach ``tolerance`` (relative to |W|) are NaN.
    """
    load = np.atleast_2d(np.asarray(load, dtype=float))
    samples = len(load)
    con = contacts(geometry)
    g, cs, n = con.directions, geometry.slice_stiffness, geometry.exponent
    c = geometry.clearance * con.cos_alpha
    carried = _free_axes(geometry)
    not_carried = np.where(carried, 0.0, load)
    w = np.where(carried, load, 0.0)
    radius = 0.5 * geometry.pitch_diameter
    # Scales: forces by |W| (moments by |W| R), displacements by the one-element deflection.
    scale_w = np.maximum(
        np.linalg.norm(w[:, :3], axis=1) + np.linalg.norm(w[:, 3:], axis=1) / radius, 1e-300
    )
    elements_share = max(geometry.rollers * geometry.rows / 4.0, 1.0) * geometry.slice_count
    delta0 = (scale_w / (cs * elements_share)) ** (1.0 / n)
    u = np.zeros((samples, 5))
    direction = w[:, :3] / scale_w[:, None]
    u[:, :3] = direction * (delta0 + abs(geometry.clearance))[:, None]
    u[:, :3] = np.where(carried[:3], u[:, :3], 0.0)
    active = np.flatnonzero(carried)
    ga = g[:, active]
    unit = np.where(np.arange(5) < 3, 1.0, radius)[active]

    def residual(x: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        delta, q = _loads(x, g, c, cs, n)
        r = (q @ ga - w[rows][:, active]) / unit
        return r, delta

    r, delta = residual(u, np.arange(samples))
    norm = np.linalg.norm(r, axis=1)
    done = norm <= tolerance * scale_w
    stalled = np.zeros(samples, dtype=bool)  # no step lowers the residual: no equilibrium
    for _ in range(iterations):
        todo = np.flatnonzero(~done & ~stalled)
        if len(todo) == 0:
            break
        d = np.maximum(delta[todo], 0.0)
        slope = cs * n * np.where(d > 0.0, d, 0.0) ** (n - 1.0)
        jac = np.einsum("sm,mi,mj->sij", slope, ga, ga)
        ridge = 1e-12 * np.trace(jac, axis1=1, axis2=2)[:, None, None] + 1e-300
        jac = jac + ridge * np.eye(len(active))[None]
        rhs = -r[todo] * unit[None, :]
        step = np.linalg.solve(jac, rhs[..., None])[..., 0]
        factor = np.ones(len(todo))
        for _ in range(12):
            trial = u[todo].copy()
            trial[:, active] = trial[:, active] + factor[:, None] * step
            r_t, delta_t = residual(trial, todo)
            better = np.linalg.norm(r_t, axis=1) < norm[todo]
            if better.all():
                break
            factor = np.where(better, factor, 0.5 * factor)
        stalled[todo[~better]] = True
        keep = todo[better]  # a sample whose residual would not fall keeps its displacement
        u[keep] = trial[better]
        r[keep], delta[keep] = r_t[better], delta_t[better]
        norm[keep] = np.linalg.norm(r_t[better], axis=1)
        done = norm <= tolerance * scale_w
    converged = done | (scale_w <= 1e-300)
    _, q = _loads(u, g, c, cs, n)
    z = geometry.rollers * geometry.rows
    q = q.reshape(samples, z, geometry.slice_count)
    zone = load_zone(geometry, u)
    u = np.where(converged[:, None], u, np.nan)
    q = np.where(converged[:, None, None], q, np.nan)
    return Distribution(
        u, q, np.max(q.sum(axis=2), axis=1), np.where(converged, zone, np.nan), converged,
        not_carried,
    )  # fmt: skip


def load_zone(geometry: InternalGeometry, u: np.ndarray) -> np.ndarray:
    """The load-zone angle 2ψ_l [rad] of the ring displacements u (n, 5): the widest row's.

    Roller j of row r (sign s_r) is in contact where δ > 0, ρ cos(ψ_j − φ) > c − s_r a tan α
    (module docstring; a = u_z: an angular row carries no tilt), so its row's zone is
    2ψ_l, cos ψ_l = (c − s_r u_z tan α)/ρ, ρ = |(u_x, u_y)| (Harris and Kotzalas 2007 §7.3;
    with α = 0, cos ψ_l = c/ρ). An axial approach widens one row's zone past 180° (360°: every
    roller in contact, as under a pure axial load) and narrows the other's; the widest is
    reported, the arc of the most loaded row. At ρ = 0 a row is all in contact (360°) when its
    axial approach exceeds the clearance, else out of contact (0).
    """
    rho = np.hypot(u[:, 0], u[:, 1])
    axial = u[:, 2] * math.tan(geometry.contact_angle)
    zone = np.zeros(len(u))
    for sign in (1.0, -1.0)[: geometry.rows]:
        edge = geometry.clearance - sign * axial  # ρ cos ψ_l
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_l = np.where(rho > 0.0, edge / rho, np.where(edge < 0.0, -1.0, 1.0))
        zone = np.maximum(zone, 2.0 * np.arccos(np.clip(cos_l, -1.0, 1.0)))
    return zone


def _damage_degree(geometry: InternalGeometry) -> float:
    return 10.0 / 3.0 if geometry.ball else 4.5


def _ring_exponents(geometry: InternalGeometry) -> tuple[float, float]:
    """(rotating, stationary) ring exponents of the equivalent element load."""
    return (3.0, 10.0 / 3.0) if geometry.ball else (4.0, 4.5)


def lamina_damage(geometry: InternalGeometry, slice_loads: np.ndarray) -> np.ndarray:
    """D (n,) of slice loads (n, elements, slices) [N] with q_ce = 1 N (module docstring).

    The rows of a double-row bearing each have their raceways; D adds over them.
    """
    rotating, stationary = _ring_exponents(geometry)
    d = _damage_degree(geometry)
    inner_rate, outer_rate = geometry.rating_ratio, 1.0
    z = geometry.rollers
    total = np.zeros(slice_loads.shape[0])
    for r in range(geometry.rows):
        q = slice_loads[:, r * z : (r + 1) * z, :]
        q_rot = np.mean(q**rotating, axis=1) ** (1.0 / rotating)
        q_sta = np.mean(q**stationary, axis=1) ** (1.0 / stationary)
        q_inner, q_outer = (q_rot, q_sta) if geometry.rotating == "inner" else (q_sta, q_rot)
        total += np.sum((q_inner / inner_rate) ** d + (q_outer / outer_rate) ** d, axis=1)
    return total


def _cos_integral(power: float) -> float:
    """(1/2π) ∫_{−π/2}^{π/2} cos^a ψ dψ = Γ((a+1)/2) / (2√π Γ(a/2 + 1))."""
    return math.gamma((power + 1.0) / 2.0) / (
        2.0 * math.sqrt(math.pi) * math.gamma(power / 2.0 + 1.0)
    )


def calibration_damage(geometry: InternalGeometry, radial_load: float) -> float:
    """D_cal(F) of the calibration case: F radial, no clearance, a continuum of elements.

    The loads of the elements of each row are q(ψ) = q_max cos^n ψ over |ψ| < π/2 (n = 10/9 or
    3/2), with F = i Z n_s q_max cos α · J_r, J_r = (1/2π)∫cos^(n+1) ψ dψ; the ring equivalent
    loads are q_max J_w^(1/w), J_w = (1/2π)∫cos^(n w) ψ dψ.
    """
    n = geometry.exponent
    ns = geometry.slice_count
    rows = geometry.rows
    j_r = _cos_integral(n + 1.0)
    q_max = radial_load / (rows * geometry.rollers * ns * math.cos(geometry.contact_angle) * j_r)
    rotating, stationary = _ring_exponents(geometry)
    q_rot = q_max * _cos_integral(n * rotating) ** (1.0 / rotating)
    q_sta = q_max * _cos_integral(n * stationary) ** (1.0 / stationary)
    q_inner, q_outer = (q_rot, q_sta) if geometry.rotating == "inner" else (q_sta, q_rot)
    d = _damage_degree(geometry)
    return rows * ns * ((q_inner / geometry.rating_ratio) ** d + q_outer**d)


def reference_load(geometry: InternalGeometry, slice_loads: np.ndarray) -> np.ndarray:
    """P_ref (n,) [N]: the radial load of equal lamina damage in the calibration case."""
    damage = lamina_damage(geometry, slice_loads)
    unit = calibration_damage(geometry, 1.0)
    return (damage / unit) ** (1.0 / _damage_degree(geometry))
