// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file ParamsJson.hpp
/// Meshing parameters from a JSON document (the CLI's --params FILE.json; schema in README.md).
#pragma once
#include <string>

#include "paramesh/pipeline/Params.hpp"

namespace paramesh {

/// Reads the keys present in `text` into p (others keep their value). Unknown keys and wrong
/// types throw ParameterError naming the key.
void applyParamsJson(const std::string& text, MeshParams& p);
/// The same from a file; throws InputError when it cannot be read.
void applyParamsFile(const std::string& path, MeshParams& p);

}  // namespace paramesh
