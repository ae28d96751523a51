// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file make_seeds.cpp
/// Writes small seed files for the reader harnesses: usage fuzz_make_seeds OUTDIR [MODEL...].
///
/// OUTDIR/{step,iges,brep}/ get (1) OpenCASCADE primitives (box, cylinder, cone with an apex,
/// sphere, torus, a B-spline face, a filleted Boolean), and (2) for each real MODEL, up to 6 of
/// its faces spread over the face list, each alone in a file: real geometry (trimmed B-splines,
/// surfaces of revolution, seams, poles) in files of a few kB, which libFuzzer mutates far faster
/// than the whole models (1-3 MB for the IGES ones).
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Precision.hxx>
#include <STEPControl_Writer.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/util/Error.hpp"

namespace fs = std::filesystem;

namespace {

void writeAll(const TopoDS_Shape& s, const fs::path& out, const std::string& name) {
  BRepTools::Write(s, (out / "brep" / (name + ".brep")).string().c_str());
  {
    STEPControl_Writer w;
    if (w.Transfer(s, STEPControl_AsIs) == IFSelect_RetDone) w.Write((out / "step" / (name + ".step")).string().c_str());
  }
  {
    IGESControl_Writer w("MM", 1);  // BRep mode (faces as MSBO / trimmed surfaces)
    if (w.AddShape(s)) {
      w.ComputeModel();
      w.Write((out / "iges" / (name + ".iges")).string().c_str());
    }
  }
}

TopoDS_Shape bsplineFace() {
  TColgp_Array2OfPnt poles(1, 4, 1, 4);
  for (int i = 1; i <= 4; ++i)
    for (int j = 1; j <= 4; ++j) poles(i, j) = gp_Pnt(i, j, ((i * 7 + j * 3) % 5) * 0.3);
  TColStd_Array1OfReal k(1, 2);
  k(1) = 0;
  k(2) = 1;
  TColStd_Array1OfInteger m(1, 2);
  m(1) = m(2) = 4;
  Handle(Geom_BSplineSurface) s = new Geom_BSplineSurface(poles, k, k, m, m, 3, 3);
  return BRepBuilderAPI_MakeFace(s, Precision::Confusion());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: fuzz_make_seeds OUTDIR [MODEL...]\n");
    return 1;
  }
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));  // the writers are chatty
  IGESControl_Controller::Init();
  const fs::path out = argv[1];
  for (const char* d : {"step", "iges", "brep"}) fs::create_directories(out / d);
  int n = 0;
  writeAll(BRepPrimAPI_MakeBox(2, 3, 4).Shape(), out, "p_box"), ++n;
  writeAll(BRepPrimAPI_MakeCylinder(1, 3).Shape(), out, "p_cylinder"), ++n;
  writeAll(BRepPrimAPI_MakeCone(1.5, 0, 2).Shape(), out, "p_cone_apex"), ++n;
  writeAll(BRepPrimAPI_MakeSphere(2).Shape(), out, "p_sphere"), ++n;
  writeAll(BRepPrimAPI_MakeTorus(3, 1).Shape(), out, "p_torus"), ++n;
  writeAll(bsplineFace(), out, "p_bspline_face"), ++n;
  {
    TopoDS_Shape s = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeBox(2, 2, 2).Shape(),
                                      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(1, 1, 1), gp_Dir(0, 0, 1)), 0.6, 2).Shape())
                         .Shape();
    BRepFilletAPI_MakeFillet f(s);
    TopTools_IndexedMapOfShape edges;
    TopExp::MapShapes(s, TopAbs_EDGE, edges);
    f.Add(0.2, TopoDS::Edge(edges(1)));
    f.Build();
    writeAll(f.IsDone() ? f.Shape() : s, out, "p_fused_filleted"), ++n;
  }
  for (int a = 2; a < argc; ++a) {
    const std::string path = argv[a];
    TopoDS_Shape shape;
    try {
      std::istringstream in(paramesh::occFileToBrepString(path));
      BRep_Builder b;
      BRepTools::Read(shape, in, b);
    } catch (const paramesh::Error& e) {
      std::fprintf(stderr, "fuzz_make_seeds: skipping %s: %s\n", path.c_str(), e.what());
      continue;
    }
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    const int want = std::min(6, faces.Extent());
    const std::string stem = fs::path(path).stem().string();
    for (int k = 0; k < want; ++k) {
      const int f = 1 + (int)((long)k * faces.Extent() / want);
      writeAll(faces(f), out, stem + "_face" + std::to_string(f)), ++n;
    }
  }
  std::printf("%d seed shapes written to %s/{step,iges,brep}\n", n, out.string().c_str());
  return 0;
}
