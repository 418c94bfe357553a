"""The torsional-spring modes of a gear train: the frequency of the highest one.

Torsional springs (``<torsional_spring>``, shaft compliance k = GJ/L) between joints that the
meshes and drivers leave free to twist give modes of frequency ω² = eig(K, M) over the motions the
rigid rows allow, K = Σ k (e₁ − e₂)(e₁ − e₂)ᵀ: the linear model of the machine a run steps
(``dynamics/linear_model.py``, the rotors' inertias in, the speed drivers held) with every mesh
rigid, at rest (the modes ``modes.linearisation.linearise`` gives at speed 0). The compliant
meshes' own modes are ``compliant.highest_mesh_mode_and_damping``'s.
"""

from __future__ import annotations

from pinwind.dynamics.drivetrain import Drivetrain
from pinwind.dynamics.linear_model import check_held, linear_model
from pinwind.dynamics.normal_modes import natural_modes


def highest_spring_mode(train: Drivetrain) -> float:
    """Frequency of the highest torsional-spring mode [Hz] of a drivetrain; 0 without springs.

    The meshes count as rigid; the drivetrain's speed drivers hold their joints.

    Raises:
        UnheldMember: a floating bearing that nothing holds.
    """
    if not train.gearbox.springs:
        return 0.0
    rigid = train.with_meshes({"all": "rigid"})
    linear = linear_model(rigid, at=rigid.operating_speed())
    check_held(rigid.gearbox, linear)
    modes = natural_modes(
        linear.mass,
        linear.stiffness,
        linear.damping,
        linear.constraints,
        joint_names=linear.joint_names,
        elements=linear.elements,
    )
    return max((m.frequency for m in modes), default=0.0)
