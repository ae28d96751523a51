// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file test_params_json_fuzz.cpp
/// Regressions of the JSON parameter front end found by fuzz/fuzz_params_json.cpp (inputs in
/// fuzz/regressions/params_json/): bad input is one ParameterError, one line, naming the problem,
/// never another exception or undefined behaviour.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "paramesh/io/Json.hpp"
#include "paramesh/pipeline/Params.hpp"
#include "paramesh/pipeline/ParamsJson.hpp"
#include "paramesh/util/Error.hpp"

using namespace paramesh;

namespace {

/// The message of the ParameterError applyParamsJson() throws on `text` ("" if it accepts it);
/// any other exception fails the test.
std::string refusal(const std::string& text) {
  MeshParams p;
  try {
    applyParamsJson(text, p);
  } catch (const ParameterError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a ParameterError: " << e.what() << " on " << text;
    return "?";
  }
  return "";
}

bool oneLine(const std::string& s) { return s.find_first_of("\n\r") == std::string::npos; }

std::string fileText(const std::string& rel) {
  std::ifstream in(std::string(PARAMESH_TEST_DATA) + "/../../fuzz/regressions/" + rel);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

// "\uZZZZ" made std::stoul throw std::invalid_argument out of the parser (fuzz finding
// stoul-bad-unicode-escape)
TEST(ParamsJsonFuzz, BadUnicodeEscapeIsOneParameterError) {
  const std::string text = fileText("params_json/stoul-bad-unicode-escape.json");
  ASSERT_FALSE(text.empty());
  for (const std::string& t : {text, std::string("{\"size\": \"\\uZZZZ\"}"), std::string("{\"a\\u12\": 1}"),
                               std::string("{\"a\\u+123\": 1}"), std::string("{\"a\\u 123\": 1}"),
                               std::string("{\"a\\u0x12\": 1}"), std::string("\"\\u")}) {
    const std::string e = refusal(t);
    EXPECT_NE(e.find("bad \\u escape (\\u needs four hex digits)"), std::string::npos) << e;
    EXPECT_EQ(e.rfind("parameter file: JSON: ", 0), 0u) << e;
    EXPECT_TRUE(oneLine(e)) << e;
  }
  // four hex digits still read
  MeshParams p;
  EXPECT_THROW(applyParamsJson("{\"\\u0073ize\": 1, \"x\": 1}", p), ParameterError);  // "x" unknown
  MeshParams q;
  applyParamsJson("{\"\\u0073\\u0069\\u007A\\u0065\": 2.5}", q);
  EXPECT_EQ(q.size, 2.5);
}

// an unknown key holding a line break came back raw in the message (fuzz finding newline-in-key)
TEST(ParamsJsonFuzz, KeyWithLineBreakIsQuotedOnOneLine) {
  const std::string text = fileText("params_json/newline-in-key.json");
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(refusal(text), "parameter file: unknown key 'a\\nb'");
  EXPECT_EQ(refusal("{\"a\\r\\tb\\u0001\": 1}"), "parameter file: unknown key 'a\\r\\tb\\x01'");
  const std::string e = refusal("{\"boundary_layers\": [{\"x\\ny\": 1}]}");
  EXPECT_EQ(e, "boundary_layers[0]: unknown key 'x\\ny'");
  const std::string ls = refusal("{\"local_sizes\": [\"Fa\\nce3=1\"]}");
  EXPECT_TRUE(oneLine(ls)) << ls;
  EXPECT_NE(ls.find("'Fa\\nce3'"), std::string::npos) << ls;
  // a long key is cut
  const std::string lk = refusal("{\"" + std::string(500, 'k') + "\": 1}");
  EXPECT_LT(lk.size(), 120u) << lk;
  EXPECT_NE(lk.find("...'"), std::string::npos) << lk;
}

// integers beyond int's range: a ParameterError, not a cast beyond range (UBSan float-cast-overflow)
TEST(ParamsJsonFuzz, IntegerOutOfRangeIsAParameterError) {
  for (const char* t : {"{\"threads\": 1e300}", "{\"order\": -1e19}", "{\"proximity\": 99999999999999999999}",
                        "{\"optimize_passes\": 4294967296}", "{\"boundary_layers\": [{\"edges\": [1e12]}]}"}) {
    const std::string e = refusal(t);
    EXPECT_NE(e.find("must be an integer in the range of int"), std::string::npos) << t << ": " << e;
  }
  EXPECT_NE(refusal("{\"threads\": 1.5}").find("'threads' must be an integer (got 1.5)"), std::string::npos);
  MeshParams p;
  applyParamsJson("{\"threads\": 2147483647, \"order\": 2.0}", p);
  EXPECT_EQ(p.threads, 2147483647);
  EXPECT_EQ(p.order, 2);
}

// a JSON integer beyond int64 reads as its double value (strtoll clamped it to INT64_MAX)
TEST(ParamsJsonFuzz, HugeIntegerLiteralReadsAsDouble) {
  const Json j = Json::parse("[123456789012345678901234567890]");
  EXPECT_DOUBLE_EQ(j.at(size_t{0}).number(), 1.2345678901234568e29);
}

// "FaceN=size" must be read whole: "Face3x=1" and "Face3=1mm" were taken as Face3 = 1
TEST(ParamsJsonFuzz, LocalSizeStringIsReadWhole) {
  for (const char* t : {"Face3x=1", "Face3=1mm", "Face=1", "Face+3=1", "Face3=", "Face99999999999=1"}) {
    const std::string e = refusal(std::string("{\"local_sizes\": [\"") + t + "\"]}");
    EXPECT_EQ(e, std::string("local_sizes[0]: cannot read '") + t + "'") << e;
  }
  MeshParams p;
  applyParamsJson("{\"local_sizes\": [\"Edge12=0.25\"]}", p);
  ASSERT_EQ(p.localSizes.size(), 1u);
  EXPECT_EQ(p.localSizes[0].entities, std::vector<int>{12});
  EXPECT_EQ(p.localSizes[0].size, 0.25);
}
