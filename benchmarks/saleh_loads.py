"""The two Saleh models the streaming benchmarks run, and the loads that keep them in balance.

A rotor torque on the carrier and the output shaft taking it back at the train's ratio (6 for
the planetary stage, 6 · 3.6 · 3.96 for the drivetrain, Saleh 2017 Table 1), so
every mesh and bearing carries its rated load and the speeds stay put.
"""

from pathlib import Path

MODELS = Path(__file__).resolve().parents[1] / "models"
#: Rotor torque on the carrier [N·m]; the output shaft takes it back at its ratio.
CARRIER_TORQUE = 1.0e6
LOADS = {
    "saleh2017_planetary": {"carrier": CARRIER_TORQUE, "sun": -CARRIER_TORQUE / 6.0},
    "saleh2017_drivetrain": {
        "carrier": CARRIER_TORQUE,
        "stage2_pinion": -CARRIER_TORQUE / (6.0 * 3.6 * 3.96),
    },
}
