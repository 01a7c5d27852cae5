"""CMSIS-DSP's fixed-point CFFT (PyPI `cmsisdsp`) as a live oracle for our FFT.

Reads a JSON list of requests on stdin, each {"format": "q15"|"q31", "n": N, "data": [re, im, ...]}
(raw integers), and writes a JSON list of {"data": [...]} with CMSIS's raw output. CMSIS scales
its output down by N: true DFT = output / 2^frac_bits * N.
"""
import json
import sys

import cmsisdsp as dsp
import numpy as np


def run(req):
    n, fmt = req["n"], req["format"]
    if fmt == "q15":
        x = np.array(req["data"], dtype=np.int16)
        inst = dsp.arm_cfft_instance_q15()
        dsp.arm_cfft_init_q15(inst, n)
        y = dsp.arm_cfft_q15(inst, x, 0, 1)
    elif fmt == "q31":
        x = np.array(req["data"], dtype=np.int32)
        inst = dsp.arm_cfft_instance_q31()
        dsp.arm_cfft_init_q31(inst, n)
        y = dsp.arm_cfft_q31(inst, x, 0, 1)
    else:
        raise SystemExit(f"unknown format {fmt!r}")
    return {"data": [int(v) for v in y]}


json.dump([run(r) for r in json.load(sys.stdin)], sys.stdout)
