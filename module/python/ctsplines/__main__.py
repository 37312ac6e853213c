# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line of CTSplines: ``python3 -m ctsplines demo [--output DIR]``.

``demo`` converts the built-in default (Franke's function sampled on a Delaunay triangulation of
seeded random points, with exact gradients) into a cubic Clough-Tocher spline and writes the
Bézier spline (.vtu), its tessellation (.vtp) and a rendered PNG with reflection lines.
"""
import argparse
import os
import sys


def _demo(args):
    from . import demo

    paths = demo.run(
        output=args.output,
        construction=args.construction,
        points=args.points,
        level=args.level,
        render=not args.no_render,
    )
    for kind, path in paths.items():
        print(f"{kind}: {os.path.abspath(path)}")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m ctsplines",
        description="Clough-Tocher splines of parametrised triangle meshes (VTK).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser(
        "demo",
        help="convert the built-in default surface and write .vtu, .vtp and .png",
        description="Converts Franke's function on a Delaunay triangulation of seeded random "
        "points into a cubic C1 Clough-Tocher spline; writes the Bézier spline (spline.vtu), its "
        "tessellation (tessellation.vtp) and a PNG with reflection lines (spline.png).",
    )
    demo.add_argument("--output", "-o", default="ctsplines-output", help="output folder")
    demo.add_argument(
        "--construction",
        default="CTi",
        choices=["CTo", "CTi", "MGo", "MGi"],
        help="Clough-Tocher construction (default CTi)",
    )
    demo.add_argument("--points", type=int, default=300, help="random interior samples")
    demo.add_argument("--level", type=int, default=8, help="tessellation segments per cell edge")
    demo.add_argument("--no-render", action="store_true", help="skip the PNG")
    demo.set_defaults(func=_demo)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
