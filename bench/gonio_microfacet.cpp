// The virtual gonioreflectometer against microfacet theory (docs/gonio.md): Gaussian height
// fields of rms slope s under a silver-like conductor (exact Fresnel 0.987–0.992 over 0–85°,
// so Schlick's f0 represents it), measured over the hemisphere by `brdf measure`'s own path
// (ideal instrument) and fitted with `beckmann` by `brdf fit`'s library. Beckmann's alpha should
// equal s (DESIGN §2) where single scattering dominates; with one bounce traced (multiple
// scattering cut) at every slope. Written as CSV, one row per (slope, bounces):
//   the generated triangles' slope statistics from their vertices (rms |∇h|, per-axis standard
//   deviations, excess kurtosis of the x slope); alpha, f0 and rho_d fitted with the L2 loss and
//   no sigma weights; alpha with the log loss, no sigma weights; alpha and its standard error
//   with the L2 loss weighted by the sigma column; the traced reflectance at normal incidence
//   (all directions); the wall time of the measurement.
// `--quick` traces fewer rays and slopes (a smoke test); `key=value` arguments change the
// settings (main() lists them). Run through bench/gonio_microfacet_bench.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/angles.h"
#include "fitters/fit.h"
#include "gonio/measure.h"
#include "gonio/surface_sample.h"
#include "gonio/traced_surface.h"
#include "gonio_test_util.h"
#include "models/model_string.h"

namespace brdf::gonio {
namespace {

// A silver-like smooth conductor: its exact Fresnel reflectance stays within 0.987–0.992 up to
// 85°, so Schlick's form with a fitted f0 differs from it by less than 0.5 %.
constexpr const char* kBase = "conductor:ior=0.05:k=4.3";

// The settings of one sweep, from `key=value` arguments (the defaults are the figure's).
struct Settings {
  std::vector<double> slopes = {0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
  std::vector<int> bounces = {1, 8};
  int64_t rays = 400000;
  int resolution = 256;
  double correlation = 4;
  int seed = 1;
  std::string schedule = "hemisphere:theta_i_step=10:theta_o_step=5:phi_o_step=10";
  double max_theta_i_deg = 90;  // incidences beyond are left out
  double detector_sr = 0.001;
};

std::vector<double> ParseList(const std::string& text) {
  std::vector<double> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    values.push_back(std::stod(text.substr(start, end - start)));
    start = end + 1;
  }
  return values;
}

double FitAlpha(const Measurement& measurement, fitters::Loss loss, fitters::FitResult* out) {
  fitters::FitOptions options;
  options.loss = loss;
  *out = fitters::FitModel(measurement, "beckmann", options);
  return out->model.Param("alpha");
}

void Study(const Settings& settings) {
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / "brdfkit_gonio_microfacet.json";
  Schedule schedule = MakeSchedule(settings.schedule);
  std::vector<Incidence> kept;
  for (const Incidence& incidence : schedule.incidences) {
    if (incidence.wi.z() >= std::cos(DegToRad(settings.max_theta_i_deg)) - 1e-9)
      kept.push_back(incidence);
  }
  schedule.incidences = kept;
  std::printf(
      "rms_slope,bounces,facet_rms_slope,facet_sigma_x,facet_sigma_y,facet_kurtosis,alpha_l2,"
      "f0_l2,rho_d_l2,alpha_log,alpha_sigma_weighted,alpha_sigma_weighted_stderr,"
      "reflected_normal,seconds_trace\n");
  for (double slope : settings.slopes) {
    for (int bounces : settings.bounces) {
      {
        std::ofstream json(scratch);
        json << R"({"heightfield": {"kind": "gaussian", "rms_slope": )" << slope
             << R"(, "resolution": )" << settings.resolution << R"(, "seed": )" << settings.seed
             << R"(, "correlation": )" << settings.correlation << R"(}, "base": ")" << kBase
             << R"(", "bounces": )" << bounces << R"(, "rays_per_incidence": )" << settings.rays
             << "}";
      }
      MeasureOptions options;
      options.sample = "surface:" + scratch.string();
      options.instrument = testing::IdealInstrument();
      options.instrument.detector_solid_angle_sr = settings.detector_sr;
      const auto sample = MakeSurfaceSample(scratch.string(), options.instrument);
      const auto& traced = dynamic_cast<const TracedSurfaceSample&>(*sample);
      const testing::FacetSlopes facets = testing::MeasureFacetSlopes(traced.field());
      const auto start = std::chrono::steady_clock::now();
      Measurement measurement = Measure(options, schedule);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      fitters::FitResult weighted(ParseModel("lambert"));
      const double alpha_weighted = FitAlpha(measurement, fitters::Loss::kL2, &weighted);
      measurement.sigma.clear();
      fitters::FitResult l2 = weighted, log = weighted;
      const double alpha_l2 = FitAlpha(measurement, fitters::Loss::kL2, &l2);
      const double alpha_log = FitAlpha(measurement, fitters::Loss::kLog, &log);
      const auto trace =
          traced.TraceIncidence(options.instrument, Vec3(0, 0, 1), {}, 1, 0, settings.rays);
      std::printf("%g,%d,%.5g,%.5g,%.5g,%.3g,%.5g,%.4g,%.3g,%.5g,%.5g,%.3g,%.5g,%.3g\n", slope,
                  bounces, facets.rms, facets.sigma_x, facets.sigma_y, facets.kurtosis, alpha_l2,
                  l2.model.Param("f0"), l2.model.Param("rho_d"), alpha_log, alpha_weighted,
                  weighted.stderr_values[weighted.model.info().shape_slot()],
                  trace.reflected[0] / trace.incident, seconds);
      std::fflush(stdout);
    }
  }
  std::filesystem::remove(scratch);
}

}  // namespace
}  // namespace brdf::gonio

int main(int argc, char** argv) {
  brdf::gonio::Settings settings;
  for (int k = 1; k < argc; ++k) {
    const std::string argument = argv[k];
    const size_t equals = argument.find('=');
    const std::string key = argument.substr(0, equals), value = argument.substr(equals + 1);
    if (argument == "--quick") {
      settings.slopes = {0.1, 0.5};
      settings.rays = 100000;
    } else if (key == "slopes") {
      settings.slopes = brdf::gonio::ParseList(value);
    } else if (key == "bounces") {
      settings.bounces.clear();
      for (double b : brdf::gonio::ParseList(value)) settings.bounces.push_back(int(b));
    } else if (key == "rays") {
      settings.rays = std::stoll(value);
    } else if (key == "resolution") {
      settings.resolution = std::stoi(value);
    } else if (key == "correlation") {
      settings.correlation = std::stod(value);
    } else if (key == "seed") {
      settings.seed = std::stoi(value);
    } else if (key == "schedule") {
      settings.schedule = value;
    } else if (key == "max_theta_i") {
      settings.max_theta_i_deg = std::stod(value);
    } else if (key == "detector_sr") {
      settings.detector_sr = std::stod(value);
    } else {
      std::fprintf(stderr,
                   "usage: gonio_microfacet [--quick] [slopes=A,B,..] [bounces=1,8] [rays=N] "
                   "[resolution=N] [correlation=C] [seed=N] [schedule=SPEC] [max_theta_i=DEG] "
                   "[detector_sr=SR]\n");
      return 2;
    }
  }
  brdf::gonio::Study(settings);
  return 0;
}
