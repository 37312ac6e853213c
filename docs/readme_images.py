#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Regenerates the README's result images in docs/images/ (demo_, farin_, sphere_, fangmann_
prefixes): runs the demo and three paper examples into a scratch folder, then crops, composes and
reduces the PNGs (each below 200 KB).

    PYTHONPATH=build/lib/python3.11/dist-packages xvfb-run -a /usr/bin/python3 docs/readme_images.py
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LinearSegmentedColormap, Normalize  # noqa: E402
from PIL import Image  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "Examples", "Python")
IMAGES = os.path.join(HERE, "images")
LIMIT = 200 * 1024


def run(*command):
    print("+", " ".join(command), flush=True)
    subprocess.run([sys.executable, *command], check=True, stdout=subprocess.DEVNULL)


def save_small(image, filename, width=None, palette=True):
    """Optionally scaled to `width`, reduced to 256 colours (palette), optimised; asserts the size
    limit."""
    image = image.convert("RGB")
    if width and image.width > width:
        image = image.resize((width, round(image.height * width / image.width)), Image.LANCZOS)
    if palette:
        image = image.quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    image.save(filename, optimize=True)
    size = os.path.getsize(filename)
    print(f"{filename}: {image.width} x {image.height}, {size // 1024} KB")
    if size >= LIMIT:
        raise SystemExit(f"{filename} is {size} bytes, limit {LIMIT}")


def crop(image, box=(0.0, 0.0, 1.0, 1.0)):
    """The non-white part of the fractional region `box` (left, top, right, bottom)."""
    a = np.asarray(image.convert("RGB"))
    h, w = a.shape[:2]
    x0, y0, x1, y1 = int(box[0] * w), int(box[1] * h), int(box[2] * w), int(box[3] * h)
    region = a[y0:y1, x0:x1]
    ink = np.where(region.min(axis=2) < 245)
    return region[ink[0].min():ink[0].max() + 1, ink[1].min():ink[1].max() + 1]


def fang_mann_triple(folder, filename):
    """FO, Kashyap, quartic Gaussian curvature (forward diagonals) side by side, one colour bar
    (the examples' linear blue-white-red map over [-100, 100])."""
    names = [("FO", "cubic precision (FO)"), ("Kashyap", "Kashyap, 5 rounds"),
             ("Quartic", "quartic, 5 rounds")]
    fig, axes = plt.subplots(1, 3, figsize=(10.5, 3.3))
    for ax, (stem, label) in zip(axes, names):
        img = Image.open(os.path.join(folder, f"gauss_{stem}_Forward.png"))
        ax.imshow(crop(img, (0.0, 0.07, 0.8, 1.0)))  # without the title and the scalar bar
        ax.set_title(label, fontsize=10)
        ax.axis("off")
    cmap = LinearSegmentedColormap.from_list(
        "ctsplines_diverging", [(0.23, 0.30, 0.75), (1, 1, 1), (0.71, 0.02, 0.15)])
    fig.suptitle("Franke's function on a 5 x 5 grid: Gaussian curvature (quartic paper Fig. 12)",
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 0.93, 0.95))
    cax = fig.add_axes([0.935, 0.15, 0.012, 0.65])
    fig.colorbar(plt.cm.ScalarMappable(Normalize(-100, 100), cmap), cax=cax).ax.tick_params(labelsize=8)
    tmp = filename + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    save_small(Image.open(tmp), filename, palette=False)  # smooth shading: keep every colour
    os.remove(tmp)


def main():
    os.makedirs(IMAGES, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        out = {n: os.path.join(scratch, n) for n in ("demo", "farin", "sphere", "fangmann")}
        run("-m", "ctsplines", "demo", "--output", out["demo"])
        run(os.path.join(EXAMPLES, "farin_cubic.py"), "--output", out["farin"])
        run(os.path.join(EXAMPLES, "sphere_octant_convergence.py"), "--output", out["sphere"])
        run(os.path.join(EXAMPLES, "fang_mann_table.py"), "--output", out["fangmann"])
        save_small(Image.fromarray(crop(Image.open(os.path.join(out["demo"], "spline.png")))),
                   os.path.join(IMAGES, "demo_reflection_lines.png"), width=720)
        save_small(Image.open(os.path.join(out["farin"], "farin_cubic_Delaunay.png")),
                   os.path.join(IMAGES, "farin_cubic_contact_sheet.png"))
        save_small(Image.open(os.path.join(out["sphere"], "convergence.png")),
                   os.path.join(IMAGES, "sphere_octant_convergence.png"))
        fang_mann_triple(out["fangmann"], os.path.join(IMAGES, "fangmann_gauss_curvature.png"))


if __name__ == "__main__":
    main()
