#!/usr/bin/python3
"""Writes MODEL.reference.json: the outputs of an exported network on fixed
inputs, computed from the ONNX file by PyTorch's own operators (a small
evaluator of the graph's nodes), independently of OpenCV's dnn module. The
C++ tests (perception/learned_test.cc) run the same inputs through OpenCV
and compare within 1e-4.

The inputs are made by formula, so the C++ side makes them again:
  pattern 0: value(c, y, x) = (37 x + 91 y + 53 c) mod 256
  pattern 1: value(c, y, x) = 127.5 + 127.5 sin(0.05 x + 0.07 y + c)
"""

import argparse
import json
import os
import sys

import numpy as np
import onnx
import torch
import torch.nn.functional as F
from onnx import numpy_helper

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def pattern(index, shape):
    _, c, h, w = shape
    cc, yy, xx = np.meshgrid(np.arange(c), np.arange(h), np.arange(w), indexing="ij")
    if index == 0:
        v = (37 * xx + 91 * yy + 53 * cc) % 256
    else:
        v = 127.5 + 127.5 * np.sin(0.05 * xx + 0.07 * yy + cc)
    return torch.from_numpy(v.astype(np.float32)[None])


def attributes(node):
    return {a.name: onnx.helper.get_attribute_value(a) for a in node.attribute}


def evaluate(model, x):
    """Runs the graph's nodes with torch operators."""
    values = {t.name: torch.from_numpy(numpy_helper.to_array(t).copy())
              for t in model.graph.initializer}
    values[model.graph.input[0].name] = x
    for node in model.graph.node:
        a = attributes(node)
        i = [values[n] if n else None for n in node.input]
        op = node.op_type
        if op == "Constant":
            out = torch.from_numpy(numpy_helper.to_array(a["value"]).copy())
        elif op == "Conv":
            pads = a.get("pads", [0, 0, 0, 0])
            out = F.conv2d(i[0], i[1], i[2] if len(i) > 2 else None, stride=a.get("strides", 1),
                           padding=(pads[0], pads[1]), dilation=a.get("dilations", 1),
                           groups=a.get("group", 1))
        elif op == "Relu":
            out = torch.relu(i[0])
        elif op == "Sigmoid":
            out = torch.sigmoid(i[0])
        elif op == "Tanh":
            out = torch.tanh(i[0])
        elif op in ("Mul", "Add", "Sub", "Div"):
            out = {"Mul": torch.mul, "Add": torch.add, "Sub": torch.sub,
                   "Div": torch.div}[op](i[0], i[1])
        elif op == "Sqrt":
            out = torch.sqrt(i[0])
        elif op == "Pad":
            # ONNX pads: [x1_begin, x2_begin, ..., x1_end, x2_end, ...]
            pads = (i[1].tolist() if len(i) > 1 and i[1] is not None else a["pads"])
            if a.get("mode", b"constant") not in (b"constant", "constant"):
                common.fail(f"{node.name}: Pad mode {a['mode']} is not evaluated here")
            value = float(i[2]) if len(i) > 2 and i[2] is not None else a.get("value", 0.0)
            half = len(pads) // 2
            torch_pads = []
            for axis in reversed(range(half)):
                torch_pads += [pads[axis], pads[axis + half]]
            out = F.pad(i[0], torch_pads, value=value)
        elif op == "AveragePool":
            pads = a.get("pads", [0, 0, 0, 0])
            if pads[0] != pads[2] or pads[1] != pads[3]:
                common.fail(f"{node.name}: asymmetric AveragePool pads are not evaluated here")
            out = F.avg_pool2d(i[0], a["kernel_shape"], a.get("strides", 1),
                               padding=(pads[0], pads[1]),
                               count_include_pad=bool(a.get("count_include_pad", 0)))
        elif op == "Resize":
            mode, where = a.get("mode", b"nearest"), a.get("coordinate_transformation_mode")
            if mode != b"linear" or where not in (b"half_pixel", b"pytorch_half_pixel"):
                common.fail(f"{node.name}: Resize {mode} {where} is not evaluated here")
            scales = i[2].tolist() if len(i) > 2 and i[2] is not None else []
            if len(scales) == 4:
                out = F.interpolate(i[0], scale_factor=(scales[2], scales[3]), mode="bilinear",
                                    align_corners=False)
            else:  # sizes instead of scales
                out = F.interpolate(i[0], size=tuple(i[3].tolist()[2:]), mode="bilinear",
                                    align_corners=False)
        elif op == "Concat":
            out = torch.cat(i, dim=a["axis"])
        elif op == "Slice":
            starts, ends = i[1].tolist(), i[2].tolist()
            axes = i[3].tolist() if len(i) > 3 else list(range(len(starts)))
            out = i[0]
            for s, e, ax in zip(starts, ends, axes):
                out = out.narrow(ax, s, min(e, out.shape[ax]) - s)
        elif op == "MaxPool":
            out = F.max_pool2d(i[0], a["kernel_shape"], a["strides"])
        elif op == "Flatten":
            out = torch.flatten(i[0], a.get("axis", 1))
        elif op == "Gemm":
            b = i[1].t() if a.get("transB", 0) else i[1]
            out = i[0] @ b + i[2]
        elif op == "Reshape":
            out = i[0].reshape(i[1].tolist())
        elif op == "Softmax":
            out = torch.softmax(i[0], dim=a["axis"])
        else:
            common.fail(f"{node.name}: operator {op} is not evaluated here")
        values[node.output[0]] = out
    return values[model.graph.output[0].name]


def write_reference(model_path, shape):
    """Writes MODEL.reference.json beside model_path (MODEL.onnx)."""
    model = onnx.load(model_path)
    outputs = []
    with torch.no_grad():
        for index in (0, 1):
            y = evaluate(model, pattern(index, shape))
            outputs.append({"pattern": index, "shape": list(y.shape),
                            "values": [round(float(v), 7) for v in y.flatten()]})
    common.write_json_atomically(os.path.splitext(model_path)[0] + ".reference.json",
                                 {"model": os.path.basename(model_path),
                                  "input_shape": list(shape), "outputs": outputs})


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("model", help="an ONNX file written by the training scripts")
    parser.add_argument("--shape", type=int, nargs=4, required=True, metavar=("N", "C", "H", "W"))
    args = parser.parse_args()
    write_reference(args.model, args.shape)


if __name__ == "__main__":
    main()
