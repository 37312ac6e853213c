# SPDX-License-Identifier: GPL-3.0-or-later
"""Linear Kirchhoff-Love shells with the C1 Clough-Tocher spline space (isogeometric).

Formulation of Kiendl et al. (2009), linearised: the mid-surface x(u, v) is the spline itself
(its Bézier control points), with covariant base vectors a_a = x_,a, unit normal
a_3 = a_1 x a_2 / |a_1 x a_2|, metric a_ab = a_a . a_b and curvature b_ab = x_,ab . a_3, all exact
per micro-triangle from the control net. The displacement u has three Cartesian components, each
in the spline space through the Bézier extraction (u = sum_j d_j N_j, d_j in R^3). Strains
(Voigt: 11, 22, 2 x 12):

  membrane  e_ab = (a_a . u_,b + a_b . u_,a) / 2
  bending   k_ab = u_,ab . a_3 + (x_,ab - (x_,ab . a_3) a_3) . (u_,1 x a_2 + a_1 x u_,2) / |a_1 x a_2|

(the linearisation of b_ab), with the isotropic constitutive tensor in curvilinear coordinates
C^abcd = E / (2 (1 + nu)) (a^ac a^bd + a^ad a^bc + 2 nu / (1 - nu) a^ab a^cd) and stiffness
K = int (t B_m^T D B_m + t^3 / 12 B_b^T D B_b) dA.

Degrees of freedom: unknown 3 j + c is component c (x, y, z) of the spline's degree of freedom j
(value, d/du, d/dv of vertex v at j = 3 v, 3 v + 1, 3 v + 2; then the edge dofs). With the
boundary mode GradientPerpendicular every boundary edge carries one dof, the derivative along the
parameter-plane unit normal at its midpoint. Conditions on a straight boundary line of the
parameter domain are then exactly dof constraints (:func:`line_dofs`):
  - the trace of a component vanishes along the line (a support):  value and tangential
    derivative of that component at the line's vertices (the boundary cubic is their Hermite
    interpolant);
  - its cross-boundary derivative vanishes (a symmetry plane for the components tangent to it,
    a clamp): normal derivative at the vertices and the edges' midpoint normal derivatives (the
    cross-boundary derivative is the quadratic through these three).
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import arrays, iga

VALUE, D_DU, D_DV = 0, 1, 2


def grid_mesh(nu, nv, u_range, v_range, surface):
    """A structured triangle mesh of the parameter rectangle (alternating diagonals) sampled from
    surface(u, v) -> (x, x_u, x_v) (each (n, 3)), with exact mid-edge gradients, for
    vtkCloughTocherSplineFilter."""
    if nu < 1 or nv < 1:
        raise ValueError(f"grid_mesh needs at least one cell per direction, got {nu} x {nv}")
    us = np.linspace(*u_range, nu + 1)
    vs = np.linspace(*v_range, nv + 1)
    uu, vv = np.meshgrid(us, vs, indexing="ij")
    uv = np.column_stack([uu.ravel(), vv.ravel()])
    idx = np.arange(len(uv)).reshape(nu + 1, nv + 1)
    tris = []
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
            tris += [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
    tris = np.array(tris, dtype=np.int64)
    f, fu, fv = surface(uv[:, 0], uv[:, 1])
    mids = 0.5 * (uv[tris] + uv[np.roll(tris, -1, axis=1)])  # (T, 3, 2): edges (0,1), (1,2), (2,0)
    _, gu, gv = surface(mids[..., 0].ravel(), mids[..., 1].ravel())
    edge_gradients = np.concatenate([gu.reshape(-1, 3, 3), gv.reshape(-1, 3, 3)], -1).reshape(-1, 18)
    return arrays.mesh_from_arrays(uv, tris, f, fu, fv, edge_gradients)


def cylinder(radius):
    """Cylinder about the y axis in arc-length parameters: x = (R sin(u/R), v, R cos(u/R))."""
    def surface(u, v):
        s, c, z = np.sin(u / radius), np.cos(u / radius), np.zeros_like(u)
        return (np.column_stack([radius * s, v, radius * c]), np.column_stack([c, z, -s]),
                np.column_stack([z, z + 1.0, z]))
    return surface


def sphere(radius):
    """Sphere in arc-length parameters of longitude u / R and latitude v / R:
    x = R (cos(v/R) cos(u/R), cos(v/R) sin(u/R), sin(v/R))."""
    def surface(u, v):
        cp, sp_, ct, st = np.cos(u / radius), np.sin(u / radius), np.cos(v / radius), np.sin(v / radius)
        x = radius * np.column_stack([ct * cp, ct * sp_, st])
        return x, np.column_stack([-ct * sp_, ct * cp, 0.0 * ct]), np.column_stack([-st * cp, -st * sp_, ct])
    return surface


def spline(mesh, construction="CTi"):
    """The C1 spline of a parametrised mesh with Bézier extraction (boundary mode
    GradientPerpendicular: every boundary edge carries its midpoint normal derivative)."""
    from . import vtkCloughTocherSplineFilter

    ct = vtkCloughTocherSplineFilter()
    ct.SetInputData(mesh)
    getattr(ct, "SetConstructionTo" + construction)()
    ct.SetBoundaryModeToGradientPerpendicular()
    ct.ComputeBezierExtractionOn()
    ct.Update()
    return ct.GetOutput()


def line_dofs(ex, n_vertices, axis, value, component, condition, tol=1e-9):
    """Constrained unknowns for the boundary line {uv[axis] = value} of the parameter domain.

    condition 'trace': the component vanishes along the line; 'normal': its derivative across
    the line vanishes. Returns unknown indices (3 j + component)."""
    if condition not in ("trace", "normal"):
        raise ValueError(f"condition must be 'trace' or 'normal', got {condition!r}")
    uv = ex.uv[:n_vertices]
    on = np.abs(uv[:, axis] - value) <= tol * max(1.0, np.abs(uv).max())
    if not on.any():
        raise ValueError(f"no vertex on the line uv[{axis}] = {value}")
    v = np.nonzero(on)[0]
    normal = D_DU if axis == 0 else D_DV
    tangential = D_DV if axis == 0 else D_DU
    if condition == "trace":
        dofs = np.concatenate([3 * v + VALUE, 3 * v + tangential])
    else:
        a, b, dof = ex.edge_dofs.T
        edges = dof[on[a] & on[b] & (dof >= 0)]
        dofs = np.concatenate([3 * v + normal, edges])
    return 3 * dofs + component


class Shell:
    """Linear Kirchhoff-Love shell on a spline grid with Bézier extraction."""

    def __init__(self, grid, thickness, young, poisson, quadrature=5):
        if not (thickness > 0 and young > 0 and -1.0 < poisson < 0.5):
            raise ValueError(f"need thickness > 0, Young's modulus > 0 and -1 < Poisson's ratio < 0.5, "
                             f"got {thickness}, {young}, {poisson}")
        self.ex = iga.Extraction(grid)
        ex = self.ex
        exps = ex.exponents()
        odd = np.nonzero(np.any(exps != exps[:1], axis=(1, 2)))[0]
        if len(odd):
            raise ValueError(f"cell {odd[0]} does not have the VTK Bézier point order of cell 0")
        self.thickness, self.young, self.poisson = thickness, young, poisson
        lam, w = iga.triangle_quadrature(quadrature)
        B, dB, ddB = iga.bernstein_jets(exps[0], lam)  # (q,10), (q,10,3), (q,10,3,3)
        corners = ex.uv[ex.cell_points[:, :3]]
        G = iga.barycentric_gradients(corners)  # (C, 3, 2)
        area = iga.triangle_areas(corners)
        dBx = np.einsum("qia,cad->cqid", dB, G)
        ddBx = np.einsum("qiab,cad,cbe->cqide", ddB, G, G)
        X = ex.points[ex.cell_points]  # (C, 10, 3): the geometry's control net
        self.a = np.einsum("cqid,cik->cqdk", dBx, X)  # (C, q, 2, 3) a_1, a_2
        self.aa = np.einsum("cqide,cik->cqdek", ddBx, X)  # (C, q, 2, 2, 3) x_,ab
        n = np.cross(self.a[:, :, 0], self.a[:, :, 1])
        self.jac = np.linalg.norm(n, axis=-1)  # |a_1 x a_2|
        flat = np.nonzero(self.jac.min(axis=1) <= 1e-12 * max(self.jac.max(), 1e-300))[0]
        if len(flat):
            raise ValueError(f"the surface is singular (a_1 x a_2 = 0) in cell {flat[0]}: no normal there")
        self.a3 = n / self.jac[..., None]
        self.weights = w[None, :] * area[:, None] * self.jac  # dA
        Cop = ex.operators
        self.phi = np.einsum("qi,cij->cqj", B, Cop)
        self.dphi = np.einsum("cqid,cij->cqjd", dBx, Cop)
        self.ddphi = np.einsum("cqide,cij->cqjde", ddBx, Cop)
        self.n_unknowns = 3 * ex.n_dofs
        # Cell unknowns 3 j + c (padding -> a dummy unknown past the end).
        dofs = np.where(ex.cell_dofs >= 0, ex.cell_dofs, ex.n_dofs)
        self.cell_unknowns = (3 * dofs[:, :, None] + np.arange(3)).reshape(len(dofs), -1)

    def material(self):
        """(C, q, 3, 3) D in Voigt order 11, 22, 12 from the contravariant metric."""
        g = np.einsum("cqdk,cqek->cqde", self.a, self.a)
        gi = np.linalg.inv(g)
        pairs = [(0, 0), (1, 1), (0, 1)]
        nu = self.poisson
        D = np.empty(g.shape[:2] + (3, 3))
        for I, (a, b) in enumerate(pairs):
            for J, (c, d) in enumerate(pairs):
                D[..., I, J] = (gi[..., a, c] * gi[..., b, d] + gi[..., a, d] * gi[..., b, c]
                                + 2 * nu / (1 - nu) * gi[..., a, b] * gi[..., c, d])
        return D * self.young / (2 * (1 + nu))

    def strain_operators(self, s):
        """Membrane and bending strain operators over the cells s: (c, q, 3, M, 3), the last two
        axes the spline dof and the displacement component."""
        a1, a2 = self.a[s, :, 0], self.a[s, :, 1]  # (c, q, 3)
        dN = self.dphi[s]  # (c, q, M, 2)
        Bm = np.stack([
            dN[..., 0, None] * a1[:, :, None],
            dN[..., 1, None] * a2[:, :, None],
            dN[..., 1, None] * a1[:, :, None] + dN[..., 0, None] * a2[:, :, None],
        ], 2)
        a3 = self.a3[s]
        aa = self.aa[s]
        h = (aa - np.einsum("cqdek,cqk->cqde", aa, a3)[..., None] * a3[:, :, None, None]) \
            / self.jac[s][..., None, None, None]
        # k_ab = N_,ab a3 + N_,1 (a2 x h_ab) + N_,2 (h_ab x a1), per component.
        c2 = np.cross(a2[:, :, None, None], h)  # (c, q, 2, 2, 3)
        c1 = np.cross(h, a1[:, :, None, None])
        ddN = self.ddphi[s]

        def curvature(p, r):
            return (ddN[..., p, r, None] * a3[:, :, None] + dN[..., 0, None] * c2[:, :, None, p, r]
                    + dN[..., 1, None] * c1[:, :, None, p, r])

        Bb = np.stack([curvature(0, 0), curvature(1, 1), 2.0 * curvature(0, 1)], 2)
        return Bm, Bb

    def stiffness(self, chunk=400):
        """The global stiffness matrix (scipy.sparse CSR, unknowns 3 j + c)."""
        D = self.material()
        t = self.thickness
        n = self.n_unknowns + 3
        rows, cols, vals = [], [], []
        for start in range(0, len(self.phi), chunk):
            s = slice(start, start + chunk)
            Bm, Bb = self.strain_operators(s)
            c, q = Bm.shape[:2]
            Bm, Bb = Bm.reshape(c, q, 3, -1), Bb.reshape(c, q, 3, -1)
            wD = self.weights[s][..., None, None] * D[s]
            Ke = t * np.einsum("cqia,cqij,cqjb->cab", Bm, wD, Bm, optimize=True)
            Ke += t**3 / 12.0 * np.einsum("cqia,cqij,cqjb->cab", Bb, wD, Bb, optimize=True)
            u = self.cell_unknowns[s]
            m = u.shape[1]
            rows.append(np.repeat(u, m, axis=1).ravel())
            cols.append(np.tile(u, (1, m)).ravel())
            vals.append(Ke.ravel())
        K = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
        return K.tocsr()[: self.n_unknowns, : self.n_unknowns]

    def surface_load(self, force):
        """Load vector of a constant force per unit area (3-vector)."""
        f = np.einsum("cq,cqj->cj", self.weights, self.phi)[:, :, None] * np.asarray(force, float)
        b = np.bincount(self.cell_unknowns.ravel(), weights=f.ravel(), minlength=self.n_unknowns + 3)
        return b[: self.n_unknowns]

    def point_load(self, vertex, force):
        """Load vector of a point force at an input vertex (the spline interpolates there, so
        only the vertex's value dof sees it)."""
        b = np.zeros(self.n_unknowns)
        b[3 * (3 * vertex + VALUE) + np.arange(3)] = force
        return b

    def solve(self, K, b, fixed):
        """Displacement dofs (n_dofs, 3) with the unknowns `fixed` held at zero."""
        fixed = np.unique(np.asarray(fixed, dtype=np.int64))
        free = np.setdiff1d(np.arange(self.n_unknowns), fixed)
        x = np.zeros(self.n_unknowns)
        R = self.rigid_motions()[fixed]
        R /= np.maximum(np.linalg.norm(self.rigid_motions(), axis=0), 1e-300)
        if len(fixed) < 6 or np.linalg.svd(R, compute_uv=False)[-1] < 1e-10:
            raise ValueError("the conditions leave a rigid-body motion free (the stiffness is singular)")
        x[free] = spla.spsolve(K[free][:, free].tocsc(), b[free])
        return x.reshape(-1, 3)

    def rigid_motions(self):
        """(unknowns, 6): the translations along x, y, z and the infinitesimal rotations about
        them (u = w x x), exactly in the space: the rotations' dofs are w x the geometry's."""
        ex = self.ex
        n_vertices = (ex.n_dofs - np.count_nonzero(ex.edge_dofs[:, 2] >= 0)) // 3
        value = np.zeros(ex.n_dofs)
        value[0 : 3 * n_vertices : 3] = 1.0
        motions = [np.outer(value, e) for e in np.eye(3)] + [np.cross(w, ex.dofs) for w in np.eye(3)]
        return np.stack([m.ravel() for m in motions], -1)

    def vertex_displacement(self, d, vertex):
        """The displacement at an input vertex (its value dof)."""
        return d[3 * vertex + VALUE]

    def control_point_displacement(self, d):
        """(P, 3) the displacement's Bézier ordinates at the grid's control points."""
        return self.ex.global_matrix() @ d


def _vertex_count(ex):
    return (ex.n_dofs - np.count_nonzero(ex.edge_dofs[:, 2] >= 0)) // 3


def interface_map(exA, exB, tol=1e-9):
    """Couples patch B to patch A along the edges they share (vertices at the same points):
    returns (slaves, S) with B's interface dofs d_B[slaves] = S @ d_A (S sparse), per component.

    The patches' parameters may differ: at a shared vertex J = dU_A/dU_B solves
    [x_uB x_vB] = [x_uA x_vA] J (exact where the tangent planes agree, a G1 join), and
    value_B = value_A, grad_B = J^T grad_A. A shared boundary edge's dof on B (its midpoint
    normal derivative along n_B, boundary mode GradientPerpendicular on both) is
    grad_A . (J n_B) at the midpoint (J the mean of the ends'), with grad_A from A's edge dof
    (along n_A) and the derivative of A's boundary cubic along the edge. For an affine
    parameter transition this makes the coupled space C1 across the interface."""
    import scipy.sparse as sp

    nA, nB = _vertex_count(exA), _vertex_count(exB)
    pA, pB = exA.dofs[0 : 3 * nA : 3], exB.dofs[0 : 3 * nB : 3]
    scale = tol * max(1.0, np.abs(pA).max())
    dist = np.linalg.norm(pB[:, None] - pA[None], axis=-1)
    match = {int(b): int(np.argmin(dist[b])) for b in np.nonzero(dist.min(1) <= scale)[0]}
    if not match:
        raise ValueError("the patches share no vertex")
    rows, cols, vals, J = [], [], [], {}
    for b, a in match.items():
        GA, GB = exA.dofs[[3 * a + 1, 3 * a + 2]].T, exB.dofs[[3 * b + 1, 3 * b + 2]].T
        J[b] = np.linalg.lstsq(GA, GB, rcond=None)[0]
        rows += [3 * b, 3 * b + 1, 3 * b + 1, 3 * b + 2, 3 * b + 2]
        cols += [3 * a, 3 * a + 1, 3 * a + 2, 3 * a + 1, 3 * a + 2]
        vals += [1.0, J[b][0, 0], J[b][1, 0], J[b][0, 1], J[b][1, 1]]
    edgesA = {frozenset((int(a1), int(a2))): (int(a1), int(a2), int(d)) for a1, a2, d in exA.edge_dofs}
    for b1, b2, dB in exB.edge_dofs:
        if dB < 0 or b1 not in match or b2 not in match:
            continue
        a1, a2, dA = edgesA.get(frozenset((match[b1], match[b2])), (0, 0, -1))
        if dA < 0:
            raise ValueError(f"edge ({b1}, {b2}) of patch B is on the interface but patch A's has no edge dof")
        eB = exB.uv[b2] - exB.uv[b1]
        nvec = np.array([-eB[1], eB[0]]) / np.linalg.norm(eB)
        w = 0.5 * (J[b1] + J[b2]) @ nvec  # n_B in A's parameters
        eA = exA.uv[a2] - exA.uv[a1]
        L = np.linalg.norm(eA)
        tA, nA_ = eA / L, np.array([-eA[1], eA[0]]) / L
        wt = (w @ tA) / L  # along the edge: d/ds of A's boundary cubic at s = 1/2, over L
        rows += [dB] * 7
        cols += [dA, 3 * a2, 3 * a1, 3 * a1 + 1, 3 * a1 + 2, 3 * a2 + 1, 3 * a2 + 2]
        vals += [w @ nA_, 1.5 * wt, -1.5 * wt] + list(-0.25 * wt * np.concatenate([eA, eA]))
    S = sp.csr_matrix((vals, (rows, cols)), shape=(exB.n_dofs, exA.n_dofs))
    slaves = np.unique(rows)
    return slaves, S[slaves]


def couple(shellA, shellB, tol=1e-9):
    """T (sparse, unknowns of A then B by reduced unknowns) with full = T @ reduced: every
    unknown of A and the unknowns of B off the interface are kept, B's interface unknowns follow
    A's by :func:`interface_map` (the same map for the three components). Returns (T, slaves)
    with slaves in the full numbering."""
    import scipy.sparse as sp

    slaves, S = interface_map(shellA.ex, shellB.ex, tol)
    nA, nB = shellA.n_unknowns, shellB.n_unknowns
    S3 = sp.kron(S, sp.identity(3)).tocoo()  # unknown 3 j + c
    slave_unknowns = (3 * slaves[:, None] + np.arange(3)).ravel()
    keepB = np.setdiff1d(np.arange(nB), slave_unknowns)
    rows = np.concatenate([np.arange(nA), nA + keepB, nA + slave_unknowns[S3.row]])
    cols = np.concatenate([np.arange(nA), nA + np.arange(len(keepB)), S3.col])
    vals = np.concatenate([np.ones(nA + len(keepB)), S3.data])
    T = sp.csr_matrix((vals, (rows, cols)), shape=(nA + nB, nA + len(keepB)))
    return T, nA + slave_unknowns


def solve_coupled(shellA, shellB, K, b, fixed, tol=1e-9):
    """Solves the two coupled patches: K, b over the unknowns of A then B (block diagonal and
    stacked), fixed in that numbering. A condition on a slave unknown must follow from the
    fixed unknowns of A (e.g. the same support on both sides); otherwise ValueError. Returns the
    displacement dofs of A and of B."""
    T, slaves = couple(shellA, shellB, tol)
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    master_of = np.full(T.shape[0], -1)
    kept = np.setdiff1d(np.arange(T.shape[0]), slaves)
    master_of[kept] = np.arange(len(kept))
    on_master = fixed[master_of[fixed] >= 0]
    fixed_reduced = master_of[on_master]
    for f in fixed[master_of[fixed] < 0]:
        used = T[f].indices[np.abs(T[f].data) > 1e-14]
        if not np.isin(used, fixed_reduced).all():
            raise ValueError(f"the condition on interface unknown {f} does not follow from patch A's")
    Kr, br = (T.T @ K @ T).tocsr(), T.T @ b
    free = np.setdiff1d(np.arange(T.shape[1]), fixed_reduced)
    r = np.zeros(T.shape[1])
    r[free] = spla.spsolve(Kr[free][:, free].tocsc(), br[free])
    x = T @ r
    return x[: shellA.n_unknowns].reshape(-1, 3), x[shellA.n_unknowns:].reshape(-1, 3)


def vertex_at(ex, n_vertices, uv, tol=1e-9):
    """The input vertex at parameter uv (ValueError if none)."""
    dist = np.linalg.norm(ex.uv[:n_vertices] - np.asarray(uv, float), axis=1)
    v = int(np.argmin(dist))
    if dist[v] > tol * max(1.0, np.abs(ex.uv).max()):
        raise ValueError(f"no vertex at parameter {tuple(uv)} (nearest at distance {dist[v]:.3g})")
    return v


def write_displacement(grid, displacement, path):
    """Writes the spline grid with a point array `Displacement` (P, 3) on its Bézier control
    points: the displacement is a spline on the same cells, so Warp By Vector in ParaView moves
    the control net to the exact deformed shell."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    from .io import VTKMessages, write

    out = grid.NewInstance()
    out.ShallowCopy(grid)
    arr = numpy_to_vtk(np.ascontiguousarray(displacement, dtype=np.float64), deep=True)
    arr.SetName("Displacement")
    out.GetPointData().AddArray(arr)
    write(out, path, VTKMessages())
    return path
