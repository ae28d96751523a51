// SPDX-License-Identifier: LGPL-2.1-or-later
// OpenCASCADE backend: the only translation unit family that includes OCC headers.
#include "paramesh/geom/occ/OccModel.hpp"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepTools.hxx>
#include <BRepTools_ShapeSet.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GeomAbs_SurfaceType.hxx>
#include <Geom2d_Curve.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <TCollection_HAsciiString.hxx>
#include <XSControl_WorkSession.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Message_SequenceOfPrinters.hxx>
#include <STEPControl_Reader.hxx>
#include <OSD.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>
#include <gp_Vec2d.hxx>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iostream>
#include <iterator>
#include <streambuf>
#include <mutex>
#include <sstream>
#include <string>

#include "paramesh/geom/occ/BrepPrecheck.hpp"
#include "paramesh/util/Error.hpp"

#include <Standard_Version.hxx>

namespace paramesh {
namespace {

inline Vec3 toVec(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
inline Vec3 toVec(const gp_Vec& p) { return {p.X(), p.Y(), p.Z()}; }

class OccSurface final : public ISurface {
 public:
  explicit OccSurface(const TopoDS_Face& f) : a_(f, Standard_True) {
    box_.u0 = a_.FirstUParameter();
    box_.u1 = a_.LastUParameter();
    box_.v0 = a_.FirstVParameter();
    box_.v1 = a_.LastVParameter();
    uPer_ = a_.IsUPeriodic() ? a_.UPeriod() : 0.0;
    vPer_ = a_.IsVPeriodic() ? a_.VPeriod() : 0.0;
    switch (a_.GetType()) {
      case GeomAbs_Plane: kind_ = SurfaceKind::Plane; break;
      case GeomAbs_Cylinder: kind_ = SurfaceKind::Cylinder; break;
      case GeomAbs_Cone: kind_ = SurfaceKind::Cone; break;
      case GeomAbs_Sphere: kind_ = SurfaceKind::Sphere; break;
      case GeomAbs_Torus: kind_ = SurfaceKind::Torus; break;
      case GeomAbs_BezierSurface: kind_ = SurfaceKind::Bezier; break;
      case GeomAbs_BSplineSurface: kind_ = SurfaceKind::BSpline; break;
      case GeomAbs_SurfaceOfRevolution: kind_ = SurfaceKind::Revolution; break;
      case GeomAbs_SurfaceOfExtrusion: kind_ = SurfaceKind::Extrusion; break;
      case GeomAbs_OffsetSurface: kind_ = SurfaceKind::Offset; break;
      default: kind_ = SurfaceKind::Other;
    }
  }
  SurfaceKind kind() const override { return kind_; }
  Vec3 eval(Vec2 uv) const override { return toVec(a_.Value(uv.x, uv.y)); }
  void d1(Vec2 uv, Vec3& p, Vec3& du, Vec3& dv) const override {
    gp_Pnt P;
    gp_Vec U, V;
    a_.D1(uv.x, uv.y, P, U, V);
    p = toVec(P);
    du = toVec(U);
    dv = toVec(V);
  }
  void d2(Vec2 uv, SurfaceD2& d) const override {
    gp_Pnt P;
    gp_Vec U, V, UU, VV, UV;
    a_.D2(uv.x, uv.y, P, U, V, UU, VV, UV);
    d.p = toVec(P);
    d.du = toVec(U);
    d.dv = toVec(V);
    d.duu = toVec(UU);
    d.duv = toVec(UV);
    d.dvv = toVec(VV);
  }
  UVBox bounds() const override { return box_; }
  double uPeriod() const override { return uPer_; }
  double vPeriod() const override { return vPer_; }

 private:
  BRepAdaptor_Surface a_;
  UVBox box_;
  double uPer_ = 0, vPer_ = 0;
  SurfaceKind kind_ = SurfaceKind::Other;
};

class OccCurve final : public ICurve {
 public:
  explicit OccCurve(const TopoDS_Edge& e) : a_(e) {
    switch (a_.GetType()) {
      case GeomAbs_Line: kind_ = CurveKind::Line; break;
      case GeomAbs_Circle: kind_ = CurveKind::Circle; break;
      case GeomAbs_Ellipse: kind_ = CurveKind::Ellipse; break;
      case GeomAbs_BSplineCurve: kind_ = CurveKind::BSpline; break;
      case GeomAbs_BezierCurve: kind_ = CurveKind::Bezier; break;
      default: kind_ = CurveKind::Other;
    }
  }
  CurveKind kind() const override { return kind_; }
  Vec3 eval(double t) const override { return toVec(a_.Value(t)); }
  void d1(double t, Vec3& p, Vec3& dt) const override {
    gp_Pnt P;
    gp_Vec V;
    a_.D1(t, P, V);
    p = toVec(P);
    dt = toVec(V);
  }
  void d2(double t, Vec3& p, Vec3& d1v, Vec3& d2v) const override {
    gp_Pnt P;
    gp_Vec V1, V2;
    a_.D2(t, P, V1, V2);
    p = toVec(P);
    d1v = toVec(V1);
    d2v = toVec(V2);
  }

 private:
  BRepAdaptor_Curve a_;
  CurveKind kind_ = CurveKind::Other;
};

class OccPCurve final : public IPCurve {
 public:
  explicit OccPCurve(Handle(Geom2d_Curve) c) : c_(std::move(c)) {}
  Vec2 eval(double t) const override {
    gp_Pnt2d p = c_->Value(t);
    return {p.X(), p.Y()};
  }
  void d1(double t, Vec2& p, Vec2& dt) const override {
    gp_Pnt2d P;
    gp_Vec2d V;
    c_->D1(t, P, V);
    p = {P.X(), P.Y()};
    dt = {V.X(), V.Y()};
  }

 private:
  Handle(Geom2d_Curve) c_;
};

/// A p-curve as BRep_Tool::CurveOnSurface gave it (null: none), or why it could not: computed
/// once per edge use. On a plane without a stored p-curve OpenCASCADE projects the 3D curve on
/// every call (BRep_Tool::CurveOnPlane), and the face boundaries are built several times (the
/// narrow-gap stage, then each nearest-face round).
struct PCurveSlot {
  bool done = false;
  Handle(Geom2d_Curve) curve;
  std::string error;
};

struct FaceData {
  TopoDS_Face face;  // as stored in the map (orientation of first occurrence)
  std::vector<Wire> wires;
  std::vector<std::vector<TopoDS_Edge>> oriented;  // oriented edge per use, as explored from face
  int solid = -1;
  std::string surfaceError;  // why OpenCASCADE cannot build the face's surface adaptor (probeSurface)
  mutable std::vector<std::vector<PCurveSlot>> pcurves;  // per wire and use (OccModel::pcurveMutex_)
};

class OccModel final : public IGeometryModel {
 public:
  /// warnings: what the reader noticed (readWarnings()).
  OccModel(const TopoDS_Shape& shape, std::string source, std::vector<std::string> warnings = {})
      : shape_(shape), source_(std::move(source)), readWarnings_(std::move(warnings)) {
    TopExp::MapShapes(shape_, TopAbs_FACE, faces_);
    TopExp::MapShapes(shape_, TopAbs_EDGE, edges_);
    TopExp::MapShapes(shape_, TopAbs_VERTEX, vertices_);
    TopExp::MapShapes(shape_, TopAbs_SOLID, solids_);
    if (faces_.Extent() == 0)
      throw InputError("the model contains no face (" + source_ + ")");
    edgeFaces_.resize(edges_.Extent());
    faceData_.resize(faces_.Extent());
    for (int s = 1; s <= solids_.Extent(); ++s)
      for (TopExp_Explorer ex(solids_(s), TopAbs_FACE); ex.More(); ex.Next()) {
        int fi = faces_.FindIndex(ex.Current()) - 1;
        if (fi >= 0 && faceData_[fi].solid < 0) faceData_[fi].solid = s - 1;
      }
    for (int f = 1; f <= faces_.Extent(); ++f) {
      FaceData& fd = faceData_[f - 1];
      fd.face = TopoDS::Face(faces_(f));
      for (TopoDS_Iterator wit(fd.face); wit.More(); wit.Next()) {
        if (wit.Value().ShapeType() != TopAbs_WIRE) continue;
        const TopoDS_Wire& w = TopoDS::Wire(wit.Value());
        Wire wire;
        std::vector<TopoDS_Edge> oriented;
        for (BRepTools_WireExplorer we(w, fd.face); we.More(); we.Next()) {
          const TopoDS_Edge& e = we.Current();
          int ei = edges_.FindIndex(e) - 1;
          if (ei < 0) continue;
          wire.uses.push_back({ei, e.Orientation() == TopAbs_REVERSED});
          oriented.push_back(e);
        }
        // BRepTools_WireExplorer skips nothing on valid wires; fall back to plain order otherwise.
        int nPlain = 0;
        for (TopoDS_Iterator eit(w); eit.More(); eit.Next()) ++nPlain;
        if ((int)wire.uses.size() < nPlain) {
          wire.uses.clear();
          oriented.clear();
          for (TopoDS_Iterator eit(w); eit.More(); eit.Next()) {
            if (eit.Value().ShapeType() != TopAbs_EDGE) continue;
            const TopoDS_Edge& e = TopoDS::Edge(eit.Value());
            int ei = edges_.FindIndex(e) - 1;
            if (ei < 0) continue;
            wire.uses.push_back({ei, e.Orientation() == TopAbs_REVERSED});
            oriented.push_back(e);
          }
        }
        if (wire.uses.empty()) continue;
        for (const EdgeUse& u : wire.uses) {
          auto& ef = edgeFaces_[u.edge];
          if (std::find(ef.begin(), ef.end(), f - 1) == ef.end()) ef.push_back(f - 1);
        }
        fd.pcurves.emplace_back(oriented.size());
        fd.wires.push_back(std::move(wire));
        fd.oriented.push_back(std::move(oriented));
      }
    }
    for (FaceData& fd : faceData_) fd.surfaceError = probeSurface(fd.face);
    Bnd_Box bb;
    BRepBndLib::Add(shape_, bb);
    if (!bb.IsVoid()) {
      double x0, y0, z0, x1, y1, z1;
      bb.Get(x0, y0, z0, x1, y1, z1);
      box_.add({x0, y0, z0});
      box_.add({x1, y1, z1});
    }
    // Bnd_Box is enlarged by tolerances; tighten with vertex positions when possible
    Box3 vb;
    for (int v = 1; v <= vertices_.Extent(); ++v) vb.add(toVec(BRep_Tool::Pnt(TopoDS::Vertex(vertices_(v)))));
    (void)vb;
  }

  int numFaces() const override { return faces_.Extent(); }
  int numEdges() const override { return edges_.Extent(); }
  int numVertices() const override { return vertices_.Extent(); }
  int numSolids() const override { return solids_.Extent(); }

  Vec3 vertexPoint(int v) const override { return toVec(BRep_Tool::Pnt(TopoDS::Vertex(vertices_(v + 1)))); }
  double vertexTolerance(int v) const override { return BRep_Tool::Tolerance(TopoDS::Vertex(vertices_(v + 1))); }

  void edgeRange(int e, double& t0, double& t1) const override {
    BRep_Tool::Range(edge(e), t0, t1);
  }
  int edgeVertex(int e, int end) const override {
    TopoDS_Edge E = edge(e);
    TopoDS_Vertex V = end == 0 ? TopExp::FirstVertex(E) : TopExp::LastVertex(E);
    if (V.IsNull()) return -1;
    return vertices_.FindIndex(V) - 1;
  }
  bool edgeDegenerate(int e) const override { return BRep_Tool::Degenerated(edge(e)); }
  // OpenCASCADE's adaptors throw Standard_Failure on damaged geometry (BRepAdaptor_Curve:
  // Standard_ConstructionError on a fuzzed small-edges-01.brep edge, which ended the CLI in
  // std::terminate): the backend turns it into an InputError naming the entity
  std::unique_ptr<ICurve> makeCurve(int e) const override {
    try {
      if (edgeDegenerate(e)) return nullptr;
      return std::make_unique<OccCurve>(edge(e));
    } catch (const Standard_Failure& x) {
      throw InputError("Edge" + std::to_string(e + 1) + ": OpenCASCADE cannot evaluate its curve (" + describe(x) + ")");
    }
  }
  double edgeTolerance(int e) const override { return BRep_Tool::Tolerance(edge(e)); }
  const std::vector<int>& edgeFaces(int e) const override { return edgeFaces_[e]; }

  std::unique_ptr<ISurface> makeSurface(int f) const override {
    if (!faceData_[f].surfaceError.empty())
      throw InputError("Face" + std::to_string(f + 1) + ": OpenCASCADE cannot evaluate its surface (" +
                       faceData_[f].surfaceError + ")");
    try {
      return std::make_unique<OccSurface>(faceData_[f].face);
    } catch (const Standard_Failure& x) {
      throw InputError("Face" + std::to_string(f + 1) + ": OpenCASCADE cannot evaluate its surface (" + describe(x) + ")");
    }
  }
  bool faceReversed(int f) const override { return faceData_[f].face.Orientation() == TopAbs_REVERSED; }
  const std::vector<Wire>& faceWires(int f) const override { return faceData_[f].wires; }
  std::unique_ptr<IPCurve> makePCurve(int f, int wire, int use) const override {
    const FaceData& fd = faceData_[f];
    PCurveSlot got;
    {
      std::lock_guard<std::mutex> lock(pcurveMutex_);
      got = fd.pcurves[wire][use];
    }
    if (!got.done) {
      got.done = true;
      try {
        double a, b;
        got.curve = BRep_Tool::CurveOnSurface(fd.oriented[wire][use], fd.face, a, b);
      } catch (const Standard_Failure& x) {
        got.error = "Face" + std::to_string(f + 1) + ": OpenCASCADE cannot read a p-curve of its wire " +
                    std::to_string(wire + 1) + " (" + describe(x) + ")";
      }
      // two threads may both compute it: the same curve, kept once
      std::lock_guard<std::mutex> lock(pcurveMutex_);
      if (!fd.pcurves[wire][use].done) fd.pcurves[wire][use] = got;
    }
    if (!got.error.empty()) throw InputError(got.error);
    if (got.curve.IsNull()) return nullptr;
    return std::make_unique<OccPCurve>(got.curve);
  }
  double faceTolerance(int f) const override { return BRep_Tool::Tolerance(faceData_[f].face); }
  int faceSolid(int f) const override { return faceData_[f].solid; }
  std::vector<SolidFace> solidFaces(int s) const override {
    std::vector<SolidFace> out;
    for (TopExp_Explorer ex(solids_(s + 1), TopAbs_FACE); ex.More(); ex.Next()) {
      int fi = faces_.FindIndex(ex.Current()) - 1;
      if (fi >= 0) out.push_back({fi, ex.Current().Orientation() != faceData_[fi].face.Orientation()});
    }
    return out;
  }
  Box3 boundingBox() const override { return box_; }
  std::string source() const override { return source_; }
  std::vector<std::string> readWarnings() const override { return readWarnings_; }

 private:
  /// An OpenCASCADE exception as "Type: message", for the InputErrors the factories throw.
  static std::string describe(const Standard_Failure& x) {
    return std::string(x.DynamicType()->Name()) + ": " + x.GetMessageString();
  }
  TopoDS_Edge edge(int e) const { return TopoDS::Edge(edges_(e + 1).Oriented(TopAbs_FORWARD)); }
  /// Builds the face's surface adaptor once while the model loads, so that what its parameter
  /// bounds compute (BRepTools::UVBounds projects p-curve-less edges on a plane, where OCC 7.6
  /// dereferences a failed approximation of a damaged curve: fuzz_brep) fails here, under the
  /// loader's OCC_CATCH_SIGNALS (a Standard_Failure when signals are guarded), and not later in
  /// the mesher. Returns "" or what failed.
  static std::string probeSurface(const TopoDS_Face& face) {
    try {
      OCC_CATCH_SIGNALS
      BRepAdaptor_Surface probe(face, Standard_True);
      (void)probe;
    } catch (const Standard_Failure& x) {
      return describe(x);
    }
    return {};
  }

  TopoDS_Shape shape_;
  std::string source_;
  std::vector<std::string> readWarnings_;
  TopTools_IndexedMapOfShape faces_, edges_, vertices_, solids_;
  std::vector<FaceData> faceData_;
  mutable std::mutex pcurveMutex_;  // guards FaceData::pcurves
  std::vector<std::vector<int>> edgeFaces_;
  Box3 box_;
};

std::string lowerExt(const std::string& path) {
  auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot + 1);
  for (char& c : e) c = (char)std::tolower((unsigned char)c);
  return e;
}

/// OpenCASCADE's readers report through the process-wide default messenger, whose printer writes
/// to stdout. The library must not print: the printers are detached while a file is read and put
/// back afterwards (serialised, since the messenger is global).
/// Some readers also write to std::cout directly (e.g. BRepTools::Read on a bad header): its
/// buffer is swapped for a null one during the read.
class SilenceOcc {
 public:
  SilenceOcc() : lock_(mutex()) {
    Handle(Message_Messenger) m = Message::DefaultMessenger();
    saved_ = m->Printers();
    for (Message_SequenceOfPrinters::Iterator it(saved_); it.More(); it.Next()) m->RemovePrinter(it.Value());
    coutBuf_ = std::cout.rdbuf(&null_);
  }
  ~SilenceOcc() {
    std::cout.rdbuf(coutBuf_);
    Handle(Message_Messenger) m = Message::DefaultMessenger();
    for (Message_SequenceOfPrinters::Iterator it(saved_); it.More(); it.Next()) m->AddPrinter(it.Value());
  }

 private:
  struct NullBuf : std::streambuf {
    int overflow(int c) override { return traits_type::not_eof(c); }
  };
  static std::mutex& mutex() {
    static std::mutex mu;
    return mu;
  }
  std::lock_guard<std::mutex> lock_;
  Message_SequenceOfPrinters saved_;
  NullBuf null_;
  std::streambuf* coutBuf_ = nullptr;
};

/// True when the text has OpenCASCADE's BREP version line somewhere (the reader skips the lines
/// before it, e.g. DRAW's "DBRep_DrawableShape"); brepStructureProblem() checks it exactly.
bool looksLikeBrep(const std::string& text) { return text.find("CASCADE Topology V") != std::string::npos; }

TopoDS_Shape readBrepText(const std::string& text, const std::string& what) {
  const std::string problem = detail::brepStructureProblem(text);
  if (!problem.empty()) throw InputError(what + " is not a complete BREP text: " + problem);
  // OpenCASCADE's reader goes on after a value fails to parse (a damaged number, a line too
  // many or too few) and can loop on the failed stream for ever (fuzz cases of wing.brep and
  // sheet_metal_54.brep): the stream throws at the first failed extraction instead
  std::istringstream in(text);
  in.exceptions(std::ios::failbit | std::ios::badbit);
  TopoDS_Shape shape;
  BRep_Builder b;
  BRepTools_ShapeSet set(b);  // BRepTools::Read, in its two steps
  try {
    set.Read(in);
  } catch (const std::ios_base::failure&) {
    const std::streamoff at = in.rdbuf()->pubseekoff(0, std::ios::cur, std::ios::in);
    const size_t pos = at < 0 ? text.size() : std::min(text.size(), (size_t)at);
    const long line = 1 + std::count(text.begin(), text.begin() + (std::ptrdiff_t)pos, '\n');
    throw InputError(what + " is not a readable BREP text: a value could not be read at line " +
                     std::to_string(line));
  }
  // the root reference as OpenCASCADE reads it: a location index it cannot read is the identity
  // (the pre-check made sure the reference itself is there)
  in.exceptions(std::ios::goodbit);
  set.Read(shape, in);
  // an internal or external root (DRAW writes "i1 0") would pass its orientation on to every face
  // and edge (TopAbs::Compose), leaving no wire with a direction: the model as a whole has none
  if (shape.Orientation() == TopAbs_INTERNAL || shape.Orientation() == TopAbs_EXTERNAL)
    shape.Orientation(TopAbs_FORWARD);
  return shape;
}

/// What the STEP / IGES reader's load check found damaged (a failed check: an unresolved
/// reference, an entity of the wrong type, a syntax error). Entities whose only fault is a name
/// that is not a quoted string (boxed_sphere.step has 295, all harmless) are not counted.
struct Damage {
  int count = 0;
  std::string first;     // the first failure message
  std::string refused;   // the first damage refused (refusedIfDamaged(), a syntax error), described; empty if none
  std::string missing;   // the first entity referred to but not defined ("#932"), if any
};

/// Entities whose damage is refused: geometry (points, curves, surfaces, p-curves) and the topology
/// inside a face (bounds, loops, edges, vertices). OpenCASCADE 7.6's translators dereference their
/// missing parts without a test (screw.step without one CARTESIAN_POINT of a p-curve: SIGSEGV in
/// StepGeom_CartesianPoint::NbCoordinates; fuzzed ANC101.stp copies: in StepShape_FaceBound::Bound
/// and through a null edge loop), which only an application's signal handler turns into an error.
/// A shell or solid missing a face is translated without it, with a warning.
bool refusedIfDamaged(const Handle(Standard_Transient)& ent) {
  if (ent.IsNull()) return false;
  const std::string type = ent->DynamicType()->Name();
  if (type.rfind("StepGeom_", 0) == 0 || type.rfind("IGESGeom_", 0) == 0 || type.rfind("IGESSolid_", 0) == 0)
    return true;
  if (type.rfind("StepShape_", 0) != 0) return false;
  for (const char* whole : {"Shell", "FaceSet", "SurfaceModel", "Brep", "Solid"})
    if (type.find(whole) != std::string::npos) return false;
  return true;
}

/// A failure that leaves a hole in the entity (a reference to an entity that is missing, not an
/// entity or of the wrong kind, or a check that could not even run on it), not a value written
/// sloppily (an integer where a real belongs, which the reader still takes: such files are
/// translated, with a warning).
bool refersToMissing(const std::string& msg) {
  for (const char* hole : {"illegal type", "Unresolved", "not an Entity", "Exception Raised", "Null", "null"})
    if (msg.find(hole) != std::string::npos) return true;
  return false;
}

Damage damagedEntities(XSControl_Reader& r) {
  Damage d;
  const Handle(Interface_InterfaceModel) model = r.WS()->Model();
  Interface_CheckIterator chk = r.WS()->ModelCheckList();
  for (chk.Start(); chk.More(); chk.Next()) {
    const Handle(Interface_Check)& c = chk.Value();
    std::string msg;
    for (int i = 1; i <= c->NbFails() && msg.empty(); ++i) {
      const std::string m = c->CFail(i);
      if (m.find("quoted String") == std::string::npos) msg = m;
    }
    if (msg.empty()) continue;
    ++d.count;
    if (d.first.empty()) d.first = msg;
    // a syntax error in the data: the entity there is dropped, and whatever refers to it holds a
    // null (fuzzed ANC101.stp: SIGSEGV through an edge loop that lost its edges)
    if (d.refused.empty() && msg.find("Incorrect syntax") != std::string::npos) d.refused = msg;
    const size_t id = msg.find("(Id.#");
    if (d.missing.empty() && msg.find("Unresolved Reference") != std::string::npos && id != std::string::npos)
      d.missing = msg.substr(id + 4, msg.find(')', id) - id - 4);
    const int num = chk.Number();
    if (d.refused.empty() && !model.IsNull() && num >= 1 && num <= model->NbEntities()) {
      const Handle(Standard_Transient) ent = model->Value(num);
      if (refusedIfDamaged(ent) && refersToMissing(msg)) {
        const Handle(TCollection_HAsciiString) label = model->StringLabel(ent);
        d.refused = std::string("entity ") + (label.IsNull() ? "number " + std::to_string(num) : label->ToCString()) +
                     " (" + model->TypeName(ent, false) + "): " + msg;
      }
    }
  }
  return d;
}

/// Applies damagedEntities() before the transfer: refuses the damage it would crash on, warns on the rest.
void checkDamage(XSControl_Reader& r, const char* format, const std::string& path,
                 std::vector<std::string>& warnings) {
  const Damage d = damagedEntities(r);
  if (!d.refused.empty())
    throw InputError("'" + path + "' is damaged where the " + format + " reader cannot translate it safely: " +
                     d.refused + (d.missing.empty() ? "" : "; the file refers to " + d.missing + ", which it does not define") +
                     (d.count > 1 ? " (" + std::to_string(d.count) + " damaged entities in all)" : ""));
  if (d.count)
    warnings.push_back(std::string("the ") + format + " reader found " + std::to_string(d.count) +
                       " damaged entities in '" + path + "' (first: " + d.first + "): the shape may lack parts");
}

/// The last non-blank line of a text file (at most its last 4 kB are read).
std::string lastLine(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - 4096);
  in.seekg(from);
  std::string tail((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  size_t e = tail.find_last_not_of(" \t\r\n");
  if (e == std::string::npos) return "";
  size_t b = tail.find_last_of("\r\n", e);
  return tail.substr(b == std::string::npos ? 0 : b + 1, e - (b == std::string::npos ? 0 : b + 1) + 1);
}

/// A STEP or IGES file that does not end as its format ends (a cut-short download) is refused
/// before its reader runs. Kept out of readShapeUnguarded(): an access violation inside a reader
/// jumps (longjmp) back to readShape()'s OCC_CATCH_SIGNALS past the destructors of that frame,
/// so the strings made here would leak (found by fuzz_iges under LeakSanitizer).
void requireWholeFile(const std::string& path, const std::string& ext) {
  if (ext == "step" || ext == "stp") {
    const std::string last = lastLine(path);
    if (last.find("END-ISO-10303-21;") == std::string::npos)
      throw InputError("'" + path + "' is cut short: a STEP file ends with END-ISO-10303-21;");
  } else if (ext == "iges" || ext == "igs") {
    const std::string last = lastLine(path);
    if (last.size() < 73 || last[72] != 'T')
      throw InputError("'" + path + "' is cut short: an IGES file ends with its Terminate (T) section line");
  }
}

/// The readers themselves; readShape() runs them under OCC_CATCH_SIGNALS (after requireWholeFile).
/// Nothing of ParaMesh's own that owns memory may live in this frame across a reader call.
TopoDS_Shape readShapeUnguarded(const std::string& path, const std::string& ext, std::vector<std::string>& warnings) {
  TopoDS_Shape shape;
  if (ext == "step" || ext == "stp") {
    STEPControl_Reader r;
    if (r.ReadFile(path.c_str()) != IFSelect_RetDone) throw InputError("'" + path + "' is not a readable STEP file");
    checkDamage(r, "STEP", path, warnings);
    int n = r.NbRootsForTransfer();
    for (int i = 1; i <= n; ++i) r.TransferRoot(i);
    shape = r.OneShape();
  } else if (ext == "iges" || ext == "igs") {
    IGESControl_Reader r;
    if (r.ReadFile(path.c_str()) != IFSelect_RetDone) throw InputError("'" + path + "' is not a readable IGES file");
    checkDamage(r, "IGES", path, warnings);
    r.ClearShapes();
    r.TransferRoots();
    shape = r.OneShape();
  } else {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!looksLikeBrep(text))
      throw InputError("'" + path + "' is not an OpenCASCADE BREP file (no 'CASCADE Topology' header)");
    shape = readBrepText(text, "'" + path + "'");
  }
  return shape;
}

TopoDS_Shape readShape(const std::string& path, std::vector<std::string>& warnings) {
  const std::string ext = lowerExt(path);
  if (ext == "stl" || ext == "obj")
    throw InputError("'" + path + "' is triangulated input: it is read by loadDiscreteModel, not by OpenCASCADE's CAD readers");
  if (ext != "step" && ext != "stp" && ext != "iges" && ext != "igs" && ext != "brep" && ext != "brp")
    throw InputError("unknown CAD format '." + ext + "' of '" + path +
                     "' (expected .step/.stp, .iges/.igs or .brep/.brp)");
  SilenceOcc silence;
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw InputError("cannot open '" + path + "'");
  }
  requireWholeFile(path, ext);
  TopoDS_Shape shape;
  try {
    // an access violation inside a reader (OCC 7.6's STEP and IGES readers dereference null
    // entities of some damaged files) becomes a Standard_Failure here when the application has
    // installed OpenCASCADE's signal handlers (OccReaderSignalGuard, as the CLI does)
    OCC_CATCH_SIGNALS
    shape = readShapeUnguarded(path, ext, warnings);
  } catch (const Standard_Failure& e) {
    throw InputError("OpenCASCADE could not read '" + path + "': " + e.GetMessageString());
  }
  if (shape.IsNull()) throw InputError("'" + path + "' contains no shape");
  return shape;
}

}  // namespace

std::unique_ptr<IGeometryModel> loadOccModel(const std::string& path) {
  std::vector<std::string> warnings;
  TopoDS_Shape s = readShape(path, warnings);
  try {
    OCC_CATCH_SIGNALS
    return std::make_unique<OccModel>(s, path, std::move(warnings));
  } catch (const Standard_Failure& e) {
    throw InputError("OpenCASCADE failed on '" + path + "': " + e.GetMessageString());
  }
}

std::unique_ptr<IGeometryModel> loadOccModelFromBrepString(const std::string& brep) {
  TopoDS_Shape shape;
  if (!looksLikeBrep(brep))
    throw InputError("not a BREP string (no 'CASCADE Topology' header)");
  SilenceOcc silence;
  try {
    OCC_CATCH_SIGNALS
    shape = readBrepText(brep, "the BREP string");
  } catch (const Standard_Failure& e) {
    throw InputError(std::string("not a valid BREP string: ") + e.GetMessageString());
  }
  if (shape.IsNull()) throw InputError("not a valid BREP string (no shape could be read)");
  try {
    OCC_CATCH_SIGNALS
    return std::make_unique<OccModel>(shape, "BREP string");
  } catch (const Standard_Failure& e) {
    throw InputError(std::string("OpenCASCADE failed on the BREP string: ") + e.GetMessageString());
  }
}

std::string occFileToBrepString(const std::string& path) {
  std::vector<std::string> warnings;
  TopoDS_Shape s = readShape(path, warnings);
  std::ostringstream out;
  BRepTools::Write(s, out);
  return out.str();
}

OccReaderSignalGuard::OccReaderSignalGuard() { OSD::SetSignal(OSD_SignalMode_Set, false); }
OccReaderSignalGuard::~OccReaderSignalGuard() { OSD::SetSignal(OSD_SignalMode_Unset, false); }

std::string occtVersion() { return OCC_VERSION_COMPLETE; }

}  // namespace paramesh
