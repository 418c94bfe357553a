"""Whether a run's applied torques balance through the gear train, and the torque that would.

A gear train with one degree of freedom turns in one mode φ (joint speeds per unit speed of a
reference joint r, ``ratios.train_modes``). At steady speed the applied torques do no net work
along it: Σ_j φ_j τ_j = 0. What is left, N_r = Σ_j φ_j τ_j / φ_r, is the torque at joint r that
accelerates the train (J_eq dω_r/dt = N_r, the equation of motion of its one mode). Unless
something holds the mode (a speed driver, a generator, a rotor, bearing damping), a run with
N_r ≠ 0 spins up for its whole length:
the quick start without its sun torque turns the carrier at 9615 rpm after 2 s. Changing the
torque of another joint o of the mode by −N_r / (φ_o/φ_r) balances it: the ratio
φ_o/φ_r = ω_o/ω_r is the model's own (``ratios.speed_ratio``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.ratios import train_modes
from pinwind.loads.signals import Signal
from pinwind.model.gearbox import Gearbox

#: |N_r| below this fraction of the largest applied torque referred to r counts as balanced.
BALANCE_TOLERANCE = 1e-3


@dataclass(frozen=True)
class Imbalance:
    """The net torque along one mode of the train and the torque change that cancels it.

    Attributes:
        joint: the reference joint r: the one whose applied torque does most work in the mode.
        net_torque: N_r, the applied torques referred to r through the gear ratios [N·m].
        balancing_joint: the joint o whose torque would balance the train.
        ratio: ω_o / ω_r in the mode [-].
        torque: the torque now applied on o [N·m] (a signal's mean over the run).
        averaged: whether the torques are signals' means over the run (the text says so).
    """

    joint: str
    net_torque: float
    balancing_joint: str
    ratio: float
    torque: float
    averaged: bool = False

    @property
    def balancing_torque(self) -> float:
        """The torque on ``balancing_joint`` that balances the train, τ_o − N_r / ratio [N·m]."""
        return self.torque - self.net_torque / self.ratio

    def text(self) -> str:
        """One line: the imbalance, where, and the torque that balances it."""
        mean = " (torque signals taken at their mean over the run)" if self.averaged else ""
        return (
            f"the applied torques do not balance through the gear train{mean}: referred to "
            f'joint "{self.joint}" they leave {self.net_torque:.4g} N·m that nothing holds (no '
            "speed driver, generator, rotor or bearing damping on that train), so the train "
            f"accelerates for the whole run. A torque of {self.balancing_torque:.10g} N·m on "
            f'"{self.balancing_joint}" (now {self.torque:.4g} N·m; '
            f"ω_{self.balancing_joint} / ω_{self.joint} = {self.ratio:.6g}) balances it, or "
            "drive a joint at its speed"
        )


def imbalances(
    gearbox: Gearbox,
    torques: Mapping[str, float],
    *,
    held: Iterable[str] = (),
    tolerance: float = BALANCE_TOLERANCE,
    averaged: bool = False,
) -> list[Imbalance]:
    """The modes of the train along which ``torques`` leave a net torque, one `Imbalance` each.

    Args:
        torques: joint name → applied torque [N·m] (constant; the caller picks the value of a
            signal).
        held: joints whose speed something holds or resists (speed drivers, generators,
            rotors, damped bearings): their modes are not checked.
        tolerance: a mode counts as balanced when |N_r| ≤ tolerance × max_j |φ_j τ_j / φ_r|.
        averaged: the torques are signals' means over the run (``representative_torque``).

    Torsional springs keep their joints turning together (a spring cannot hold a whole train);
    a spring to the ground holds its joint (a ring on its torsional support).
    """
    nv = gearbox.model.nv
    tau = np.zeros(nv)
    for name, value in torques.items():
        tau[gearbox.v_index(name)] += value
    springs = np.zeros((len(gearbox.springs), nv))
    for i, s in enumerate(gearbox.springs):
        if s.stiffness > 0.0:
            springs[i] = s.twist_row(nv)
    names = {gearbox.v_index(n): n for n in gearbox.joint_names}
    out = []
    for mode in train_modes(gearbox, held, springs):
        work = mode * tau
        r = int(np.argmax(np.abs(work)))
        if work[r] == 0.0:
            continue
        net = float(work.sum() / mode[r])
        if abs(net) <= tolerance * float(np.abs(work).max()) / abs(mode[r]):
            continue
        others = [int(j) for j in np.flatnonzero(mode) if j != r]
        if not others:  # a joint alone in its mode: only its own torque could balance it
            others = [r]
        loaded = [j for j in others if tau[j] != 0.0]
        o = max(loaded or others, key=lambda j: abs(mode[j]))
        ratio = float(mode[o] / mode[r])
        out.append(Imbalance(names[r], net, names[o], ratio, float(tau[o]), averaged))
    return out


def representative_torque(signal, duration: float, *, samples: int = 10001) -> float:
    """The torque [N·m] a load applies for the balance check.

    A number is itself; a ``pinwind.loads.signals.Signal`` (tables, sines: evaluated at once)
    its mean over [0, duration] on ``samples`` times; any other function of time its value at
    t = 0, since it may keep state between the calls the run makes in order.
    """
    if isinstance(signal, Signal):
        values = np.asarray(signal.values(np.linspace(0.0, duration, samples)), dtype=float)
        return float(np.mean(values)) if np.all(np.isfinite(values)) else math.nan
    return float(signal(0.0)) if callable(signal) else float(signal)
