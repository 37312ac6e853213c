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

JSON files written by :func:`export_json` (read back by :func:`read_json`), two layouts:

``layout="coreform"``: the field names of the Bézier-extraction JSON Coreform Cubit exports
(``nodes`` as x y z w, ``elements.element_blocks`` with one entry per element: ``us_cid``,
``node_ids``, ``coeff_vector_ids``; ``coefficients.dense_coefficient_vectors`` of
``components``; 0-based), with element type ``BERNSTEIN_TRIANGLE`` in ``element_block_info``
(Cubit's elements are tensor-product): the global "nodes" are the degrees of freedom (their
coordinates the geometry's dofs, some of them tangent vectors, weights 1), and the coefficient
vector of node ``node_ids[n]`` of an element holds its 10 Bernstein coefficients in the order
``bernstein_exponents``: N_j|e = sum_i c_i B_i.

``layout="ctsplines"``: the Bernstein mesh (``bezier_mesh``: uv, points, cells of 10 point ids),
the global extraction matrix (points x dofs, CSR ``indptr``/``indices``/``data``), the dofs
(``coordinates``, ``num_vertices``, ``edge_dofs``), each cell's dof ids, and named ``dof_sets``.
See docs/iga.md.
"""
import json

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

    def common_exponents(self):
        """(10, 3) the Bernstein exponents of the cells' point order, the same for every cell (as
        the spline filter writes them), so that one basis evaluation serves all cells;
        ValueError naming the first cell in another order."""
        exps = self.exponents()
        odd = np.nonzero(np.any(exps != exps[:1], axis=(1, 2)))[0]
        if len(odd):
            raise ValueError(f"cell {odd[0]} does not have the VTK Bézier point order of cell 0")
        return exps[0]


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


JSON_FORMAT = "ctsplines-bezier-extraction"


def export_json(grid, path, layout="ctsplines", dof_sets=None):
    """Writes the extraction of a spline grid as JSON (layouts: this module's docstring).
    dof_sets: optional {name: dof ids} (boundary sets, say), stored with either layout."""
    ex = Extraction(grid)
    head = _json_head(layout, ex.exponents()[0] if len(ex.cell_points) else [], ex.uv, ex.points,
                      dof_sets, ex.n_dofs)
    if layout == "coreform":
        body = _coreform_body(ex)
    elif layout == "ctsplines":
        body = _ctsplines_body(ex.cell_points, ex.global_matrix(), ex.dofs,
                               [dofs for dofs, _ in ex.element_matrices()])
        body["dofs"].update({"num_vertices": int((ex.n_dofs - np.count_nonzero(ex.edge_dofs[:, 2] >= 0)) // 3),
                             "edge_dofs": ex.edge_dofs.tolist()})
    else:
        raise ValueError(f"unknown layout {layout!r}: 'coreform' or 'ctsplines'")
    with open(path, "w") as f:
        json.dump({**head, **body}, f)


def export_json_patches(path, extractions, T, masters, dof_sets=None):
    """Writes patches (the faces of a CAD model) joined by one global numbering, stacked dofs =
    T @ global dofs (shell.FacePatches.T; the patches' dofs stacked in order), in the "ctsplines"
    layout: the patches' Bézier points and cells concatenated, the global extraction matrix
    blockdiag(M_patch) T, each cell's global dof ids (the columns its points use), and the global
    dofs' coordinates (the geometry's dofs at `masters`, (patch, dof) of each global dof). Extra
    field ``patches``: ``point_patch``, ``cell_patch``, ``masters``. read_json reads it."""
    import scipy.sparse as sp

    exps = [ex.common_exponents() for ex in extractions]
    if any(not np.array_equal(e, exps[0]) for e in exps):
        raise ValueError("the patches' cells have different Bézier point orders")
    starts = np.cumsum([0] + [len(ex.uv) for ex in extractions])
    cells = np.concatenate([ex.cell_points + s for ex, s in zip(extractions, starts)])
    M = (sp.block_diag([ex.global_matrix() for ex in extractions], format="csr") @ T).tocsr()
    M.eliminate_zeros()
    cell_dofs = [np.unique(M[c].indices) for c in cells]
    masters = np.asarray(masters, dtype=np.int64).reshape(-1, 2)
    coords = np.array([extractions[f].dofs[j] for f, j in masters]).reshape(-1, 3)
    head = _json_head("ctsplines", exps[0], np.concatenate([ex.uv for ex in extractions]),
                      np.concatenate([ex.points for ex in extractions]), dof_sets, T.shape[1])
    body = _ctsplines_body(cells, M, coords, cell_dofs)
    body["patches"] = {"point_patch": np.repeat(np.arange(len(extractions)), np.diff(starts)).tolist(),
                       "cell_patch": np.repeat(np.arange(len(extractions)),
                                               [len(ex.cell_points) for ex in extractions]).tolist(),
                       "masters": masters.tolist()}
    with open(path, "w") as f:
        json.dump({**head, **body}, f)


def _json_head(layout, exponents, uv, points, dof_sets, n_dofs):
    sets = {str(k): [int(i) for i in v] for k, v in (dof_sets or {}).items()}
    for name, ids in sets.items():
        if ids and (min(ids) < 0 or max(ids) >= n_dofs):
            raise ValueError(f"dof set {name!r} has ids outside 0..{n_dofs - 1}")
    return {"format": JSON_FORMAT, "layout": layout, "version": 1, "degree": 3,
            "bernstein_exponents": np.asarray(exponents).tolist(),
            "bezier_points": {"uv": uv.tolist(), "coordinates": points.tolist()}, "dof_sets": sets}


def _ctsplines_body(cells, M, coordinates, cell_dofs):
    return {"bezier_mesh": {"cells": cells.tolist()},
            "extraction": {"shape": list(M.shape), "indptr": M.indptr.tolist(),
                           "indices": M.indices.tolist(), "data": M.data.tolist()},
            "dofs": {"num_dofs": int(M.shape[1]), "coordinates": coordinates.tolist()},
            "cell_dofs": [np.asarray(d).tolist() for d in cell_dofs]}


def _coreform_body(ex):
    """The field names of the JSON that Coreform Cubit exports (``nodes`` x y z w,
    ``elements.element_blocks`` one entry per element with ``us_cid``, ``node_ids``,
    ``coeff_vector_ids``, ``coefficients.dense_coefficient_vectors[i].components``)."""
    elements, vectors = [], []
    for c, (dofs, op) in enumerate(ex.element_matrices()):
        elements.append({"us_cid": c, "node_ids": dofs.tolist(),
                         "coeff_vector_ids": list(range(len(vectors), len(vectors) + len(dofs))),
                         "bezier_point_ids": ex.cell_points[c].tolist()})
        vectors.extend({"components": row} for row in op.T.tolist())
    corners = np.unique(ex.cell_points[:, :3])
    return {"is_rational": False, "num_nodes": ex.n_dofs, "num_vertices": len(corners),
            "num_elems": len(elements), "dim": 2, "num_coeff_vecs": len(vectors), "patch_id": 0,
            "nodes": np.column_stack([ex.dofs, np.ones(ex.n_dofs)]).tolist(),
            "vertex_connectivity": ex.cell_points[:, :3].tolist(),
            "block_elem_map": [{"block_name": "spline", "block_id": 1, "elem_ids": list(range(len(elements)))}],
            "elements": {"element_block_info": [{"element_type": "BERNSTEIN_TRIANGLE", "deg_s": 3, "deg_t": 3,
                                                 "num_elems": len(elements)}],
                         "element_blocks": elements},
            "coefficients": {"num_dense_coeff_blocks": 1, "dense_coefficient_vectors": vectors,
                             "dense_vector_info": [], "num_sparse_coeff_blocks": 0,
                             "sparse_coefficient_vectors": [], "sparse_vector_info": []}}


def read_json(path):
    """Reads :func:`export_json`'s files (either layout): dict with degree, n_dofs, uv, points,
    dofs (the geometry's dof coordinates), dof_sets, and elements as a list of (point ids,
    dof ids, operator 10 x k). ValueError naming the problem for malformed files."""
    with open(path) as f:
        try:
            d = json.load(f)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}: not JSON ({e})") from None
    if not isinstance(d, dict) or d.get("format") != JSON_FORMAT or d.get("version") != 1:
        raise ValueError(f"{path}: not a {JSON_FORMAT} file of version 1")
    try:
        uv = np.asarray(d["bezier_points"]["uv"], dtype=float).reshape(-1, 2)
        points = np.asarray(d["bezier_points"]["coordinates"], dtype=float).reshape(-1, 3)
        if d["layout"] == "coreform":
            n_dofs, coords, elements = _read_coreform(d)
        elif d["layout"] == "ctsplines":
            n_dofs, coords, elements = _read_ctsplines(d, len(points))
        else:
            raise ValueError(f"unknown layout {d['layout']!r}")
    except (KeyError, TypeError, IndexError) as e:
        raise ValueError(f"{path}: malformed ({type(e).__name__}: {e})") from None
    for c, (ids, dofs, op) in enumerate(elements):
        if len(ids) != 10 or ids.min() < 0 or ids.max() >= len(points):
            raise ValueError(f"{path}: element {c} has point ids outside 0..{len(points) - 1} or not 10")
        if len(dofs) and (dofs.min() < 0 or dofs.max() >= n_dofs):
            raise ValueError(f"{path}: element {c} has dof ids outside 0..{n_dofs - 1}")
    return {"degree": int(d["degree"]), "n_dofs": n_dofs, "uv": uv, "points": points, "dofs": coords,
            "dof_sets": {k: np.asarray(v, dtype=np.int64) for k, v in d.get("dof_sets", {}).items()},
            "elements": elements}


def _read_coreform(d):
    n_dofs = int(d["num_nodes"])
    nodes = np.asarray(d["nodes"], dtype=float).reshape(n_dofs, 4)
    if d["is_rational"] or not np.all(nodes[:, 3] == 1.0):
        raise ValueError("rational extraction (weights other than 1) is not a CT spline")
    for info in d["elements"]["element_block_info"]:
        if info["element_type"] != "BERNSTEIN_TRIANGLE" or int(info["deg_s"]) != 3:
            raise ValueError(f"unsupported element block {info['element_type']} of degree {info['deg_s']}")
    vectors = d["coefficients"]["dense_coefficient_vectors"]
    elements = []
    for e in d["elements"]["element_blocks"]:
        dofs = np.asarray(e["node_ids"], dtype=np.int64)
        op = np.array([vectors[i]["components"] for i in e["coeff_vector_ids"]], dtype=float)
        elements.append((np.asarray(e["bezier_point_ids"], dtype=np.int64), dofs, op.reshape(len(dofs), 10).T.copy()))
    return n_dofs, nodes[:, :3], elements


def _read_ctsplines(d, n_points):
    import scipy.sparse as sp

    x = d["extraction"]
    M = sp.csr_matrix((x["data"], x["indices"], x["indptr"]), shape=tuple(x["shape"]))
    n_dofs = int(d["dofs"]["num_dofs"])
    if M.shape != (n_points, n_dofs):
        raise ValueError(f"extraction matrix of shape {M.shape}, expected ({n_points}, {n_dofs})")
    coords = np.asarray(d["dofs"]["coordinates"], dtype=float).reshape(n_dofs, 3)
    cells = d["bezier_mesh"]["cells"]
    if len(cells) != len(d["cell_dofs"]):
        raise ValueError(f"{len(cells)} cells but {len(d['cell_dofs'])} cell dof lists")
    elements = []
    for c, (ids, dofs) in enumerate(zip(cells, d["cell_dofs"])):
        ids, dofs = np.asarray(ids, dtype=np.int64), np.asarray(dofs, dtype=np.int64)
        elements.append((ids, dofs, M[ids][:, dofs].toarray()))
    return n_dofs, coords, elements
