"""The learned detectors' networks (docs/learned_perception.md).

Both take 8-bit BGR pixels as floats in [0, 255] (OpenCV's order, so the C++
side feeds cv::dnn::blobFromImage without swapping or scaling) and end in
their activations, so that the exported ONNX graph gives probabilities,
offsets and unit-ish direction components directly.
"""

import torch
import torch.nn.functional as F
from torch import nn


def conv_bn(c_in, c_out, stride=1, dilation=1):
    """3x3 convolution, batch norm (folded into the convolution by the
    exporter and by OpenCV's dnn), ReLU."""
    return nn.Sequential(
        nn.Conv2d(c_in, c_out, 3, stride=stride, padding=dilation, dilation=dilation, bias=False),
        nn.BatchNorm2d(c_out),
        nn.ReLU(inplace=True),
    )


class LocalContrastNorm(nn.Module):
    """Each channel minus its local mean, divided by its local standard
    deviation (never below `floor`):

        y = (x - mean(x)) / sqrt(mean((x - mean(x))^2) + floor^2)

    on x already scaled to [-1, 1]. A faint line on a dim floor and a bright
    one in sunlight come out alike, so the network cannot lean on the
    rendering's brightness and contrast.

    mean() is taken coarsely: 4 x 4 blocks averaged, a 3 x 3 box over the
    blocks (zero padding: mid-grey), and bilinear interpolation back to full
    size, about a 12-pixel window (0.5 m at 256 px for 10 m). OpenCV's dnn
    runs it in under a millisecond, where a full-resolution box of that size
    takes five.
    """

    def __init__(self, block=4, floor=0.08):
        super().__init__()
        self.block = block
        self.floor2 = floor * floor

    def mean(self, x):
        m = F.avg_pool2d(F.avg_pool2d(x, self.block, self.block), 3, 1, 1)
        return F.interpolate(m, scale_factor=float(self.block), mode="bilinear",
                             align_corners=False)

    def forward(self, x):
        centred = x - self.mean(x)
        return centred / torch.sqrt(self.mean(centred * centred) + self.floor2)


class Greyscale(nn.Module):
    """The three channels replaced by their mean: the network sees no colour
    (neither the paint's nor the rendering's colour casts). A fixed 1 x 1
    convolution, which every runtime here reads."""

    def __init__(self, channels=3):
        super().__init__()
        self.register_buffer("weight", torch.full((channels, channels, 1, 1), 1.0 / channels))

    def forward(self, x):
        return F.conv2d(x, self.weight)


class MarkingPointNet(nn.Module):
    """Fully convolutional marking-point detector in the manner of DMPR-PS.

    Input 1 x 3 x S x S (S a multiple of 16); output 1 x 6 x S/16 x S/16, per
    grid cell: [0] confidence that a marking point lies in the cell, [1:3]
    its position inside the cell (x, y in [0, 1]), [3:5] the direction of its
    separating line (cos, sin; image axes, y down), [5] the probability that
    it is T-shaped (else L-shaped). With input_norm "local" the scaled
    pixels pass LocalContrastNorm first; with "grey", Greyscale.
    """

    OUTPUTS = 6
    STRIDE = 16

    def __init__(self, widths=(16, 32, 64, 128), input_norm="none"):
        super().__init__()
        norms = {"none": nn.Identity, "local": LocalContrastNorm, "grey": Greyscale}
        if input_norm not in norms:
            raise ValueError(f"input_norm: {input_norm!r} is not one of {sorted(norms)}")
        self.norm = norms[input_norm]()
        w0, w1, w2, w3 = widths
        self.features = nn.Sequential(
            conv_bn(3, w0, stride=2),      # S/2
            conv_bn(w0, w1, stride=2),     # S/4
            conv_bn(w1, w1),
            conv_bn(w1, w2, stride=2),     # S/8
            conv_bn(w2, w2),
            conv_bn(w2, w3, stride=2),     # S/16
            conv_bn(w3, w3),
            conv_bn(w3, w3, dilation=2),   # wider context: a junction's arms
        )
        self.head = nn.Conv2d(w3, self.OUTPUTS, 1)

    def raw(self, bgr):
        x = self.norm(bgr * (1.0 / 127.5) - 1.0)
        return self.head(self.features(x))

    def forward(self, bgr):
        r = self.raw(bgr)
        return torch.cat([torch.sigmoid(r[:, 0:3]), torch.tanh(r[:, 3:5]), torch.sigmoid(r[:, 5:6])], 1)


# The characters a slot ID may hold; class 0 of every position is "no
# character" (IDs are left-aligned: 1 to 4 characters, then nothing).
ID_ALPHABET = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-"
ID_POSITIONS = 4


class SlotIdNet(nn.Module):
    """Reads an upright 96 x 32 crop of a painted ID: for each of the four
    character positions, probabilities over "none" and ID_ALPHABET.

    Output 1 x 4 x (1 + len(ID_ALPHABET)), softmax over the last axis.
    """

    def __init__(self, widths=(24, 48, 96), hidden=192):
        super().__init__()
        w0, w1, w2 = widths
        self.features = nn.Sequential(
            conv_bn(3, w0), nn.MaxPool2d(2),           # 16 x 48
            conv_bn(w0, w1), nn.MaxPool2d(2),          # 8 x 24
            conv_bn(w1, w2), conv_bn(w2, w2), nn.MaxPool2d(2),  # 4 x 12
        )
        self.classes = 1 + len(ID_ALPHABET)
        self.fc = nn.Sequential(
            nn.Flatten(), nn.Dropout(0.2), nn.Linear(w2 * 4 * 12, hidden), nn.ReLU(inplace=True),
            nn.Linear(hidden, ID_POSITIONS * self.classes))

    def raw(self, bgr):
        x = bgr * (1.0 / 127.5) - 1.0
        return self.fc(self.features(x)).view(-1, ID_POSITIONS, self.classes)

    def forward(self, bgr):
        return torch.softmax(self.raw(bgr), dim=2)


def export_onnx(model, shape, path, output_name):
    """Exports `model` (in eval mode) for OpenCV's dnn module: opset 11, one
    input "bgr" of `shape`, one output named `output_name`.

    The exporter shares equal constants through Identity nodes, which
    OpenCV 4.6 cannot read; they are replaced by copies of the constant.
    """
    import io
    import onnx
    from onnx import numpy_helper

    model.eval()
    buffer = io.BytesIO()
    torch.onnx.export(model, torch.zeros(*shape), buffer, opset_version=11,
                      input_names=["bgr"], output_names=[output_name],
                      do_constant_folding=True)
    graph_model = onnx.load_from_string(buffer.getvalue())
    graph = graph_model.graph
    initializers = {t.name: t for t in graph.initializer}
    kept = []
    for node in graph.node:
        if node.op_type == "Identity" and node.input[0] in initializers:
            copy = numpy_helper.from_array(numpy_helper.to_array(initializers[node.input[0]]),
                                           node.output[0])
            graph.initializer.append(copy)
            initializers[copy.name] = copy
        else:
            kept.append(node)
    del graph.node[:]
    graph.node.extend(kept)
    onnx.checker.check_model(graph_model)
    onnx.save(graph_model, path)
