"""Settings of the constrained-dynamics QP that every step solves.

By default the solve is direct (the Schur complement of the KKT system over an orthonormal basis
of the rows' span); proxsuite's proximal method is the reference alternative
(``SolverSettings(method="proxsuite")``) and gives the same multipliers by iteration.

The solve itself is compiled, ``cpp/constrained_qp.hpp``: Gauss's principle, the
constrained equations of motion of Saleh 2017 (eqs. 1-28) in QP form,

    minimise ½ aᵀ M a − (τ − b)ᵀ a     subject to   J a = r,

with λ = −y from the QP's duals, minimum-norm multipliers for the redundant rows of rigid
multi-planet stages (with proxsuite: no preconditioner, an equality-constrained initial guess,
then warm starts, and the right-hand side projected onto range(J)), and the QP scaled to unit
size by powers of two, so that one absolute tolerance means the same relative accuracy in every run.
"""

from __future__ import annotations

from dataclasses import dataclass

import proxsuite

from pinwind.errors import InputError

#: How redundant constraint rows are solved (``SolverSettings.method``).
METHODS = ("direct", "proxsuite")


@dataclass(frozen=True)
class SolverSettings:
    """Settings of every step's solve: the method (direct by default) and proxsuite's tolerances.

    Attributes:
        eps_abs: absolute tolerance on the primal and dual residuals of the QP scaled to unit
            size (module docstring): a relative accuracy of the accelerations and forces.
        eps_rel: relative tolerance (proxsuite's scaled residuals).
        max_iter: iteration cap of the outer loop.
        method: ``"direct"``: the Schur complement of the KKT system over an orthonormal basis
            of the rows' span (the minimum-norm multipliers of redundant rows, in one step;
            ``cpp/constrained_qp.hpp``); ``"proxsuite"``: redundant rows by proxsuite's
            proximal method (the same multipliers, by iteration). Rows of full rank are always
            solved directly.
    """

    eps_abs: float = 1e-13
    eps_rel: float = 0.0
    max_iter: int = 1000
    method: str = "direct"

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise InputError(
                f'solver method "{self.method}" is unknown; use one of: {", ".join(METHODS)}'
            )

    def as_dict(self) -> dict:
        """Settings for metadata: which solve ran, and its tolerances."""
        solve = {
            "direct": "Schur complement of the KKT system over an orthonormal basis of the rows",
            "proxsuite": "proxsuite.proxqp.dense (proximal iterations) for redundant rows",
        }
        return {
            "solver": solve[self.method],
            "proxsuite_version": getattr(proxsuite, "__version__", "unknown"),
            "eps_abs": self.eps_abs,
            "eps_rel": self.eps_rel,
            "max_iter": self.max_iter,
            "method": self.method,
        }
