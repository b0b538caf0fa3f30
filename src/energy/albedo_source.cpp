#include "energy/albedo_source.h"

#include "models/model_source.h"

namespace brdf {
namespace {

nlohmann::json RgbJson(const Rgb& value) { return {value[0], value[1], value[2]}; }

}  // namespace

AlbedoCurve SourceAlbedoCurve(const std::string& source, const AlbedoOptions& options,
                              Progress* progress) {
  if (IsModelSpec(source)) return ModelAlbedoCurve(LoadModel(source), options, progress);
  return MeasuredAlbedoCurve(LoadMeasuredBrdf(source), options, progress);
}

nlohmann::json AlbedoCurveJson(const AlbedoCurve& curve, double seconds) {
  nlohmann::json albedo = nlohmann::json::array();
  for (const AlbedoPoint& point : curve.points) {
    albedo.push_back({{"theta_deg", point.theta_deg},
                      {"rgb", RgbJson(point.estimate.albedo)},
                      {"error", RgbJson(point.estimate.error)},
                      {"coverage", point.estimate.coverage}});
  }
  const EnergyVerdict verdict = curve.verdict();
  return {{"source", curve.source},
          {"method", AlbedoMethodName(curve.method)},
          {"max_albedo", RgbJson(curve.max_albedo)},
          {"max_albedo_error", RgbJson(curve.error_at_max)},
          {"theta_deg_at_max",
           {curve.theta_deg_at_max[0], curve.theta_deg_at_max[1], curve.theta_deg_at_max[2]}},
          {"albedo", albedo},
          {"verdict", verdict.name()},
          {"reason", verdict.reason},
          {"excess", curve.excess()},
          {"largest_measured_incidence_deg", curve.largest_measured_incidence_deg},
          {"min_coverage", curve.min_coverage},
          {"notes", curve.notes},
          {"warnings", curve.warnings},
          {"evaluations", curve.evaluations},
          {"time_s", seconds}};
}

}  // namespace brdf
