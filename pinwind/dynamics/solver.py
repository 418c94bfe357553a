"""Constrained dynamics of one step as an equality QP solved with proxsuite.

Gauss's principle (design.md §2):

    minimise ½ aᵀ M a − (τ − b)ᵀ a     subject to   J a = r

proxsuite's stationarity condition is M a − (τ − b) + Jᵀ y = 0, so the constraint forces are
λ = −y: the generalised force of the constraints is Jᵀ λ. Rigid multi-planet stages give redundant
rows (a 3-planet stage's 6 mesh rows have rank 4): the KKT matrix is singular and a plain KKT solve
fails, but the proximal method of multipliers converges, and because its dual updates stay in
range(J M⁻¹ Jᵀ) it returns the minimum-norm multipliers, i.e. equal load sharing in a symmetric
stage. Two settings keep that property:

- no preconditioner: proxsuite's Ruiz equilibration rescales the rows, and the multipliers it
  returns are then minimum-norm in the scaled rows, not in newtons;
- a fresh solve starts from proxsuite's equality-constrained initial guess, the solution of the
  regularised KKT system, which lies in range(J M⁻¹ Jᵀ); later solves warm-start from the
  previous solution. Neither has a null-space component, and the dual updates add none. Warm
  starting also brings a step down to zero to two proximal iterations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import proxsuite

_SOLVED = proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED


def _power_of_two(x: float) -> float:
    """A power of two within a factor two of x (x > 0): dividing by it is exact."""
    return math.ldexp(1.0, math.frexp(x)[1])


@dataclass(frozen=True)
class SolverSettings:
    """proxsuite settings used for every step.

    Attributes:
        eps_abs: absolute tolerance on the primal and dual residuals of the QP scaled to unit
            size (see ``solve``): a relative accuracy of the accelerations and forces.
        eps_rel: relative tolerance (proxsuite's scaled residuals).
        max_iter: iteration cap of the outer loop.
    """

    eps_abs: float = 1e-13
    eps_rel: float = 0.0
    max_iter: int = 1000

    def as_dict(self) -> dict:
        """Settings for metadata."""
        return {
            "solver": "proxsuite.proxqp.dense",
            "proxsuite_version": getattr(proxsuite, "__version__", "unknown"),
            "eps_abs": self.eps_abs,
            "eps_rel": self.eps_rel,
            "max_iter": self.max_iter,
        }


@dataclass
class Solution:
    """One QP solution.

    Attributes:
        acceleration: a [rad/s²], (nv,).
        multipliers: λ, (rows,) [N for mesh rows, N·m for driver rows].
        primal_residual: ‖J a − r‖∞.
        dual_residual: ‖M a − (τ − b) − Jᵀ λ‖∞ [N·m].
        iterations: proxsuite iterations.
        solved: proxsuite reported success.
        status: proxsuite's status text.
    """

    acceleration: np.ndarray
    multipliers: np.ndarray
    primal_residual: float
    dual_residual: float
    iterations: int
    solved: bool
    status: str


class ConstrainedDynamicsSolver:
    """A proxsuite dense QP of fixed size reused for every step."""

    def __init__(self, nv: int, rows: int, settings: SolverSettings | None = None):
        self.settings = settings or SolverSettings()
        self.nv = nv
        self.rows = rows
        self._qp = None
        self._data_scale = 0.0
        self._mass_cache: np.ndarray | None = None
        self._mass_scale = 1.0
        self._h = np.zeros((nv, nv))
        self._jac_cache: np.ndarray | None = None
        self._range = np.zeros((0, 0))
        self._full_rank = True

    def _new_qp(self, m, g, jac, rhs):
        qp = proxsuite.proxqp.dense.QP(self.nv, self.rows, 0)
        qp.settings.eps_abs = self.settings.eps_abs
        qp.settings.eps_rel = self.settings.eps_rel
        qp.settings.max_iter = self.settings.max_iter
        qp.settings.initial_guess = proxsuite.proxqp.InitialGuess.EQUALITY_CONSTRAINED_INITIAL_GUESS
        qp.settings.verbose = False
        qp.init(m, g, jac, rhs, None, None, None, compute_preconditioner=False)
        qp.solve()
        qp.settings.initial_guess = proxsuite.proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
        return qp

    def _rows_changed(self, jac: np.ndarray) -> bool:
        """Whether J differs from the previous step's (to 1e-12); refreshes the range projector.

        Redundant rows have right-hand sides that agree only up to rounding; left as they are,
        the system is inconsistent at the 1e-12 level, the proximal iterations cannot converge
        and the multipliers of the redundant directions drift. So the right-hand side is
        projected onto range(J). The projector is kept while J stays the same, which it does
        for gears on fixed or carrier-borne axes.
        """
        cached = self._jac_cache
        if (
            cached is not None
            and cached.shape == jac.shape
            and np.max(np.abs(jac - cached), initial=0.0)
            <= 1e-12 * np.max(np.abs(jac), initial=0.0)
        ):
            return False
        u, sv, _ = np.linalg.svd(jac, full_matrices=False)
        basis = u[:, sv > 1e-10 * sv[0]] if sv.size and sv[0] > 0 else u[:, :0]
        self._range = basis @ basis.T
        self._full_rank = basis.shape[1] == jac.shape[0]
        self._jac_cache = jac.copy()
        return True

    def solve(
        self, mass: np.ndarray, force: np.ndarray, jac: np.ndarray, rhs: np.ndarray
    ) -> Solution:
        """Solve M a = force + Jᵀ λ, J a = rhs.

        Args:
            mass: joint-space inertia M (nv, nv) [kg·m²].
            force: τ − b, applied minus bias forces (nv,) [N·m].
            jac: constraint rows J (rows, nv).
            rhs: right-hand side r (rows,).
        """
        if self.rows == 0:
            acc = np.linalg.solve(mass, force)
            return Solution(acc, np.zeros(0), 0.0, 0.0, 0, True, "unconstrained")
        rows_changed = self._rows_changed(jac)
        if not self._full_rank:
            rhs = self._range @ rhs
        # Scale the QP to unit size with powers of two, which are exact in floating point:
        # the cost by the largest inertia (so the dual residual is in rad/s² like the primal
        # one), the unknowns by the size of the data. One absolute tolerance then means the
        # same relative accuracy in every run, and a uniform scaling keeps the multipliers
        # minimum-norm. A change of the data scale restarts the solve like new rows do.
        previous_scale = self._mass_scale
        mass_changed = self._mass_changed(mass)
        mass_scale = self._mass_scale
        h, g = self._h, -force / mass_scale
        size = max(float(np.abs(g).max()), float(np.abs(rhs).max()))
        data_scale = _power_of_two(size) if size > 0.0 else 1.0
        restart = (
            rows_changed
            or data_scale != self._data_scale
            or mass_scale != previous_scale
            or self._qp is None
        )
        self._data_scale = data_scale
        g, b = g / data_scale, rhs / data_scale
        if restart:
            self._qp = self._new_qp(h, g, jac, b)
        else:
            # Unchanged H and A are not passed again: proxsuite then keeps its factorisation.
            self._qp.update(
                H=h if mass_changed else None, g=g, A=None, b=b, update_preconditioner=False
            )
            self._qp.solve()
            if self._qp.results.info.status != _SOLVED:
                self._qp = self._new_qp(h, g, self._jac_cache, b)
        res = self._qp.results
        acc = data_scale * res.x
        lam = -(mass_scale * data_scale) * res.y
        solved = res.info.status == _SOLVED
        # proxsuite's residuals (∞-norms) of the scaled problem, back in SI units.
        primal = float(res.info.pri_res) * data_scale
        dual = float(res.info.dua_res) * data_scale * mass_scale
        return Solution(
            acceleration=acc,
            multipliers=lam,
            primal_residual=primal,
            dual_residual=dual,
            iterations=int(res.info.iter),
            solved=solved,
            status="PROXQP_SOLVED" if solved else str(res.info.status).split(".")[-1],
        )

    def _mass_changed(self, mass: np.ndarray) -> bool:
        """Whether M differs from the previous step's (to 1e-12); refreshes its scaled copy."""
        cached = self._mass_cache
        if cached is not None and np.max(np.abs(mass - cached)) <= 1e-12 * self._mass_scale:
            return False
        self._mass_cache = mass.copy()
        self._mass_scale = _power_of_two(float(np.abs(mass).max()))
        self._h = mass / self._mass_scale
        return True
