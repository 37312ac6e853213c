// SPDX-License-Identifier: GPL-3.0-or-later
// Inputs for the filter tests: analytic surfaces of the kernel sampled on parameter meshes, as
// the vtkPolyData the filters expect (point data UV, dFdu, dFdv; cell data EdgeGradients).
#ifndef CTSplines_FilterTestUtilities_h
#define CTSplines_FilterTestUtilities_h

#include "AnalyticSurfaces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <Eigen/Dense>

namespace ctsplines_test
{
/// Samples surface s on the parameter mesh m. With an affine map (A, t), the parameters become
/// A U + t and the derivatives J A^{-1}; positions are unchanged.
inline vtkSmartPointer<vtkPolyData> MakeSampledPolyData(const ctk::ParameterMesh& m,
  ctk::AnalyticSurface s, const Eigen::Matrix2d& A = Eigen::Matrix2d::Identity(),
  const ctk::Vec2& t = ctk::Vec2::Zero())
{
  const Eigen::Matrix2d Ainv = A.inverse();
  auto sample = [&](const ctk::Vec2& U, ctk::Vec3& F, ctk::Vec3& Fu, ctk::Vec3& Fv) {
    const ctk::SurfacePoint p = ctk::EvaluateAnalyticSurface(s, U.x(), U.y());
    Eigen::Matrix<double, 3, 2> J;
    J << p.Fu, p.Fv;
    const Eigen::Matrix<double, 3, 2> Jp = J * Ainv;
    F = p.F;
    Fu = Jp.col(0);
    Fv = Jp.col(1);
  };
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> uv, du, dv, eg;
  uv->SetName("UV");
  uv->SetNumberOfComponents(2);
  du->SetName("dFdu");
  du->SetNumberOfComponents(3);
  dv->SetName("dFdv");
  dv->SetNumberOfComponents(3);
  eg->SetName("EdgeGradients");
  eg->SetNumberOfComponents(18);
  for (const ctk::Vec2& U : m.UV)
  {
    ctk::Vec3 F, Fu, Fv;
    sample(U, F, Fu, Fv);
    pts->InsertNextPoint(F.data());
    const ctk::Vec2 Up = A * U + t;
    uv->InsertNextTuple(Up.data());
    du->InsertNextTuple(Fu.data());
    dv->InsertNextTuple(Fv.data());
  }
  vtkNew<vtkCellArray> polys;
  for (ctk::Id c = 0; c < m.NumberOfTriangles(); ++c)
  {
    const vtkIdType ids[3] = { m.Triangles[3 * c], m.Triangles[3 * c + 1], m.Triangles[3 * c + 2] };
    polys->InsertNextCell(3, ids);
    double g[18];
    for (int l = 0; l < 3; ++l)
    {
      const ctk::Vec2 mid = 0.5 * (m.UV[ids[l]] + m.UV[ids[(l + 1) % 3]]);
      ctk::Vec3 F, Fu, Fv;
      sample(mid, F, Fu, Fv);
      for (int c3 = 0; c3 < 3; ++c3)
      {
        g[6 * l + c3] = Fu[c3];
        g[6 * l + 3 + c3] = Fv[c3];
      }
    }
    eg->InsertNextTuple(g);
  }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  pd->GetPointData()->AddArray(uv);
  pd->GetPointData()->AddArray(du);
  pd->GetPointData()->AddArray(dv);
  pd->GetCellData()->AddArray(eg);
  return pd;
}

} // namespace ctsplines_test

#endif
