// SPDX-License-Identifier: GPL-3.0-or-later
#include "DerivativeEstimation.h"

#include "CrossDerivativeRules.h"
#include "CubicMacroElement.h"
#include "SplineDataValidation.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace ctk
{
const char* ToString(DerivativeEstimation method)
{
  switch (method)
  {
    case DerivativeEstimation::None:
      return "None";
    case DerivativeEstimation::LocalQuadratic:
      return "LocalQuadratic";
    case DerivativeEstimation::MinimumEnergy:
      return "MinimumEnergy";
  }
  return "?";
}

namespace
{
BuildStatus Failure(std::string message)
{
  return BuildStatus{ false, std::move(message) };
}

BuildStatus VertexFailure(Id v, const std::string& what)
{
  MessageBuilder os;
  os << "cannot estimate the derivatives at vertex " << VertexId{ v } << ": " << what;
  return os.Failure<BuildStatus>();
}

/// The neighbours of every vertex (sorted), from the unique edges: CSR.
struct VertexNeighbours
{
  std::vector<Id> Offsets, Ids;
  const Id* Begin(Id v) const { return this->Ids.data() + this->Offsets[v]; }
  const Id* End(Id v) const { return this->Ids.data() + this->Offsets[v + 1]; }
  Id Count(Id v) const { return this->Offsets[v + 1] - this->Offsets[v]; }
};

VertexNeighbours BuildVertexNeighbours(Id nV, const MeshTopology& topology)
{
  VertexNeighbours n;
  n.Offsets.assign(nV + 1, 0);
  for (const auto& e : topology.Edges)
  {
    ++n.Offsets[e[0] + 1];
    ++n.Offsets[e[1] + 1];
  }
  for (Id v = 0; v < nV; ++v)
  {
    n.Offsets[v + 1] += n.Offsets[v];
  }
  n.Ids.resize(n.Offsets[nV]);
  std::vector<Id> fill(n.Offsets.begin(), n.Offsets.end() - 1);
  for (const auto& e : topology.Edges)
  {
    n.Ids[fill[e[0]]++] = e[1];
    n.Ids[fill[e[1]]++] = e[0];
  }
  for (Id v = 0; v < nV; ++v)
  {
    std::sort(n.Ids.begin() + n.Offsets[v], n.Ids.begin() + n.Offsets[v + 1]);
  }
  return n;
}

/// Usable UV and F: the check both methods need first.
BuildStatus CheckEstimationInput(const SplineData& data)
{
  if (!data.UV || !data.F || (data.NumberOfTriangles > 0 && !data.Triangles))
  {
    return Failure("cannot estimate derivatives: missing parameter values, positions or triangles");
  }
  for (Id v = 0; v < data.NumberOfVertices; ++v)
  {
    const double* uv = data.UV + 2 * v;
    const double* f = data.F + 3 * v;
    if (!IsUsableValue(uv[0]) || !IsUsableValue(uv[1]) || !IsUsableValue(f[0]) ||
      !IsUsableValue(f[1]) || !IsUsableValue(f[2]))
    {
      return VertexFailure(v, "its parameter values or position are not finite (or beyond 1e100)");
    }
  }
  return {};
}

// ---- LocalQuadratic ----------------------------------------------------------------------

/// The rings around one vertex, grown breadth-first on demand. One per chunk of vertices: its
/// buffers are reused, so that no vertex allocates once they have grown.
class RingNeighbourhood
{
public:
  explicit RingNeighbourhood(const VertexNeighbours& n)
    : Neighbours(n)
  {
  }
  void Start(Id vertex)
  {
    this->Centre = vertex;
    this->Ids.clear();
    this->Sorted.assign(1, vertex);
    this->RingEnd[0] = 0;
    this->Rings = 0;
  }
  /// Grows to r rings (fewer when the component is exhausted); returns the neighbour count.
  Id GrowTo(int r)
  {
    while (this->Rings < r)
    {
      this->Next.clear();
      const Id* frontier = this->Rings == 0 ? &this->Centre : this->Ids.data() + this->RingEnd[this->Rings - 1];
      const Id frontierCount =
        this->Rings == 0 ? 1 : this->RingEnd[this->Rings] - this->RingEnd[this->Rings - 1];
      for (Id k = 0; k < frontierCount; ++k)
      {
        const Id v = frontier[k];
        for (const Id* w = this->Neighbours.Begin(v); w != this->Neighbours.End(v); ++w)
        {
          if (!std::binary_search(this->Sorted.begin(), this->Sorted.end(), *w))
          {
            this->Next.push_back(*w);
          }
        }
      }
      std::sort(this->Next.begin(), this->Next.end());
      this->Next.erase(std::unique(this->Next.begin(), this->Next.end()), this->Next.end());
      this->Ids.insert(this->Ids.end(), this->Next.begin(), this->Next.end());
      const auto middle = static_cast<std::ptrdiff_t>(this->Sorted.size());
      this->Sorted.insert(this->Sorted.end(), this->Next.begin(), this->Next.end());
      std::inplace_merge(this->Sorted.begin(), this->Sorted.begin() + middle, this->Sorted.end());
      ++this->Rings;
      this->RingEnd[this->Rings] = static_cast<Id>(this->Ids.size());
    }
    return this->RingEnd[r];
  }
  const Id* Data() const { return this->Ids.data(); }

private:
  const VertexNeighbours& Neighbours;
  Id Centre = -1;
  std::vector<Id> Ids, Sorted, Next;
  Id RingEnd[MaxEstimationRings + 1] = {};
  int Rings = 0;
};

/// Largest condition number of a fit's (whitened) design matrix: beyond it the rings grow.
constexpr double MaxFitCondition = 1e6;
/// Largest condition number of the neighbours' second moment (whitening amplifies round-off by
/// its square root).
constexpr double MaxMomentCondition = 1e12;

using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 5, 5>;
using SmallRhs = Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 5, 3>;

/// Householder QR in place of the m x (cols + 3) column-major work matrix [A | B]; returns
/// R (cols x cols) and the first cols rows of Q^T B, or false when A is rank deficient.
bool HouseholderInPlace(Eigen::Map<Eigen::MatrixXd>& W, int cols, SmallMatrix& R, SmallRhs& QtB)
{
  const Id m = W.rows();
  R.setZero(cols, cols);
  for (int k = 0; k < cols; ++k)
  {
    auto v = W.col(k).tail(m - k);
    const double norm = v.norm();
    if (!(norm > 0.0))
    {
      return false;
    }
    const double alpha = v[0] > 0.0 ? -norm : norm;
    v[0] -= alpha;
    const double vv = v.squaredNorm();
    for (Id j = k + 1; j < W.cols(); ++j)
    {
      auto w = W.col(j).tail(m - k);
      w -= (2.0 * v.dot(w) / vv) * v;
    }
    R(k, k) = alpha;
    for (int j = k + 1; j < cols; ++j)
    {
      R(k, j) = W(k, j);
    }
  }
  QtB = W.block(0, cols, cols, 3);
  return true;
}

/// Least-squares fit of f_j - f_i over the neighbours nb (m of them), linear or quadratic, in
/// the neighbours' whitened frame: d' = L^-1 d / h with L L^T the second moment of d / h (h the
/// largest offset coordinate), so that the fit
/// and its condition number do not change under affine reparameterisation. The quadratic
/// columns x'^2, sqrt(2) x'y', y'^2 make the singular values rotation-invariant too. Writes the
/// gradient (row 0: d/du, row 1: d/dv; one column per coordinate of F).
bool FitGradient(const SplineData& data, Id i, const Id* nb, Id m, bool quadratic,
  std::vector<double>& work, Eigen::Matrix<double, 2, 3>& gradient)
{
  const int cols = quadratic ? 5 : 2;
  if (m < cols)
  {
    return false;
  }
  const Vec2 Ui(data.UV[2 * i], data.UV[2 * i + 1]);
  const Vec3 Fi(data.F[3 * i], data.F[3 * i + 1], data.F[3 * i + 2]);
  // Offsets relative to the largest one first: the second moment of (u, v) offsets of 1e-100
  // would underflow.
  double h = 0.0;
  for (Id r = 0; r < m; ++r)
  {
    h = std::max(h, (Vec2(data.UV[2 * nb[r]], data.UV[2 * nb[r] + 1]) - Ui).cwiseAbs().maxCoeff());
  }
  if (!(h > 0.0))
  {
    return false;
  }
  Eigen::Matrix2d moment = Eigen::Matrix2d::Zero();
  for (Id r = 0; r < m; ++r)
  {
    const Vec2 d = (Vec2(data.UV[2 * nb[r]], data.UV[2 * nb[r] + 1]) - Ui) / h;
    moment += d * d.transpose();
  }
  moment /= static_cast<double>(m);
  const double trace = moment.trace(), det = moment.determinant();
  if (!(det > trace * trace / MaxMomentCondition))
  {
    return false;
  }
  const Eigen::Matrix2d L = moment.llt().matrixL();
  const Eigen::Matrix2d Linv = L.inverse();
  work.resize(static_cast<size_t>(m) * (cols + 3));
  Eigen::Map<Eigen::MatrixXd> W(work.data(), m, cols + 3);
  for (Id r = 0; r < m; ++r)
  {
    const Id j = nb[r];
    const Vec2 d = Linv * ((Vec2(data.UV[2 * j], data.UV[2 * j + 1]) - Ui) / h);
    W(r, 0) = d.x();
    W(r, 1) = d.y();
    if (quadratic)
    {
      W(r, 2) = d.x() * d.x();
      W(r, 3) = std::sqrt(2.0) * d.x() * d.y();
      W(r, 4) = d.y() * d.y();
    }
    for (int c = 0; c < 3; ++c)
    {
      W(r, cols + c) = data.F[3 * j + c] - Fi[c];
    }
  }
  SmallMatrix R;
  SmallRhs QtB;
  if (!HouseholderInPlace(W, cols, R, QtB))
  {
    return false;
  }
  // cond(A) = cond(R); the eigenvalues of R^T R are its squared singular values.
  const Eigen::SelfAdjointEigenSolver<SmallMatrix> eig(R.transpose() * R, Eigen::EigenvaluesOnly);
  const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(cols - 1);
  if (!(lo > hi / (MaxFitCondition * MaxFitCondition)))
  {
    return false;
  }
  const SmallRhs X = R.triangularView<Eigen::Upper>().solve(QtB);
  // f - f_i ~ X_lin^T d' = X_lin^T L^-1 d / h: the gradient is L^-T X_lin / h.
  gradient = Linv.transpose() * X.topRows(2) / h;
  return true;
}

/// Quadratic fits over two, three, .. rings, then linear fits over one, two, .. rings: the first
/// well-conditioned one.
bool EstimateAtVertex(const SplineData& data, Id i, RingNeighbourhood& rings,
  std::vector<double>& work, Eigen::Matrix<double, 2, 3>& gradient)
{
  rings.Start(i);
  for (const bool quadratic : { true, false })
  {
    Id previous = -1;
    for (int r = quadratic ? 2 : 1; r <= MaxEstimationRings; ++r)
    {
      const Id m = rings.GrowTo(r);
      if (m == previous)
      {
        break; // the component is exhausted: more rings add nothing
      }
      previous = m;
      if (FitGradient(data, i, rings.Data(), m, quadratic, work, gradient))
      {
        return true;
      }
    }
  }
  return false;
}

BuildStatus EstimateLocalQuadratic(const SplineData& data, const VertexNeighbours& neighbours,
  double* fu, double* fv, const ParallelFor& parallelFor)
{
  LowestId failed;
  parallelFor(data.NumberOfVertices, [&](Id begin, Id end) {
    RingNeighbourhood rings(neighbours);
    std::vector<double> work;
    Eigen::Matrix<double, 2, 3> g;
    for (Id i = begin; i < end; ++i)
    {
      if (neighbours.Count(i) == 0)
      {
        g.setZero(); // in no triangle: read by no construction
      }
      else if (!EstimateAtVertex(data, i, rings, work, g))
      {
        failed.Report(i);
        continue;
      }
      for (int c = 0; c < 3; ++c)
      {
        fu[3 * i + c] = g(0, c);
        fv[3 * i + c] = g(1, c);
      }
    }
  });
  if (failed.Get() >= 0)
  {
    std::ostringstream os;
    os << "its neighbours (up to " << MaxEstimationRings
       << " rings) do not span the parameter plane (collinear (u, v))";
    return VertexFailure(failed.Get(), os.str());
  }
  return {};
}

// ---- MinimumEnergy -----------------------------------------------------------------------

/// Local numbering of one CTo macro-element's 19 control points.
MacroElementIds LocalMacroElementIds()
{
  MacroElementIds ids;
  for (int i = 0; i < 3; ++i)
  {
    ids.V[i] = i;
    ids.T[i][i] = -1;
    ids.I1[i] = 9 + i;
    ids.I2[i] = 12 + i;
    ids.C[i] = 15 + i;
  }
  for (int l = 0; l < 3; ++l)
  {
    ids.T[l][(l + 1) % 3] = 3 + 2 * l;
    ids.T[(l + 1) % 3][l] = 4 + 2 * l;
  }
  ids.S = 18;
  return ids;
}

/// Gradient-gradient block (6 x 6, unknowns f_u,i f_v,i of vertex i at 2 i, 2 i + 1) and
/// gradient-value block (6 x 3) of a macro-element's energy.
struct EnergyBlocks
{
  Eigen::Matrix<double, 6, 6> GG;
  Eigen::Matrix<double, 6, 3> GV;
};

EnergyBlocks SplitEnergy(const Eigen::Matrix<double, 9, 9>& K)
{
  EnergyBlocks b;
  for (int i = 0; i < 3; ++i)
  {
    for (int a = 0; a < 2; ++a)
    {
      for (int j = 0; j < 3; ++j)
      {
        b.GV(2 * i + a, j) = K(3 * i + 1 + a, 3 * j);
        for (int c = 0; c < 2; ++c)
        {
          b.GG(2 * i + a, 2 * j + c) = K(3 * i + 1 + a, 3 * j + 1 + c);
        }
      }
    }
  }
  return b;
}

/// Sparse pattern of the gradient system: 2 x 2 blocks for each vertex and its neighbours, in
/// the sorted order of {v} and its neighbours (symmetric, so CSR and CSC at once).
struct GradientSystem
{
  std::vector<Id> Outer, Inner;
  std::vector<double> Values;
  Eigen::Matrix<double, Eigen::Dynamic, 3> Rhs;

  GradientSystem(const VertexNeighbours& n, Id nV)
  {
    this->Outer.assign(2 * nV + 1, 0);
    for (Id v = 0; v < nV; ++v)
    {
      const Id width = 2 * (n.Count(v) + 1);
      this->Outer[2 * v + 1] = this->Outer[2 * v] + width;
      this->Outer[2 * v + 2] = this->Outer[2 * v + 1] + width;
    }
    this->Inner.resize(this->Outer.back());
    for (Id v = 0; v < nV; ++v)
    {
      for (int a = 0; a < 2; ++a)
      {
        Id* out = this->Inner.data() + this->Outer[2 * v + a];
        bool selfDone = false;
        for (const Id* w = n.Begin(v);; ++w)
        {
          const bool last = w == n.End(v);
          if (!selfDone && (last || *w > v))
          {
            *out++ = 2 * v;
            *out++ = 2 * v + 1;
            selfDone = true;
          }
          if (last)
          {
            break;
          }
          *out++ = 2 * *w;
          *out++ = 2 * *w + 1;
        }
      }
    }
    this->Values.assign(this->Inner.size(), 0.0);
    this->Rhs.setZero(2 * nV, 3);
    for (Id v = 0; v < nV; ++v)
    {
      if (n.Count(v) == 0) // in no triangle, read by no construction: zero derivatives
      {
        this->Add(2 * v, 2 * v, 1.0);
        this->Add(2 * v + 1, 2 * v + 1, 1.0);
      }
    }
  }

  /// Adds value at (row, column); the column is in the row's pattern.
  void Add(Id row, Id column, double value)
  {
    const auto begin = this->Inner.begin() + this->Outer[row];
    const auto end = this->Inner.begin() + this->Outer[row + 1];
    this->Values[std::lower_bound(begin, end, column) - this->Inner.begin()] += value;
  }

  /// Adds a triangle's energy: the gradient block to the matrix, -GV (F - F_0) to the
  /// right-hand sides (GV annihilates constants, so F relative to the first vertex).
  void AddTriangle(const Id* p, const EnergyBlocks& b, const double* F)
  {
    Eigen::Matrix3d values;
    for (int j = 0; j < 3; ++j)
    {
      for (int c = 0; c < 3; ++c)
      {
        values(j, c) = F[3 * p[j] + c] - F[3 * p[0] + c];
      }
    }
    const Eigen::Matrix<double, 6, 3> rhs = -b.GV * values;
    for (int r = 0; r < 6; ++r)
    {
      const Id row = 2 * p[r / 2] + r % 2;
      this->Rhs.row(row) += rhs.row(r);
      for (int s = 0; s < 6; ++s)
      {
        this->Add(row, 2 * p[s / 2] + s % 2, b.GG(r, s));
      }
    }
  }
};

/// Element energies in parallel, batch by batch, added to the system in triangle order (so
/// that the sums do not depend on the chunking). Names the lowest degenerate triangle.
BuildStatus AssembleEnergy(const SplineData& data, GradientSystem& system, const ParallelFor& parallelFor)
{
  constexpr Id batch = 8192;
  std::vector<EnergyBlocks> blocks(static_cast<size_t>(std::min(batch, data.NumberOfTriangles)));
  for (Id first = 0; first < data.NumberOfTriangles; first += batch)
  {
    const Id count = std::min(batch, data.NumberOfTriangles - first);
    LowestId degenerate;
    parallelFor(count, [&](Id begin, Id end) {
      for (Id k = begin; k < end; ++k)
      {
        const Id* p = data.Triangles + 3 * (first + k);
        auto uv = [&](int i) { return Vec2(data.UV[2 * p[i]], data.UV[2 * p[i] + 1]); };
        const Eigen::Matrix<double, 9, 9> K = ReducedCloughTocherEnergy(uv(0), uv(1), uv(2));
        if (!K.allFinite())
        {
          degenerate.Report(first + k);
        }
        blocks[k] = SplitEnergy(K);
      }
    });
    if (degenerate.Get() >= 0)
    {
      MessageBuilder os;
      os << "cannot estimate derivatives by minimum energy: parameter triangle "
         << TriangleId{ degenerate.Get() }
         << " is degenerate (zero area), its bending energy is undefined";
      return os.Failure<BuildStatus>();
    }
    for (Id k = 0; k < count; ++k)
    {
      system.AddTriangle(data.Triangles + 3 * (first + k), blocks[k], data.F);
    }
  }
  return {};
}

BuildStatus EstimateMinimumEnergy(const SplineData& data, const VertexNeighbours& neighbours,
  double* fu, double* fv, const ParallelFor& parallelFor)
{
  const Id nV = data.NumberOfVertices;
  GradientSystem system(neighbours, nV);
  const BuildStatus assembled = AssembleEnergy(data, system, parallelFor);
  if (!assembled.Ok)
  {
    return assembled;
  }
  // The gradient block is scale-free (the energy of a gradient is dimensionless), so the
  // pivots of meshes with small and large triangles side by side stay comparable.
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, Id>;
  const Eigen::Map<const Sparse> A(2 * nV, 2 * nV, static_cast<Id>(system.Values.size()),
    system.Outer.data(), system.Inner.data(), system.Values.data());
  Eigen::SimplicialLDLT<Sparse> ldlt(A);
  // An SPD system has positive pivots; the first non-positive (or tiny) one names the vertex.
  const auto& D = ldlt.vectorD();
  const double scale = D.size() ? D.cwiseAbs().maxCoeff() : 0.0;
  for (Id k = 0; ldlt.info() == Eigen::Success && k < D.size(); ++k)
  {
    if (!(D[k] > 1e-14 * scale))
    {
      const Id unknown = ldlt.permutationPinv().indices()[k];
      return VertexFailure(unknown / 2, "the minimum-energy system is singular there");
    }
  }
  if (ldlt.info() != Eigen::Success)
  {
    return Failure("cannot estimate derivatives by minimum energy: the sparse factorisation failed");
  }
  const Eigen::Matrix<double, Eigen::Dynamic, 3> X = ldlt.solve(system.Rhs);
  for (Id v = 0; v < nV; ++v)
  {
    for (int c = 0; c < 3; ++c)
    {
      fu[3 * v + c] = X(2 * v, c);
      fv[3 * v + c] = X(2 * v + 1, c);
    }
  }
  return {};
}
} // namespace

Eigen::Matrix<double, 9, 9> ReducedCloughTocherEnergy(const Vec2& U0, const Vec2& U1, const Vec2& U2)
{
  // In the frame s = (u - Z) / h about the split point Z (the barycentre), h the largest offset:
  // no over- or underflow whatever the size. There the degrees of freedom are (f, h f_u, h f_v)
  // and the energy is h^2 times the one in u (second derivatives scale by 1 / h^2, areas by h^2).
  const Vec2 Z = (U0 + U1 + U2) / 3.0;
  const double h = std::max({ (U0 - Z).cwiseAbs().maxCoeff(), (U1 - Z).cwiseAbs().maxCoeff(),
    (U2 - Z).cwiseAbs().maxCoeff() });
  const Vec2 U[3] = { (U0 - Z) / h, (U1 - Z) / h, (U2 - Z) / h };
  const Vec3 tau = Vec3::Constant(1.0 / 3.0);
  const MacroElementIds ids = LocalMacroElementIds();
  // Rows: sqrt(weight) f_uu, sqrt(2 weight) f_uv, sqrt(weight) f_vv at the three points of the
  // degree-2 rule (barycentric (2/3, 1/6, 1/6) and permutations, weight area / 3) of each
  // micro-triangle; f'' is linear there, so the rule is exact. E = |S d|^2.
  Eigen::Matrix<double, 27, 9> S;
  // The element is linear in its data: probe p sets vertex p's value, f_u, f_v to the three
  // unit coordinates, so coordinate c of every result is the response to degree of freedom 3p+c.
  for (int p = 0; p < 3; ++p)
  {
    Vec3 P[19];
    for (int i = 0; i < 3; ++i)
    {
      const Vec3 f = i == p ? Vec3(Vec3::UnitX()) : Vec3(Vec3::Zero());
      const Vec3 fu = i == p ? Vec3(Vec3::UnitY()) : Vec3(Vec3::Zero());
      const Vec3 fv = i == p ? Vec3(Vec3::UnitZ()) : Vec3(Vec3::Zero());
      P[ids.V[i]] = f;
      for (int j = 0; j < 3; ++j)
      {
        if (j != i)
        {
          P[ids.T[i][j]] = EdgeControlPoint(f, fu, fv, U[i], U[j]);
        }
      }
    }
    ComputeInnerRing1(ids, tau, P);
    for (int l = 0; l < 3; ++l)
    {
      const int i = l, j = (l + 1) % 3;
      const EdgeRows rows{ P[ids.V[i]], P[ids.T[i][j]], P[ids.T[j][i]], P[ids.V[j]], P[ids.I1[i]],
        P[ids.I1[j]] };
      P[ids.C[(l + 2) % 3]] = LinearCrossDerivativeCentre(rows, PerpendicularLambda(U[i], U[j], Vec2::Zero()));
    }
    ComputeInnerRing2AndSplitPoint(ids, tau, P);
    for (int k = 0; k < 3; ++k)
    {
      const std::array<Id, 10> net = MicroTriangleNet(ids, k);
      Vec3 Q[10];
      for (int a = 0; a < 10; ++a)
      {
        Q[a] = P[net[a]];
      }
      const Vec2 &A0 = U[(k + 1) % 3], &A1 = U[(k + 2) % 3];
      const double weight = std::abs(SignedArea2(A0, A1, Vec2::Zero())) / 6.0;
      for (int q = 0; q < 3; ++q)
      {
        Vec3 b = Vec3::Constant(1.0 / 6.0);
        b[q] = 2.0 / 3.0;
        const ParametricJet jet = EvaluateOverDomain(3, Q, nullptr, A0, A1, Vec2::Zero(), b, 2);
        const int row = 9 * k + 3 * q;
        S.block<1, 3>(row, 3 * p) = std::sqrt(weight) * jet.Duu.transpose();
        S.block<1, 3>(row + 1, 3 * p) = std::sqrt(2.0 * weight) * jet.Duv.transpose();
        S.block<1, 3>(row + 2, 3 * p) = std::sqrt(weight) * jet.Dvv.transpose();
      }
    }
  }
  Eigen::Matrix<double, 9, 1> toScaled; // d_s = toScaled .* d
  for (int i = 0; i < 3; ++i)
  {
    toScaled.segment<3>(3 * i) = Vec3(1.0, h, h);
  }
  const Eigen::Matrix<double, 9, 1> D = toScaled / h;
  return D.asDiagonal() * (S.transpose() * S) * D.asDiagonal();
}

BuildStatus EstimateDerivatives(const SplineData& data, const MeshTopology& topology,
  DerivativeEstimation method, double* fu, double* fv, const ParallelFor& parallelFor)
{
  if (method == DerivativeEstimation::None)
  {
    return Failure("cannot estimate derivatives: no estimation method chosen (None)");
  }
  const VertexNeighbours neighbours = BuildVertexNeighbours(data.NumberOfVertices, topology);
  BuildStatus status = CheckEstimationInput(data);
  if (status.Ok)
  {
    status = method == DerivativeEstimation::LocalQuadratic
      ? EstimateLocalQuadratic(data, neighbours, fu, fv, parallelFor)
      : EstimateMinimumEnergy(data, neighbours, fu, fv, parallelFor);
  }
  if (!status.Ok)
  {
    return status;
  }
  for (Id k = 0; k < 3 * data.NumberOfVertices; ++k)
  {
    if (!IsUsableValue(fu[k]) || !IsUsableValue(fv[k]))
    {
      return VertexFailure(k / 3, "the estimate is not finite (or beyond 1e100)");
    }
  }
  return status;
}

} // namespace ctk
