// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkSampledSurfaceSource
 * @brief   Parametrised triangle meshes sampled from analytic surfaces, with exact derivatives.
 *
 * Produces the input that vtkCloughTocherSplineFilter expects: a triangulated parameter domain
 * whose vertices carry the exact position and first derivatives of one of the papers' test
 * surfaces (the kernel's ctk::EvaluateAnalyticSurface), plus exact mid-edge gradients for the MG
 * constructions.
 *
 * Surfaces: Plane, Quadratic, FarinCubic, Franke, SineWave (functional, z = f(u, v)) and the
 * rational quartic SphereOctant.
 *
 * Domains:
 * - Grid: [0, 1]^2 with Resolution x Resolution cells, two triangles per cell split along
 *   GridDiagonal. Not available for SphereOctant.
 * - EquilateralTriangle: the triangle (0,0), (1,0), (1/2, sqrt(3)/2) (ctk::SphereOctantDomain())
 *   refined Resolution times by midpoint subdivision, 4^Resolution triangles. Any surface.
 * - RandomDelaunay: the Delaunay triangulation (CGAL's, ctk::DelaunayTriangulation; 0.2 s for
 *   1e5 points, 1.7 s for 5e5) of the domain corners, evenly spaced boundary points and
 *   Resolution random interior points drawn from Seed. The domain is [0, 1]^2 for functional
 *   surfaces and the equilateral triangle for SphereOctant.
 *
 * An optional affine reparameterisation U' = A U + t (AffineMatrix row-major, AffineTranslation)
 * is applied consistently: UV = A U + t, derivatives and edge gradients J A^{-1} (columns f_u,
 * f_v), positions unchanged. An invariant spline construction then gives the same surface.
 *
 * Output vtkPolyData: double points (positions), triangles (counter-clockwise in the original
 * parameter domain), point data `UV` (2 components, also the active texture coordinates),
 * `dFdu`, `dFdv` (3 components), cell data `EdgeGradients` (18 components: for the local edges
 * (p0,p1), (p1,p2), (p2,p0) in that order, f_u then f_v at the edge midpoint), field data
 * `Surface` and `Domain` (strings).
 *
 * Random meshes are reproducible across platforms: the interior points come from a splitmix64
 * generator seeded with Seed, not from the standard library's distributions.
 */
#ifndef vtkSampledSurfaceSource_h
#define vtkSampledSurfaceSource_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

class CTSPLINESFILTERS_EXPORT vtkSampledSurfaceSource : public vtkPolyDataAlgorithm
{
public:
  static vtkSampledSurfaceSource* New();
  vtkTypeMacro(vtkSampledSurfaceSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Analytic surfaces (values match the kernel's ctk::AnalyticSurface).
  enum SurfaceType
  {
    Plane = 0,
    Quadratic = 1,
    FarinCubic = 2,
    Franke = 3,
    SineWave = 4,
    SphereOctant = 5
  };
  enum DomainType
  {
    Grid = 0,
    EquilateralTriangle = 1,
    RandomDelaunay = 2
  };
  /// Diagonal of the grid cells (values match the kernel's ctk::GridDiagonal).
  enum GridDiagonalType
  {
    Forward = 0,
    Backward = 1,
    Alternating = 2
  };

  ///@{
  /// The sampled surface. Default Franke.
  vtkSetClampMacro(Surface, int, Plane, SphereOctant);
  vtkGetMacro(Surface, int);
  void SetSurfaceToPlane() { this->SetSurface(Plane); }
  void SetSurfaceToQuadratic() { this->SetSurface(Quadratic); }
  void SetSurfaceToFarinCubic() { this->SetSurface(FarinCubic); }
  void SetSurfaceToFranke() { this->SetSurface(Franke); }
  void SetSurfaceToSineWave() { this->SetSurface(SineWave); }
  void SetSurfaceToSphereOctant() { this->SetSurface(SphereOctant); }
  ///@}

  ///@{
  /// The triangulated parameter domain. Default RandomDelaunay.
  vtkSetClampMacro(Domain, int, Grid, RandomDelaunay);
  vtkGetMacro(Domain, int);
  void SetDomainToGrid() { this->SetDomain(Grid); }
  void SetDomainToEquilateralTriangle() { this->SetDomain(EquilateralTriangle); }
  void SetDomainToRandomDelaunay() { this->SetDomain(RandomDelaunay); }
  ///@}

  ///@{
  /// Grid: cells per side, 1..4096. EquilateralTriangle: refinement level, 0..12 (4^level
  /// triangles). RandomDelaunay: number of random interior points, 0..10^7. Checked when the
  /// output is generated. Default 100.
  vtkSetMacro(Resolution, int);
  vtkGetMacro(Resolution, int);
  ///@}

  ///@{
  /// Diagonal of the grid cells (Grid domain only). Default Forward.
  vtkSetClampMacro(GridDiagonal, int, Forward, Alternating);
  vtkGetMacro(GridDiagonal, int);
  void SetGridDiagonalToForward() { this->SetGridDiagonal(Forward); }
  void SetGridDiagonalToBackward() { this->SetGridDiagonal(Backward); }
  void SetGridDiagonalToAlternating() { this->SetGridDiagonal(Alternating); }
  ///@}

  ///@{
  /// Seed of the random interior points (RandomDelaunay only). Default 1.
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /// Affine reparameterisation U' = A U + t. AffineMatrix is A in row-major order
  /// (a00, a01, a10, a11), default identity; it must be non-singular. AffineTranslation is t,
  /// default (0, 0).
  vtkSetVector4Macro(AffineMatrix, double);
  vtkGetVector4Macro(AffineMatrix, double);
  vtkSetVector2Macro(AffineTranslation, double);
  vtkGetVector2Macro(AffineTranslation, double);
  ///@}

  /// Names of the surface and domain values ("Franke", "RandomDelaunay", ...).
  static const char* GetSurfaceName(int surface);
  static const char* GetDomainName(int domain);

protected:
  vtkSampledSurfaceSource();
  ~vtkSampledSurfaceSource() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Surface = Franke;
  int Domain = RandomDelaunay;
  int Resolution = 100;
  int GridDiagonal = Forward;
  unsigned int Seed = 1;
  double AffineMatrix[4] = { 1.0, 0.0, 0.0, 1.0 };
  double AffineTranslation[2] = { 0.0, 0.0 };

private:
  vtkSampledSurfaceSource(const vtkSampledSurfaceSource&) = delete;
  void operator=(const vtkSampledSurfaceSource&) = delete;
};

#endif
