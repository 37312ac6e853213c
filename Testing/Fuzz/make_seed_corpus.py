#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the seed corpora of the fuzz targets (docs/fuzzing.md): valid inputs in each target's
byte format (FuzzInput.h and the comments at the top of each *Fuzzer.cxx), from which libFuzzer
mutates. Deterministic; nothing is downloaded.

  make_seed_corpus.py OUTDIR            writes OUTDIR/kernel, OUTDIR/filters, OUTDIR/cad
  make_seed_corpus.py OUTDIR --step DIR adds the *.step/*.stp/*.igs files of DIR (< 100 kB) to cad
"""
import argparse
import math
import pathlib
import shutil
import struct

NAN = 241  # special-value tags of FuzzInput::Value
INF = 242


def value(x):
    """One value in the grid encoding (tag < 240): int16 / 256."""
    q = max(-32768, min(32767, int(round(x * 256.0))))
    return bytes([0]) + struct.pack("<h", q)


def values(xs):
    return b"".join(value(x) for x in xs)


# Surfaces (height, d/du, d/dv) over parameters in about [0, 2].
SURFACES = {
    "plane": (lambda u, v: 0.5 * u - 0.25 * v, lambda u, v: 0.5, lambda u, v: -0.25),
    "paraboloid": (lambda u, v: u * u + v * v, lambda u, v: 2 * u, lambda u, v: 2 * v),
    "saddle": (lambda u, v: u * v - 0.5 * u * u, lambda u, v: v - u, lambda u, v: u),
    "wave": (lambda u, v: math.sin(u) * math.cos(v),
             lambda u, v: math.cos(u) * math.cos(v), lambda u, v: -math.sin(u) * math.sin(v)),
}


def grid(n, surface, step=0.5, diagonal=0):
    """(uv, f, fu, fv, triangles) of an n x n grid of quads split into triangles."""
    h, hu, hv = SURFACES[surface]
    uv, f, fu, fv = [], [], [], []
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i * step, j * step
            uv.append((u, v))
            f.append((u, v, h(u, v)))
            fu.append((1.0, 0.0, hu(u, v)))
            fv.append((0.0, 1.0, hv(u, v)))
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            if (diagonal + i + j) % 2 == 0:
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
    return uv, f, fu, fv, tris


def edge_gradients(surface, uv, tris):
    _, hu, hv = SURFACES[surface]
    out = []
    for t in tris:
        for l in range(3):
            p, q = uv[t[l]], uv[t[(l + 1) % 3]]
            u, v = (p[0] + q[0]) / 2, (p[1] + q[1]) / 2
            out += [1.0, 0.0, hu(u, v), 0.0, 1.0, hv(u, v)]
    return out


def boundary_curve_points(f, fu, fv, uv, tris):
    """The edge cubic's inner points from the vertex derivatives (eq. 11) on every local edge."""
    out = []
    for t in tris:
        for l in range(3):
            i, j = t[l], t[(l + 1) % 3]
            du, dv = uv[j][0] - uv[i][0], uv[j][1] - uv[i][1]
            for a, b, s in ((i, j, 1.0), (j, i, -1.0)):
                out += [f[a][k] + s * (fu[a][k] * du + fv[a][k] * dv) / 3 for k in range(3)]
    return out


def kernel_seed(construction, split, boundary, iterations, flags, n, surface, queries=4):
    uv, f, fu, fv, tris = grid(n, surface, diagonal=construction % 2)
    out = bytes([construction, split, boundary, iterations, flags, len(uv), len(tris)])
    out += bytes(i for t in tris for i in t)
    out += values(c for p in uv for c in p)
    for arr in (f, fu, fv):
        out += values(c for p in arr for c in p)
    if flags & 1:
        out += values(edge_gradients(surface, uv, tris))
    if flags & 2:
        out += values(boundary_curve_points(f, fu, fv, uv, tris))
    if flags & 4:
        out += values([0.3, 0.3] * len(tris))
    out += bytes([queries])
    for q in range(queries):
        out += values([0.37 * q, 0.23 * q + 0.1, 0.5 * q])
    return out


def kernel_corpus():
    seeds = {}
    for construction in range(10):
        for split in range(3):
            boundary = (construction + split) % 4
            flags = 0b1110000 | (1 if construction in (5, 6, 7) or boundary >= 2 else 0)
            seeds[f"c{construction}-s{split}"] = kernel_seed(
                construction, split, boundary, split % 2, flags, 2 + split, "paraboloid")
    for i, surface in enumerate(SURFACES):
        seeds[f"curve-{surface}"] = kernel_seed(i % 8, 0, 1, 0, 0b1110011, 3, surface)
        seeds[f"tau-{surface}"] = kernel_seed(1, 2, 3, 1, 0b11111101, 2, surface)
    return seeds


# Filters target: see the layout at the top of FiltersFuzzer.cxx.
FILTERS = 8


def array_spec(present, components, delta=0, kind=0):
    """Descriptor of one fuzzed array: presence, component count, tuple count delta, type."""
    return bytes([1 if present else 0, components, (delta + 8) % 256, kind])


def filters_seed(filt, mode, construction, split, boundary, n, surface, level=2):
    uv, f, fu, fv, tris = grid(n, surface, diagonal=construction % 2)
    needs_gradients = construction in (5, 6, 7) or boundary >= 2
    out = bytes([filt, mode, construction, split, boundary, 0, level, 0])
    out += bytes([len(uv), len(tris)])
    out += values(c for p in f for c in p)
    out += b"".join(bytes([0, t[0], t[1], t[2]]) for t in tris)
    out += array_spec(True, 2) + values(c for p in uv for c in p)
    out += array_spec(True, 3) + values(c for p in fu for c in p)
    out += array_spec(True, 3) + values(c for p in fv for c in p)
    out += array_spec(needs_gradients, 18)
    if needs_gradients:
        out += values(edge_gradients(surface, uv, tris))
    out += array_spec(False, 18) + array_spec(False, 1) + array_spec(False, 1)
    # Filter parameters and the second input (probe points, reference mesh).
    out += values([0.3, 0.7, 1.1, 0.2, 0.9, 1.3, 0.5, 0.5, 1.0, 0.25, 0.1, 0.0])
    if filt == 7:  # sampled source: resolution 4, seed 1
        out += bytes([6, 1])
    if mode == 1:  # damage: shorten UV, a linear triangle, rational weights of 1.5 but one
        out += bytes([0, 1, 5, 2, 9, 3]) + value(1.5)
    return out


def filters_corpus():
    seeds = {}
    for filt in range(FILTERS):
        for mode in range(2):
            construction = (3 * filt + mode) % 10
            seeds[f"f{filt}-m{mode}"] = filters_seed(
                filt, mode, construction, filt % 3, (filt + mode) % 4, 2 + mode, "saddle")
    for i, surface in enumerate(SURFACES):
        seeds[f"spline-{surface}"] = filters_seed(0, 0, i + 4, 2, 3, 3, surface)
    return seeds


# CAD target: a one-byte header (bit 0: IGES instead of STEP; 1: stitch; 4: read in-process)
# then the file. The
# STEP/IGES files come from --step directories (run_fuzzer.sh passes the model the tests write
# and the ones they fetch); files above 100 kB are left out (seconds per run under ASan).
def cad_corpus(step_dirs):
    seeds = {"empty": bytes([0])}
    for step_dir in step_dirs:
        for path in sorted(pathlib.Path(step_dir).iterdir()):
            if path.suffix.lower() in (".step", ".stp", ".igs", ".iges") and path.stat().st_size < 100000:
                iges = 1 if path.suffix.lower() in (".igs", ".iges") else 0
                seeds[path.stem] = bytes([iges]) + path.read_bytes()
                seeds[path.stem + "-stitch"] = bytes([iges | 2]) + path.read_bytes()
                seeds[path.stem + "-in-process"] = bytes([iges | 16]) + path.read_bytes()
    return seeds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir")
    parser.add_argument("--step", action="append", default=[],
                        help="directory of STEP/IGES files for the cad seeds (repeatable)")
    args = parser.parse_args()
    root = pathlib.Path(args.outdir)
    for name, seeds in (("kernel", kernel_corpus()), ("filters", filters_corpus()),
                        ("cad", cad_corpus(args.step))):
        directory = root / name
        shutil.rmtree(directory, ignore_errors=True)
        directory.mkdir(parents=True)
        for seed, data in seeds.items():
            (directory / seed).write_bytes(data)
        print(f"{directory}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
