#!/usr/bin/env python3
"""Copies a bundle with extra receiver noise: Gaussian of SIGMA LSB added to every int16 of
radar.bin (each I and Q sample), rounded and clipped to int16; the other files copied as they
are. The source bundle is not modified. Seeded, so a run gives the same bytes again.

    .venv/bin/python scripts/add-noise.py SRC_BUNDLE DST_BUNDLE SIGMA [--seed N]

README "the screen keeps over the noise" uses it to put a scene's noise within 40 dB of its
strongest return. numpy only.
"""
import argparse
import os
import shutil
import sys

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("sigma", type=float, help="noise per I/Q component, LSB")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if not a.sigma >= 0:
        sys.exit(f"add-noise.py: SIGMA must be 0 or more, got {a.sigma}")
    raw = os.path.join(a.src, "radar.bin")
    if not os.path.isfile(raw):
        sys.exit(f"add-noise.py: {raw}: no such file (is {a.src} a bundle?)")
    if os.path.abspath(a.src) == os.path.abspath(a.dst):
        sys.exit("add-noise.py: DST_BUNDLE must differ from SRC_BUNDLE (inputs are never modified)")
    shutil.copytree(a.src, a.dst, dirs_exist_ok=True)
    x = np.fromfile(raw, dtype="<i2").astype(np.float64)
    x += np.random.default_rng(a.seed).normal(0.0, a.sigma, x.size)
    np.clip(np.round(x), -32768, 32767).astype("<i2").tofile(os.path.join(a.dst, "radar.bin"))


if __name__ == "__main__":
    main()
