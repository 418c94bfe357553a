"""A Result keeps link poses at their own samples: cutting and joining Results keeps them there."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from pinwind.dynamics.result import Result, concatenate


def _result(n: int, pose_rows: np.ndarray) -> Result:
    """n samples with t_k = k, one link at x = t at the samples ``pose_rows``."""
    time = np.arange(n, dtype=float)
    empty = np.zeros((n, 0))
    vectors = np.zeros((n, 0, 3))
    posed = time[pose_rows]
    position = np.zeros((len(pose_rows), 1, 3))
    position[:, 0, 0] = posed
    quaternion = np.zeros((len(pose_rows), 1, 4))
    quaternion[:, 0, 3] = 1.0
    return Result(
        time=time,
        joint_names=[],
        mesh_names=[],
        bearing_names=[],
        body_names=["link"],
        **{
            name: vectors if name.endswith(("force_on_b", "pitch_point")) else empty
            for name in Result.ARRAYS
            if name not in ("time", "body_position", "body_quaternion", "constraint_residual")
            and not name.startswith("bearing")
        },
        bearing_force=vectors,
        bearing_moment=vectors,
        bearing_force_local=vectors,
        bearing_moment_local=vectors,
        body_position=position,
        body_quaternion=quaternion,
        constraint_residual=time.copy(),
        pose_rows=np.asarray(pose_rows),
    )


EVERY_THIRD = np.arange(0, 20, 3)  # samples 0, 3, ..., 18 of 20


@pytest.mark.parametrize(
    "rows",
    [
        slice(2, 13),
        slice(None),
        slice(1, 19, 2),
        slice(13, 2),
        np.array([0, 1, 3, 4, 6, 19]),
        np.array([18, 2, 9]),
        np.arange(20) % 4 == 0,
        np.array([-2, -1]),
    ],
)
def test_samples_taken_keep_the_poses_of_those_samples_and_no_others(rows):
    res = _result(20, EVERY_THIRD)
    part = res.take(rows)
    taken = np.arange(20)[rows]
    assert_array_equal(part.time, taken)
    # a sample has a pose when its number is a multiple of 3, and it is x = t
    expected = np.flatnonzero(taken % 3 == 0)
    assert_array_equal(part.pose_rows, expected)
    assert_array_equal(part.pose_time, taken[expected])
    assert_array_equal(part.body("link").position[:, 0], taken[expected])
    assert_array_equal(part.body("link").time, taken[expected])


def test_poses_at_samples_are_nan_between_the_posed_samples():
    res = _result(10, np.array([0, 4, 8]))
    x = res.pose_at_samples("body_position")[:, 0, 0]
    assert_array_equal(x[[0, 4, 8]], [0.0, 4.0, 8.0])
    assert np.isnan(np.delete(x, [0, 4, 8])).all()
    posed = res.posed()
    assert_array_equal(posed.time, [0.0, 4.0, 8.0])
    assert_array_equal(posed.pose_rows, [0, 1, 2])


def test_joined_parts_number_their_poses_from_the_first_sample():
    res = _result(20, EVERY_THIRD)
    joined = concatenate([res.take(slice(0, 7)), res.take(slice(7, 8)), res.take(slice(8, 20))])
    assert_array_equal(joined.pose_rows, EVERY_THIRD)
    assert_array_equal(joined.body_position, res.body_position)


def test_a_pose_count_that_differs_from_the_pose_rows_is_refused():
    res = _result(10, np.array([0, 4, 8]))
    with pytest.raises(ValueError, match="2 pose rows for 3 positions"):
        res.holding(res.arrays(), res.energy, pose_rows=np.array([0, 4]))
