#include "export/export.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "core/angles.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/format.h"
#include "core/text.h"
#include "export/targets.h"
#include "fitters/fit.h"
#include "models/lambert.h"
#include "models/model_string.h"
#include "models/term.h"

namespace brdf::exporters {
namespace {

constexpr EnumName<Target> kTargetNames[] = {
    {Target::kMitsuba3, "mitsuba3"},
    {Target::kPbrtV4, "pbrt-v4"},
    {Target::kGltf, "gltf"},
};

// Samples the renderer's parameters are chosen on: the fitting library's stratified subsample
// (the brightest 1 % and a seeded uniform draw, reweighted), enough to pin three colours, a blend
// weight and a roughness while keeping a MERL table's export well under a second.
constexpr size_t kMappingSamples = 4000;
constexpr uint64_t kMappingSeed = 1;
// Samples a power-cosine lobe is refitted as ggx on: the refit follows a noise-free model, so a
// thousand samples pin its seven parameters.
constexpr size_t kRefitSamples = 1000;
// Relative errors are taken against max(f_fit, this share of the fit's largest value): below it a
// value is too dark for a relative difference to mean anything a renderer shows.
constexpr double kRelativeFloorShare = 1e-3;
// The highlight is looked for where both directions are within this angle of the normal: there
// the renderers' masking and Fresnel stay near ours (Schlick's (1 - cos)^5 is below 0.04), so a
// highlight lost there is the lobe's loss; toward grazing a microfacet fit's brightest values
// are those very terms (on the bundled data, separable G put them at 0.53 of the fit's).
constexpr double kHighlightMaxThetaDeg = 60.0;
// The lobe-matched map tries alphas half_width_alpha * ratio^k, |k| <= steps: a factor 4 either
// way in steps of 2^(1/4), enough to bracket a power-cosine lobe's best ggx stand-in, whose tails
// differ from its own.
constexpr int kLobeAlphaSteps = 8;
constexpr double kLobeAlphaRatio = 1.189207115002721;  // 2^(1/4)

Rgb ParamRgb(const Model& model, const char* name) {
  return Rgb(model.Param(name, 0), model.Param(name, 1), model.Param(name, 2));
}

// The ggx refit of a fit no target holds (see SourceFor), on at most kRefitSamples samples.
MicrofacetSource RefitAsGgx(const Model& fit, const std::vector<fitters::FitSample>& all_samples,
                            const std::vector<Rgb>& all_fit_values);
// ggx with the fit's own diffuse term and a lobe matched to the fit's, channel by channel.
MicrofacetSource LobeMatchedGgx(const Model& fit, const std::vector<fitters::FitSample>& samples,
                                const std::vector<Rgb>& fit_values);
// The weighted log-rmse of a ggx source against the fit's values (MappingLogRmse's measure).
double GgxLogRmse(const MicrofacetSource& source, const Model& fit,
                  const std::vector<fitters::FitSample>& samples,
                  const std::vector<Rgb>& fit_values);

// The fit itself when the target holds its distribution; otherwise ggx, whichever of the general
// refit and the lobe-matched map follows the fit's values on the mapping samples more closely.

// The distribution of a renderer's microfacet lobe that holds our lobe exactly: ggx in every
// target, beckmann in Mitsuba 3 (the only one that has it); none for any other lobe.
std::optional<Distribution> HeldDistribution(const LobeInfo& lobe, Target target) {
  if (lobe.term == models::GgxLobe::kName) return Distribution::kGgx;
  if (lobe.term == models::BeckmannLobe::kName && target == Target::kMitsuba3) {
    return Distribution::kBeckmann;
  }
  return std::nullopt;
}

MicrofacetSource SourceFor(const Model& fit, Target target,
                           const std::vector<fitters::FitSample>& samples,
                           const std::vector<Rgb>& fit_values, MicrofacetSource* refit_cache) {
  MicrofacetSource source;
  const ModelInfo& info = fit.info();
  const bool lambert = info.diffuse == models::Lambert::kName;
  if (lambert && info.lobes.empty()) {
    source.model = fit.name();
    source.rho_d = ParamRgb(fit, "rho_d");
    return source;
  }
  const std::optional<Distribution> held =
      lambert && info.lobes.size() == 1 ? HeldDistribution(info.lobes[0], target) : std::nullopt;
  if (held) {
    source.model = fit.name();
    source.has_lobe = true;
    source.distribution = *held;
    source.rho_d = ParamRgb(fit, "rho_d");
    source.f0 = ParamRgb(fit, "f0");
    source.alpha = fit.Param("alpha");
    return source;
  }
  if (refit_cache->model.empty()) {
    const MicrofacetSource refit = RefitAsGgx(fit, samples, fit_values);
    const MicrofacetSource matched = LobeMatchedGgx(fit, samples, fit_values);
    *refit_cache =
        GgxLogRmse(matched, fit, samples, fit_values) < GgxLogRmse(refit, fit, samples, fit_values)
            ? matched
            : refit;
  }
  return *refit_cache;
}

// The ggx alpha whose lobe has the fit's half width (Ggx::AlphaEquivalentExponent inverted).
double HalfWidthGgxAlpha(const Model& fit) {
  const double exponent = std::max(fit.info().EquivalentExponent(fit.params().data()), 1.0);
  return std::sqrt(2.0 * std::log(2.0) / ((std::sqrt(2.0) - 1.0) * exponent));
}

Model GgxModel(const Rgb& rho_d, const Rgb& f0, double alpha) {
  auto rgb = [](const Rgb& value) {
    return Format("%.17g,%.17g,%.17g", value[0], value[1], value[2]);
  };
  return ParseModel("ggx:rho_d=" + rgb(rho_d) + ":f0=" + rgb(f0) +
                    ":alpha=" + Format("%.17g", alpha));
}

double GgxLogRmse(const MicrofacetSource& source, const Model& fit,
                  const std::vector<fitters::FitSample>& samples,
                  const std::vector<Rgb>& fit_values) {
  const Model ggx = GgxModel(source.rho_d, source.f0, source.alpha);
  const MappingInput input{source, fit, samples, fit_values};
  return MappingLogRmse([&](const Vec3& wi, const Vec3& wo) { return ggx.Eval(wi, wo); }, input);
}

// Every lambert-plus-lobe model shares our lambert term, so rho_d carries over exactly, colour
// and all. Schlick's F makes the ggx lobe affine in f0, lobe = f0 A + B (A, B from the lobe
// evaluated at f0 = 1 and 0), so for each alpha on a log grid about the fit's half width the f0
// of each channel is weighted least squares on the linearised log loss (FitDiffuseScale's
// weights), clamped to [0, 1]; the alpha whose result follows the fit best is kept.
MicrofacetSource LobeMatchedGgx(const Model& fit, const std::vector<fitters::FitSample>& samples,
                                const std::vector<Rgb>& fit_values) {
  MicrofacetSource best;
  best.model = "ggx";
  best.distribution = Distribution::kGgx;
  best.has_lobe = true;
  best.rho_d = ParamRgb(fit, "rho_d");
  double best_error = std::numeric_limits<double>::infinity();
  const double half_width_alpha = HalfWidthGgxAlpha(fit);
  for (int step = -kLobeAlphaSteps; step <= kLobeAlphaSteps; ++step) {
    const double alpha = std::clamp(half_width_alpha * std::pow(kLobeAlphaRatio, step),
                                    models::kMinFitRoughness, models::kMaxFitRoughness);
    const Model white = GgxModel(Rgb::Zero(), Rgb::Ones(), alpha);
    const Model black = GgxModel(Rgb::Zero(), Rgb::Zero(), alpha);
    Rgb numerator = Rgb::Zero(), denominator = Rgb::Zero();
    for (size_t k = 0; k < samples.size(); ++k) {
      const fitters::FitSample& sample = samples[k];
      const Rgb b = black.Eval(sample.wi, sample.wo);
      const Rgb a = white.Eval(sample.wi, sample.wo) - b;
      const double c = sample.cos_theta_i();
      const Rgb target = fit_values[k] - best.rho_d * kInvPi - b;
      const Rgb w = sample.weight * (c / (1.0 + fit_values[k] * c)).square();
      numerator += w * a * target;
      denominator += w * a * a;
    }
    MicrofacetSource candidate = best;
    candidate.alpha = alpha;
    for (int ch = 0; ch < 3; ++ch) {
      candidate.f0[ch] =
          denominator[ch] > 0 ? std::clamp(numerator[ch] / denominator[ch], 0.0, 1.0) : 0.0;
    }
    const double error = GgxLogRmse(candidate, fit, samples, fit_values);
    if (error < best_error) {
      best_error = error;
      best = candidate;
    }
  }
  best.via = "ggx with the " + fit.name() + " fit's rho_d and its lobe matched per channel on " +
             std::to_string(samples.size()) + " of its samples (" +
             GgxModel(best.rho_d, best.f0, best.alpha).ToString(4) + ")";
  return best;
}

MicrofacetSource RefitAsGgx(const Model& fit, const std::vector<fitters::FitSample>& all_samples,
                            const std::vector<Rgb>& all_fit_values) {
  const std::string& name = fit.name();
  MicrofacetSource source;
  // Every kth sample: the mapping samples are already a stratified draw.
  const size_t stride = (all_samples.size() + kRefitSamples - 1) / kRefitSamples;
  std::vector<fitters::FitSample> samples;
  std::vector<Rgb> fit_values;
  for (size_t k = 0; k < all_samples.size(); k += stride) {
    samples.push_back(all_samples[k]);
    fit_values.push_back(all_fit_values[k]);
  }
  fitters::PreparedSamples prepared;
  prepared.weighting = "the fit's own values on its samples";
  for (size_t k = 0; k < samples.size(); ++k) {
    fitters::FitSample sample = samples[k];
    sample.value = fit_values[k];
    sample.scale = Rgb::Constant(std::sqrt(sample.weight));
    prepared.samples.push_back(sample);
  }
  fitters::FitOptions options;
  options.loss = fitters::Loss::kLog;
  options.max_samples = 0;
  // Starts around the ggx alpha whose lobe has the fit's half width: the refit follows a known
  // lobe, not unknown data.
  const double alpha = HalfWidthGgxAlpha(fit);
  options.start_alphas.clear();
  for (double start : {0.5 * alpha, alpha, 2.0 * alpha}) {
    options.start_alphas.push_back(
        std::clamp(start, models::kMinFitRoughness, models::kMaxFitRoughness));
  }
  const fitters::FitResult refit = fitters::FitPreparedSamples(prepared, "ggx", options);
  source.model = "ggx";
  source.distribution = Distribution::kGgx;
  source.has_lobe = true;
  source.rho_d = ParamRgb(refit.model, "rho_d");
  source.f0 = ParamRgb(refit.model, "f0");
  source.alpha = refit.model.Param("alpha");
  source.via = "ggx refitted to the " + name + " fit's values on " +
               std::to_string(samples.size()) + " of its samples (" + refit.model.ToString(4) +
               (refit.converged ? "" : ", not converged") + ")";
  return source;
}

std::string CommentSafe(std::string text) {
  // "--" may not appear inside an XML comment.
  for (size_t at = text.find("--"); at != std::string::npos; at = text.find("--")) {
    text.replace(at, 2, "- -");
  }
  return text;
}

// The fit, the mapping and its measured error, as comments (XML, pbrt) or glTF extras.
void AnnotateText(const Model& fit, const std::string& samples_origin, ExportedMaterial* m) {
  std::vector<std::string> lines = {
      "brdfkit export of " + fit.ToString() + " to " + TargetName(m->target) + ": " + m->material +
          (m->exact ? " (exact)" : " (approximate)"),
      "measured on " + samples_origin + ": log-rmse " + Num(m->error.log_rmse) +
          ", max relative error " + Num(m->error.max_relative)};
  if (!m->source.via.empty()) lines.push_back("mapped from " + m->source.via);
  for (const std::string& warning : m->warnings) lines.push_back("WARNING: " + warning);
  for (const std::string& note : m->notes) lines.push_back(note);
  switch (m->target) {
    case Target::kMitsuba3: {
      std::string comment;
      for (const std::string& line : lines) comment += "     " + CommentSafe(line) + "\n";
      const size_t end_of_declaration = m->text.find('\n') + 1;
      m->text.insert(end_of_declaration, "<!--\n" + comment + "-->\n");
      break;
    }
    case Target::kPbrtV4: {
      std::string comment;
      for (const std::string& line : lines) comment += "# " + line + "\n";
      m->text = comment + m->text;
      break;
    }
    case Target::kGltf: {
      nlohmann::json document = nlohmann::json::parse(m->text);
      document["materials"][0]["extras"] = {{"brdfkit", lines}};
      m->text = document.dump(2) + "\n";
      break;
    }
  }
}

}  // namespace

Target ParseTarget(const std::string& name) {
  return ParseEnum(kTargetNames, name, "export target");
}

const char* TargetName(Target target) { return NameOf(kTargetNames, target); }

const char* TargetExtension(Target target) {
  switch (target) {
    case Target::kMitsuba3:
      return ".xml";
    case Target::kPbrtV4:
      return ".pbrt";
    case Target::kGltf:
      return ".gltf";
  }
  return "";
}

std::vector<Target> AllTargets() {
  std::vector<Target> targets;
  for (const EnumName<Target>& entry : kTargetNames) targets.push_back(entry.value);
  return targets;
}

ExportSamples SamplesForExport(const Measurement& measurement) {
  ExportSamples result;
  result.samples = fitters::PrepareSamples(measurement).samples;
  result.origin =
      "the fit's " + std::to_string(result.samples.size()) + " samples of " + measurement.source;
  return result;
}

ExportSamples HemisphereGridSamples(double step_deg) {
  ExportSamples result;
  const int theta_steps = static_cast<int>(std::ceil(90.0 / step_deg));
  const int phi_steps = static_cast<int>(std::ceil(360.0 / step_deg));
  for (int i = 0; i < theta_steps; ++i) {
    const Vec3 wi = SphericalDirection(DegToRad(i * step_deg), 0.0);
    for (int o = 0; o < theta_steps; ++o) {
      for (int p = 0; p < (o == 0 ? 1 : phi_steps); ++p) {
        fitters::FitSample sample;
        sample.wi = wi;
        sample.wo = SphericalDirection(DegToRad(o * step_deg), DegToRad(p * step_deg));
        result.samples.push_back(sample);
      }
    }
  }
  result.has_data = false;
  result.origin = std::to_string(result.samples.size()) + " directions of a " +
                  FormatNumber(step_deg) + "-degree hemisphere grid (the fit's data not found)";
  return result;
}

ExportError MeasureExportError(const std::function<Rgb(const Vec3&, const Vec3&)>& renderer,
                               const Model& fit, const std::vector<fitters::FitSample>& samples) {
  ExportError error;
  error.samples = samples.size();
  std::vector<Rgb> fit_values(samples.size());
  size_t highlight_sample = 0;
  int highlight_channel = 0;
  const double cos_highlight_max = std::cos(DegToRad(kHighlightMaxThetaDeg));
  double largest = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    fit_values[k] = fit.Eval(samples[k].wi, samples[k].wo);
    int channel = 0;
    const double value = fit_values[k].maxCoeff(&channel);
    largest = std::max(largest, value);
    if (value > error.highlight_fit && samples[k].wi.z() >= cos_highlight_max &&
        samples[k].wo.z() >= cos_highlight_max) {
      error.highlight_fit = value;
      highlight_sample = k;
      highlight_channel = channel;
    }
  }
  error.relative_floor = kRelativeFloorShare * largest;
  if (error.highlight_fit > 0) {
    error.highlight_wi = samples[highlight_sample].wi;
    error.highlight_wo = samples[highlight_sample].wo;
    error.highlight_renderer = renderer(error.highlight_wi, error.highlight_wo)[highlight_channel];
  }
  double sum = 0, weight = 0;
  for (size_t k = 0; k < samples.size(); ++k) {
    const fitters::FitSample& sample = samples[k];
    const Rgb f = renderer(sample.wi, sample.wo);
    const double c = sample.cos_theta_i();
    const Rgb log_difference = (1.0 + f * c).log() - (1.0 + fit_values[k] * c).log();
    sum += sample.weight * log_difference.square().sum();
    weight += 3 * sample.weight;
    const Rgb relative = (f - fit_values[k]).abs() / fit_values[k].max(error.relative_floor);
    if (error.relative_floor > 0)
      error.max_relative = std::max(error.max_relative, relative.maxCoeff());
  }
  error.log_rmse = weight > 0 ? std::sqrt(sum / weight) : 0.0;
  return error;
}

double FitLogRmse(const Model& fit, const std::vector<fitters::FitSample>& samples) {
  double sum = 0, weight = 0;
  for (const fitters::FitSample& sample : samples) {
    const double c = sample.cos_theta_i();
    const Rgb f = fit.Eval(sample.wi, sample.wo);
    const Rgb log_difference = (1.0 + f * c).log() - (1.0 + (sample.value * c).max(-0.999)).log();
    sum += sample.weight * log_difference.square().sum();
    weight += 3 * sample.weight;
  }
  return weight > 0 ? std::sqrt(sum / weight) : 0.0;
}

std::vector<std::string> ExportWarnings(const ExportError& error, double fit_log_rmse) {
  std::vector<std::string> warnings;
  if (error.max_relative > kMaxRelativeWarning) {
    warnings.push_back("the renderer's material differs from the fit by up to " +
                       Num(error.max_relative) + " times the fit's value (more than " +
                       Num(kMaxRelativeWarning) + "): it does not keep the fitted material");
  }
  const double allowed = std::max(kLogRmseWarningFloor, kLogRmseWarningFactor * fit_log_rmse);
  if (error.log_rmse > allowed) {
    warnings.push_back(
        "the renderer's material is " + Num(error.log_rmse) + " from the fit in log-rmse" +
        (fit_log_rmse >= 0
             ? ", more than " + Num(kLogRmseWarningFactor) +
                   " times the fit's own distance to the data (" + Num(fit_log_rmse) + ")"
             : std::string()) +
        (allowed == kLogRmseWarningFloor ? " and above " + Num(kLogRmseWarningFloor) : "") +
        ": the export loses more than the fit did");
  }
  if (error.highlight_fit > 0) {
    const double ratio = error.highlight_renderer / error.highlight_fit;
    if (ratio < 1.0 / kHighlightWarningFactor || ratio > kHighlightWarningFactor) {
      warnings.push_back(
          "at the fit's highlight (theta_i " + Num(RadToDeg(std::acos(error.highlight_wi.z()))) +
          " deg, theta_o " + Num(RadToDeg(std::acos(error.highlight_wo.z()))) +
          " deg) the renderer's material gives " + Num(error.highlight_renderer) +
          " sr^-1 where the fit gives " + Num(error.highlight_fit) + " (" + Num(ratio) +
          " times the fit's, outside 1/" + Num(kHighlightWarningFactor) + " to " +
          Num(kHighlightWarningFactor) + "): " +
          (ratio < 1 ? "it loses the fitted highlight" : "its highlight is brighter than fitted"));
    }
  }
  return warnings;
}

ExportedMaterial ExportMaterial(const ExportRequest& request, Target target) {
  return ExportMaterials(request, {target}).front();
}

std::vector<ExportedMaterial> ExportMaterials(const ExportRequest& request,
                                              const std::vector<Target>& targets) {
  const std::vector<fitters::FitSample>& all = request.samples.samples;
  if (all.empty()) throw InputError(request.samples.origin, "no usable samples to export on");
  const std::vector<fitters::FitSample> mapping_samples =
      fitters::Subsample(all, kMappingSamples, kMappingSeed);
  std::vector<Rgb> fit_values;
  fit_values.reserve(mapping_samples.size());
  for (const fitters::FitSample& sample : mapping_samples) {
    fit_values.push_back(request.fit.Eval(sample.wi, sample.wo));
  }
  MicrofacetSource refit_cache;
  const double fit_log_rmse = request.samples.has_data ? FitLogRmse(request.fit, all) : -1.0;
  std::vector<ExportedMaterial> materials;
  for (Target target : targets) {
    const MicrofacetSource source =
        SourceFor(request.fit, target, mapping_samples, fit_values, &refit_cache);
    const MappingInput input{source, request.fit, mapping_samples, fit_values};
    ExportedMaterial material;
    switch (target) {
      case Target::kMitsuba3:
        material = MapToMitsuba3(input);
        break;
      case Target::kPbrtV4:
        material = MapToPbrtV4(input);
        break;
      case Target::kGltf:
        material = MapToGltf(input);
        break;
    }
    material.source = source;
    if (!source.via.empty()) material.exact = false;
    material.error = MeasureExportError(material.eval, request.fit, all);
    material.fit_log_rmse = fit_log_rmse;
    material.warnings = ExportWarnings(material.error, fit_log_rmse);
    AnnotateText(request.fit, request.samples.origin, &material);
    materials.push_back(std::move(material));
  }
  return materials;
}

std::string ResolveFitSource(const std::string& fit_path) {
  namespace fs = std::filesystem;
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(ReadFileBytes(fit_path, int64_t{16} << 20));
  } catch (const std::exception&) {
    return "";
  }
  if (!report.is_object() || !report.contains("source") || !report["source"].is_string()) {
    return "";
  }
  const std::string source = report["source"].get<std::string>();
  std::error_code error;
  if (!source.empty() && fs::is_regular_file(source, error)) return source;
  if (source.empty() || !fs::path(source).is_relative()) return "";
  // Beside the report, or one directory up: brdf demo keeps fits/ next to measurements/.
  const fs::path directory = fs::path(fit_path).parent_path();
  for (const fs::path& base : {directory, directory.parent_path()}) {
    const fs::path candidate = base / source;
    if (fs::is_regular_file(candidate, error)) return candidate.string();
  }
  return "";
}

nlohmann::json ExportJson(const ExportedMaterial& material, const std::string& fit_path,
                          const std::string& out_path, const std::string& samples_origin) {
  const MicrofacetSource& source = material.source;
  nlohmann::json json = {
      {"fit", fit_path},
      {"target", TargetName(material.target)},
      {"out", out_path},
      {"material", material.material},
      {"exact", material.exact},
      {"parameters", material.parameters},
      {"notes", material.notes},
      {"error",
       {{"log_rmse", material.error.log_rmse},
        {"max_relative", material.error.max_relative},
        {"relative_floor", material.error.relative_floor},
        {"highlight",
         {{"fit", material.error.highlight_fit},
          {"renderer", material.error.highlight_renderer},
          {"theta_i_deg", RadToDeg(std::acos(material.error.highlight_wi.z()))},
          {"theta_o_deg", RadToDeg(std::acos(material.error.highlight_wo.z()))},
          {"phi_o_deg", RadToDeg(std::atan2(material.error.highlight_wo.y(),
                                            material.error.highlight_wo.x()))}}},
        {"samples", material.error.samples},
        {"samples_origin", samples_origin},
        {"fit_log_rmse", material.fit_log_rmse >= 0 ? nlohmann::json(material.fit_log_rmse)
                                                    : nlohmann::json(nullptr)}}},
      {"warnings", material.warnings},
      {"mapped_from",
       {{"model", source.model},
        {"rho_d", {source.rho_d[0], source.rho_d[1], source.rho_d[2]}},
        {"f0", {source.f0[0], source.f0[1], source.f0[2]}},
        {"alpha", source.alpha},
        {"via", source.via}}}};
  return json;
}

std::string ExportSummary(const ExportedMaterial& material, const std::string& out_path,
                          const std::string& samples_origin) {
  std::string text =
      "target      " + std::string(TargetName(material.target)) + " -> " + out_path + "\n";
  text += "material    " + material.material + (material.exact ? "  (exact)" : "  (approximate)") +
          "\n";
  if (!material.source.via.empty()) text += "mapped from " + material.source.via + "\n";
  for (const std::string& note : material.notes) text += "mapping     " + note + "\n";
  text += "error       log-rmse " + Num(material.error.log_rmse) + ", max relative error " +
          Num(material.error.max_relative) + " (values below " +
          Num(material.error.relative_floor) + " sr^-1 taken as that), on " + samples_origin + "\n";
  text += "highlight   the fit's brightest value " + Num(material.error.highlight_fit) +
          " sr^-1, the renderer's there " + Num(material.error.highlight_renderer) + "\n";
  if (material.fit_log_rmse >= 0) {
    text += "fit         log-rmse " + Num(material.fit_log_rmse) + " against the data\n";
  }
  for (const std::string& warning : material.warnings) text += "WARNING     " + warning + "\n";
  return text;
}

}  // namespace brdf::exporters
