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
        self.grid = grid
        self.ex = iga.Extraction(grid)
        ex = self.ex
        exps = ex.common_exponents()
        self.thickness, self.young, self.poisson = thickness, young, poisson
        lam, w = iga.triangle_quadrature(quadrature)
        B, dB, ddB = iga.bernstein_jets(exps, lam)  # (q,10), (q,10,3), (q,10,3,3)
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
        check_rigid_motions_held(self.rigid_motions(), fixed)
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


def check_rigid_motions_held(motions, fixed):
    """ValueError unless holding the unknowns `fixed` at zero stops each rigid motion (columns of
    motions): otherwise the stiffness on the free unknowns is singular."""
    R = motions[fixed] / np.maximum(np.linalg.norm(motions, axis=0), 1e-300)
    if len(fixed) < 6 or np.linalg.svd(R, compute_uv=False)[-1] < 1e-10:
        raise ValueError("the conditions leave a rigid-body motion free (the stiffness is singular)")


def _vertex_count(ex):
    return (ex.n_dofs - np.count_nonzero(ex.edge_dofs[:, 2] >= 0)) // 3


def tangent_map(exA, a, exB, b):
    """J = dU_A/dU_B at vertex a of patch A and vertex b of patch B at the same point: the least
    squares solution of [x_uB x_vB] = [x_uA x_vA] J from the geometry's derivative dofs (exact
    where the two tangent planes coincide, a G1 join). A field's gradients then map as
    grad_B = J^T grad_A."""
    GA, GB = exA.dofs[[3 * a + 1, 3 * a + 2]].T, exB.dofs[[3 * b + 1, 3 * b + 2]].T
    return np.linalg.lstsq(GA, GB, rcond=None)[0]


def _midpoint_derivatives(ex, edge):
    """At the midpoint of a boundary edge (a1, a2, dof) with GradientPerpendicular: the
    derivatives along the unit chord t and the unit parameter normal n, as (dof ids, coefficients
    for d/dt, coefficients for d/dn): d/dt from the boundary cubic (3/2 (f2 - f1) - 1/4 (m1 + m2))
    / L, m_i the end derivatives along the chord vector, d/dn the edge dof."""
    a1, a2, d = edge
    e = ex.uv[a2] - ex.uv[a1]
    L = np.linalg.norm(e)
    ids = [3 * a2, 3 * a1, 3 * a1 + 1, 3 * a1 + 2, 3 * a2 + 1, 3 * a2 + 2, d]
    along = np.concatenate([[1.5, -1.5], -0.25 * e, -0.25 * e, [0.0]]) / L
    return ids, along, np.eye(7)[-1]


def edge_dof_in_a(exA, edgeA, exB, edgeB):
    """B's dof of a shared boundary edge (its midpoint derivative along B's unit parameter normal,
    boundary mode GradientPerpendicular on both) as a combination of A's dofs: with F_A, F_B the
    two spline geometries' derivatives at the midpoint along (t, n) of each, M solves
    F_B = F_A M (exact where their tangent planes there coincide, a G1 join) and
    d/dn_B = M[0, 1] d/dt_A + M[1, 1] d/dn_A. Returns (A's dof ids, coefficients)."""
    frames = []
    for ex, edge in ((exA, edgeA), (exB, edgeB)):
        ids, along, across = _midpoint_derivatives(ex, edge)
        frames.append(np.column_stack([along @ ex.dofs[ids], across @ ex.dofs[ids]]))
    M = np.linalg.lstsq(frames[0], frames[1], rcond=None)[0]
    ids, along, across = _midpoint_derivatives(exA, edgeA)
    return ids, list(M[0, 1] * along + M[1, 1] * across)


def interface_map(exA, exB, tol=1e-9):
    """Couples patch B to patch A along the edges they share (vertices at the same points):
    returns (slaves, S) with B's interface dofs d_B[slaves] = S @ d_A (S sparse), per component.

    The patches' parameters may differ: at a shared vertex value_B = value_A and
    grad_B = J^T grad_A (:func:`tangent_map`); a shared boundary edge's dof on B is
    :func:`edge_dof_in_a` (the map between the geometries' derivatives at the edge midpoint).
    For an affine parameter transition this makes the coupled space C1 across the interface."""
    nA, nB = _vertex_count(exA), _vertex_count(exB)
    pA, pB = exA.dofs[0 : 3 * nA : 3], exB.dofs[0 : 3 * nB : 3]
    scale = tol * max(1.0, np.abs(pA).max())
    dist = np.linalg.norm(pB[:, None] - pA[None], axis=-1)
    match = {int(b): int(np.argmin(dist[b])) for b in np.nonzero(dist.min(1) <= scale)[0]}
    if not match:
        raise ValueError("the patches share no vertex")
    rows, cols, vals, J = [], [], [], {}
    for b, a in match.items():
        J[b] = tangent_map(exA, a, exB, b)
        rows += [3 * b, 3 * b + 1, 3 * b + 1, 3 * b + 2, 3 * b + 2]
        cols += [3 * a, 3 * a + 1, 3 * a + 2, 3 * a + 1, 3 * a + 2]
        vals += [1.0, J[b][0, 0], J[b][1, 0], J[b][0, 1], J[b][1, 1]]
    edgesA = {frozenset((int(a1), int(a2))): (int(a1), int(a2), int(d)) for a1, a2, d in exA.edge_dofs}
    for b1, b2, dB in exB.edge_dofs:
        if dB < 0 or b1 not in match or b2 not in match:
            continue
        edgeA = edgesA.get(frozenset((match[b1], match[b2])), (0, 0, -1))
        if edgeA[2] < 0:
            raise ValueError(f"edge ({b1}, {b2}) of patch B is on the interface but patch A's has no edge dof")
        c, v = edge_dof_in_a(exA, edgeA, exB, (b1, b2, dB))
        rows += [dB] * len(c)
        cols += c
        vals += v
    S = sp.csr_matrix((vals, (rows, cols)), shape=(exB.n_dofs, exA.n_dofs))
    slaves = np.unique(rows)
    return slaves, S[slaves]


def couple(shellA, shellB, tol=1e-9):
    """T (sparse, unknowns of A then B by reduced unknowns) with full = T @ reduced: every
    unknown of A and the unknowns of B off the interface are kept, B's interface unknowns follow
    A's by :func:`interface_map` (the same map for the three components). Returns (T, slaves)
    with slaves in the full numbering."""
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


class FacePatches:
    """Kirchhoff-Love shells on the faces of a sampled CAD model (vtkCADFaceSampler's blocks:
    faces share their boundary nodes, `GlobalNodeId`), one spline space per face in the face's
    own parameters, joined into one global dof numbering: full = T @ global, the faces' dofs
    stacked (face f's dof j at offsets[f] + j); for the unknowns (three components) T3 = T (x) I3.

    At a model node on several faces the first face (block order) owns it:
      - its value dof is the one global dof of every face there (C0 at the node);
      - a face whose unit normal there is within g1_threshold degrees of an earlier face's (a
        tangent join) has grad = J^T grad_earlier (:func:`tangent_map`): the tangent-plane
        gradient is shared (G1 of the space at the node);
      - at a crease only the derivative along each shared boundary edge is tied: the derivative
        at unit 3D speed (|x_u t_u + x_v t_v| = 1) along the B-rep edge's tangent (the sampler's
        EdgeCurvePoints; the parameter chord on meshes without them) is the same on both faces,
        so the trace along the edge, the Hermite cubic of the end values and derivatives, is one
        curve where the edge is straight in both parameter planes (else up to the chords'
        turning); the cross-edge derivative stays the face's own dof (a hinge).
    A boundary edge shared by two faces: at a tangent join (normals within the threshold at both
    ends) the later face's midpoint normal derivative follows the earlier face's dofs
    (:func:`edge_dof_in_a`, through the geometries' derivatives at the midpoint): C1 across the
    edge for an affine parameter transition, G1 at the vertices and midpoints otherwise (between
    them up to the interpolation of the transition); at a crease it stays free.
    `joins` counts the tied vertices ('tangent', 'crease') and edges ('tangent_edges')."""

    def __init__(self, meshes, construction, thickness, young, poisson, g1_threshold=10.0):
        self.meshes = list(meshes)
        if not self.meshes:
            raise ValueError("FacePatches needs at least one face")
        self.node_ids = []
        for f, mesh in enumerate(self.meshes):
            if mesh.GetPointData().GetArray("GlobalNodeId") is None:
                raise ValueError(f"face {f} has no point array GlobalNodeId (vtkCADFaceSampler's output has)")
            self.node_ids.append(arrays.point_array(mesh, "GlobalNodeId").astype(np.int64))
        self.shells = [Shell(spline(m, construction), thickness, young, poisson) for m in self.meshes]
        self.n_vertices = [m.GetNumberOfPoints() for m in self.meshes]
        self.offsets = np.cumsum([0] + [s.ex.n_dofs for s in self.shells])
        self.g1_threshold = g1_threshold
        numbering = _FaceNumbering(self)
        self.T, self.joins, self.masters = numbering.matrix()
        self.shared_edges = numbering.shared  # {frozenset of node ids: [(face, a, b, edge dof)]}
        self.T3 = sp.kron(self.T, sp.identity(3), format="csr")
        self.n_unknowns = self.T3.shape[1]

    def stiffness(self):
        """The coupled stiffness T3^T K T3 over the global unknowns (3 g + component)."""
        K = sp.block_diag([s.stiffness() for s in self.shells], format="csr")
        return (self.T3.T @ K @ self.T3).tocsr()

    def point_load(self, face, vertex, force):
        """Load vector over the faces' stacked unknowns of a point force at a vertex of a face
        (at a shared node give it on one face only: the value dofs are one)."""
        b = np.zeros(self.T3.shape[0])
        b[3 * self.offsets[face]:3 * self.offsets[face + 1]] = self.shells[face].point_load(vertex, force)
        return b

    def vertex_near(self, point, tol=1e-9):
        """(face, vertex) of the first face with an input vertex at the 3D point (ValueError if none)."""
        point = np.asarray(point, float)
        for f, s in enumerate(self.shells):
            x = s.ex.dofs[0 : 3 * self.n_vertices[f] : 3]
            dist = np.linalg.norm(x - point, axis=1)
            if dist.min() <= tol * max(1.0, np.abs(x).max()):
                return f, int(np.argmin(dist))
        raise ValueError(f"no face has a vertex at {tuple(point)}")

    def plane_dofs(self, axis, value, component, condition, tol=1e-7):
        """Stacked unknowns of :func:`line_dofs` on every face boundary line {uv[k] = c} (of the
        face's parameter rectangle) whose vertices all lie in the plane {x[axis] = value}."""
        out = []
        for f, s in enumerate(self.shells):
            nv = self.n_vertices[f]
            uv, x = s.ex.uv[:nv], s.ex.dofs[0 : 3 * nv : 3]
            scale = tol * max(1.0, np.abs(x).max())
            for k in (0, 1):
                for c in (uv[:, k].min(), uv[:, k].max()):
                    on = np.abs(uv[:, k] - c) <= 1e-9 * max(1.0, np.abs(uv).max())
                    if on.sum() >= 2 and np.all(np.abs(x[on, axis] - value) <= scale):
                        out.append(3 * self.offsets[f] + line_dofs(s.ex, nv, k, c, component, condition))
        if not out:
            raise ValueError(f"no face boundary line lies in the plane x[{axis}] = {value}")
        return np.concatenate(out)

    def held(self, fixed):
        """Global unknowns to hold at zero for the stacked unknowns `fixed`: a condition on an
        unknown that follows others (a slave) holds its one remaining global unknown once the
        others are held; ValueError if it remains a relation among several."""
        T = self.T3[np.unique(np.asarray(fixed, dtype=np.int64))].tolil()
        pending = [[c for c, v in zip(r, d) if abs(v) > 1e-12 * max(map(abs, d))] for r, d in zip(T.rows, T.data)]
        held, changed = set(), True
        while changed:
            changed, rest = False, []
            for cols in pending:
                left = [c for c in cols if c not in held]
                if len(left) == 1:
                    held.add(left[0])
                    changed = True
                elif left:
                    rest.append(left)
            pending = rest
        if pending:
            raise ValueError(f"a condition ties the global unknowns {pending[0]} together: it is a relation, "
                             f"not a set of dofs to hold")
        return np.array(sorted(held), dtype=np.int64)

    def rigid_motions(self):
        """(global unknowns, 6): the faces' rigid motions (Shell.rigid_motions) read at the global
        unknowns' own rows; T3 @ them equals the stacked motions when the coupling admits them."""
        stacked = np.concatenate([s.rigid_motions() for s in self.shells])
        own = (3 * self.masters[:, None] + np.arange(3)).ravel()
        return stacked[own]

    def solve(self, b, fixed):
        """Displacement dofs per face (list of (n_dofs_f, 3)) for the stacked load vector b with
        the stacked unknowns `fixed` held at zero."""
        K, br = self.stiffness(), self.T3.T @ b
        held = self.held(fixed)
        check_rigid_motions_held(self.rigid_motions(), held)
        free = np.setdiff1d(np.arange(self.n_unknowns), held)
        r = np.zeros(self.n_unknowns)
        r[free] = spla.spsolve(K[free][:, free].tocsc(), br[free])
        return self.stacked_dofs(r)


    def export_json(self, path, dof_sets=None):
        """The faces' Bézier extraction in the global numbering as JSON (iga.export_json_patches;
        dof_sets over the global dofs)."""
        face = np.searchsorted(self.offsets, self.masters, side="right") - 1
        iga.export_json_patches(path, [s.ex for s in self.shells], self.T,
                                np.column_stack([face, self.masters - self.offsets[face]]), dof_sets)

    def stacked_dofs(self, global_unknowns):
        """The faces' displacement dofs (list of (n_dofs_f, 3)) of a global unknown vector."""
        x = self.T3 @ global_unknowns
        return [x[3 * a : 3 * b].reshape(-1, 3) for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    def interface_jets(self, dofs, s):
        """Along every boundary edge shared by faces, at the parameters s in [0, 1] from the
        edge's smaller node id: {(edge, sample): [(position, value, surface gradient 3 x 3) per
        face]} of the fields dofs (per face (n_dofs, 3)); surface gradient sum a^alpha (x) u_,alpha
        (row: component of u), from each face's own spline geometry."""
        out = {}
        for f, face in enumerate(self.shells):
            ex, nv, ids = face.ex, self.n_vertices[f], self.node_ids[f]
            exps = ex.exponents()
            for cell, corners in enumerate(ex.cell_points[:, :3]):
                for i, j in ((0, 1), (1, 2), (2, 0)):
                    p, q = corners[i], corners[j]
                    if p >= nv or q >= nv or frozenset((ids[p], ids[q])) not in self.shared_edges:
                        continue
                    if ids[p] > ids[q]:
                        i, j = j, i
                    lam = np.zeros((len(s), 3))
                    lam[:, i], lam[:, j] = 1.0 - s, s
                    B, dB, _ = iga.bernstein_jets(exps[cell], lam)
                    dBx = dB @ iga.barycentric_gradients(ex.uv[corners][None])[0]  # (q, 10, 2)
                    k = int(np.count_nonzero(ex.cell_dofs[cell] >= 0))
                    coef = ex.operators[cell, :, :k] @ dofs[f][ex.cell_dofs[cell, :k]]
                    X = ex.points[ex.cell_points[cell]]
                    a = np.einsum("qia,ik->qak", dBx, X)
                    dual = np.linalg.solve(np.einsum("qak,qbk->qab", a, a), a)  # a^alpha
                    grad = np.einsum("qia,ik,qal->qkl", dBx, coef, dual)
                    edge = frozenset((ids[p], ids[q]))
                    for n in range(len(s)):
                        out.setdefault((edge, n), []).append((B[n] @ X, B[n] @ coef, grad[n]))
        return out

    def interface_jumps(self, dofs, samples=5):
        """The sampled jumps across the shared edges (two faces each): ((largest position gap,
        largest value jump / largest value, largest surface-gradient jump / largest gradient
        there), number of sample points)."""
        jets = self.interface_jets(dofs, np.linspace(0.0, 1.0, samples))
        if not jets or any(len(v) != 2 for v in jets.values()):
            raise ValueError("interface_jumps needs every shared edge on exactly two faces")
        worst = [max(np.abs(v[0][c] - v[1][c]).max() for v in jets.values()) for c in range(3)]
        scale = [max(np.abs(v[0][c]).max() for v in jets.values()) for c in (1, 2)]
        return (worst[0], worst[1] / max(scale[0], 1e-300), worst[2] / max(scale[1], 1e-300)), len(jets)


class _FaceNumbering:
    """Builds FacePatches.T row by row: rows[i] = {global dof: coefficient} for stacked dof i;
    a dof not tied to an earlier face's becomes a new global dof when first used."""

    def __init__(self, model):
        self.m = model
        self.rows = [None] * int(model.offsets[-1])
        self.masters = []  # the stacked dof of each global dof
        self.cos_threshold = np.cos(np.radians(model.g1_threshold))
        self.joins = {"tangent": 0, "crease": 0, "tangent_edges": 0}
        self.shared = self._shared_boundary_edges()

    def full(self, f, j):
        return int(self.m.offsets[f] + j)

    def expr(self, i):
        if self.rows[i] is None:
            self.rows[i] = {len(self.masters): 1.0}
            self.masters.append(i)
        return self.rows[i]

    def combo(self, terms):
        out = {}
        for coef, i in terms:
            for g, v in self.expr(i).items():
                out[g] = out.get(g, 0.0) + coef * v
        return out

    def _shared_boundary_edges(self):
        """{frozenset of two node ids: [(face, a, b, edge dof)]} for edges on two or more faces;
        self.curve_tangents[(face, a, b)]: the 3D tangents at a and b of the B-rep edge's Hermite
        cubic (the sampler's EdgeCurvePoints; absent on meshes without them)."""
        shared, self.curve_tangents = {}, {}
        for f, mesh in enumerate(self.m.meshes):
            tris = arrays.triangles(mesh)
            e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
            edges, count = np.unique(e, axis=0, return_counts=True)
            dofs = {frozenset((int(a), int(b))): (int(a), int(b), int(d))
                    for a, b, d in self.m.shells[f].ex.edge_dofs}
            ids = self.m.node_ids[f]
            for a, b in edges[count == 1]:
                entry = dofs.get(frozenset((int(a), int(b))), (int(a), int(b), -1))
                shared.setdefault(frozenset((int(ids[a]), int(ids[b]))), []).append((f, *entry))
            if mesh.GetCellData().GetArray("EdgeCurvePoints") is not None:
                self._curve_tangents(f, mesh, tris)
        return {k: v for k, v in shared.items() if len(v) > 1}

    def _curve_tangents(self, f, mesh, tris):
        """Local edge k of triangle t runs from tris[t, k] to tris[t, k + 1]; its Hermite cubic's
        inner control points c1 (near the start) and c2: tangents c1 - x_start, x_end - c2 (and
        c2 - x_end, x_start - c1 the other way)."""
        curve = arrays.cell_array(mesh, "EdgeCurvePoints").reshape(-1, 3, 2, 3)
        x = arrays.points(mesh)
        for t, k in zip(*np.nonzero(np.all(np.isfinite(curve), axis=(2, 3)))):
            a, b = int(tris[t, k]), int(tris[t, (k + 1) % 3])
            self.curve_tangents[(f, a, b)] = (curve[t, k, 0] - x[a], x[b] - curve[t, k, 1])
            self.curve_tangents[(f, b, a)] = (curve[t, k, 1] - x[b], x[a] - curve[t, k, 0])

    def unit_normal(self, f, v):
        d = self.m.shells[f].ex.dofs
        n = np.cross(d[3 * v + 1], d[3 * v + 2])
        return n / np.linalg.norm(n)

    def tangent(self, f, v, g, w):
        return self.unit_normal(f, v) @ self.unit_normal(g, w) > self.cos_threshold

    def matrix(self):
        occurrences = {}
        for f, ids in enumerate(self.m.node_ids):
            for v, node in enumerate(ids):
                occurrences.setdefault(int(node), []).append((f, v))
        self.edges_at = {}
        for key in self.shared:
            for node in key:
                self.edges_at.setdefault(node, []).append(key)
        for node, occ in occurrences.items():
            for k in range(1, len(occ)):
                self.join_vertex(node, occ[k], occ[:k])
        for occ in self.shared.values():
            self.join_edge(occ)
        for i in range(len(self.rows)):
            self.expr(i)
        r, c, v = zip(*[(i, g, x) for i, row in enumerate(self.rows) for g, x in row.items()])
        T = sp.csr_matrix((v, (r, c)), shape=(len(self.rows), len(self.masters)))
        return T, self.joins, np.array(self.masters, dtype=np.int64)

    def join_vertex(self, node, fv, earlier):
        f, v = fv
        g0, w0 = earlier[0]
        self.rows[self.full(f, 3 * v)] = dict(self.expr(self.full(g0, 3 * w0)))
        smooth = next(((g, w) for g, w in earlier if self.tangent(f, v, g, w)), None)
        if smooth is not None:
            g, w = smooth
            J = tangent_map(self.m.shells[g].ex, w, self.m.shells[f].ex, v)
            gu, gv = self.full(g, 3 * w + 1), self.full(g, 3 * w + 2)
            for c in range(2):
                self.rows[self.full(f, 3 * v + 1 + c)] = self.combo([(J[0, c], gu), (J[1, c], gv)])
            self.joins["tangent"] += 1
            return
        ties = [t for g, w in earlier for t in self.edge_ties(node, f, v, g, w)]
        self.joins["crease"] += 1
        if len(ties) == 1:
            (a, terms), = ties
            j = int(np.argmax(np.abs(a)))  # solve for this component, the other stays f's own
            own = self.full(f, 3 * v + 2 - j)
            self.rows[self.full(f, 3 * v + 1 + j)] = self.combo([(t / a[j], i) for t, i in terms]
                                                                + [(-a[1 - j] / a[j], own)])
        elif len(ties) > 1:
            pairs = [(abs(np.cross(p[0], q[0])), p, q) for k, p in enumerate(ties) for q in ties[k + 1:]]
            _, p, q = max(pairs, key=lambda t: t[0])
            inv = np.linalg.inv(np.array([p[0], q[0]]))
            for c in range(2):
                self.rows[self.full(f, 3 * v + 1 + c)] = self.combo(
                    [(inv[c, 0] * t, i) for t, i in p[1]] + [(inv[c, 1] * t, i) for t, i in q[1]])

    def edge_ties(self, node, f, v, g, w):
        """The tie of f's derivative along the boundary edges through `node` shared with face g:
        [(direction a in f's parameters, [(coefficient, stacked dof of g)])] with a . grad_f equal
        to the combination (both at unit 3D speed; the chords of one pair averaged)."""
        exf, exg = self.m.shells[f].ex, self.m.shells[g].ex
        a_f, a_g = [], []
        for key in self.edges_at.get(node, []):
            # The edge's entries on f at v and on g at w (a seam puts a node twice in a face).
            mine = [e for e in self.shared[key] if e[0] == f and v in e[1:3]]
            theirs = [e for e in self.shared[key] if e[0] == g and w in e[1:3]]
            if not mine or not theirs:
                continue
            dirs = []
            for ex, vertex, (face, a, b, _) in ((exf, v, mine[0]), (exg, w, theirs[0])):
                other = b if a == vertex else a
                t = ex.uv[other] - ex.uv[vertex]
                dF = ex.dofs[[3 * vertex + 1, 3 * vertex + 2]].T
                curve = self.curve_tangents.get((face, vertex, other))
                if curve is not None:  # the B-rep edge's tangent, not the chord's direction
                    t = np.linalg.lstsq(dF, curve[0], rcond=None)[0]
                dirs.append(t / np.linalg.norm(dF @ t))
            if a_f and dirs[0] @ a_f[0] < 0:  # the chord on the other side of the node
                dirs = [-d for d in dirs]
            a_f.append(dirs[0])
            a_g.append(dirs[1])
        if not a_f:
            return []
        a, b = np.mean(a_f, axis=0), np.mean(a_g, axis=0)
        return [(a, [(b[0], self.full(g, 3 * w + 1)), (b[1], self.full(g, 3 * w + 2))])]

    def join_edge(self, occ):
        g, a1, a2, dA = occ[0]
        exA, ids_g = self.m.shells[g].ex, self.m.node_ids[g]
        local_a = {int(ids_g[a1]): a1, int(ids_g[a2]): a2}
        for f, b1, b2, dB in occ[1:]:
            exB, ids_f = self.m.shells[f].ex, self.m.node_ids[f]
            ends = [(local_a[int(ids_f[b])], b) for b in (b1, b2)]
            if dB < 0 or not all(self.tangent(f, b, g, a) for a, b in ends):
                continue  # no dof, or a crease: f's edge dof stays its own
            if dA < 0:
                raise ValueError(f"the edge ({b1}, {b2}) of face {f} joins face {g} tangentially but "
                                 f"face {g}'s edge has no edge dof (use boundary mode GradientPerpendicular)")
            cols, vals = edge_dof_in_a(exA, (a1, a2, dA), exB, (b1, b2, dB))
            self.rows[self.full(f, dB)] = self.combo([(x, self.full(g, c)) for c, x in zip(cols, vals)])
            self.joins["tangent_edges"] += 1


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
