// Every fit reaches the global optimum of its objective (DESIGN §6): on every bundled real
// file and every lobed rung, the default fit's final cost is compared with a slow exhaustive
// search under the same loss and weighting. The search solves the fit to convergence from every
// width of a dense grid over the rung's whole fitted range (each with the lobe read from the
// data's peak and with a fixed guess), on every sample, without the multi-start's subsample or
// screen; its lowest cost is the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fitters/fit.h"
#include "fitters/fit_samples.h"
#include "io/formats.h"
#include "models/registry.h"
#include "test_util.h"

namespace brdf {
namespace {

using fitters::FitOptions;
using fitters::FitPreparedSamples;
using fitters::PreparedSamples;

// Widths per decade of the one-lobe grid (the default multi-start has about two), and of each
// lobe's grid in the two-lobe search (a grid of pairs, so coarser).
constexpr int kGridPerDecade = 5;
constexpr int kTwoLobeGridPerDecade = 2;

// The bundled real files: those without an evaluator first (their fits are quick), then the
// RGL-EPFL files, fitted under the image loss.
constexpr const char* kQuickFiles[] = {
    "cornell-astm/acryl_blue.astm",          "cornell-astm/cayman.astm",
    "cornell-astm/garnet_red.astm",          "cornell-astm/krylon_blue.astm",
    "cornell-pbrt-v2/mystique.brdf",         "zemax-bsdf/test_13_planesymmetric_brdf_zemax.bsdf",
    "alta-retro/retro-3M-jaune.dat",         "alta-retro/retro-gray-tape.dat",
    "gonio-csv/test_brdf_viewer_2D_data.csv"};
constexpr const char* kRglFiles[] = {
    "rgl-bsdf/cc_ibiza_sunset_rgb.bsdf",  "rgl-bsdf/cc_iris_purple_gem_rgb.bsdf",
    "rgl-bsdf/cg_sunflower_rgb.bsdf",     "rgl-bsdf/colodur_napoli_4f_rgb.bsdf",
    "rgl-bsdf/paper_white_rgb.bsdf",      "rgl-bsdf/satin_rosaline_rgb.bsdf",
    "rgl-bsdf/vch_golden_yellow_rgb.bsdf"};

// A test name from a file's name: its stem, with every other character than a letter or digit
// made '_'.
std::string FileTestName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  name = name.substr(name.find('/') + 1);
  name = name.substr(0, name.find('.'));
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

// `per_decade` log-spaced widths from `low` to `high`, both included.
std::vector<double> LogGrid(double low, double high, int per_decade) {
  const int count = static_cast<int>(std::ceil(per_decade * std::log10(high / low))) + 1;
  std::vector<double> grid(count);
  for (int k = 0; k < count; ++k) {
    grid[k] = low * std::pow(high / low, static_cast<double>(k) / (count - 1));
  }
  return grid;
}

// The file's samples under the default loss, and the default options with that loss.
struct DefaultFit {
  FitOptions options;
  PreparedSamples prepared;
};
DefaultFit PrepareDefaultFit(const char* file) {
  const Measurement measurement = ReadMeasurement(testing::DataPath(file));
  DefaultFit fit;
  fit.options.loss = fitters::ResolveLoss(fitters::Loss::kAuto, measurement);
  fit.prepared = fitters::PrepareSamples(measurement, fit.options.loss);
  return fit;
}

// The options of one fit of the search: every start solved to convergence on every sample.
FitOptions SearchOptions(const FitOptions& defaults) {
  FitOptions options = defaults;
  options.max_samples = 0;
  options.start_iterations = options.max_iterations;
  return options;
}

// The lowest final cost over the exhaustive grid of `model`'s width.
double ExhaustiveCost(const DefaultFit& fit, const std::string& model) {
  const LobeInfo& lobe = FindModel(model).lobes.front();
  double lowest = std::numeric_limits<double>::infinity();
  for (double width : LogGrid(lobe.fit_shape_min, lobe.fit_shape_max, kGridPerDecade)) {
    FitOptions options = SearchOptions(fit.options);
    if (lobe.shape_scale == models::ShapeScale::kRoughness) {
      options.start_alphas = {width};
    } else {
      options.start_exponents = {width};
    }
    const double cost = FitPreparedSamples(fit.prepared, model, options).final_cost;
    if (std::isfinite(cost)) lowest = std::min(lowest, cost);
  }
  return lowest;
}

class GlobalOptimum : public ::testing::TestWithParam<const char*> {};

TEST_P(GlobalOptimum, DefaultFitIsWithinOnePercentOfAnExhaustiveSearch) {
  const DefaultFit fit = PrepareDefaultFit(GetParam());
  // blinn-phong-exact spans blinn-phong's family of lobes (a constant factor rho_s absorbs).
  for (const char* model : {"phong", "blinn-phong", "ggx", "beckmann"}) {
    const double fitted = FitPreparedSamples(fit.prepared, model, fit.options).final_cost;
    const double exhaustive = ExhaustiveCost(fit, model);
    EXPECT_LE(fitted, exhaustive * 1.01)
        << GetParam() << " " << model << ": the default fit's cost " << fitted
        << ", the exhaustive search's " << exhaustive;
  }
}

INSTANTIATE_TEST_SUITE_P(QuickFiles, GlobalOptimum, ::testing::ValuesIn(kQuickFiles), FileTestName);
INSTANTIATE_TEST_SUITE_P(RglFiles, GlobalOptimum, ::testing::ValuesIn(kRglFiles), FileTestName);

// The second lobe, on the files without an evaluator (whose fits are quick): lambert+ggx+ggx's
// default fit (its 196 starts screened, on a subsample) against the lowest cost over every pair
// of distinct widths of a grid of kTwoLobeGridPerDecade, each pair solved to convergence from all
// its starts (both orders, each lobe read from the peak or not) on every sample.
class GlobalOptimumTwoLobes : public ::testing::TestWithParam<const char*> {};

TEST_P(GlobalOptimumTwoLobes, DefaultFitIsWithinOnePercentOfAnExhaustiveSearch) {
  const char* model = "lambert+ggx+ggx";
  const DefaultFit fit = PrepareDefaultFit(GetParam());
  const double fitted = FitPreparedSamples(fit.prepared, model, fit.options).final_cost;
  const LobeInfo& lobe = FindModel(model).lobes.front();
  const std::vector<double> grid =
      LogGrid(lobe.fit_shape_min, lobe.fit_shape_max, kTwoLobeGridPerDecade);
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < grid.size(); ++i) {
    for (size_t j = i + 1; j < grid.size(); ++j) {
      FitOptions options = SearchOptions(fit.options);
      options.start_alphas = {grid[i], grid[j]};
      const double cost = FitPreparedSamples(fit.prepared, model, options).final_cost;
      if (std::isfinite(cost)) lowest = std::min(lowest, cost);
    }
  }
  EXPECT_LE(fitted, lowest * 1.01) << GetParam() << ": the default fit's cost " << fitted
                                   << ", the exhaustive search's " << lowest;
}

INSTANTIATE_TEST_SUITE_P(QuickFiles, GlobalOptimumTwoLobes, ::testing::ValuesIn(kQuickFiles),
                         FileTestName);

}  // namespace
}  // namespace brdf
