// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Format.hpp
/// Numbers in messages: six significant digits.
#pragma once

#include <sstream>
#include <string>

namespace paramesh {

inline std::string fmt(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

}  // namespace paramesh
