# SPDX-License-Identifier: GPL-3.0-or-later
"""Isogeometric analysis with the C1 Clough-Tocher spline space.

The spline filter with ``ComputeBezierExtractionOn()`` attaches, per micro-triangle (cell), its
global degrees of freedom (``GlobalDofIds``) and its Bézier extraction operator
(``BezierExtraction``: rows = the cell's Bernstein ordinates in VTK point order, columns = those
degrees of freedom), so that basis function j restricted to a cell is sum_i C[i, j] B_i.
Degrees of freedom: value, d/du, d/dv per input vertex (3 v, 3 v + 1, 3 v + 2), then one per
edge carrying mid-edge data (MGo, MGi everywhere; KaG and gradient boundary modes on boundary
edges), the derivative along the construction's unit direction at the edge midpoint.

File format written by :func:`export` (plain text, whitespace separated, '#' starts a comment)::

    CTSPLINES-BEZIER-EXTRACTION 1
    degree 3
    dofs <number of degrees of freedom>
    points <P>                       then P lines: u v x y z (domain point and position)
    elements <E>                     then per element three lines:
      <10 point ids, VTK order> ; <k> <k dof ids>
      <10 x k coefficients, row-major>
"""
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy


class Extraction:
    """The extraction arrays of a spline grid as numpy arrays.

    cell_points: (C, 10) control point ids (VTK order); cell_dofs: (C, M) global dof ids (-1
    padded); operators: (C, 10, M); n_dofs; dofs: (n_dofs, 3) the input data as degrees of
    freedom; edge_dofs: (E, 3) input edges (a, b, dof or -1); uv: (P, 2) domain points (the
    input vertices' control points come first); points: (P, 3)."""

    def __init__(self, grid):
        cd = grid.GetCellData()
        ids = cd.GetArray("GlobalDofIds")
        ops = cd.GetArray("BezierExtraction")
        if ids is None or ops is None:
            raise ValueError(
                "the grid has no Bézier extraction: run vtkCloughTocherSplineFilter with "
                "ComputeBezierExtractionOn()"
            )
        self.cell_dofs = vtk_to_numpy(ids).astype(np.int64)
        m = self.cell_dofs.shape[1]
        self.operators = vtk_to_numpy(ops).reshape(-1, 10, m)
        conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
        self.cell_points = conn.reshape(-1, 10).astype(np.int64)
        fd = grid.GetFieldData()
        self.n_dofs = int(fd.GetArray("NumberOfDofs").GetValue(0))
        self.dofs = vtk_to_numpy(fd.GetArray("DegreesOfFreedom"))
        # (E, 3): the input mesh's edges (vertex a, vertex b, their dof or -1).
        self.edge_dofs = vtk_to_numpy(fd.GetArray("EdgeDofIds")).astype(np.int64)
        self.uv = vtk_to_numpy(grid.GetPointData().GetArray("UV"))
        self.points = vtk_to_numpy(grid.GetPoints().GetData())

    def element_matrices(self):
        """Per cell: (dof ids, operator) with the padding removed."""
        for c in range(len(self.cell_dofs)):
            k = int(np.count_nonzero(self.cell_dofs[c] >= 0))
            yield self.cell_dofs[c, :k], self.operators[c, :, :k]

    def global_matrix(self):
        """scipy.sparse matrix (points x dofs) mapping degrees of freedom to control points."""
        import scipy.sparse as sp

        rows, cols, vals = [], [], []
        seen = np.zeros(len(self.uv), dtype=bool)
        for c, (dofs, op) in enumerate(self.element_matrices()):
            for a, p in enumerate(self.cell_points[c]):
                if seen[p]:
                    continue
                seen[p] = True
                nz = op[a] != 0.0
                rows.extend([p] * int(nz.sum()))
                cols.extend(dofs[nz])
                vals.extend(op[a][nz])
        return sp.csr_matrix((vals, (rows, cols)), shape=(len(self.uv), self.n_dofs))

    def exponents(self):
        """(C, 10, 3) Bernstein exponents of every cell point, from the domain points."""
        corners = self.uv[self.cell_points[:, :3]]  # (C, 3, 2)
        bary = barycentric(corners, self.uv[self.cell_points])
        return np.rint(3.0 * bary).astype(int)


def barycentric(corners, x):
    """Barycentric coordinates of points x (C, n, 2) w.r.t. triangles corners (C, 3, 2)."""
    a, b, c = corners[:, 0:1], corners[:, 1:2], corners[:, 2:3]
    v0, v1, v2 = b - a, c - a, x - a
    det = v0[..., 0] * v1[..., 1] - v0[..., 1] * v1[..., 0]
    l1 = (v2[..., 0] * v1[..., 1] - v2[..., 1] * v1[..., 0]) / det
    l2 = (v0[..., 0] * v2[..., 1] - v0[..., 1] * v2[..., 0]) / det
    return np.stack([1.0 - l1 - l2, l1, l2], axis=-1)


def triangle_quadrature(n):
    """Collapsed (Duffy) Gauss rule of n x n points on the reference triangle: barycentric
    points (n^2, 3) and weights summing to 1 (exact for polynomials of degree 2 n - 2)."""
    g, w = np.polynomial.legendre.leggauss(n)
    g, w = 0.5 * (g + 1.0), 0.5 * w
    r = np.repeat(g, n)
    s = np.tile(g, n) * (1.0 - r)
    return np.stack([1.0 - r - s, r, s], -1), 2.0 * np.outer(w, w).ravel() * (1.0 - r)


def bernstein(exps, lam):
    """Bernstein polynomials B_e(lam) for exponents exps (n, 3) (zero where an exponent is
    negative) at barycentric points lam (q, 3): (q, n)."""
    from math import factorial

    exps = np.asarray(exps)
    valid = np.all(exps >= 0, -1)
    e = np.maximum(exps, 0)
    coef = np.array([factorial(int(k.sum())) / np.prod([factorial(int(i)) for i in k]) for k in e])
    powers = np.prod(lam[:, None, :] ** e[None], -1)
    return np.where(valid, coef * powers, 0.0)


def bernstein_jets(exps, lam):
    """Bernstein basis of the exponents exps (n, 3) (one degree) with its first and second
    derivatives w.r.t. the barycentric coordinates: (q, n), (q, n, 3), (q, n, 3, 3)."""
    deg = int(np.asarray(exps)[0].sum())
    unit = np.eye(3, dtype=int)
    d1 = np.stack([deg * bernstein(exps - unit[a], lam) for a in range(3)], -1)
    d2 = np.stack([np.stack([deg * (deg - 1) * bernstein(exps - unit[a] - unit[b], lam)
                             for b in range(3)], -1) for a in range(3)], -2)
    return bernstein(exps, lam), d1, d2


def barycentric_gradients(corners):
    """(C, 3, 2) gradients of the barycentric coordinates of triangles corners (C, 3, 2)."""
    e = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], -1)
    inv = np.linalg.inv(e)  # rows: grad l1, grad l2
    return np.concatenate([-(inv[:, 0:1] + inv[:, 1:2]), inv], 1)


def triangle_areas(corners):
    """(C,) areas of triangles corners (C, 3, 2)."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def export(grid, path):
    """Writes the extraction of a spline grid in the plain format of this module's docstring."""
    ex = Extraction(grid)
    with open(path, "w") as f:
        f.write("CTSPLINES-BEZIER-EXTRACTION 1\ndegree 3\n")
        f.write(f"dofs {ex.n_dofs}\npoints {len(ex.uv)}\n")
        for (u, v), (x, y, z) in zip(ex.uv, ex.points):
            f.write(f"{u!r} {v!r} {x!r} {y!r} {z!r}\n")
        f.write(f"elements {len(ex.cell_points)}\n")
        for c, (dofs, op) in enumerate(ex.element_matrices()):
            f.write(" ".join(map(str, ex.cell_points[c])) + " ; " + str(len(dofs)) + " ")
            f.write(" ".join(map(str, dofs)) + "\n")
            f.write(" ".join(repr(float(v)) for v in op.ravel()) + "\n")


def read(path):
    """Reads :func:`export`'s format: dict with n_dofs, uv, points, and elements as a list of
    (point ids, dof ids, operator)."""
    with open(path) as f:
        tokens = [line.split("#", 1)[0].strip() for line in f]
    lines = iter([t for t in tokens if t])
    header = next(lines).split()
    if header != ["CTSPLINES-BEZIER-EXTRACTION", "1"]:
        raise ValueError(f"{path}: not a CTSplines Bézier extraction file (header {header})")
    degree = int(next(lines).split()[1])
    n_dofs = int(next(lines).split()[1])
    n_points = int(next(lines).split()[1])
    pts = np.array([list(map(float, next(lines).split())) for _ in range(n_points)])
    n_el = int(next(lines).split()[1])
    count = (degree + 1) * (degree + 2) // 2
    elements = []
    for _ in range(n_el):
        left, right = next(lines).split(";")
        ids = np.array(left.split(), dtype=np.int64)
        k, *dofs = right.split()
        op = np.array(next(lines).split(), dtype=float).reshape(count, int(k))
        elements.append((ids, np.array(dofs, dtype=np.int64), op))
    return {"degree": degree, "n_dofs": n_dofs, "uv": pts[:, :2], "points": pts[:, 2:],
            "elements": elements}
