"""Each element's tangent against finite differences of its force, and forces against −∇U.

The compiled step treats the stiff elements implicitly: each adds its force f(q, v) and its
tangents K = −∂f/∂q and C = −∂f/∂v to the step's Newton matrix (``cpp/elements.hpp``). A wrong
tangent does not change a static answer but changes every dynamic one (the step's frequency, its
energy, its stability), and no closed form of a whole run catches it. These checks read the
elements of a model through ``CompiledStepper.element_forces`` (each element built anew at the
state, as at a run's first sample: a contact is in contact wherever it overlaps) and compare

- ``element_tangents``: K and C with central differences of f along each coordinate,
  K_fd e_j = −(f(q + h e_j) − f(q − h e_j)) / 2h, and C the same along v;
- ``conservative_forces``: f at v = 0 with −∇U, U the elements' stored energy, by central
  differences of U: a contact that is the gradient of its potential keeps an undamped train's
  energy through any number of contact changes (docs/testing.md).

Where the step's tangent is not the exact derivative on purpose, compare the force with −∇U
instead: a compliant mesh between gears whose centres move (floating members, compliant
bearings) is taken with the Gauss-Newton tangent k JᵀJ, without the curvature of its line of
action; a mesh whose stiffness varies along the path of contact (``stiffness_variation="path"``)
leaves the dk/ds δ term to the ledger's parametric work, and its force is not −∇U either (use
``"constant"`` to check it).

Both checks work in the states' own scale: coordinate j is measured in its spread s_j (the
``spread_m`` of a slide, ``spread_rad`` of a rotation), so that K̃ = S K S is an energy per
spread², and the error is max |K̃ − K̃_fd| / max |K̃_fd| over the matrix, the largest over the
states. A state whose differences straddle a contact opening or closing (the one-sided slopes
differ there, and differences at h and h/2 disagree) is left out and counted.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.drivetrain import Drivetrain, drivetrain
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from pinwind.errors import InputError
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox
from pinwind.testing.figure import CheckFigure

#: Default spread of the seeded states about the reference pose: 10 µm on a slide (a bearing's
#: or a mesh's deflection under load), 1e-4 rad on a rotation (10 µm at a 0.1 m radius) [m, rad],
#: and the speed spread per unit of position spread [1/s].
SPREAD_M = 10e-6
SPREAD_RAD = 1e-4
SPEED_PER_SPREAD = 1e3
#: Default difference step, relative to each coordinate's spread: small enough that a state
#: rarely straddles a contact change, large enough that rounding stays near 1e-10 of the tangent.
STEP = 1e-3

State = tuple[np.ndarray, np.ndarray]


def element_stepper(
    machine: Gearbox | Drivetrain,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
) -> CompiledStepper:
    """A compiled stepper of the machine's elements, for ``element_forces`` alone.

    Args:
        machine: a gearbox (its elements as the file writes them), or a run's drivetrain (its
            mesh choice, generator and rotor laws).
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a
            ``MeshCompliance``, replacing the machine's choice.
    """
    train = machine if isinstance(machine, Drivetrain) else drivetrain(machine)
    if meshes is not None:
        train = train.with_meshes(meshes)
    gearbox = train.gearbox
    rows = [r.v_index for r in train.rows]
    return CompiledStepper(
        gearbox,
        2,
        gearbox.neutral(),
        np.zeros(gearbox.model.nv),
        dt=1e-4,  # the step's tangents do not depend on dt (κ gains of 1 in element_forces)
        gravity=train.gravity,
        driver_index=rows,
        driver_names=[r.joint for r in train.rows],
        settings=SolverSettings(),
        meshes=mesh_setup(gearbox, train.meshes, driver_index=rows, dt=None),
        loads=train.loads,
    )


def spreads(gearbox: Gearbox, spread_m: float, spread_rad: float) -> np.ndarray:
    """Each coordinate's spread s (nv,): ``spread_m`` on a slide, ``spread_rad`` on a rotation."""
    return np.array(
        [spread_m if kind == "prismatic" else spread_rad for kind in gearbox.joint_kinds]
    )


def seeded_states(
    gearbox: Gearbox,
    count: int,
    *,
    seed: int = 0,
    spread_m: float = SPREAD_M,
    spread_rad: float = SPREAD_RAD,
) -> list[State]:
    """``count`` states (q, v) drawn uniformly within ± the spreads about the reference pose.

    v within ± ``SPEED_PER_SPREAD`` × the spreads [m/s, rad/s]; seeded (``numpy`` PCG64).
    """
    rng = np.random.default_rng(seed)
    s = spreads(gearbox, spread_m, spread_rad)
    q0 = gearbox.neutral()
    out = []
    for _ in range(count):
        q = q0 + rng.uniform(-1.0, 1.0, len(s)) * s
        out.append((q, rng.uniform(-1.0, 1.0, len(s)) * s * SPEED_PER_SPREAD))
    return out


def _differences(
    value: Callable[[np.ndarray], np.ndarray], x: np.ndarray, steps: np.ndarray
) -> np.ndarray:
    """Central differences of ``value`` at x, one column per coordinate (steps h_j)."""
    columns = []
    for j, h in enumerate(steps):
        e = np.zeros(len(x))
        e[j] = h
        columns.append((np.asarray(value(x + e)) - np.asarray(value(x - e))) / (2.0 * h))
    return np.array(columns).T


def _states(
    gearbox: Gearbox, states: int | Sequence[State], seed: int, spread_m: float, spread_rad: float
) -> list[State]:
    if isinstance(states, int):
        if states < 1:
            raise InputError(f"states must be at least 1; got {states}")
        return seeded_states(gearbox, states, seed=seed, spread_m=spread_m, spread_rad=spread_rad)
    out = [(np.asarray(q, dtype=float), np.asarray(v, dtype=float)) for q, v in states]
    nv = gearbox.model.nv
    for q, v in out:
        if q.shape != (nv,) or v.shape != (nv,):
            raise InputError(f"each state is (q, v) of {nv} values each; got {q.shape}, {v.shape}")
    return out


@dataclass(frozen=True)
class _Mismatch:
    """The worst entry of one comparison, in the states' scale (module docstring)."""

    error: float  # |exact − fd| / max |fd| [-]
    where: tuple[int, ...]  # its index
    exact: float  # the entry, unscaled
    differences: float  # the differences' entry, unscaled


def _compare(
    exact: np.ndarray,
    value: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    steps: np.ndarray,
    scale: np.ndarray,
    rtol: float,
) -> _Mismatch | None:
    """The worst entry of ``exact`` against −(central differences of ``value`` at x).

    None where they straddle a kink: differences at the steps and at half of them that
    disagree by more than rtol/2 mean a contact opens or closes within a step of x. Both are
    compared times ``scale`` (the spreads, an outer product for a matrix).
    """
    fd = -_differences(value, x, steps).reshape(exact.shape)
    fd_half = -_differences(value, x, 0.5 * steps).reshape(exact.shape)
    size = max(float(np.abs(fd * scale).max()), float(np.abs(exact * scale).max()))
    if size == 0.0:
        return _Mismatch(0.0, (0,) * exact.ndim, 0.0, 0.0)
    if float(np.abs((fd - fd_half) * scale).max()) > 0.5 * rtol * size:
        return None
    error = np.abs((exact - fd) * scale)
    where = tuple(int(i) for i in np.unravel_index(int(np.argmax(error)), error.shape))
    return _Mismatch(float(error[where]) / size, where, float(exact[where]), float(fd[where]))


def element_tangents(
    machine: Gearbox | Drivetrain,
    *,
    states: int | Sequence[State] = 8,
    seed: int = 0,
    spread_m: float = SPREAD_M,
    spread_rad: float = SPREAD_RAD,
    step: float = STEP,
    rtol: float = 1e-6,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
) -> CheckFigure:
    """The elements' tangents K = −∂f/∂q and C = −∂f/∂v equal central differences of f.

    Args:
        machine: a gearbox or a run's drivetrain (``element_stepper``).
        states: how many seeded states (``seeded_states``), or the states (q, v) themselves.
        seed: the states' seed.
        spread_m: the states' spread about the reference pose on slides [m], and the unit a
            slide is measured in (module docstring).
        spread_rad: the same on rotations [rad].
        step: the difference step relative to the spread [-].
        rtol: the largest error accepted, relative to the largest entry [-].
        meshes: the mesh choice (``element_stepper``).

    Returns:
        The figure: the largest error of K or C over the states.

    Raises:
        CheckFailed: beyond ``rtol`` (or every state on a contact change), naming the state,
            the tangent and the two joints of its worst entry.
    """
    stepper = element_stepper(machine, meshes=meshes)
    gearbox = machine.gearbox if isinstance(machine, Drivetrain) else machine
    names = sorted(gearbox.joint_names, key=gearbox.v_index)
    s = spreads(gearbox, spread_m, spread_rad)
    speed = s * SPEED_PER_SPREAD
    cases = _states(gearbox, states, seed, spread_m, spread_rad)
    worst, detail, skipped = 0.0, "", 0
    for n, (q, v) in enumerate(cases):
        at = stepper.element_forces(q, v)

        def along_q(y: np.ndarray, v: np.ndarray = v) -> np.ndarray:
            return np.asarray(stepper.element_forces(y, v).force)

        def along_v(y: np.ndarray, q: np.ndarray = q) -> np.ndarray:
            return np.asarray(stepper.element_forces(q, y).force)

        comparisons = (
            ("stiffness −∂f/∂q", np.asarray(at.stiffness), along_q, q, s),
            ("damping −∂f/∂v", np.asarray(at.damping), along_v, v, speed),
        )
        for label, exact, force, x, unit in comparisons:
            found = _compare(exact, force, x, step * unit, np.outer(s, unit), rtol)
            if found is None:
                skipped += 1
                continue
            if not found.error <= worst:
                i, j = found.where
                worst = found.error
                detail = (
                    f"state {n}: {label} of {names[i]} along {names[j]} is {found.exact:.9g}, "
                    f"the differences give {found.differences:.9g}; "
                )
    if skipped == 2 * len(cases):
        worst = float("nan")
    return CheckFigure(
        "element_tangents",
        "the elements' tangents against central differences of their force, relative to the "
        "largest entry in the states' scale",
        worst,
        rtol,
        f"{detail}{len(cases)} states, {skipped} of {2 * len(cases)} comparisons left out on a "
        "contact change",
    ).enforced()


def conservative_forces(
    machine: Gearbox | Drivetrain,
    *,
    states: int | Sequence[State] = 8,
    seed: int = 0,
    spread_m: float = SPREAD_M,
    spread_rad: float = SPREAD_RAD,
    step: float = STEP,
    rtol: float = 1e-6,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
) -> CheckFigure:
    """The elements' force at rest is the gradient of their stored energy: f(q, 0) = −∇U(q).

    The states' speeds are not used (the dampers and laws act on speeds; at v = 0 only the
    springs and contacts push). Generator and rotor laws are not conservative: check a
    gearbox, or a drivetrain without them.

    Args:
        machine: a gearbox or a run's drivetrain (``element_stepper``).
        states: how many seeded states (``seeded_states``), or the states (q, v) themselves.
        seed: the states' seed.
        spread_m: the states' spread about the reference pose on slides [m], and the unit a
            slide is measured in (module docstring).
        spread_rad: the same on rotations [rad].
        step: the difference step relative to the spread [-].
        rtol: the largest error accepted, relative to the largest force in the states' scale.
        meshes: the mesh choice (``element_stepper``).

    Returns:
        The figure: the largest error of f against −∇U over the states.

    Raises:
        CheckFailed: beyond ``rtol`` (or every state on a contact change), naming the state
            and the joint of the worst entry.
    """
    stepper = element_stepper(machine, meshes=meshes)
    gearbox = machine.gearbox if isinstance(machine, Drivetrain) else machine
    names = sorted(gearbox.joint_names, key=gearbox.v_index)
    s = spreads(gearbox, spread_m, spread_rad)
    rest = np.zeros(gearbox.model.nv)
    cases = _states(gearbox, states, seed, spread_m, spread_rad)
    worst, detail, skipped = 0.0, "", 0

    def potential(y: np.ndarray) -> np.ndarray:
        return np.array([stepper.element_forces(y, rest).potential])

    for n, (q, _) in enumerate(cases):
        force = np.asarray(stepper.element_forces(q, rest).force)
        found = _compare(force, potential, q, step * s, s, rtol)
        if found is None:
            skipped += 1
            continue
        if not found.error <= worst:
            worst = found.error
            detail = (
                f"state {n}: the force on {names[found.where[0]]} is {found.exact:.9g}, "
                f"−∂U/∂q {found.differences:.9g}; "
            )
    if skipped == len(cases):
        worst = float("nan")
    return CheckFigure(
        "conservative_forces",
        "the elements' force at rest against −∇U by central differences, relative to the "
        "largest force in the states' scale",
        worst,
        rtol,
        f"{detail}{len(cases)} states, {skipped} left out on a contact change",
    ).enforced()
