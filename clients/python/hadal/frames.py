"""Rotations of the poses Hadal publishes: a ROS quaternion (x, y, z, w) as a matrix, and its heading.

    R_WB = hadal.frames.rotation_matrix(odometry.q_WB)   # B's axes in W: v_W = R_WB @ v_B
    psi = hadal.frames.yaw(odometry.q_WB)                 # heading about W's z [rad], x east, counter-clockwise
"""

import math

import numpy as np


def rotation_matrix(q):
    """The rotation matrix of a unit quaternion q = (x, y, z, w) (ROS's order)."""
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def yaw(q):
    """The heading of a unit quaternion (x, y, z, w): the angle of its x axis about z [rad]."""
    x, y, z, w = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
