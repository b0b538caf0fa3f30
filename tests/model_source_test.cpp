// Fit reports accepted wherever a model is (DESIGN §3).
#include "models/model_source.h"

#include <gtest/gtest.h>

#include "core/errors.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::ScratchDir;

TEST(ModelSource, ReadsTheModelOfAFitReport) {
  ScratchDir dir;
  const std::string path = dir.Write("fit.json", R"({
    "model": "blinn-phong",
    "params": {"rho_d": [0.5, 0.25, 0.125], "rho_s": 0.04, "m": 123.4},
    "stderr": {"rho_d": [0.01, 0.01, 0.01], "rho_s": [0, 0, 0], "m": 2.0},
    "converged": true})");
  const Model model = LoadModel(path);
  EXPECT_EQ(model.name(), "blinn-phong");
  EXPECT_EQ(model.Param("rho_d", 1), 0.25);
  EXPECT_EQ(model.Param("rho_s", 2), 0.04);
  EXPECT_EQ(model.Param("m"), 123.4);
}

TEST(ModelSource, ModelStringsStillWork) {
  EXPECT_EQ(LoadModel("lambert:rho_d=0.3").Param("rho_d", 2), 0.3);
  EXPECT_THROW(LoadModel("nope"), UsageError);
}

TEST(ModelSource, BrokenReportsNameTheFile) {
  ScratchDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"not-json.json", "{ model: phong"},
      {"no-model.json", R"({"params": {}})"},
      {"unknown.json", R"({"model": "cook-torrance", "params": {}})"},
      {"missing-param.json", R"({"model": "phong", "params": {"rho_d": 0.5, "rho_s": 0.1}})"},
      {"bad-shape.json", R"({"model": "phong", "params": {"rho_d": [1, 2], "rho_s": 0, "n": 1}})"},
      {"negative.json", R"({"model": "lambert", "params": {"rho_d": -0.5}})"},
      // Found by fuzz_model_string: a number beyond double range made nlohmann throw
      // out_of_range, which escaped as an internal error.
      {"huge-number.json", "8888888888888E8888888_\xdb________Q______________"},
      {"huge-field.json", R"({"model": "lambert", "params": {"rho_d": 1e999}})"},
  };
  for (const auto& [name, contents] : cases) {
    const std::string path = dir.Write(name, contents);
    try {
      LoadModel(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    }
  }
  EXPECT_THROW(LoadModel(dir.File("absent.json")), InputError);
}

}  // namespace
}  // namespace brdf
