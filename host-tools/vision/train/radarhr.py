#!/usr/bin/env python3
"""Trains 3D-RadarHR (dense radar mapping, Sec. 3.3) on simulated submap/lidar depth-image pairs
and writes it as ONNX for `metamoran map` (tract-onnx on the host).

Why JAX: PyTorch's CPU index is unreachable here and PyPI's `torch` pulls gigabytes of CUDA
libraries; JAX's CPU wheel is ~100 MB, differentiates the network for us and compiles it with
XLA, so this small U-Net trains on two cores in minutes. The graph is written with the `onnx`
package, opset 13, from ops tract runs (Conv, MaxPool, Resize nearest, Concat, Mul, Div, Add,
Relu, Sigmoid, Greater, Cast).

The network, as the paper describes it:
  - the input depth image is binarized into the observation mask o;
  - sparse convolutions (Uhrig et al.): y = conv(x * o, W) / (conv(o, 1) + eps) + b, with the
    mask carried on by max pooling over the kernel; each followed by batch normalization and
    ReLU (folded into the convolution's weights and bias in the exported graph);
  - four max-pool downsamplings (320 x 80 -> 20 x 5), the mask pooled with the features;
  - a decoder of nearest-neighbour upsampling, concatenation with the encoder's features at
    the same scale (skip connections), convolution, BN and ReLU; at full scale the input depth
    and mask are concatenated once more before a last convolution;
  - a 1 x 1 convolution and a sigmoid: depth / max_depth_m.
With `--guide` the network also takes the submap's IP-Basic completion (the pairs'
ip_basic_FFFFFF.png, which `map` computes again before inference) as a second input channel:
  - the encoder sees [submap, observation mask, guide], its sparse convolutions' mask being where
    either has a depth, and the full-scale features see all three again;
  - a second 1 x 1 convolution and sigmoid give a gate g per pixel, and the output is
    g * guide + (1 - g) * the network's own depth: where the network has learnt nothing of a
    place (an environment held out of training) it can keep the completion it was given.
Loss: alpha * Dice + (1 - alpha) * BCE, alpha = 0.3 (the paper's Eq. 7), the target being the
lidar depth / max_depth_m (0 where the lidar has no return); with `--l1 W`, plus W times the mean
absolute error of depth / max_depth_m over the pixels the lidar fills. BCE's gradient is the
error itself, so a pixel 0.8 m off at 5 m (0.01 of the 80 m scale) pulls as little as one 0.8 m
off at 60 m and the near ground stays biased; the L1 term's pull does not shrink with the
error, which is what MAE and point accuracy measure. 0 (the paper's loss) for the small
board's model, 1 for the imaging board's.

Usage: radarhr.py PAIRS_DIR OUT.onnx [--minutes M] [--seed S] [--l1 W] [--guide]
PAIRS_DIR holds bundle folders' `map --training-pairs` outputs: */pairs/submap_FFFFFF.png,
*/pairs/ip_basic_FFFFFF.png and */pairs/lidar_FFFFFF.png (16-bit KITTI PNG: metres x 256,
0 = none).
"""

import argparse
import glob
import os
import sys
import time

import cv2
import jax
import jax.numpy as jnp
import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

WIDTH, HEIGHT = 320, 80
MAX_DEPTH_M = 80.0  # the lidar truth's range
MIN_DEPTH_M = 1.0  # network outputs nearer than this mean "no return"
CHANNELS = [8, 16, 32, 32, 32]  # per scale, 320x80 .. 20x5
FIRST_KERNEL = 5
ALPHA = 0.3
EPS = 1e-6
BN_EPS = 1e-5
BN_MOMENTUM = 0.9
HEADS = ("head", "gate")  # the 1 x 1 output convolutions: no batch normalization
GUIDED = False  # set by --guide before the network is built


def read_kitti(path):
    img = cv2.imread(path, cv2.IMREAD_UNCHANGED)
    if img is None or img.shape != (HEIGHT, WIDTH) or img.dtype != np.uint16:
        sys.exit(f"{path}: not a {WIDTH} x {HEIGHT} 16-bit depth PNG")
    return img.astype(np.float32) / 256.0


def load_pairs(root):
    """{scene: [(x [C, H, W], target [1, H, W])]}, C = 2 (submap, guide) with --guide, else 1."""
    scenes = {}
    for sub in sorted(glob.glob(os.path.join(root, "*", "pairs", "submap_*.png"))):
        inputs = [sub] + ([sub.replace("submap_", "ip_basic_")] if GUIDED else [])
        lid = sub.replace("submap_", "lidar_")
        for f in inputs[1:] + [lid]:
            if not os.path.exists(f):
                sys.exit(f"{f}: missing (every submap_F.png needs its lidar_F.png, and with --guide its ip_basic_F.png)")
        scene = os.path.dirname(os.path.dirname(sub))
        x = np.stack([np.minimum(read_kitti(f) / MAX_DEPTH_M, 1.0) for f in inputs])
        g = np.minimum(read_kitti(lid) / MAX_DEPTH_M, 1.0)[None]
        scenes.setdefault(scene, []).append((x, g))
    if not scenes:
        sys.exit(f"{root}: no */pairs/submap_*.png")
    return scenes


# ---- the network (NCHW) -------------------------------------------------------------------


def conv(x, w, pad):
    return jax.lax.conv_general_dilated(
        x, w, (1, 1), [(pad, pad), (pad, pad)], dimension_numbers=("NCHW", "OIHW", "NCHW")
    )


def pool(x, k, stride):
    pad = [(0, 0), (0, 0), ((k - 1) // 2, k // 2), ((k - 1) // 2, k // 2)] if stride == 1 else "VALID"
    return jax.lax.reduce_window(x, -jnp.inf, jax.lax.max, (1, 1, k, k), (1, 1, stride, stride), pad)


def up(x):
    return jnp.repeat(jnp.repeat(x, 2, axis=2), 2, axis=3)


def layers():
    """(name, in, out, kernel, sparse) of every convolution, in order."""
    out = []
    cin = 3 if GUIDED else 1
    for lvl, c in enumerate(CHANNELS):
        out.append((f"enc{lvl}a", cin, c, FIRST_KERNEL if lvl == 0 else 3, True))
        out.append((f"enc{lvl}b", c, c, 3, True))
        cin = c
    for lvl in reversed(range(len(CHANNELS) - 1)):
        out.append((f"dec{lvl}", CHANNELS[lvl + 1] + CHANNELS[lvl], CHANNELS[lvl], 3, False))
    # The last features see the input depth and its mask again, at full resolution: the far
    # walls the radar does see are a few pixels each, easily averaged away on the way down.
    out.append(("refine", CHANNELS[0] + (3 if GUIDED else 2), CHANNELS[0], 3, False))
    out.append(("head", CHANNELS[0], 1, 1, False))
    if GUIDED:
        out.append(("gate", CHANNELS[0], 1, 1, False))
    return out


def init(key):
    params, stats = {}, {}
    for name, cin, cout, k, _ in layers():
        key, sub = jax.random.split(key)
        std = np.sqrt(2.0 / (cin * k * k))
        params[name] = {"w": jax.random.normal(sub, (cout, cin, k, k)) * std, "b": jnp.zeros(cout)}
        if name not in HEADS:
            params[name]["gamma"] = jnp.ones(cout)
            params[name]["beta"] = jnp.zeros(cout)
            stats[name] = {"mean": jnp.zeros(cout), "var": jnp.ones(cout)}
    return params, stats


def forward(params, stats, x, train):
    """x: [N, C, H, W] depth / max (C = 2 with the guide). Returns (prediction, new batch-norm
    statistics)."""
    new_stats = {}
    spec = {name: (k, sparse) for name, _, _, k, sparse in layers()}

    def unit(name, h, mask=None):
        p, (k, sparse) = params[name], spec[name]
        if sparse:
            ones = jnp.ones((1, 1, k, k))
            y = conv(h * mask, p["w"], k // 2) / (conv(mask, ones, k // 2) + EPS)
            mask = pool(mask, k, 1)
        else:
            y = conv(h, p["w"], k // 2)
        y = y + p["b"][None, :, None, None]
        if name in HEADS:
            return y, mask
        if train:
            mean, var = y.mean(axis=(0, 2, 3)), y.var(axis=(0, 2, 3))
            s = stats[name]
            new_stats[name] = {
                "mean": BN_MOMENTUM * s["mean"] + (1 - BN_MOMENTUM) * mean,
                "var": BN_MOMENTUM * s["var"] + (1 - BN_MOMENTUM) * var,
            }
        else:
            mean, var = stats[name]["mean"], stats[name]["var"]
        y = (y - mean[None, :, None, None]) / jnp.sqrt(var[None, :, None, None] + BN_EPS)
        y = y * p["gamma"][None, :, None, None] + p["beta"][None, :, None, None]
        return jax.nn.relu(y), mask

    sub = x[:, :1]
    mask = observed = (sub > 0).astype(x.dtype)
    h, seen = sub, [sub, observed]
    if GUIDED:
        guide = x[:, 1:2]
        mask = ((sub + guide) > 0).astype(x.dtype)
        h = seen = jnp.concatenate([sub, observed, guide], axis=1)
    skips = []
    for lvl in range(len(CHANNELS)):
        if lvl > 0:
            h, mask = pool(h, 2, 2), pool(mask, 2, 2)
        h, mask = unit(f"enc{lvl}a", h, mask)
        h, mask = unit(f"enc{lvl}b", h, mask)
        skips.append(h)
    for lvl in reversed(range(len(CHANNELS) - 1)):
        h, _ = unit(f"dec{lvl}", jnp.concatenate([up(h), skips[lvl]], axis=1))
    h, _ = unit("refine", jnp.concatenate([h] + ([seen] if GUIDED else seen), axis=1))
    y, _ = unit("head", h)
    y = jax.nn.sigmoid(y)
    if GUIDED:
        gate = jax.nn.sigmoid(unit("gate", h)[0])
        y = y + gate * (guide - y)
    return y, new_stats


def loss_fn(params, stats, x, g, l1):
    y, new_stats = forward(params, stats, x, True)
    inter = (y * g).sum(axis=(1, 2, 3))
    dice = 1.0 - (2.0 * inter + 1.0) / (y.sum(axis=(1, 2, 3)) + g.sum(axis=(1, 2, 3)) + 1.0)
    yc = jnp.clip(y, 1e-6, 1.0 - 1e-6)
    bce = -(g * jnp.log(yc) + (1.0 - g) * jnp.log(1.0 - yc)).mean(axis=(1, 2, 3))
    seen = (g > 0).astype(y.dtype)
    mae = (jnp.abs(y - g) * seen).sum(axis=(1, 2, 3)) / (seen.sum(axis=(1, 2, 3)) + 1.0)
    return (ALPHA * dice + (1.0 - ALPHA) * bce + l1 * mae).mean(), new_stats


@jax.jit
def step(params, stats, opt, x, g, lr, l1):
    (loss, new_stats), grads = jax.value_and_grad(loss_fn, has_aux=True)(params, stats, x, g, l1)
    m, v, t = opt
    t = t + 1
    m = jax.tree_util.tree_map(lambda m, g: 0.9 * m + 0.1 * g, m, grads)
    v = jax.tree_util.tree_map(lambda v, g: 0.999 * v + 0.001 * g * g, v, grads)
    params = jax.tree_util.tree_map(
        lambda p, m, v: p - lr * (m / (1 - 0.9**t)) / (jnp.sqrt(v / (1 - 0.999**t)) + 1e-8),
        params,
        m,
        v,
    )
    return params, new_stats, (m, v, t), loss


predict = jax.jit(lambda params, stats, x: forward(params, stats, x, False)[0])


def errors(pred, g):
    """(MAE, RMSE) in metres over pixels where both have a depth (as `metamoran map`)."""
    p, t = pred * MAX_DEPTH_M, g * MAX_DEPTH_M
    both = (p >= MIN_DEPTH_M) & (t > 0)
    d = (p - t)[both]
    return float(np.abs(d).mean()), float(np.sqrt((d * d).mean()))


# ---- ONNX export ----------------------------------------------------------------------------


def export(params, stats, path):
    nodes, inits = [], []

    def const(name, array):
        inits.append(numpy_helper.from_array(np.asarray(array, dtype=np.float32), name))
        return name

    def node(op, inputs, output, **attrs):
        nodes.append(helper.make_node(op, inputs, [output], name=output, **attrs))
        return output

    spec = {name: (k, sparse) for name, _, _, k, sparse in layers()}

    def unit(name, h, mask=None):
        p, (k, sparse) = params[name], spec[name]
        w, b = np.asarray(p["w"], np.float64), np.asarray(p["b"], np.float64)
        if name not in HEADS:  # fold batch normalization into the convolution
            s = np.asarray(p["gamma"]) / np.sqrt(np.asarray(stats[name]["var"]) + BN_EPS)
            w = w * s[:, None, None, None]
            b = s * (b - np.asarray(stats[name]["mean"])) + np.asarray(p["beta"])
        pads = [k // 2] * 4
        if sparse:
            masked = node("Mul", [h, mask], f"{name}_masked")
            y = node("Conv", [masked, const(f"{name}_w", w)], f"{name}_conv", pads=pads)
            count = node("Conv", [mask, const(f"ones{k}", np.ones((1, 1, k, k)))], f"{name}_count", pads=pads)
            y = node("Div", [y, node("Add", [count, const("eps", [EPS])], f"{name}_count_eps")], f"{name}_norm")
            y = node("Add", [y, const(f"{name}_b", b.reshape(1, -1, 1, 1))], f"{name}_biased")
            lo, hi = (k - 1) // 2, k // 2
            mask = node("MaxPool", [mask], f"{name}_mask", kernel_shape=[k, k], pads=[lo, lo, hi, hi])
        else:
            y = node("Conv", [h, const(f"{name}_w", w), const(f"{name}_b", b)], f"{name}_conv", pads=pads)
        if name in HEADS:
            return y, mask
        return node("Relu", [y], f"{name}_relu"), mask

    x = "submap_depth"
    channels = 2 if GUIDED else 1
    sub = x
    if GUIDED:  # each channel picked out by a fixed 1 x 1 convolution (no Slice in the op set)
        sub = node("Conv", [x, const("pick_submap", np.array([1.0, 0.0]).reshape(1, 2, 1, 1))], "submap")
        guide = node("Conv", [x, const("pick_guide", np.array([0.0, 1.0]).reshape(1, 2, 1, 1))], "guide")
    zero = const("zero", [0.0])
    mask = node("Cast", [node("Greater", [sub, zero], "observed")], "mask", to=TensorProto.FLOAT)
    h, seen = sub, [sub, "mask"]
    if GUIDED:
        either = node("Greater", [node("Add", [sub, guide], "sub_plus_guide"), zero], "either")
        mask = node("Cast", [either], "enc_mask", to=TensorProto.FLOAT)
        h = node("Concat", [sub, "mask", guide], "enc_input", axis=1)
        seen = [h]
    skips = []
    for lvl in range(len(CHANNELS)):
        if lvl > 0:
            h = node("MaxPool", [h], f"down{lvl}", kernel_shape=[2, 2], strides=[2, 2])
            mask = node("MaxPool", [mask], f"down{lvl}_mask", kernel_shape=[2, 2], strides=[2, 2])
        h, mask = unit(f"enc{lvl}a", h, mask)
        h, mask = unit(f"enc{lvl}b", h, mask)
        skips.append(h)
    for lvl in reversed(range(len(CHANNELS) - 1)):
        u = node(
            "Resize",
            [h, "", const("scale2", [1, 1, 2, 2])],
            f"up{lvl}",
            mode="nearest",
            coordinate_transformation_mode="asymmetric",
            nearest_mode="floor",
        )
        h, _ = unit(f"dec{lvl}", node("Concat", [u, skips[lvl]], f"cat{lvl}", axis=1))
    h, _ = unit("refine", node("Concat", [h] + seen, "cat_input", axis=1))
    y, _ = unit("head", h)
    if GUIDED:  # depth = y + gate * (guide - y)
        y = node("Sigmoid", [y], "own_depth")
        gate = node("Sigmoid", [unit("gate", h)[0]], "gate_open")
        minus_y = node("Mul", [y, const("minus_one", [-1.0])], "minus_own")
        pulled = node("Mul", [gate, node("Add", [guide, minus_y], "guide_minus_own")], "pulled")
        node("Add", [y, pulled], "depth")
    else:
        node("Sigmoid", [y], "depth")
    # de-duplicate shared constants (eps, ones3, scale2, ...)
    seen, unique = set(), []
    for t in inits:
        if t.name not in seen:
            seen.add(t.name)
            unique.append(t)
    graph = helper.make_graph(
        nodes,
        "radarhr",
        [helper.make_tensor_value_info(x, TensorProto.FLOAT, [1, channels, HEIGHT, WIDTH])],
        [helper.make_tensor_value_info("depth", TensorProto.FLOAT, [1, 1, HEIGHT, WIDTH])],
        unique,
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)], producer_name="metamoran radarhr.py")
    for k, v in {"max_depth_m": MAX_DEPTH_M, "min_depth_m": MIN_DEPTH_M}.items():
        model.metadata_props.add(key=k, value=str(v))
    onnx.checker.check_model(model)
    onnx.save(model, path)


# ---- training ---------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pairs")
    ap.add_argument("out")
    ap.add_argument("--minutes", type=float, default=8.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--l1", type=float, default=0.0, help="weight of the L1 term (0: the paper's loss)")
    ap.add_argument("--guide", action="store_true", help="also take the submap's IP-Basic completion")
    args = ap.parse_args()
    global GUIDED
    GUIDED = args.guide

    scenes = load_pairs(args.pairs)
    names = sorted(scenes)
    val_names = names[:: max(1, len(names) // max(1, len(names) // 6))][: max(1, len(names) // 6)]
    train = [p for n in names if n not in val_names for p in scenes[n]]
    val = [p for n in val_names for p in scenes[n]]
    print(f"{len(train)} training pairs, {len(val)} validation pairs ({len(val_names)} scenes)")
    xt = np.stack([p[0] for p in train])
    gt = np.stack([p[1] for p in train])
    xv = np.stack([p[0] for p in val])
    gv = np.stack([p[1] for p in val])

    rng = np.random.default_rng(args.seed)
    params, stats = init(jax.random.PRNGKey(args.seed))
    # Start the output at the mean target: Adam moves a bias about lr per step, so from
    # sigmoid(0) = 40 m it would take a thousand steps just to reach the typical depth.
    mean = float(np.clip(gt.mean(), 1e-3, 1 - 1e-3))
    params["head"]["b"] = jnp.full(1, np.log(mean / (1 - mean)))
    zeros = jax.tree_util.tree_map(jnp.zeros_like, params)
    opt = (zeros, zeros, 0)
    start, it, lr0 = time.time(), 0, 3e-3
    budget = args.minutes * 60
    best = (np.inf, params, stats)  # the checkpoint with the lowest validation MAE
    while time.time() - start < budget:
        idx = rng.choice(len(xt), args.batch, replace=len(xt) < args.batch)
        x, g = xt[idx], gt[idx]
        flip = rng.random(args.batch) < 0.5  # the street mirrored left-right is a street
        x[flip], g[flip] = x[flip][..., ::-1], g[flip][..., ::-1]
        frac = (time.time() - start) / budget
        lr = lr0 * 0.5 * (1 + np.cos(np.pi * min(frac, 1.0)))
        params, stats, opt, loss = step(params, stats, opt, jnp.asarray(x), jnp.asarray(g), lr, args.l1)
        it += 1
        if it % 100 == 0:
            pv = np.concatenate([np.asarray(predict(params, stats, jnp.asarray(xv[i : i + 8]))) for i in range(0, len(xv), 8)])
            mae, rmse = errors(pv, gv)
            sub = errors(xv[:, :1], gv)
            if mae < best[0]:
                best = (mae, params, stats)
            print(
                f"step {it:5d}  {time.time() - start:5.0f} s  loss {float(loss):.4f}  "
                f"validation MAE/RMSE network {mae:.2f}/{rmse:.2f} m, submap {sub[0]:.2f}/{sub[1]:.2f} m",
                flush=True,
            )
    export(best[1], best[2], args.out)
    print(f"wrote {args.out} ({os.path.getsize(args.out)} bytes): validation MAE {best[0]:.2f} m, {it} steps")


if __name__ == "__main__":
    main()
