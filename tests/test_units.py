from __future__ import annotations

import math

import numpy as np

from pinwind.units import rad_s_to_rpm, rpm_to_rad_s


def test_sixty_rpm_is_one_revolution_per_second():
    np.testing.assert_allclose(rpm_to_rad_s(60.0), 2.0 * math.pi, rtol=1e-15)
    np.testing.assert_allclose(rad_s_to_rpm(2.0 * math.pi), 60.0, rtol=1e-15)


def test_rpm_conversions_undo_each_other_on_arrays():
    rpm = np.array([-1800.0, 0.0, 14.2, 85.2])
    np.testing.assert_allclose(rpm_to_rad_s(rpm), rpm * math.pi / 30.0, rtol=1e-15)
    np.testing.assert_allclose(rad_s_to_rpm(rpm_to_rad_s(rpm)), rpm, rtol=1e-15)
