"""IP-Basic's fill_in_fast (Ku et al. 2018) with Gaussian blur and no extrapolation, in OpenCV:
the reference for host-tools/src/map/ip_basic.rs.

    ip_basic.py IN.f32 OUT.f32 WIDTH HEIGHT

reads a little-endian float32 depth image (0 = empty) and writes the completed one.
"""

import sys

import cv2
import numpy as np

FULL_5 = np.ones((5, 5), np.uint8)
FULL_7 = np.ones((7, 7), np.uint8)
FULL_31 = np.ones((31, 31), np.uint8)
DIAMOND_5 = np.array([[0, 0, 1, 0, 0], [0, 1, 1, 1, 0], [1, 1, 1, 1, 1], [0, 1, 1, 1, 0],
                      [0, 0, 1, 0, 0]], np.uint8)


def fill_in_fast(depth, max_depth=100.0):
    depth = depth.copy()
    valid = depth > 0.1
    depth[valid] = max_depth - depth[valid]
    depth = cv2.dilate(depth, DIAMOND_5)
    depth = cv2.morphologyEx(depth, cv2.MORPH_CLOSE, FULL_5)
    empty = depth < 0.1
    depth[empty] = cv2.dilate(depth, FULL_7)[empty]
    empty = depth < 0.1
    depth[empty] = cv2.dilate(depth, FULL_31)[empty]
    depth = cv2.medianBlur(depth, 5)
    valid = depth > 0.1
    blurred = cv2.GaussianBlur(depth, (5, 5), 0)
    depth[valid] = blurred[valid]
    valid = depth > 0.1
    depth[valid] = max_depth - depth[valid]
    return depth


def main():
    w, h = int(sys.argv[3]), int(sys.argv[4])
    depth = np.fromfile(sys.argv[1], dtype="<f4").reshape(h, w)
    fill_in_fast(depth).astype("<f4").tofile(sys.argv[2])


if __name__ == "__main__":
    main()
