// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file WriterSupport.hpp
/// What the mesh writers share: buffered locale-independent text output, sorted runs of
/// elements, the file extension.
#pragma once
#include <algorithm>
#include <charconv>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "paramesh/io/Json.hpp"
#include "paramesh/io/MeshWriters.hpp"

namespace paramesh {
namespace io {


/// Buffered, locale-independent text output on top of an AtomicFile.
class TextOut {
 public:
  explicit TextOut(const std::string& path) : f_(path) {}
  TextOut& operator<<(std::string_view s) {
    f_.write(s);
    return *this;
  }
  TextOut& operator<<(char c) {
    f_.write(std::string_view(&c, 1));
    return *this;
  }
  template <class T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, char> &&
                                        !std::is_same_v<T, bool>,
                                    int> = 0>
  TextOut& operator<<(T v) {
    char b[32];
    std::to_chars_result r = std::to_chars(b, b + sizeof b, v);
    f_.write(std::string_view(b, static_cast<std::size_t>(r.ptr - b)));
    return *this;
  }
  /// Doubles with 17 significant digits (like printf "%.17g"): exact round trip.
  TextOut& operator<<(double v) {
    char b[40];
    f_.write(std::string_view(b, formatDouble(v, b, 17)));
    return *this;
  }
  void commit() { f_.commit(); }

 private:
  AtomicFile f_;
};

/// Indices 0..n-1 stably sorted by key(i).
template <class Key>
inline std::vector<int> sortedBy(std::size_t n, Key key) {
  std::vector<int> idx(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<int>(i);
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return key(a) < key(b); });
  return idx;
}

/// Calls f(begin, end) for each run of equal key(idx[k]) in idx.
template <class Key, class F>
inline void forEachRun(const std::vector<int>& idx, Key key, F f) {
  for (std::size_t b = 0; b < idx.size();) {
    std::size_t e = b + 1;
    while (e < idx.size() && key(idx[e]) == key(idx[b])) ++e;
    f(b, e);
    b = e;
  }
}

inline std::string lowerExtension(const std::string& path) {
  std::size_t slash = path.find_last_of("/\\");
  std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}


}  // namespace io
}  // namespace paramesh
