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
- the first solve starts from y = 0 and later solves warm-start from the previous solution, whose
  null-space component is zero and stays zero under the dual updates. Warm starting also brings a
  step down to one or two proximal iterations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import proxsuite


@dataclass(frozen=True)
class SolverSettings:
    """proxsuite settings used for every step.

    Attributes:
        eps_abs: absolute tolerance on primal and dual residuals.
        eps_rel: relative tolerance (proxsuite's scaled residuals).
        max_iter: iteration cap of the outer loop.
    """

    eps_abs: float = 1e-9
    eps_rel: float = 1e-14
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

    def _new_qp(self, m, g, jac, rhs):
        qp = proxsuite.proxqp.dense.QP(self.nv, self.rows, 0)
        qp.settings.eps_abs = self.settings.eps_abs
        qp.settings.eps_rel = self.settings.eps_rel
        qp.settings.max_iter = self.settings.max_iter
        qp.settings.initial_guess = proxsuite.proxqp.InitialGuess.NO_INITIAL_GUESS
        qp.settings.verbose = False
        qp.init(m, g, jac, rhs, None, None, None, compute_preconditioner=False)
        qp.solve()
        qp.settings.initial_guess = proxsuite.proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
        return qp

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
        g = -force
        if self.rows == 0:
            acc = np.linalg.solve(mass, force)
            return Solution(acc, np.zeros(0), 0.0, 0.0, 0, True, "unconstrained")
        if self._qp is None:
            self._qp = self._new_qp(mass, g, jac, rhs)
        else:
            self._qp.update(H=mass, g=g, A=jac, b=rhs, update_preconditioner=False)
            self._qp.solve()
        qp = self._qp
        res = qp.results
        acc = np.array(res.x)
        lam = -np.array(res.y)
        status = str(res.info.status).split(".")[-1]
        primal = float(np.max(np.abs(jac @ acc - rhs)))
        dual = float(np.max(np.abs(mass @ acc - force - jac.T @ lam)))
        return Solution(
            acceleration=acc,
            multipliers=lam,
            primal_residual=primal,
            dual_residual=dual,
            iterations=int(res.info.iter),
            solved=status == "PROXQP_SOLVED",
            status=status,
        )
