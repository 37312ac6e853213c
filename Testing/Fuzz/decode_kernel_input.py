#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Prints a kernel fuzz input (ctsplines_fuzz_kernel, layout in KernelFuzzer.cxx) as readable
mesh data, to turn a reproducer into a unit test:  decode_kernel_input.py FILE"""
import struct
import sys

SPECIALS = [0.0, float("nan"), float("inf"), float("-inf"), 1e300, -1e300, 1e-310, 1e150]
CONSTRUCTIONS = ["CTo", "CTi", "Fa", "FO", "Ka", "MGo", "MGi", "KaG", "Kashyap", "quartic"]


class Reader:
    def __init__(self, data):
        self.data, self.pos = data, 0

    def byte(self):
        if self.pos >= len(self.data):
            return 0
        self.pos += 1
        return self.data[self.pos - 1]

    def value(self):
        tag = self.byte()
        if tag < 240:
            return struct.unpack("<h", bytes([self.byte(), self.byte()]))[0] / 256.0
        if tag < 248:
            return SPECIALS[tag - 240]
        return struct.unpack("<d", bytes(self.byte() for _ in range(8)))[0]

    def values(self, n):
        return [self.value() for _ in range(n)]


def main():
    r = Reader(open(sys.argv[1], "rb").read())
    construction, split, boundary, iterations = r.byte() % 10, r.byte() % 3, r.byte() % 4, r.byte() % 4
    flags = r.byte()
    nv, nt = r.byte() % 64, r.byte() % 96
    print(f"construction {CONSTRUCTIONS[construction]}, split point {split}, boundary mode {boundary},"
          f" iterations {iterations}, flags {flags:08b}, {nv} vertices, {nt} triangles")
    tris = []
    for _ in range(nt):
        tri = []
        for _ in range(3):
            b = r.byte()
            tri.append(-1 if b == 255 else b % (nv + 1))
        tris.append(tri)
    print("triangles", tris)
    for name, k in (("UV", 2), ("F", 3), ("Fu", 3), ("Fv", 3)):
        vals = r.values(k * nv)
        print(name, [vals[i:i + k] for i in range(0, len(vals), k)])
    for bit, name, k in ((0, "EdgeGradients", 18), (1, "BoundaryCurvePoints", 18)):
        if flags >> bit & 1:
            vals = r.values(k * nt)
            print(name, [vals[i:i + k] for i in range(0, len(vals), k)])
    if flags >> 2 & 1:
        vals = r.values(2 * nt)
        print("SplitTau", [(a, b, 1 - a - b) for a, b in zip(vals[0::2], vals[1::2])])
    nq = r.byte() % 16
    vals = r.values(3 * nq)
    print("queries", [vals[i:i + 3] for i in range(0, len(vals), 3)])
    print("steps:", ", ".join(name for bit, name in ((3, "chunked ParallelFor"), (4, "extraction"),
                                                     (5, "locator"), (6, "distance")) if flags >> bit & 1))


if __name__ == "__main__":
    main()
