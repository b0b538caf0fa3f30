// `brdf export` (DESIGN §3): a fitted material in a renderer's own terms, Mitsuba 3 XML, pbrt-v4
// scene text or a glTF 2.0 material, and how far the renderer's model is from the fit.
//
// Every target's model is evaluated here by our own code (renderer_terms.h and the target files)
// on the samples the fit was made from, so the error printed with an export is measured, not
// claimed: the weighted log-rmse of the fit's metrics (fitters/fit.cpp) and the largest relative
// error. Where the renderer holds the fitted model exactly (lambert everywhere) the two agree to
// rounding; where it does not (Schlick's Fresnel against a conductor's eta and k, separable
// against height-correlated masking, a power-cosine lobe against a microfacet one) the renderer's
// parameters are chosen to follow the fit on those samples and the error says what is left.
//
// Example:
//   ExportRequest request;
//   request.fit = ReadFitReportModel("fit.json");
//   request.samples = SamplesForExport(measurement);
//   ExportedMaterial material = ExportMaterial(request, Target::kMitsuba3);
//   WriteFileAtomically("fit.xml", [&](std::ostream& out) { out << material.text; });
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "core/vec.h"
#include "export/renderer_terms.h"
#include "fitters/fit_samples.h"
#include "models/registry.h"

namespace brdf::exporters {

enum class Target { kMitsuba3, kPbrtV4, kGltf };
// "mitsuba3", "pbrt-v4" or "gltf"; UsageError naming the three otherwise.
Target ParseTarget(const std::string& name);
const char* TargetName(Target target);
// The file name extension a target's file takes (".xml", ".pbrt", ".gltf").
const char* TargetExtension(Target target);
std::vector<Target> AllTargets();

// The samples an export is measured on: the fit's usable samples with their solid-angle weights
// (fitters::PrepareSamples), or a hemisphere grid when the fit's data cannot be had.
struct ExportSamples {
  std::vector<fitters::FitSample> samples;
  std::string origin;    // "the fit's 1234 samples of FILE" or the grid's description
  bool has_data = true;  // the samples carry measured values (not so for the grid)
};
ExportSamples SamplesForExport(const Measurement& measurement);
// Every (theta_i, theta_o, phi_o) at `step_deg` steps over the hemisphere (theta < 90°), equal
// weights: for a fit whose data are not at hand.
ExportSamples HemisphereGridSamples(double step_deg);
// The grid step `brdf export` and brdfkit.export measure on when the fit's data are not at hand.
inline constexpr double kFallbackGridStepDeg = 5.0;

// Our fitted model in microfacet terms: what a renderer's material is mapped from.
struct MicrofacetSource {
  std::string model;  // what it is, for people: the fit's model name, or "ggx" for a refit
  bool has_lobe = false;
  Distribution distribution = Distribution::kGgx;  // the lobe's, when has_lobe
  Rgb rho_d = Rgb::Zero();
  Rgb f0 = Rgb::Zero();
  double alpha = 0;
  std::string via;  // empty when it is the fit itself; else how it was found (a refit)
};

struct ExportRequest {
  Model fit = Model(FindModel("lambert"), {0.5, 0.5, 0.5});
  ExportSamples samples;
};

// How the renderer's model, evaluated by our code, differs from the fit on the samples.
struct ExportError {
  double log_rmse = 0;        // sqrt(Σ w |log(1 + f_r cos_i) − log(1 + f_fit cos_i)|² / Σ 3w)
  double max_relative = 0;    // max |f_r − f_fit| / max(f_fit, floor) over samples and channels
  double relative_floor = 0;  // 1e-3 of the fit's largest value: where relative error means
  size_t samples = 0;
  // The fit's highlight: its largest value over the samples with both directions within 60° of
  // the normal and over channels, where it is, and the renderer's value of the same channel
  // there (0 and 0 without such samples). A lobe the renderer cannot follow shows here even
  // when it covers too few samples to move the log-rmse, and an underestimate, which
  // max_relative caps at 1, shows as a ratio far below 1.
  double highlight_fit = 0, highlight_renderer = 0;
  Vec3 highlight_wi = Vec3::UnitZ(), highlight_wo = Vec3::UnitZ();
};
ExportError MeasureExportError(const std::function<Rgb(const Vec3&, const Vec3&)>& renderer,
                               const Model& fit, const std::vector<fitters::FitSample>& samples);
// The fit's own log-rmse against the measured values of the samples, weighted as ExportError's.
double FitLogRmse(const Model& fit, const std::vector<fitters::FitSample>& samples);

// When an export loses the material. The renderer's model is measured against the fit; a warning
// is due when it differs from the fit by more than the fit differs from the data, somewhere by
// an order of magnitude, or at the fit's highlight:
//  - max relative error above kMaxRelativeWarning, or
//  - log-rmse above kLogRmseWarningFactor times the fit's own log-rmse on the same samples and
//    above kLogRmseWarningFloor (without data, the floor alone), or
//  - the renderer's value at the fit's highlight below 1/kHighlightWarningFactor or above
//    kHighlightWarningFactor times the fit's there.
inline constexpr double kMaxRelativeWarning = 10.0;
inline constexpr double kLogRmseWarningFactor = 2.0;
// Below this a log-rmse is a few percent of a bright value: no renderer shows it, however well a
// noise-free fit follows its data.
inline constexpr double kLogRmseWarningFloor = 0.02;
// A highlight at less than half or more than twice the fit's brightness is a different highlight
// in a render. On the bundled real data (bench/export_real) microfacet fits keep 0.99-1.38 of it
// in every target; the power-cosine fits whose lobe no ggx follows keep 0.002-0.045.
inline constexpr double kHighlightWarningFactor = 2.0;
// The warnings for an export's error; `fit_log_rmse` is negative when the fit's own is unknown.
std::vector<std::string> ExportWarnings(const ExportError& error, double fit_log_rmse);

struct ExportedMaterial {
  Target target = Target::kMitsuba3;
  std::string text;                // the file's contents
  std::string material;            // the renderer's material, e.g. "roughconductor (ggx)"
  bool exact = false;              // the renderer's model is the fit's, term for term
  std::vector<std::string> notes;  // what maps exactly and what does not, and why
  nlohmann::json parameters;       // the renderer's parameters, as written
  MicrofacetSource source;         // what the material was mapped from
  std::function<Rgb(const Vec3&, const Vec3&)> eval;  // the renderer's model (our code)
  ExportError error;                                  // measured on the request's samples
  double fit_log_rmse = -1;           // the fit's own against the samples' data; -1 without data
  std::vector<std::string> warnings;  // ExportWarnings: the material is not what was fitted
};

// Maps the fit to the target, evaluates the result and measures its error. A phong or
// blinn-phong fit (and beckmann for targets without Beckmann) is first refitted as ggx to the
// fit's own values on the samples, with the fitting library.
ExportedMaterial ExportMaterial(const ExportRequest& request, Target target);
// The same for several targets, refitting at most once.
std::vector<ExportedMaterial> ExportMaterials(const ExportRequest& request,
                                              const std::vector<Target>& targets);

// The fit's source measurement as written in its report, resolved as given, or relative to the
// report's directory or the one above it (brdf demo's layout); empty when none exists.
std::string ResolveFitSource(const std::string& fit_path);

// The report of an export as JSON (for --json and the demo).
nlohmann::json ExportJson(const ExportedMaterial& material, const std::string& fit_path,
                          const std::string& out_path, const std::string& samples_origin);
// The same for people: a few lines.
std::string ExportSummary(const ExportedMaterial& material, const std::string& out_path,
                          const std::string& samples_origin);

}  // namespace brdf::exporters
