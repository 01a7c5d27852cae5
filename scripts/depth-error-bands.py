#!/usr/bin/env python3
"""Where a completed depth image's error lies, from `metamoran map --out DIR`'s 16-bit KITTI PNGs.

    .venv/bin/python scripts/depth-error-bands.py DIR [IMAGE]

IMAGE is one of frame, submap, ip_basic, network (default network); it is compared with
DIR/lidar.png over every pixel the lidar fills, an empty image pixel counting as 0 m (the
report's `lidar_pixels` set, so the total MAE is the one `map --json` prints there). Per band of
lidar depth it prints the pixels, their MAE, their share of the total error, how many the image
leaves empty and the median signed error (image minus lidar: negative is too near); then per
quarter of the image's rows (top = highest elevation) the MAE and the share of the band 10-20 m's
empty pixels that lie there. numpy and opencv (the test venv).
"""
import sys

import cv2
import numpy as np

BANDS_M = [(0, 10), (10, 20), (20, 30), (30, 45), (45, 59), (59, 81)]


def read(path):
    img = cv2.imread(path, cv2.IMREAD_UNCHANGED)
    if img is None or img.dtype != np.uint16:
        sys.exit(f"{path}: not a 16-bit depth PNG (run `metamoran map BUNDLE --out DIR` first)")
    return img.astype(np.float64) / 256.0


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out, name = sys.argv[1], sys.argv[2] if len(sys.argv) == 3 else "network"
    lidar, image = read(f"{out}/lidar.png"), read(f"{out}/{name}.png")
    if lidar.shape != image.shape:
        sys.exit(f"{out}/{name}.png: {image.shape} pixels, the lidar image has {lidar.shape}")
    seen = lidar > 0
    if not seen.any():
        sys.exit(f"{out}/lidar.png: no lidar pixel")
    err = np.abs(image - lidar)
    total = err[seen].sum()
    print(f"{out}/{name}.png: {seen.sum()} lidar pixels, MAE {err[seen].mean():.2f} m")
    for lo, hi in BANDS_M:
        m = seen & (lidar >= lo) & (lidar < hi)
        if m.any():
            print(
                f"  lidar {lo:2d}-{hi:2d} m: {m.sum():5d} px, MAE {err[m].mean():6.2f} m, "
                f"{err[m].sum() / total * 100:5.1f} % of the error, {(image[m] < 1).mean() * 100:5.1f} % empty, "
                f"median signed {np.median((image - lidar)[m]):+.2f} m"
            )
    empty = seen & (lidar >= 10) & (lidar < 20) & (image < 1)
    rows = lidar.shape[0]
    for q in range(4):
        m = seen.copy()
        m[: q * rows // 4] = False
        m[(q + 1) * rows // 4 :] = False
        share = empty[q * rows // 4 : (q + 1) * rows // 4].sum() / max(empty.sum(), 1) * 100
        mae = err[m].mean() if m.any() else float("nan")
        print(f"  rows quarter {q + 1} of 4: MAE {mae:6.2f} m, {share:5.1f} % of the 10-20 m empty pixels")


if __name__ == "__main__":
    main()
