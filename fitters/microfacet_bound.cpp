#include "fitters/microfacet_bound.h"

#include <tbb/parallel_for.h>

#include <tuple>

#include "core/angles.h"
#include "energy/lobe_quadrature.h"
#include "energy/model_terms.h"

namespace brdf::fitters {
namespace {

// Tolerance of each tabulated albedo: far below the margin (see the header).
constexpr double kTableTolerance = 1e-7;

}  // namespace

double MicrofacetAlbedoTable::NodeAlpha(int j) {
  const double log_min = std::log(kMinAlpha), log_max = std::log(kMaxAlpha);
  return std::exp(log_min + (log_max - log_min) * j / (kAlphaNodes - 1));
}

double MicrofacetAlbedoTable::NodeTheta(int k, double alpha) {
  if (k < kUniformThetaNodes) return DegToRad(k * kUniformThetaStepDeg);
  const int m = k - kUniformThetaNodes;
  const double scale = kMinGrazingScale * std::pow(kMaxGrazingScale / kMinGrazingScale,
                                                   m / double(kGrazingThetaNodes - 1));
  return std::atan(scale / alpha);
}

std::pair<double, double> MicrofacetAlbedoTable::IntegrateNode(const ModelInfo& info, int j,
                                                               int k) {
  LobeQuadratureOptions options;
  options.tolerance = kTableTolerance;
  options.max_intervals = 400;
  const double alpha = NodeAlpha(j);
  // The lobe alone (rho_d = 0); the red channel has its per-channel parameter (f0) at 0, the
  // green at 1.
  std::vector<double> params(info.num_params, 0.0);
  params[info.lobes.front().first_slot + 1] = 1.0;  // the lobe's per-channel parameter
  params[info.shape_slot()] = alpha;
  const Model lobe(info, params);
  const Vec3 wo = SphericalDirection(NodeTheta(k, alpha), 0.0);
  const AlbedoEstimate estimate =
      IntegrateInLobeCoordinates(ModelBrdf(lobe), wo, lobe.Lobe(), options);
  return {estimate.albedo[0], estimate.albedo[1]};
}

MicrofacetAlbedoTable::MicrofacetAlbedoTable(const ModelInfo& info) {
  e0_.assign(NodeCount(), 0.0);
  e1_.assign(NodeCount(), 0.0);
  tbb::parallel_for(0, NodeCount(), [&](int node) {
    std::tie(e0_[node], e1_[node]) = IntegrateNode(info, node / ThetaNodes(), node % ThetaNodes());
  });
}

}  // namespace brdf::fitters
