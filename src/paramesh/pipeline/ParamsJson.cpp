// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/pipeline/ParamsJson.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "paramesh/io/Json.hpp"
#include "paramesh/util/Error.hpp"
#include "paramesh/util/Format.hpp"

namespace paramesh {

namespace {

/// A key or value of the input quoted back in a message: between '...', its control characters
/// written as escapes (a key "a\nb" must not break the message's one line, util/Error.hpp), cut
/// after 60 characters.
std::string quoted(const std::string& s) {
  static const char* hex = "0123456789abcdef";
  std::string out = "'";
  for (size_t i = 0; i < s.size(); ++i) {
    if (i == 60) {
      out += "...";
      break;
    }
    const unsigned char c = (unsigned char)s[i];
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 0xF];
    } else {
      out += (char)c;
    }
  }
  return out + "'";
}

double num(const Json& j, const std::string& key) {
  double v = 0;
  try {
    v = j.number();
  } catch (const Error&) {
    throw ParameterError("parameter " + quoted(key) + " must be a number");
  }
  // 1e999 reads as inf; NaN would read as a length left out (kNotGiven)
  if (!std::isfinite(v)) throw ParameterError("parameter " + quoted(key) + " must be a finite number");
  return v;
}
/// A boundary-layer value that is derived when left out: a given one must be > 0.
double positive(double v, const std::string& key, const char* leftOut) {
  if (!(v > 0))
    throw ParameterError("parameter " + quoted(key) + " must be > 0 (got " + fmt(v) + "); leave it out " + leftOut);
  return v;
}
int integer(const Json& j, const std::string& key) {
  const double v = num(j, key);
  // range first: casting a double beyond int's range is undefined behaviour
  if (!(v >= -2147483648.0 && v <= 2147483647.0))
    throw ParameterError("parameter " + quoted(key) + " must be an integer in the range of int (got " + fmt(v) + ")");
  if (v != std::trunc(v)) throw ParameterError("parameter " + quoted(key) + " must be an integer (got " + fmt(v) + ")");
  return (int)v;
}
bool boolean(const Json& j, const std::string& key) {
  try {
    return j.boolean();
  } catch (const Error&) {
    throw ParameterError("parameter " + quoted(key) + " must be true or false");
  }
}
std::vector<int> ints(const Json& j, const std::string& key) {
  std::vector<int> out;
  if (!j.isArray()) {
    out.push_back(integer(j, key));
    return out;
  }
  for (size_t i = 0; i < j.size(); ++i) out.push_back(integer(j.at(i), key + "[" + std::to_string(i) + "]"));
  return out;
}

LocalSize localSize(const Json& j, const std::string& key) {
  LocalSize l;
  if (j.type() == Json::Type::String) {
    const std::string s = j.str();
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw ParameterError(key + ": expected 'FaceN=size', got " + quoted(s));
    const std::string name = s.substr(0, eq);
    std::string digits;
    if (name.rfind("Face", 0) == 0) { l.kind = LocalSize::Kind::Face; digits = name.substr(4); }
    else if (name.rfind("Edge", 0) == 0) { l.kind = LocalSize::Kind::Edge; digits = name.substr(4); }
    else if (name.rfind("Vertex", 0) == 0) { l.kind = LocalSize::Kind::Vertex; digits = name.substr(6); }
    else throw ParameterError(key + ": expected FaceN, EdgeN or VertexN, got " + quoted(name));
    // the whole of both parts: std::stoi("3x") would give 3
    const std::string value = s.substr(eq + 1);
    size_t usedDigits = 0, usedValue = 0;
    try {
      l.entities = {std::stoi(digits, &usedDigits)};
      l.size = std::stod(value, &usedValue);
    } catch (const std::exception&) {
      throw ParameterError(key + ": cannot read " + quoted(s));
    }
    if (usedDigits != digits.size() || usedValue != value.size() || digits.empty() || !std::isdigit((unsigned char)digits[0]))
      throw ParameterError(key + ": cannot read " + quoted(s));
    return l;
  }
  if (!j.isObject()) throw ParameterError(key + " must be an object or a 'FaceN=size' string");
  int kinds = 0;
  for (const std::string& k : j.keys()) {
    if (k == "faces") { l.kind = LocalSize::Kind::Face; l.entities = ints(j.at(k), key + ".faces"); ++kinds; }
    else if (k == "edges") { l.kind = LocalSize::Kind::Edge; l.entities = ints(j.at(k), key + ".edges"); ++kinds; }
    else if (k == "vertices") { l.kind = LocalSize::Kind::Vertex; l.entities = ints(j.at(k), key + ".vertices"); ++kinds; }
    else if (k == "size") l.size = num(j.at(k), key + ".size");
    else throw ParameterError(key + ": unknown key " + quoted(k));
  }
  if (kinds != 1) throw ParameterError(key + ": give exactly one of faces, edges, vertices");
  return l;
}

BoundaryLayerSpec boundaryLayer(const Json& j, const std::string& key) {
  if (!j.isObject()) throw ParameterError(key + " must be an object");
  BoundaryLayerSpec b;
  for (const std::string& k : j.keys()) {
    const Json& v = j.at(k);
    const std::string kk = key + "." + k;
    if (k == "edges") b.edges = ints(v, kk);
    else if (k == "first_height") b.firstHeight = num(v, kk);
    else if (k == "growth") b.growth = num(v, kk);
    else if (k == "layers") b.layers = (int)positive(integer(v, kk), kk, "to derive it from thickness");
    else if (k == "thickness") b.thickness = positive(num(v, kk), kk, "to derive it from layers");
    else if (k == "max_aspect") b.maxAspect = num(v, kk);
    else if (k == "quads") b.quads = boolean(v, kk);
    else throw ParameterError(key + ": unknown key " + quoted(k));
  }
  return b;
}

}  // namespace

void applyParamsJson(const std::string& text, MeshParams& p) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Error& e) {
    throw ParameterError(std::string("parameter file: ") + e.what());
  }
  if (!j.isObject()) throw ParameterError("parameter file: the top level must be an object");
  for (const std::string& k : j.keys()) {
    const Json& v = j.at(k);
    if (k == "size") p.size = num(v, k);
    else if (k == "min_size") p.minSize = num(v, k);
    else if (k == "max_size") p.maxSize = num(v, k);
    else if (k == "curvature_angle") p.curvatureAngle = num(v, k);
    else if (k == "max_deviation") p.maxDeviation = num(v, k);
    else if (k == "grading") p.grading = num(v, k);
    else if (k == "threads") p.threads = integer(v, k);
    else if (k == "order") p.order = integer(v, k);
    else if (k == "quads") p.quads = boolean(v, k);
    else if (k == "volume") p.volume = boolean(v, k);
    else if (k == "volume_max_size") p.volumeMaxSize = num(v, k);
    else if (k == "volume_optimize") p.volumeOptimize = integer(v, k);
    else if (k == "optimize_passes") p.optimizePasses = integer(v, k);
    else if (k == "max_elements") p.maxElements = checkedMaxElements(num(v, k));
    else if (k == "proximity") p.proximity = integer(v, k);
    else if (k == "nearest_face_check") p.nearestFaceCheck = boolean(v, k);
    else if (k == "nearest_face_budget") p.nearestFaceBudget = num(v, k);
    else if (k == "local_sizes") {
      if (!v.isArray()) throw ParameterError("parameter 'local_sizes' must be a list");
      for (size_t i = 0; i < v.size(); ++i) p.localSizes.push_back(localSize(v.at(i), "local_sizes[" + std::to_string(i) + "]"));
    } else if (k == "groups") {
      // {"inlet": ["Face3", "Face7"], ...} or ["inlet=Face3,Face7", ...]
      if (v.isObject()) {
        for (const std::string& name : v.keys()) {
          const Json& list = v.at(name);
          if (!list.isArray()) throw ParameterError("groups." + name + " must be a list like [\"Face3\", \"Face7\"]");
          std::string text = name + "=";
          for (size_t i = 0; i < list.size(); ++i) {
            if (list.at(i).type() != Json::Type::String) throw ParameterError("groups." + name + " must hold names like \"Face3\"");
            text += (i ? "," : "") + list.at(i).str();
          }
          p.groups.push_back(parseGroup(text));
        }
      } else if (v.isArray()) {
        for (size_t i = 0; i < v.size(); ++i) {
          if (v.at(i).type() != Json::Type::String) throw ParameterError("groups[" + std::to_string(i) + "] must read \"NAME=Face3,Face7\"");
          p.groups.push_back(parseGroup(v.at(i).str()));
        }
      } else {
        throw ParameterError("parameter 'groups' must be an object {\"NAME\": [\"Face3\", ...]} or a list");
      }
    } else if (k == "boundary_layers") {
      if (!v.isArray()) throw ParameterError("parameter 'boundary_layers' must be a list");
      for (size_t i = 0; i < v.size(); ++i)
        p.boundaryLayers.push_back(boundaryLayer(v.at(i), "boundary_layers[" + std::to_string(i) + "]"));
    } else {
      throw ParameterError("parameter file: unknown key " + quoted(k));
    }
  }
}

void applyParamsFile(const std::string& path, MeshParams& p) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open the parameter file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  applyParamsJson(ss.str(), p);
}

}  // namespace paramesh
