// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_geometry_load.cpp
/// Tests of the geometry loaders' error paths: missing, empty, truncated and invalid files give a
/// clear error and print nothing.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "paramesh/geom/Geometry.hpp"
#include "paramesh/geom/occ/OccModel.hpp"
#include "paramesh/util/Error.hpp"

using namespace paramesh;


// ---------------------------------------------------------------------------------------------
// Error paths

TEST(Geometry, LoadErrors) {
  EXPECT_THROW(loadOccModelFromBrepString("garbage"), InputError);
  EXPECT_THROW(loadOccModelFromBrepString(""), InputError);
  const std::string missing = "/nonexistent-dir-paramesh/missing_model.step";
  try {
    loadOccModel(missing);
    ADD_FAILURE() << "no exception for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  const std::string txt =
      (std::filesystem::temp_directory_path() / ("paramesh_test_geometry_" + std::to_string(::getpid()) + ".txt"))
          .string();
  {
    std::ofstream o(txt);
    o << "this is not a CAD model\n";
  }
  try {
    loadOccModel(txt);
    ADD_FAILURE() << "no exception for a .txt file";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("format"), std::string::npos) << w;
    EXPECT_NE(w.find(".txt"), std::string::npos) << w;
  }
  std::filesystem::remove(txt);
  // a missing file is reported with its path whatever the extension
  try {
    loadOccModel("/nonexistent-dir-paramesh/notes.txt");
    ADD_FAILURE() << "no exception for a missing .txt file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("notes.txt"), std::string::npos) << e.what();
  }
  // a .brep file whose content is not BREP
  {
    const std::string brep = (std::filesystem::temp_directory_path() /
                              ("paramesh_test_geometry_" + std::to_string(::getpid()) + ".brep"))
                                 .string();
    std::ofstream o(brep);
    o << "not a brep at all\n";
    o.close();
    EXPECT_THROW(loadOccModel(brep), InputError);
    std::filesystem::remove(brep);
  }
}

/// The library never writes to stdout/stderr (util/Log.hpp), also not when the input is invalid.
TEST(Geometry, InvalidBrepIsSilent) {
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_THROW(loadOccModelFromBrepString("garbage"), InputError);
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}
