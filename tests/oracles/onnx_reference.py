#!/usr/bin/env python3
"""Independent reference for ONNX inference: evaluates a model's graph node by node in numpy
float64, from the ONNX operator definitions (not from tract, not from the framework that
trained it). Covers the ops of the shipped 3D-RadarHR network: Conv (with pads), MaxPool (pads,
strides), Resize (nearest, integer scales), Concat, Mul, Div, Add, Relu, Sigmoid, Greater, Cast.

Usage: onnx_reference.py MODEL.onnx INPUT.f32 OUTPUT.f64
INPUT.f32 is the model's single input, little-endian float32 in its declared (static) shape;
OUTPUT.f64 receives the first output as little-endian float64.
"""

import sys

import numpy as np
import onnx
from numpy.lib.stride_tricks import sliding_window_view
from onnx import numpy_helper


def attrs(node):
    return {a.name: onnx.helper.get_attribute_value(a) for a in node.attribute}


def pad(x, pads, value):
    n = len(pads) // 2
    widths = [(0, 0), (0, 0)] + [(pads[i], pads[i + n]) for i in range(n)]
    return np.pad(x, widths, constant_values=value)


def conv(x, w, b, a):
    assert a.get("group", 1) == 1 and all(s == 1 for s in a.get("strides", [1, 1]))
    assert all(d == 1 for d in a.get("dilations", [1, 1]))
    x = pad(x, a.get("pads", [0, 0, 0, 0]), 0.0)
    k = w.shape[2:]
    win = sliding_window_view(x, k, axis=(2, 3))  # N, C, H', W', kh, kw
    y = np.einsum("nchwij,ocij->nohw", win, w, optimize=True)
    return y if b is None else y + b[None, :, None, None]


def maxpool(x, a):
    k = a["kernel_shape"]
    s = a.get("strides", [1, 1])
    x = pad(x, a.get("pads", [0, 0, 0, 0]), -np.inf)
    win = sliding_window_view(x, k, axis=(2, 3))[:, :, :: s[0], :: s[1]]
    return win.max(axis=(4, 5))


def resize(x, scales, a):
    assert a.get("mode", b"nearest") in (b"nearest", "nearest")
    assert all(float(s).is_integer() for s in scales)
    for axis, s in enumerate(scales):
        x = np.repeat(x, int(s), axis=axis)
    return x


def run(model, x):
    values = {t.name: numpy_helper.to_array(t).astype(np.float64) for t in model.graph.initializer}
    values[model.graph.input[0].name] = x
    for node in model.graph.node:
        a = attrs(node)
        i = [values[n] if n else None for n in node.input]
        op = node.op_type
        if op == "Conv":
            y = conv(i[0], i[1], i[2] if len(i) > 2 else None, a)
        elif op == "MaxPool":
            y = maxpool(i[0], a)
        elif op == "Resize":
            y = resize(i[0], i[2], a)
        elif op == "Concat":
            y = np.concatenate(i, axis=a["axis"])
        elif op == "Mul":
            y = i[0] * i[1]
        elif op == "Div":
            y = i[0] / i[1]
        elif op == "Add":
            y = i[0] + i[1]
        elif op == "Relu":
            y = np.maximum(i[0], 0.0)
        elif op == "Sigmoid":
            y = 1.0 / (1.0 + np.exp(-i[0]))
        elif op == "Greater":
            y = i[0] > i[1]
        elif op == "Cast":
            y = i[0].astype(np.float64)
        else:
            sys.exit(f"onnx_reference.py: op {op} is not implemented")
        values[node.output[0]] = y
    return values[model.graph.output[0].name]


def main():
    model_path, input_path, output_path = sys.argv[1:4]
    model = onnx.load(model_path)
    dims = [d.dim_value for d in model.graph.input[0].type.tensor_type.shape.dim]
    x = np.fromfile(input_path, dtype="<f4").astype(np.float64).reshape(dims)
    run(model, x).astype("<f8").tofile(output_path)


if __name__ == "__main__":
    main()
