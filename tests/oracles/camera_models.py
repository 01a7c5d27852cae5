"""Writes small ONNX camera models whose outputs are known in closed form, for the tests of
`process --segmenter/--depth-model` and of the tract inference path (onnx package; no PyTorch).

    camera_models.py OUT_DIR

writes into OUT_DIR:
  palette.json   {"labels": [...], "colours": [[r, g, b], ...]}: class k is drawn as s * colour[k]
                 (each colour's largest component is 1, no two are parallel)
  segmenter.onnx Conv 1x1 with the unit colour vectors as filters: the arg-max over classes of
                 <colour_k / |colour_k|, pixel> is the pixel's class, whatever its brightness s
                 (Cauchy-Schwarz); labels in the metadata property "labels"
  depth.onnx     ReduceMax over the channels, times 65535 / 256: a pixel drawn with brightness
                 s = v / 65535 (v = KITTI depth value) gives v / 256 metres
  fixed.onnx     a fixed 8x12 input through MaxPool 2x2, Conv 3x3 (pad 1), Relu, Resize nearest
                 x2 and Sigmoid, with fixed_input.json / fixed_expected.json computed here with
                 numpy (the independent reference for tract's result)
"""

import json
import sys
from pathlib import Path

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

LABELS = ["background", "car", "person", "sign", "building", "wall", "fence", "pole", "tree",
          "vehicle_parked"]
COLOURS = [[1, 1, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1],
           [1, 0.5, 0], [0.5, 1, 0], [0, 0.5, 1]]
OPSET = [helper.make_opsetid("", 13)]


def image_input(h="H", w="W"):
    return helper.make_tensor_value_info("image", TensorProto.FLOAT, [1, 3, h, w])


def save(graph, path, labels=None):
    model = helper.make_model(graph, opset_imports=OPSET, producer_name="metamoran-tests")
    model.ir_version = 8
    if labels is not None:
        helper.set_model_props(model, {"labels": ",".join(labels)})
    onnx.checker.check_model(model)
    onnx.save(model, str(path))


def segmenter(out):
    c = np.array(COLOURS, dtype=np.float32)
    w = (c / np.linalg.norm(c, axis=1, keepdims=True)).reshape(len(LABELS), 3, 1, 1)
    graph = helper.make_graph(
        [helper.make_node("Conv", ["image", "w"], ["scores"])],
        "segmenter",
        [image_input()],
        [helper.make_tensor_value_info("scores", TensorProto.FLOAT, [1, len(LABELS), "H", "W"])],
        [numpy_helper.from_array(w, "w")],
    )
    save(graph, out / "segmenter.onnx", LABELS)


def depth(out):
    scale = np.array(65535.0 / 256.0, dtype=np.float32)
    graph = helper.make_graph(
        [helper.make_node("ReduceMax", ["image"], ["m"], axes=[1], keepdims=1),
         helper.make_node("Mul", ["m", "scale"], ["depth"])],
        "depth",
        [image_input()],
        [helper.make_tensor_value_info("depth", TensorProto.FLOAT, [1, 1, "H", "W"])],
        [numpy_helper.from_array(scale, "scale")],
    )
    save(graph, out / "depth.onnx")


def fixed(out):
    rng = np.random.default_rng(7)
    k = rng.normal(0, 0.5, (2, 3, 3, 3)).astype(np.float32)
    b = rng.normal(0, 0.1, (2,)).astype(np.float32)
    scales = np.array([1, 1, 2, 2], dtype=np.float32)
    graph = helper.make_graph(
        [helper.make_node("MaxPool", ["image"], ["p"], kernel_shape=[2, 2], strides=[2, 2]),
         helper.make_node("Conv", ["p", "k", "b"], ["c"], pads=[1, 1, 1, 1]),
         helper.make_node("Relu", ["c"], ["r"]),
         helper.make_node("Resize", ["r", "", "scales"], ["u"], mode="nearest"),
         helper.make_node("Sigmoid", ["u"], ["y"])],
        "fixed",
        [image_input(8, 12)],
        [helper.make_tensor_value_info("y", TensorProto.FLOAT, [1, 2, 8, 12])],
        [numpy_helper.from_array(k, "k"), numpy_helper.from_array(b, "b"),
         numpy_helper.from_array(scales, "scales")],
    )
    save(graph, out / "fixed.onnx")
    x = rng.uniform(0, 1, (1, 3, 8, 12)).astype(np.float64)
    # Reference in float64 numpy.
    p = x.reshape(1, 3, 4, 2, 6, 2).max(axis=(3, 5))
    padded = np.pad(p, ((0, 0), (0, 0), (1, 1), (1, 1)))
    c = np.zeros((1, 2, 4, 6))
    for o in range(2):
        for i in range(3):
            for dy in range(3):
                for dx in range(3):
                    c[0, o] += k[o, i, dy, dx] * padded[0, i, dy:dy + 4, dx:dx + 6]
        c[0, o] += b[o]
    r = np.maximum(c, 0)
    u = r.repeat(2, axis=2).repeat(2, axis=3)
    y = 1 / (1 + np.exp(-u))
    (out / "fixed_input.json").write_text(json.dumps(x.ravel().tolist()))
    (out / "fixed_expected.json").write_text(json.dumps(y.ravel().tolist()))


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    (out / "palette.json").write_text(json.dumps({"labels": LABELS, "colours": COLOURS}))
    segmenter(out)
    depth(out)
    fixed(out)


if __name__ == "__main__":
    main()
