"""Energy-ledger closure of a run: what the forces did is what the train holds and lost.

The ledger (``Result.energy``, ``dynamics/series.py``) keeps, cumulative from t = 0, the kinetic
energy K, the springs' stored energy U (compliant meshes, torsional springs, compliant bearings,
the support) and the work of every force: the applied torques and the generator and rotor laws
(W_applied), the speed drivers and locks (W_drivers), gravity (W_gravity), the rigid meshes
(W_constraints, zero up to drift), the meshes' time-varying stiffness (W_parametric, the
parametric excitation), the dampers (``dissipated``, taken) and friction (``friction_loss``,
taken: the tooth flanks of compliant meshes). Energy is conserved when

    r(t) = Δ(K + U) − (W_applied + W_drivers + W_gravity + W_constraints + W_parametric)
           + dissipated + friction_loss = 0,

Δ from the first sample (the static start's stored energy is there at t = 0). r is what the time
step itself created or lost: −``numerical`` up to the step's kinetic-energy balance, which is
exact to rounding with the mid-step speed (``dynamics/simulate.py``). It is zero to rounding for
linear elements with ρ∞ = 1; contact that opens or closes within a step (flank changes with
moving centres, bearing clearance) leaves an O(dt²) error, and ρ∞ < 1 dissipates the unresolved
modes on purpose (both are what this check measures: give a tolerance that says what you accept).
"""

from __future__ import annotations

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.errors import InputError
from pinwind.testing.figure import CheckFigure

#: The work terms of the balance (module docstring), each added; ``LOSS_TERMS`` are taken.
WORK_TERMS = (
    "work_applied",
    "work_drivers",
    "work_gravity",
    "work_constraints",
    "work_parametric",
)

#: The losses of the balance, each taken (counted positive when lost). ``friction_loss`` may be
#: absent (a log written before flank friction was modelled): none then.
LOSS_TERMS = ("dissipated", "friction_loss")


def _loss(energy: dict[str, np.ndarray], term: str) -> np.ndarray:
    """A loss term of the ledger [J], zeros where an older log has no ``friction_loss``."""
    if term == "friction_loss" and term not in energy:
        return np.zeros_like(energy["dissipated"])
    return energy[term]


def ledger_residual(result: Result) -> np.ndarray:
    """r(t) (n,) [J] of the module docstring: energy the run created (> 0) or lost (< 0)."""
    e = result.energy
    missing = [t for t in ("kinetic", "potential_spring", "dissipated", *WORK_TERMS) if t not in e]
    if missing:
        raise InputError(
            f"the Result has no energy terms {', '.join(missing)}; check the ledger of a Result "
            "of pinwind.simulate or of a log written with them"
        )
    held = e["kinetic"] + e["potential_spring"]
    work = np.sum([e[t] for t in WORK_TERMS], axis=0) - np.sum(
        [_loss(e, t) for t in LOSS_TERMS], axis=0
    )
    return (held - held[0]) - (work - work[0])


def energy_scale(result: Result) -> float:
    """The run's energy scale [J]: the largest magnitude any ledger term reaches.

    The kinetic and stored energy, each work term and each loss, over the run.
    """
    e = result.energy
    held = (e["kinetic"], e["potential_spring"], *(_loss(e, t) for t in LOSS_TERMS))
    return float(max(np.abs(a).max() for a in (*held, *(e[t] for t in WORK_TERMS))))


def ledger_closure(result: Result, *, rtol: float = 1e-6) -> CheckFigure:
    """The energy ledger of a run closes: max |r(t)| ≤ rtol × the run's energy scale.

    Args:
        result: a run (every ledger term cumulative from its first sample; a Result that keeps
            every N-th sample checks those).
        rtol: the largest |r| accepted, relative to ``energy_scale`` [-].

    Returns:
        The figure: max |r| / energy scale.

    Raises:
        CheckFailed: beyond ``rtol``, with the sample and time of the worst r and its sign.
        InputError: a Result without an energy ledger.
    """
    r = ledger_residual(result)
    scale = energy_scale(result)
    worst = int(np.argmax(np.abs(r))) if len(r) else 0
    measured = float(abs(r[worst]) / scale) if scale > 0.0 else 0.0
    if not np.all(np.isfinite(r)):
        measured = float("nan")
    created = "created" if len(r) and r[worst] > 0 else "lost"
    beyond = np.flatnonzero(~(np.abs(r) <= rtol * scale))
    first = (
        f"first beyond it at sample {beyond[0]} (t = {result.time[beyond[0]]:.6g} s), "
        if len(beyond)
        else ""
    )
    detail = (
        f"{first}worst at sample {worst} (t = {result.time[worst]:.6g} s): {abs(r[worst]):.3g} J "
        f"{created} of an energy scale of {scale:.3g} J (numerical term "
        f"{result.energy.get('numerical', np.full(len(r), np.nan))[worst]:.3g} J)"
        if len(r)
        else "no samples"
    )
    return CheckFigure(
        "ledger_closure",
        "energy created or lost by the step, Δ(K + U) − ΣW + dissipated, over the run's "
        "energy scale",
        measured,
        rtol,
        detail,
    ).enforced()
