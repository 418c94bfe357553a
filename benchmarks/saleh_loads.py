"""The two Saleh models the streaming benchmarks run, and the loads that keep them in balance.

A rotor torque on the carrier and the output shaft taking it back at the train's ratio (6 for
the planetary stage, 6 · 83/23 · 103/26 = 85.78 for the drivetrain: its teeth, Saleh 2017
Table 1), so every mesh and bearing carries its rated load. The runs start with the carrier at
its rated 14.2 rpm (Saleh 2017) and the speeds stay put: a log of a turning gearbox, whose
angles, contact positions and pitch points change at every sample, as a user's would. (Until
2026-12-08 the runs started at rest, so the planetary's log held a gearbox at rest, speeds of
1e-15 rad/s, 125 bytes a sample instead of 313, and the drivetrain's used the table's rounded
ratios 3.6 and 3.96, leaving 33 N·m that accelerated it from rest.)
"""

from pathlib import Path

from pinwind.units import rpm_to_rad_s

MODELS = Path(__file__).resolve().parents[1] / "models"
#: Rotor torque on the carrier [N·m]; the output shaft takes it back at its ratio.
CARRIER_TORQUE = 1.0e6
LOADS = {
    "saleh2017_planetary": {"carrier": CARRIER_TORQUE, "sun": -CARRIER_TORQUE / 6.0},
    "saleh2017_drivetrain": {
        "carrier": CARRIER_TORQUE,
        "stage2_pinion": -CARRIER_TORQUE / (6.0 * 83 / 23 * 103 / 26),
    },
}
#: Each model's initial speeds [rad/s]: the carrier at its rated 14.2 rpm (Saleh 2017), the other
#: joints at the speeds the meshes impose.
INITIAL_SPEEDS = {name: {"carrier": rpm_to_rad_s(14.2)} for name in LOADS}
