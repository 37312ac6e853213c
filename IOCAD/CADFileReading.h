// SPDX-License-Identifier: GPL-3.0-or-later
// Reading a STEP or IGES file into an OpenCASCADE shape, bounded in time and isolated from
// OCCT's crashes: the numbers of the file are checked first, then OCCT's translation and the
// healing that belongs to reading (missing seams, slivers and short edges, sewing: see
// HealingOptions in CADBRepSampling.h) run in a child process (fork) whose result
// comes back through a pipe. A child that crashes, loops past the time limit or throws is an
// error naming the file and the stage; this process never crashes or hangs on a malformed file.
// For OpenCASCADE translation units only (CADBRepSampling.cxx).
#ifndef CTSplines_IOCAD_CADFileReading_h
#define CTSplines_IOCAD_CADFileReading_h

#include "CADBRepSampling.h"

#include <OSD_SignalMode.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Wire.hxx>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace ctcad
{
struct ShapeRead
{
  TopoDS_Shape Shape;
  /// Per face, in TopExp::MapShapes order: the name of the STEP entity it came from (may be
  /// empty, "NONE" or "''"). Healing keeps the file's order of the faces it leaves.
  std::vector<std::string> FaceNames;
  HealingReport Healing;
  double Box[6] = { 0, 0, 0, 0, 0, 0 }; // xmin, xmax, ymin, ymax, zmin, zmax
  /// What OCCT's translation could not do (entities it failed on, and so skipped): the model
  /// may miss faces.
  std::vector<std::string> Warnings;
};

/// A check of the shape read, run in the reading child (false with an error rejects the file).
using ShapeCheck = std::function<bool(const ShapeRead& shape, std::string& error)>;

/// Reads fileName (.step, .stp, .iges, .igs) and heals it. timeoutSeconds > 0: in a child
/// process killed after that time, which also runs `check` on the shape; 0: in this process
/// (with OCCT's signal handling) without a time limit, and without `check`. Returns false with
/// `error` starting with "cannot read", "no faces in" or "unknown CAD file extension".
bool ReadCADFile(const std::string& fileName, double timeoutSeconds, const HealingOptions& healing,
  const ShapeCheck& check, ShapeRead& result, std::string& error);

/// OSD::SetSignal(mode) without floating-point traps (the rest of the program relies on IEEE
/// results), and without taking SIGINT, SIGHUP and SIGQUIT, which keep what they had (OCCT's
/// handler would make Ctrl-C no longer stop the program).
void SetOCCTSignals(OSD_SignalMode mode);

/// Drops the degenerated edges of r.Shape's faces along which the surface moves by more than
/// `tol` and joins the other edges' pcurves by whole periods, rebuilding those faces (a step of
/// ReadCADFile's healing, declared for its tests; CADFileReading.cxx says why). Returns the
/// number of edges dropped; faces whose wires do not close without them are kept, with a warning.
int DropFalseDegeneratedEdges(ShapeRead& r, double tol);

/// v as the warnings print it (six significant digits).
std::string Number(double v);

/// The oriented edges of wire W of face F in the order they connect, or empty if they do not
/// (naming the first that does not in `broken`); defined in CADBRepSampling.cxx.
std::vector<TopoDS_Edge> WireEdges(const TopoDS_Wire& W, const TopoDS_Face& F, TopoDS_Edge& broken);

/// The pre-check of ReadCADFile: false with `error` (line, entity) when a real number of a STEP
/// file is out of the range of a double (1e400) or not a number, or the file is empty.
bool CheckFileNumbers(const std::string& fileName, std::string& error);

/// The whole periods nearest to the parameter step d (0 where period is 0: not periodic).
inline double WholePeriods(double d, double period)
{
  return period > 0 ? period * std::round(d / period) : 0;
}

/// A surface's periods in u and v (0 where it is not periodic); Surface is Geom_Surface or
/// BRepAdaptor_Surface.
template <class Surface>
std::array<double, 2> SurfacePeriods(const Surface& S)
{
  return { S.IsUPeriodic() ? S.UPeriod() : 0, S.IsVPeriodic() ? S.VPeriod() : 0 };
}

} // namespace ctcad

#endif
