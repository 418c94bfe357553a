"""Power losses of a gearbox: bearing friction, mesh friction, the oil (ISO/TR 14179-2).

``oil`` (ISO 3448 grades, Walther's viscosity line, density), ``bearing_friction`` (Palmgren's
M0 + M1 as ISO/TR 14179-2 gives it), ``mesh_friction`` (the mean coefficient of friction μ_mz
and Ohlendorf's tooth-loss factor H_V). The model file names a bearing's friction model
(``model/bearing_friction_data.py``); the step applies it (``cpp/bearing_friction.hpp``).
"""

from pinwind.losses.bearing_friction import (
    PALMGREN_FACTORS,
    BearingFriction,
    friction_load,
    load_moment,
    no_load_moment,
)
from pinwind.losses.mesh_friction import (
    LUBRICANT_FACTORS,
    mean_friction_coefficient,
    mesh_power_loss,
    pair_friction_coefficient,
    tooth_loss_factor,
)
from pinwind.losses.oil import Lubricant

__all__ = [
    "LUBRICANT_FACTORS",
    "PALMGREN_FACTORS",
    "BearingFriction",
    "Lubricant",
    "friction_load",
    "load_moment",
    "mean_friction_coefficient",
    "mesh_power_loss",
    "no_load_moment",
    "pair_friction_coefficient",
    "tooth_loss_factor",
]
