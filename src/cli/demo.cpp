#include "cli/demo.h"

#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli/albedo_plot.h"
#include "cli/fit_options.h"
#include "cli/slice_plot.h"
#include "core/angles.h"
#include "core/atomic_file.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/format.h"
#include "energy/albedo.h"
#include "export/export.h"
#include "fitters/report.h"
#include "gonio/measure.h"
#include "io/formats.h"
#include "models/model_string.h"
#include "render/comparison_sheet.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/sphere.h"
#include "render/view_page.h"

namespace brdf::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Steps are announced on stderr when it is a terminal (DESIGN §3).
class Steps {
 public:
  Steps(int total, bool quiet) : total_(total), enabled_(!quiet && ::isatty(STDERR_FILENO)) {}
  void Announce(const std::string& what) {
    if (enabled_) std::cerr << "[" << ++done_ << "/" << total_ << "] " << what << "\n";
  }

 private:
  int total_, done_ = 0;
  bool enabled_;
};

// Measurement files under `directory`: those a reader claims by their content (an HDR image
// beside them is not one), in a stable order.
std::vector<std::string> FindMeasurements(const std::string& directory) {
  if (!fs::is_directory(directory)) {
    throw UsageError(directory + ": not a directory (give the bundled data with --data DIR)");
  }
  std::vector<std::string> paths;
  for (const auto& entry : fs::recursive_directory_iterator(directory)) {
    if (entry.is_regular_file() && FormatByContent(entry.path().string()) != nullptr) {
      paths.push_back(entry.path().string());
    }
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// Whether two measurements hold the same samples (the same data in two layouts, as the pbrt-v2
// copies of the Cornell files are): equal directions and values to 1e-6, relative.
bool SameSamples(const Measurement& a, const Measurement& b) {
  if (a.samples.size() != b.samples.size()) return false;
  for (size_t k = 0; k < a.samples.size(); ++k) {
    const Sample& x = a.samples[k];
    const Sample& y = b.samples[k];
    if ((x.wi - y.wi).norm() > 1e-6 || (x.wo - y.wo).norm() > 1e-6 ||
        ((x.value - y.value).abs() > 1e-6 * (1 + x.value.abs())).any()) {
      return false;
    }
  }
  return true;
}

// Scattered samples (no evaluator) are previewed by interpolation, whose cost grows with their
// number: the 262,144 cells of the BRDF slice image alone took minutes to render, far beyond the
// demo's budget. Larger files are listed, not fitted.
constexpr size_t kMaxScatteredSamplesFitted = 20000;

// The real files the demo fits: the first file (by path) of every format among `bundled`, so
// that each reader's data is fitted once, passing over a file whose samples repeat those of a file
// listed before it (the pbrt-v2 copies of the Cornell ASTM files) and large scattered files.
std::vector<std::pair<std::string, Measurement>> ChooseRealData(
    const std::vector<std::string>& bundled) {
  std::vector<std::pair<std::string, Measurement>> chosen;
  std::vector<Measurement> earlier;
  std::vector<const FileFormat*> formats_done;
  for (const std::string& path : bundled) {
    const FileFormat* format = FormatByContent(path);
    Measurement measurement = ReadMeasurement(path);
    const bool repeat = std::any_of(earlier.begin(), earlier.end(), [&](const Measurement& other) {
      return SameSamples(other, measurement);
    });
    const bool format_done =
        std::find(formats_done.begin(), formats_done.end(), format) != formats_done.end();
    const bool too_large =
        measurement.tabulated == nullptr && measurement.samples.size() > kMaxScatteredSamplesFitted;
    if (!repeat && !format_done && !too_large) {
      formats_done.push_back(format);
      chosen.emplace_back(path, measurement);
    }
    earlier.push_back(std::move(measurement));
  }
  return chosen;
}

// The three simulated samples: what a gonioreflectometer, an image-based sphere rig and a
// micro-geometry simulation would each hand a user.
struct SimulatedSample {
  const char* name;
  const char* title;
  const char* truth;  // model string, or "" when there is no analytic truth
  std::string sample;
  std::string schedule;
};

std::vector<SimulatedSample> SimulatedSamples(const DemoOptions& options,
                                              const std::string& surface_json) {
  const bool quick = options.quick;
  return {
      {"matte", "Matte paint (flat analytic sample, full hemisphere)", "lambert:rho_d=0.6,0.45,0.3",
       "model:lambert:rho_d=0.6,0.45,0.3", DemoSchedule("matte", quick)},
      {"plastic-sphere", "Glossy red plastic (image-based: rasterized sphere)",
       "blinn-phong:rho_d=0.25,0.05,0.04:rho_s=0.2:m=200",
       "sphere:blinn-phong:rho_d=0.25,0.05,0.04:rho_s=0.2:m=200",
       DemoSchedule("plastic-sphere", quick)},
      {"rough-gold", "Rough gold micro-surface (ray traced with Embree, full hemisphere)", "",
       "surface:" + surface_json, DemoSchedule("rough-gold", quick)},
  };
}

// A rough gold surface (complex IOR of gold at ~650/550/450 nm, Johnson & Christy 1972) with
// as many rays as the run can afford.
std::string WriteSurfaceSample(const std::string& directory, bool quick) {
  const std::string path = directory + "/rough-gold-surface.json";
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "{\n  \"heightfield\": {\"kind\": \"gaussian\", \"rms_slope\": 0.3, \"resolution\": "
        << (quick ? 128 : 256) << ", \"seed\": 1, \"correlation\": 4},\n"
        << "  \"base\": \"conductor:ior=0.18,0.42,1.37:k=3.42,2.35,1.77\",\n"
        << "  \"bounces\": 8,\n  \"rays_per_incidence\": " << (quick ? 100000 : 1000000) << "\n}\n";
  });
  return path;
}

double MaxRelativeError(const Model& fitted, const Model& truth) {
  double worst = 0;
  for (size_t p = 0; p < truth.params().size(); ++p) {
    if (truth.params()[p] == 0) continue;
    worst = std::max(worst, std::abs(fitted.params()[p] / truth.params()[p] - 1));
  }
  return worst;
}

void FitDataset(const Measurement& measurement, const DemoOptions& options,
                const std::string& out_dir, DemoDataset* dataset) {
  // The log loss (Löw et al. 2012) weighs errors relative to the value, so a 600 sr^-1
  // highlight does not drown the diffuse floor a preview shows everywhere else.
  fitters::FitOptions fit_options;
  fit_options.loss = fitters::Loss::kLog;
  if (options.quick) {
    fit_options.max_samples = 5000;
    fit_options.start_exponents = {4, 64, 1024, 16384};
  }
  const auto start = Clock::now();
  fitters::SelectAndFit(measurement, fit_options, &dataset->selection, &dataset->fits);
  for (size_t k = 0; k < dataset->fits.size(); ++k) {
    const fitters::FitResult& fit = dataset->fits[k];
    if (fit.model.name() == dataset->selection.chosen) dataset->chosen = k;
    const std::string relative = "fits/" + dataset->name + "-" + fit.model.name() + ".json";
    const bool chosen = fit.model.name() == dataset->selection.chosen;
    const nlohmann::json report = fitters::FitReportJson(fit, dataset->measurement_path,
                                                         chosen ? &dataset->selection : nullptr);
    WriteFileAtomically(out_dir + "/" + relative,
                        [&](std::ostream& out) { out << report.dump(2) << "\n"; });
    dataset->fit_paths.push_back(relative);
  }
  if (!dataset->truth.empty()) {
    const Model truth = ParseModel(dataset->truth);
    for (const fitters::FitResult& fit : dataset->fits) {
      if (fit.model.name() == truth.name()) {
        dataset->truth_error = MaxRelativeError(fit.model, truth);
      }
    }
  }
  // The chosen fit's albedo curve, as a chart.
  const fitters::FitResult& chosen = dataset->fits[dataset->chosen];
  AlbedoCurve curve = ModelAlbedoCurve(chosen.model, AlbedoOptions{});
  curve.source = chosen.model.ToString(7);  // the chart's title, for a person: 7 digits
  const std::string plot = "images/" + dataset->name + "-albedo.png";
  WriteAlbedoPlot(curve, out_dir + "/" + plot);
  dataset->images.push_back({"directional albedo of the " + chosen.model.name() + " fit", plot});
  // The plane of incidence: the measured samples and every model's curve (Ngan et al. 2005).
  std::vector<SliceCurve> curves;
  for (const fitters::FitResult& fit : dataset->fits) {
    const Model& model = fit.model;
    curves.push_back({model.name() + (&fit == &chosen ? " (chosen)" : ""),
                      [&model](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); }});
  }
  // The chosen fit exported to every renderer target, measured on the fit's samples.
  exporters::ExportRequest request;
  request.fit = chosen.model;
  request.samples = exporters::SamplesForExport(measurement);
  for (const exporters::ExportedMaterial& material :
       exporters::ExportMaterials(request, exporters::AllTargets())) {
    const exporters::Target target = material.target;
    const std::string path =
        "exports/" + dataset->name + "-" + chosen.model.name() + exporters::TargetExtension(target);
    WriteFileAtomically(out_dir + "/" + path, [&](std::ostream& out) { out << material.text; });
    dataset->exports.push_back({exporters::TargetName(target), path, material.material,
                                material.exact, material.error.log_rmse,
                                material.error.max_relative, material.warnings});
  }
  if (!ExtractSlices(measurement).empty()) {
    const std::string slices = "images/" + dataset->name + "-slices.png";
    WriteSlicePlot(measurement, curves, "plane of incidence: " + dataset->title,
                   out_dir + "/" + slices);
    dataset->images.push_back(
        {"plane of incidence: measured samples (+- sigma) and every model's fit", slices});
  }
  dataset->seconds += SecondsSince(start);
}

// Illuminance in lux that the environment gives a plane facing the camera (+z): the integral of
// its luminance times the cosine over that hemisphere, 90 x 360 cells in (theta, phi).
double IlluminanceTowardCamera(const Environment& environment) {
  constexpr int kTheta = 90, kPhi = 360;
  const double d_theta = 0.5 * kPi / kTheta, d_phi = 2 * kPi / kPhi;
  double irradiance = 0;
  for (int i = 0; i < kTheta; ++i) {
    const double theta = (i + 0.5) * d_theta;
    for (int j = 0; j < kPhi; ++j) {
      const Vec3 omega = SphericalDirection(theta, (j + 0.5) * d_phi);
      irradiance += Luminance(environment.Radiance(omega)) * std::cos(theta) * std::sin(theta);
    }
  }
  // 683 lm/W turns W/m^2 into lux as it turns W/(m^2 sr) into cd/m^2.
  return RadianceToNits(irradiance * d_theta * d_phi);
}

// The brightest pixel of a rendered sphere, cd/m^2.
double PeakNits(const Image& radiance) {
  double peak = 0;
  for (int64_t k = 0; k < radiance.pixel_count(); ++k) {
    peak = std::max(peak, double(PixelLuminance(radiance.rgba.data() + k * Image::kChannels)));
  }
  return RadianceToNits(peak);
}

// Measured and fitted spheres side by side with the relative error, under the HDR environment
// and under a daylight preset (DESIGN §8 sheets), through one tone pipeline each. The captions
// give the lighting in lux and each sphere's peak luminance in cd/m^2 (nits).
void RenderSheets(const DemoOptions& options, const Environment& environment,
                  DemoDataset* dataset) {
  const auto start = Clock::now();
  const std::string measured_spec = dataset->kind == "simulated"
                                        ? options.out_dir + "/" + dataset->measurement_path
                                        : dataset->measurement_path;
  const std::string fitted_spec = options.out_dir + "/" + dataset->fit_paths[dataset->chosen];
  const std::unique_ptr<Material> measured = LoadMaterial(measured_spec);
  const std::unique_ptr<Material> fitted = LoadMaterial(fitted_spec);
  dataset->view_path = "views/" + dataset->name + ".html";
  WriteViewPage({measured_spec, fitted_spec}, options.out_dir + "/" + dataset->view_path);
  RenderOptions render;
  render.size = options.quick ? 128 : 256;
  render.spp = options.quick ? 8 : 32;
  render.seed = 1;
  const std::string fit_label = dataset->fits[dataset->chosen].model.name() + " fit";
  struct Lighting {
    const char* name;
    const std::string& caption;
    std::vector<DirectionalLight> lights;
    const Environment* environment;
  };
  const IlluminancePreset* sunny = nullptr;
  for (const IlluminancePreset& preset : IlluminancePresets()) {
    if (preset.name == "sunny") sunny = &preset;
  }
  if (sunny == nullptr) throw ComputeError("the 'sunny' illuminance preset is missing");
  const std::string env_caption =
      Format("under the Venice sunset environment (%.4g lx on a plane facing the camera)",
             IlluminanceTowardCamera(environment));
  const std::string sunny_caption =
      Format("under the 'sunny' preset (%s: %.5g lx on a plane facing the light)",
             sunny->description.c_str(), sunny->lux);
  const Lighting lightings[] = {
      {"env", env_caption, {}, &environment},
      {"sunny", sunny_caption, {PresetLight("sunny")}, nullptr},
  };
  for (const Lighting& lighting : lightings) {
    const RenderResult a = RenderSphere(*measured, lighting.lights, lighting.environment, render);
    const RenderResult b = RenderSphere(*fitted, lighting.lights, lighting.environment, render);
    const ComparisonSheet sheet =
        ToneMapAndCompare(a.radiance, b.radiance, ToneOptions{}, "measured", fit_label);
    const std::string path = "images/" + dataset->name + "-" + lighting.name + ".png";
    WritePng(options.out_dir + "/" + path, sheet.sheet);
    const std::string peaks = Format("; peak luminance %.4g cd/m^2 measured, %.4g fitted",
                                     PeakNits(a.radiance), PeakNits(b.radiance));
    dataset->images.push_back({"measured | fitted | colour error map, " + lighting.caption + ": " +
                                   sheet.Summary() + peaks,
                               path});
  }
  dataset->seconds += SecondsSince(start);
}

}  // namespace

DemoResult RunDemo(const DemoOptions& options) {
  const auto start = Clock::now();
  DemoResult result;
  const std::vector<std::string> bundled = FindMeasurements(options.data_dir);
  if (bundled.empty()) throw UsageError(options.data_dir + ": no measurement files found");
  for (const char* sub : {"measurements", "fits", "images", "exports", "views"}) {
    std::error_code error;
    fs::create_directories(options.out_dir + "/" + sub, error);
    if (error) {
      throw OutputError(options.out_dir, "cannot create the output directory: " + error.message());
    }
  }
  std::vector<std::pair<std::string, Measurement>> real = ChooseRealData(bundled);
  const std::string surface_json = WriteSurfaceSample(options.out_dir, options.quick);
  const std::vector<SimulatedSample> simulated = SimulatedSamples(options, surface_json);
  Steps steps(static_cast<int>(2 + 2 * simulated.size() + real.size()), options.quiet);

  steps.Announce("summarizing " + std::to_string(bundled.size()) + " bundled measurements");
  for (const std::string& path : bundled) {
    SummaryRow row = SummarizeFile(path);
    row.path = fs::relative(path, options.data_dir).string();
    row.measurement.samples.clear();
    result.bundled.push_back(std::move(row));
  }

  for (const SimulatedSample& sample : simulated) {
    steps.Announce("measuring " + std::string(sample.name) + " (" + sample.sample + ", " +
                   sample.schedule + ")");
    DemoDataset dataset;
    dataset.name = sample.name;
    dataset.title = sample.title;
    dataset.kind = "simulated";
    dataset.source = sample.sample;
    dataset.truth = sample.truth;
    const auto measure_start = Clock::now();
    gonio::MeasureOptions measure;
    measure.sample = sample.sample;
    measure.schedule = sample.schedule;
    measure.seed = 1;
    const Measurement measurement = gonio::Measure(measure, gonio::MakeSchedule(sample.schedule));
    dataset.measurement_path = "measurements/" + dataset.name + ".csv";
    WriteMeasurement(measurement, options.out_dir + "/" + dataset.measurement_path);
    dataset.samples = measurement.samples.size();
    dataset.seconds = SecondsSince(measure_start);
    steps.Announce("fitting every model to " + dataset.name);
    FitDataset(measurement, options, options.out_dir, &dataset);
    result.datasets.push_back(std::move(dataset));
  }

  for (auto& [path, measurement] : real) {
    steps.Announce("fitting every model to " + fs::relative(path, options.data_dir).string());
    DemoDataset dataset;
    dataset.name = fs::path(path).stem().string();
    dataset.kind = "real";
    dataset.source = fs::relative(path, options.data_dir).string();
    dataset.measurement_path = path;
    dataset.title = measurement.SampleName() + " (" + measurement.format + ", real)";
    dataset.samples = measurement.samples.size();
    FitDataset(measurement, options, options.out_dir, &dataset);
    measurement = Measurement();  // fitted: its samples are not needed again
    result.datasets.push_back(std::move(dataset));
  }
  steps.Announce("rendering measured-vs-fitted sheets");
  const Environment environment = Environment::Load(options.data_dir + "/hdr/venice_sunset_1k.hdr");
  tbb::parallel_for(size_t{0}, result.datasets.size(),
                    [&](size_t k) { RenderSheets(options, environment, &result.datasets[k]); });
  if (options.quick) {
    result.notes.push_back(
        "--quick: coarser schedules, fewer rays and a 5,000-sample fit subsample");
  }
  for (const SummaryRow& row : result.bundled) {
    if (row.measurement.tabulated == nullptr && row.summary.samples > kMaxScatteredSamplesFitted) {
      result.notes.push_back(row.path + ": " + std::to_string(row.summary.samples) +
                             " scattered samples, listed but not fitted (the demo fits files of "
                             "up to " +
                             std::to_string(kMaxScatteredSamplesFitted) +
                             "; brdf fit takes any size)");
    }
  }
  result.seconds = SecondsSince(start);
  return result;
}

void PrintDemoSummary(std::ostream& out, const DemoResult& result) {
  out << "Bundled real measurements (" << result.bundled.size() << " files):\n";
  PrintSummaryTable(out, result.bundled);
  out << "\nFits (--model auto --loss log over " << ModelNames()
      << "; energy integrated over 90 incidence angles):\n";
  out << Format("%-16s %-9s %8s %-17s %10s %10s %-22s %-10s %7s\n", "dataset", "kind", "samples",
                "chosen", "rmse", "log rmse", "max albedo r,g,b", "energy", "truth");
  for (const DemoDataset& dataset : result.datasets) {
    const fitters::FitResult& fit = dataset.fits[dataset.chosen];
    const std::string albedo = Format("%.3f,%.3f,%.3f", fit.energy.max_albedo[0],
                                      fit.energy.max_albedo[1], fit.energy.max_albedo[2]);
    const std::string truth =
        dataset.truth_error >= 0 ? Format("%.2g", dataset.truth_error) : std::string("-");
    out << Format("%-16s %-9s %8zu %-17s %10.4g %10.4g %-22s %-10s %7s\n",
                  dataset.name.substr(0, 16).c_str(), dataset.kind.c_str(), dataset.samples,
                  fit.model.name().c_str(), fit.metrics.rmse, fit.metrics.log_rmse, albedo.c_str(),
                  fit.energy.verdict.name(), truth.c_str());
  }
  out << "(truth: largest relative error of the truth's own model fitted to the simulated "
         "measurement)\n";
  for (const std::string& note : result.notes) out << "note: " << note << "\n";
}

void WriteDemoSummaryJson(const DemoResult& result, const DemoOptions& options) {
  nlohmann::json json;
  json["seconds"] = result.seconds;
  json["quick"] = options.quick;
  json["measurements"] = nlohmann::json::array();
  for (const SummaryRow& row : result.bundled) json["measurements"].push_back(SummaryJson(row));
  json["datasets"] = nlohmann::json::array();
  for (const DemoDataset& dataset : result.datasets) {
    const fitters::FitResult& fit = dataset.fits[dataset.chosen];
    nlohmann::json exports = nlohmann::json::array();
    for (const DemoExport& exported : dataset.exports) {
      exports.push_back({{"target", exported.target},
                         {"path", exported.path},
                         {"material", exported.material},
                         {"exact", exported.exact},
                         {"log_rmse", exported.log_rmse},
                         {"max_relative", exported.max_relative},
                         {"warnings", exported.warnings}});
    }
    json["datasets"].push_back({{"name", dataset.name},
                                {"kind", dataset.kind},
                                {"source", dataset.source},
                                {"samples", dataset.samples},
                                {"chosen", fit.model.name()},
                                {"model", fit.model.ToString()},
                                {"rmse", fit.metrics.rmse},
                                {"energy", fit.energy.verdict.name()},
                                {"energy_reason", fit.energy.verdict.reason},
                                {"truth", dataset.truth},
                                {"truth_error", dataset.truth_error},
                                {"fits", dataset.fit_paths},
                                {"exports", exports}});
  }
  WriteFileAtomically(options.out_dir + "/summary.json",
                      [&](std::ostream& out) { out << json.dump(2) << "\n"; });
}

}  // namespace brdf::cli
