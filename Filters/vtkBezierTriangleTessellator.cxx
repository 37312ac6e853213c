// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkBezierTriangleTessellator.h"

#include "BezierTriangle.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesCellPatterns.h"
#include "CTSplinesInput.h"
#include "CTSplinesRecycledArrays.h"
#include "CTSplinesSMP.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

vtkStandardNewMacro(vtkBezierTriangleTessellator);

struct vtkBezierTriangleTessellator::RecycledOutput : ctsplines::RecycledArrays
{
  // The last input's shared corners and edges, kept with the arrays (ReuseOutputArrays).
  std::unique_ptr<ctsplines::SharedCellTopology> Topology;
  std::atomic<vtkTypeUInt64> TopologyBuilds{ 0 }; // concurrent executions build their own
};

vtkBezierTriangleTessellator::vtkBezierTriangleTessellator()
  : Recycled(new RecycledOutput)
{
}
vtkBezierTriangleTessellator::~vtkBezierTriangleTessellator() = default;

vtkTypeUInt64 vtkBezierTriangleTessellator::GetReusedOutputBytes() const
{
  return this->Recycled->GetReusedBytes();
}

vtkTypeUInt64 vtkBezierTriangleTessellator::GetNumberOfTopologyBuilds() const
{
  return this->Recycled->TopologyBuilds;
}

void vtkBezierTriangleTessellator::SetReuseOutputArrays(bool reuse)
{
  if (this->Recycled->SetReuse(this->ReuseOutputArrays, reuse))
  {
    if (!reuse)
    {
      this->Recycled->Topology.reset(); // kept with the arrays
    }
    this->Modified();
  }
}

int vtkBezierTriangleTessellator::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

namespace
{
using Block = ctk::BezierBasisTable::BlockArray;

// Per-thread scratch of the cell loops.
struct CellScratch
{
  std::vector<vtkIdType> Ids;        // output id of each pattern point
  std::vector<unsigned char> Owned;  // whether the cell evaluates it
  ctk::Vec3 P[ctk::MaxBezierPoints]; // the net
  double w[ctk::MaxBezierPoints];    // its weights when rational
  ctk::ScalarNet Net;
  std::vector<double> Ordinates; // of the carried point data (PointDataInterpolator)
};

// Calls f(begin, end) on the runs of consecutive pattern points whose owned flag is `owned`,
// cut into blocks of at most BezierBasisTable::Block points.
template <typename F>
void ForEachRun(const std::vector<unsigned char>& flags, bool owned, F&& f)
{
  const int count = static_cast<int>(flags.size());
  for (int p = 0; p < count;)
  {
    int end = p;
    while (end < count && (flags[end] != 0) == owned && end - p < ctk::BezierBasisTable::Block)
    {
      ++end;
    }
    if (end > p)
    {
      f(p, end);
    }
    p = std::max(end, p + 1);
  }
}

// The output being filled: conforming points (CellPatterns), exact normals, carried point data
// and the triangles of every cell.
struct Tessellation
{
  const ctsplines::BezierCells& Cells;
  const ctsplines::CellPatterns& Patterns;
  ctsplines::PointDataInterpolator& Data;
  vtkDoubleArray* Coordinates;
  vtkDoubleArray* Normals;
  void* Offsets;      // vtkTypeInt32 when Narrow, else vtkIdType
  void* Connectivity; // same
  bool Narrow;
  vtkIdType* Source;

  // Calls f(offsets, connectivity) with the pointers of their storage type.
  template <typename F>
  void WithCellArrays(F&& f) const
  {
    if (this->Narrow)
    {
      f(static_cast<vtkTypeInt32*>(this->Offsets), static_cast<vtkTypeInt32*>(this->Connectivity));
    }
    else
    {
      f(static_cast<vtkIdType*>(this->Offsets), static_cast<vtkIdType*>(this->Connectivity));
    }
  }

  // Loads cell c's output ids, owners and net into s; returns its basis table.
  const ctk::BezierBasisTable& Load(vtkIdType c, CellScratch& s) const;
  // Points owned by cell c (positions, normals, data) and its triangles.
  void Cell(vtkIdType c, CellScratch& s) const;
  // Splits the points where a cell's own normal differs from the owner's by more than the
  // feature angle (the copies keep the coordinates); returns the number of copies.
  vtkIdType SplitSharpPoints(double featureAngle);
};

const ctk::BezierBasisTable& Tessellation::Load(vtkIdType c, CellScratch& s) const
{
  const ctk::BezierBasisTable& basis = this->Patterns.Basis(c);
  s.Ids.resize(basis.NumberOfPoints());
  s.Owned.resize(basis.NumberOfPoints());
  this->Patterns.OutputIds(c, s.Ids.data(), s.Owned.data());
  s.Net.Load(basis.Degree(), s.P, this->Cells.Net(c, s.P, s.w));
  return basis;
}

void Tessellation::Cell(vtkIdType c, CellScratch& s) const
{
  const ctk::BezierBasisTable& basis = this->Load(c, s);
  s.Ordinates.resize(std::max(1, this->Data.NumberOfComponents()) * ctk::MaxBezierPoints);
  this->Data.LoadOrdinates(this->Cells, c, s.Net.Weights, s.Ordinates.data());
  double* xyz = this->Coordinates->GetPointer(0);
  double* nrm = this->Normals->GetPointer(0);
  ForEachRun(s.Owned, true, [&](int begin, int end) {
    Block x[3], normal[3];
    double W[ctk::BezierBasisTable::Block];
    basis.Evaluate(s.Net, begin, end, x, normal, W);
    const vtkIdType* ids = s.Ids.data() + begin;
    for (int q = 0; q < end - begin; ++q)
    {
      for (int k = 0; k < 3; ++k)
      {
        xyz[3 * ids[q] + k] = x[k][q];
        nrm[3 * ids[q] + k] = normal[k][q];
      }
    }
    this->Data.Write(basis, s.Ordinates.data(), begin, end, W, ids);
  });
  this->WithCellArrays([&](auto* offsets, auto* connectivity) {
    this->Patterns.WriteTriangles(c, s.Ids.data(), offsets, connectivity, this->Source);
  });
}

vtkIdType Tessellation::SplitSharpPoints(double featureAngle)
{
  struct Use
  {
    vtkIdType Id, Cell, NewId;
    int Point;
    ctk::Vec3 Normal;
  };
  const double cosine = std::cos(vtkMath::RadiansFromDegrees(featureAngle));
  const vtkIdType nCells = this->Cells.NumberOfCells();
  // Chunks of cells in parallel, each collecting its uses in cell order (deterministic).
  const vtkIdType nChunks = std::min<vtkIdType>(nCells, 256);
  std::vector<std::vector<Use>> chunks(nChunks);
  const double* nrm = this->Normals->GetPointer(0);
  // At least GrainForEvaluations cells per thread.
  const vtkIdType cellsPerChunk = std::max<vtkIdType>(1, nCells / std::max<vtkIdType>(nChunks, 1));
  const vtkIdType minimumChunks = ctsplines::GrainForEvaluations / cellsPerChunk + 1;
  ctsplines::ParallelFor(0, nChunks, minimumChunks, [&](vtkIdType b, vtkIdType e) {
    CellScratch s;
    for (vtkIdType chunk = b; chunk < e; ++chunk)
    {
      for (vtkIdType c = chunk * nCells / nChunks; c < (chunk + 1) * nCells / nChunks; ++c)
      {
        const ctk::BezierBasisTable& basis = this->Load(c, s);
        ForEachRun(s.Owned, false, [&](int begin, int end) {
          Block normal[3];
          basis.Evaluate(s.Net, begin, end, nullptr, normal, nullptr);
          for (int q = 0; q < end - begin; ++q)
          {
            const vtkIdType id = s.Ids[begin + q];
            const ctk::Vec3 n(normal[0][q], normal[1][q], normal[2][q]);
            if (!(n.dot(ctk::Vec3(nrm + 3 * id)) >= cosine))
            {
              chunks[chunk].push_back({ id, c, -1, begin + q, n });
            }
          }
        });
      }
    }
  });
  std::vector<Use> uses;
  for (const std::vector<Use>& chunk : chunks)
  {
    uses.insert(uses.end(), chunk.begin(), chunk.end());
  }
  // Per point, in cell order: a use joins the first copy of the point whose normal is within
  // the angle of its own, or makes a new copy with its normal.
  std::stable_sort(
    uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.Id < b.Id; });
  const vtkIdType first = this->Coordinates->GetNumberOfTuples();
  std::vector<vtkIdType> copiedFrom;
  std::vector<ctk::Vec3> copyNormals;
  for (size_t begin = 0, u = 0; u < uses.size(); begin = u)
  {
    const size_t groupBase = copiedFrom.size();
    for (; u < uses.size() && uses[u].Id == uses[begin].Id; ++u)
    {
      size_t g = groupBase;
      while (g < copiedFrom.size() && !(uses[u].Normal.dot(copyNormals[g]) >= cosine))
      {
        ++g;
      }
      if (g == copiedFrom.size())
      {
        copiedFrom.push_back(uses[u].Id);
        copyNormals.push_back(uses[u].Normal);
      }
      uses[u].NewId = first + static_cast<vtkIdType>(g);
    }
  }
  const vtkIdType copies = static_cast<vtkIdType>(copiedFrom.size());
  for (vtkDoubleArray* a : { this->Coordinates, this->Normals })
  {
    a->Resize(first + copies); // keeps the values (SetNumberOfTuples alone may not)
    a->SetNumberOfTuples(first + copies);
  }
  for (vtkIdType k = 0; k < copies; ++k)
  {
    this->Coordinates->SetTuple(first + k, copiedFrom[k], this->Coordinates);
    this->Normals->SetTuple(first + k, copyNormals[k].data());
  }
  this->Data.Append(first, copiedFrom);
  // Renumber the triangles of the cells concerned; their entries follow the pattern.
  std::stable_sort(
    uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.Cell < b.Cell; });
  std::vector<vtkIdType> byPoint;
  for (size_t begin = 0, u = 0; u < uses.size(); begin = u)
  {
    const vtkIdType c = uses[begin].Cell;
    const ctsplines::SnappedLattice& pattern = this->Patterns.Pattern(c);
    byPoint.assign(pattern.Points.size(), -1);
    for (; u < uses.size() && uses[u].Cell == c; ++u)
    {
      byPoint[uses[u].Point] = uses[u].NewId;
    }
    this->WithCellArrays([&](auto*, auto* cellConnectivity) {
      auto* connectivity = cellConnectivity + 3 * this->Patterns.FirstTriangle(c);
      for (size_t k = 0; k < pattern.Triangles.size(); ++k)
      {
        const vtkIdType id = byPoint[pattern.Triangles[k]];
        connectivity[k] = id >= 0 ? static_cast<decltype(+connectivity[k])>(id) : connectivity[k];
      }
    });
  }
  return copies;
}

// Adaptive levels: per cell the smallest power of two (up to maxLevel) at which every lattice
// triangle is within the chordal tolerance (distance of the surface from the triangle at its
// edge midpoints) and the angular one (angle between the exact normals at its corners and
// edge midpoints). Both are checked on the lattice of twice the level, whose points include
// those midpoints.
std::vector<int> ChooseLevels(const ctsplines::BezierCells& cells, int maxLevel, double chordal,
  double angularDegrees)
{
  const vtkIdType nCells = cells.NumberOfCells();
  std::vector<int> levels(nCells, maxLevel);
  const double cosine =
    angularDegrees > 0 ? std::cos(vtkMath::RadiansFromDegrees(angularDegrees)) : -2.0;
  std::map<int, ctsplines::SamplingLattice> lattices;
  for (int L = 2; L <= 2 * maxLevel; L *= 2)
  {
    lattices.emplace(L, ctsplines::SamplingLattice(L));
  }
  ctsplines::ParallelFor(
    0, nCells, ctsplines::GrainForEvaluations, [&](vtkIdType begin, vtkIdType end) {
    ctk::Vec3 P[ctk::MaxBezierPoints], R[ctk::MaxBezierPoints];
    double w[ctk::MaxBezierPoints];
    std::vector<ctk::Vec3> x, normal;
    for (vtkIdType c = begin; c < end; ++c)
    {
      const int n = cells.Degree[c];
      const double* wp = cells.Net(c, P, w);
      ctk::RelativeNet(n, P, R);
      for (int L = 1; L < maxLevel; L *= 2)
      {
        const ctsplines::SamplingLattice& fine = lattices.at(2 * L);
        x.resize(fine.Points.size());
        normal.resize(fine.Points.size());
        for (size_t p = 0; p < fine.Points.size(); ++p)
        {
          x[p] = ctk::EvaluateBezierTriangle(n, R, wp, fine.Points[p].T, 0).Value;
          normal[p] = ctk::PatchNormal(n, R, wp, fine.Points[p].T);
        }
        // Level-2L index of the level-L lattice point (j, k) doubled, plus an offset.
        const int F = 2 * L;
        auto at = [F](int j, int k) { return k * (F + 1) - k * (k - 1) / 2 + j; };
        bool ok = true;
        for (int k = 0; k < L && ok; ++k)
        {
          for (int j = 0; j + k < L && ok; ++j)
          {
            for (int down = 0; down < (j + k + 1 < L ? 2 : 1) && ok; ++down)
            {
              // Corners and edge midpoints of the up (down = 0) or down triangle at (j, k).
              const int a = down ? at(2 * j + 2, 2 * k) : at(2 * j, 2 * k);
              const int b = down ? at(2 * j + 2, 2 * k + 2) : at(2 * j + 2, 2 * k);
              const int d = at(2 * j, 2 * k + 2);
              const int ab = down ? at(2 * j + 2, 2 * k + 1) : at(2 * j + 1, 2 * k);
              const int bd = down ? at(2 * j + 1, 2 * k + 2) : at(2 * j + 1, 2 * k + 1);
              const int da = down ? at(2 * j + 1, 2 * k + 1) : at(2 * j, 2 * k + 1);
              const int corner[3] = { a, b, d }, mid[3] = { ab, bd, da };
              for (int e = 0; e < 3 && ok; ++e)
              {
                const ctk::Vec3 chord = 0.5 * (x[corner[e]] + x[corner[(e + 1) % 3]]);
                ok = (x[mid[e]] - chord).norm() <= chordal &&
                  normal[corner[e]].dot(normal[corner[(e + 1) % 3]]) >= cosine &&
                  normal[corner[e]].dot(normal[mid[e]]) >= cosine;
              }
            }
          }
        }
        if (ok)
        {
          levels[c] = L;
          break;
        }
      }
    }
  });
  return levels;
}

// Largest power of two not above level.
int PowerOfTwoAtMost(int level)
{
  int p = 1;
  while (2 * p <= level)
  {
    p *= 2;
  }
  return p;
}
} // namespace

int vtkBezierTriangleTessellator::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  // The previous output's arrays, when the input and the levels are the previous execution's
  // (see ReuseOutputArrays); otherwise they are released here, before anything is allocated.
  ctsplines::RecycledArraysScope recycling(*this->Recycled, this->ReuseOutputArrays,
    { input->GetNumberOfCells(), input->GetNumberOfPoints(), this->SubdivisionLevel,
      this->IsAdaptive() ? 1 : 0 });
  ctsplines::RecycledArrays* recycled = recycling.Get();
  // The kept corners and edges are taken at once: an execution that fails keeps none.
  std::unique_ptr<ctsplines::SharedCellTopology> topology;
  if (recycled)
  {
    topology = std::move(this->Recycled->Topology);
  }
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  output->SetPoints(outPoints);
  const vtkIdType nCells = input->GetNumberOfCells();
  if (nCells == 0)
  {
    return 1;
  }

  // 1. Validate and flatten the input so that the parallel part reads plain arrays.
  ctsplines::BezierCells cells;
  std::string error = ctsplines::GatherBezierCellsAndCellData(input, cells);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  // 2. Levels (uniform, or per cell within the tolerances) and the conforming numbering:
  // shared corners and edges are evaluated once, by their owner cell.
  const std::vector<int> levels = this->IsAdaptive()
    ? ChooseLevels(cells, PowerOfTwoAtMost(this->SubdivisionLevel),
        this->GetAbsoluteChordalTolerance(input), this->AngularTolerance)
    : std::vector<int>(nCells, this->SubdivisionLevel);
  this->UpdateProgress(this->IsAdaptive() ? 0.3 : 0.0);
  // The shared corners and edges: the previous input's when its cells had the same corners.
  if (!topology || !topology->SameCorners(cells))
  {
    topology.reset(); // before the new one is built (peak memory)
    topology.reset(new ctsplines::SharedCellTopology(cells));
    ++this->Recycled->TopologyBuilds;
  }
  const ctsplines::CellPatterns patterns(cells, levels, *topology);
  const vtkIdType nOutPoints = patterns.NumberOfPoints();
  const vtkIdType nOutCells = patterns.NumberOfTriangles();
  if (recycled)
  {
    // Only arrays of the output's sizes can be taken (points split at creases have others).
    recycled->ReleaseIf([&](vtkDataArray* a) {
      const vtkIdType n = a->GetNumberOfTuples();
      return n != nOutPoints && n != nOutCells && n != nOutCells + 1 && n != 3 * nOutCells;
    });
  }
  ctsplines::PointDataInterpolator data;
  error = data.Gather(input, this->UVArrayName, nOutPoints, recycled);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }

  // 3. Output arrays, then every cell fills its triangles and the points it owns.
  auto coords = ctsplines::NewOutputArray<vtkDoubleArray>(recycled, 3, nOutPoints);
  auto normals = ctsplines::NewOutputArray<vtkDoubleArray>(recycled, 3, nOutPoints);
  normals->SetName("Normals");
  // 32-bit cell storage whenever the ids fit, split copies included (each is a triangle corner).
  vtkSmartPointer<vtkCellArray> polys =
    ctsplines::NewCellArray(nOutCells, 3 * nOutCells, nOutPoints + 3 * nOutCells, recycled);
  const bool narrow = !polys->IsStorage64Bit();
  vtkDataArray* offsets = polys->GetOffsetsArray();
  vtkDataArray* connectivity = polys->GetConnectivityArray();
  auto bezierCellId = ctsplines::NewOutputArray<vtkIdTypeArray>(recycled, 1, nOutCells);
  bezierCellId->SetName("BezierCellId");
  if (recycled)
  {
    // Only the cell data copies may still take kept arrays: the others go before the output
    // is written (peak memory).
    recycled->ReleaseIf([&](vtkDataArray* a) { return a->GetNumberOfTuples() != nOutCells; });
  }
  Tessellation tessellation{ cells, patterns, data, coords, normals, offsets->GetVoidPointer(0),
    connectivity->GetVoidPointer(0), narrow, bezierCellId->GetPointer(0) };
  const auto tessellate = [&](vtkIdType begin, vtkIdType end) {
    CellScratch s;
    for (vtkIdType c = begin; c < end; ++c)
    {
      tessellation.Cell(c, s);
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nCells, 20, this->IsAdaptive() ? 0.3 : 0.0, 0.9, tessellate))
  {
    output->Initialize();
    return 1;
  }
  offsets->SetComponent(nOutCells, 0, static_cast<double>(3 * nOutCells));
  if (this->SplitSharpEdges)
  {
    tessellation.SplitSharpPoints(this->FeatureAngle);
  }

  outPoints->SetData(coords);
  output->SetPolys(polys);
  output->GetPointData()->SetNormals(normals);
  data.AddTo(output->GetPointData());
  ctsplines::CopyCellDataBySource(
    input, output->GetCellData(), bezierCellId->GetPointer(0), nOutCells, recycled);
  output->GetCellData()->AddArray(bezierCellId);
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  const bool keep = ctsplines::RecycledArrays::MayKeepOutput(this, this->ReuseOutputArrays);
  recycling.End(output, keep);
  if (recycled && keep)
  {
    this->Recycled->Topology = std::move(topology);
  }
  this->UpdateProgress(1.0);
  return 1;
}

bool vtkBezierTriangleTessellator::IsAdaptive() const
{
  return this->ChordalTolerance > 0 || this->AngularTolerance > 0;
}

double vtkBezierTriangleTessellator::GetAbsoluteChordalTolerance(vtkDataSet* input) const
{
  if (!(this->ChordalTolerance > 0))
  {
    return std::numeric_limits<double>::infinity();
  }
  return this->RelativeChordalTolerance ? this->ChordalTolerance * input->GetLength()
                                        : this->ChordalTolerance;
}

void vtkBezierTriangleTessellator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "SplitSharpEdges: " << (this->SplitSharpEdges ? "on" : "off") << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "ChordalTolerance: " << this->ChordalTolerance
     << (this->RelativeChordalTolerance ? " (relative to the bounding-box diagonal)" : "") << "\n";
  os << indent << "AngularTolerance: " << this->AngularTolerance << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "ReuseOutputArrays: " << this->ReuseOutputArrays << "\n";
  os << indent << "ReusedOutputBytes: " << this->GetReusedOutputBytes() << "\n";
  os << indent << "NumberOfTopologyBuilds: " << this->GetNumberOfTopologyBuilds() << "\n";
}
