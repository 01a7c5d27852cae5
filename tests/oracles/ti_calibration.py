"""A TI cascade calibration file (calibrateResults*.mat) written by SciPy, and the corrections
TI's calibration_cascade.m derives from it, computed here in NumPy: the reference for
`metamoran calibrate --import-ti` (host-tools/bundle/src/calibration.rs).

    ti_calibration.py OUT.mat COMPRESS N FS SLOPE INTERP TX_REF

writes OUT.mat (zlib-compressed when COMPRESS is 1) and prints, per (TX ID, RX) in row-major
order, TI's per-sample phase step (rad) and complex phase_calib for a capture of N samples at FS
and SLOPE (Hz/s), TX_REF being TxToEnable(1) (1-based), as JSON.
"""

import json
import sys

import numpy as np
import scipy.io

out, compress, n, fs, slope, interp, tx_ref = sys.argv[1:]
n, fs, slope, interp, tx_ref = int(n), float(fs), float(slope), float(interp), int(tx_ref)
rng = np.random.default_rng(19)
# The calibration capture: other sample rate and slope than the capture it is applied to.
fs_calib, slope_calib = 8.0e6, 78.986e12
range_mat = 120.0 + rng.uniform(-2.5, 2.5, size=(12, 16))
peak_val = rng.uniform(0.5, 2.0, size=(12, 16)) * np.exp(1j * rng.uniform(-np.pi, np.pi, size=(12, 16)))
scipy.io.savemat(
    out,
    {
        "calibResult": {"RangeMat": range_mat, "PeakValMat": peak_val,
                        "AngleMat": np.zeros((12, 16)), "Note": "made by ti_calibration.py"},
        "params": {"Slope_MHzperus": slope_calib / 1e12, "Sampling_Rate_sps": fs_calib,
                   "Cells": np.array([[1.0], "x"], dtype=object)},
    },
    do_compression=compress == "1",
)
steps, gains = [], []
for tx in range(1, 13):
    # calibration_cascade.m, with TXind = tx.
    freq_calib = (range_mat[tx - 1, :] - range_mat[tx_ref - 1, 0]) * fs_calib / fs * slope / slope_calib
    freq_calib = 2 * np.pi * freq_calib / (n * interp)
    # correction_vec = (exp(1i*((0:N-1)'*freq_calib))'): the trailing ' conjugates.
    correction_vec = np.conj(np.exp(1j * np.outer(np.arange(n), freq_calib))).T
    phase_calib = peak_val[tx_ref - 1, 0] / peak_val[tx - 1, :]
    for rx in range(16):
        steps.append(float(np.angle(correction_vec[rx, 1] / correction_vec[rx, 0])))
        gains.append([float(phase_calib[rx].real), float(phase_calib[rx].imag)])
print(json.dumps({"steps": steps, "gains": gains}))
