// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file NglibLoader.cpp
/// fillWithNglib: the nglib plugin (libparamesh_nglib.so) loaded on first use, then called.
#include <dlfcn.h>

#include <cstdlib>
#include <mutex>

#include "paramesh/util/Error.hpp"
#include "paramesh/volume/nglib/NglibFill.hpp"

namespace paramesh {
namespace {

using FillFn = decltype(&paramesh_nglib_fill);
constexpr const char* kPlugin = "libparamesh_nglib.so";

struct Plugin {
  FillFn fill = nullptr;
  std::string error;  // why it could not be loaded
};

/// The directory of the executable or shared module this code is linked into.
std::string ownDirectory() {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&ownDirectory), &info) || !info.dli_fname) return "";
  const std::string path = info.dli_fname;
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

Plugin loadPlugin() {
  Plugin p;
  std::vector<std::string> tried;
  if (const char* env = std::getenv("PARAMESH_NGLIB_PLUGIN"); env && *env) tried.push_back(env);
  if (const std::string dir = ownDirectory(); !dir.empty()) tried.push_back(dir + "/" + kPlugin);
  tried.push_back(kPlugin);  // the dynamic loader's search path
  std::string errors;
  for (const std::string& path : tried) {
    // never closed: nglib keeps global state for the process' life
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      errors += (errors.empty() ? "" : "; ") + (e ? std::string(e) : path);
      continue;
    }
    p.fill = reinterpret_cast<FillFn>(dlsym(h, "paramesh_nglib_fill"));
    if (p.fill) return p;
    errors += (errors.empty() ? "" : "; ") + path + ": no paramesh_nglib_fill";
  }
  p.error = "the volume mesher plugin " + std::string(kPlugin) + " could not be loaded (" + errors + ")";
  return p;
}

}  // namespace

NglibResult fillWithNglib(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                          const NglibOptions& options) {
  static std::once_flag once;
  static Plugin plugin;
  std::call_once(once, [] { plugin = loadPlugin(); });
  if (!plugin.fill) throw Error(plugin.error);
  NglibResult r;
  plugin.fill(&points, &triangles, &options, &r);
  return r;
}

std::string nglibVersion() { return PARAMESH_NGLIB_VERSION; }

}  // namespace paramesh
