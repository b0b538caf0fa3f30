// brdf render MODEL|FIT.json|FILE [--light ...]... [--preset NAME] [--env SPEC] [--size N]
// [--spp N] [--seed N] [--threads N] [--exr OUT.exr] --out OUT.png [tone options]: a preview sphere
// through the HDR pipeline (DESIGN §8).
#include <tbb/global_control.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/tone_options.h"
#include "core/errors.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/text.h"
#include "energy/albedo.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"
#include "models/model_source.h"
#include "render/comparison_sheet.h"
#include "render/scene_lighting.h"
#include "render/sphere.h"

namespace brdf::cli {
namespace {

std::string PresetHelp() {
  std::string text = "light from theta=45, phi=45 deg with a typical illuminance:";
  for (const IlluminancePreset& preset : IlluminancePresets()) {
    text += Format(" %s (%g lx, %s)", preset.name.c_str(), preset.lux, preset.description.c_str());
  }
  return text + "; default office when no light, preset or environment is given";
}

// A model that reflects more light than it receives renders brighter than any surface can be;
// the same check as `brdf energy` (directional albedo over 0-89 deg, beyond twice its error).
void WarnIfCreatingEnergy(const std::string& spec) {
  if (!IsModelSpec(spec)) return;  // measured data are checked by `brdf energy FILE`
  const AlbedoCurve curve = ModelAlbedoCurve(LoadModel(spec), AlbedoOptions());
  if (curve.verdict().conservation != Conservation::kNotConserving) return;
  int channel = 0;
  for (int c = 1; c < 3; ++c)
    channel = curve.max_albedo[c] > curve.max_albedo[channel] ? c : channel;
  std::cerr << "brdf render: warning: " << spec << " reflects more light than it receives (up to "
            << FormatNumber(curve.max_albedo[channel], 4) << " times, at "
            << FormatNumber(curve.theta_deg_at_max[channel], 3)
            << " deg incidence): no real material does, so the preview is too bright\n";
}

}  // namespace

Command AddRenderCommand(CLI::App& parent) {
  struct Options {
    std::string material, output, exr, exr_type = "half", exr_compression = "piz", env, versus;
    std::vector<std::string> lights, presets;
    RenderOptions render;
    ToneArguments tone;
    int threads = 0;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "render", "Render a preview sphere of a material through the HDR pipeline to PNG (and EXR)");
  app->add_option("MATERIAL", options->material,
                  "model string, FIT.json, or measurement file (MERL and RGL-EPFL through "
                  "their evaluator; other formats inverse-distance, tabulated)")
      ->required();
  app->add_option("--out", options->output, "8-bit sRGB PNG to write")->required();
  app->add_option("--vs", options->versus,
                  "a second material (e.g. the fit of a measurement) rendered under the same "
                  "light: --out becomes a sheet A | B | relative error map | colour bar");
  app->add_option("--exr", options->exr,
                  "also write the radiance (W/m^2/sr) as OpenEXR (of MATERIAL, with --vs)");
  app->add_option("--exr-type", options->exr_type, "OpenEXR pixel type: half or float")
      ->capture_default_str()
      ->check(ParsesAs(ParseExrPixelType));
  app->add_option("--exr-compression", options->exr_compression,
                  "OpenEXR compression (lossless): piz, zip, rle or none")
      ->capture_default_str()
      ->check(ParsesAs(ParseExrCompression));
  app->add_option("--light", options->lights,
                  "directional light dir:theta=DEG:phi=DEG:lux=LX (or irradiance=W/m^2, "
                  "rgb=R,G,B W/m^2); theta from the viewer (+z), phi from right (+x) toward up "
                  "(+y); repeatable; lux -> W/m^2 at 683 lm/W");
  app->add_option("--preset", options->presets, PresetHelp());
  app->add_option("--env", options->env,
                  "environment: equirectangular OpenEXR/Radiance file, or uniform:L "
                  "(radiance in W/m^2/sr), importance sampled");
  app->add_option("--size", options->render.size, "image width and height in pixels")
      ->capture_default_str()
      ->check(CLI::Range(1, RenderOptions::kMaxSize));
  app->add_option("--spp", options->render.spp,
                  "environment samples per pixel (each technique: light, cosine and, for models, "
                  "the specular lobe; MIS)")
      ->capture_default_str()
      ->check(CLI::Range(1, RenderOptions::kMaxSpp));
  app->add_option("--seed", options->render.seed, "random seed (same image for any thread count)")
      ->capture_default_str();
  app->add_option("--threads", options->threads,
                  "worker threads (0 = all cores); the output does not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  AddToneOptions(app, &options->tone);
  app->add_flag("--quiet", options->quiet, "print nothing on success; no progress");

  return {app, [options]() {
            std::optional<tbb::global_control> thread_limit;
            if (options->threads > 0) {
              thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                                   static_cast<size_t>(options->threads));
            }
            options->render.Validate();
            RequireExtension("--out", options->output, ".png");
            if (!options->exr.empty()) RequireExtension("--exr", options->exr, ".exr");
            const ToneOptions tone = options->tone.Resolve();
            const ExrCompression exr_compression = ParseExrCompression(options->exr_compression);
            const ExrPixelType exr_type = ParseExrPixelType(options->exr_type);
            const SceneLighting lighting =
                MakeSceneLighting(options->lights, options->presets, options->env);
            for (const std::string& warning : lighting.warnings) {
              std::cerr << "brdf render: warning: " << warning << "\n";
            }
            const std::unique_ptr<Material> material = LoadMaterial(options->material);
            const std::unique_ptr<Material> versus =
                options->versus.empty() ? nullptr : LoadMaterial(options->versus);
            WarnIfCreatingEnergy(options->material);
            if (versus) WarnIfCreatingEnergy(options->versus);

            RenderResult render, render_versus;
            {
              Progress progress("render", options->render.size * (versus ? 2 : 1), options->quiet);
              const Environment* environment = lighting.environment_or_null();
              render =
                  RenderSphere(*material, lighting.lights, environment, options->render, &progress);
              if (versus) {
                render_versus =
                    RenderSphere(*versus, lighting.lights, environment, options->render, &progress);
              }
            }
            if (!options->exr.empty()) {
              const int64_t clamped =
                  WriteExr(options->exr, render.radiance, exr_type, exr_compression);
              if (clamped > 0) {
                std::cerr << "brdf render: warning: " << options->exr << ": " << clamped
                          << " values above the half-float maximum 65504 were clamped to it (use "
                             "--exr-type float)\n";
              }
            }
            std::string comparison;
            ToneResult toned;
            if (versus) {
              const ComparisonSheet sheet =
                  ToneMapAndCompare(render.radiance, render_versus.radiance, tone,
                                    material->Describe(), versus->Describe(), &toned);
              WritePng(options->output, sheet.sheet);
              comparison = "; " + sheet.Summary();
            } else {
              toned = RunTonePipeline(render.radiance, tone);
              WritePng(options->output, toned.display);
            }
            for (const auto& [name, result] :
                 {std::pair<const std::string&, const RenderResult&>(options->material, render),
                  {options->versus, render_versus}}) {
              if (result.missing_lookups > 0) {
                std::cerr << "brdf render: warning: " << name << ": " << result.missing_lookups
                          << " lookups fell on missing data and were rendered black\n";
              }
            }
            if (!options->quiet) {
              std::cout << "wrote " << options->output
                        << (options->exr.empty() ? "" : " and " + options->exr) << ": "
                        << material->Describe() << "; " << render.Summary() << "; "
                        << toned.Summary(/*radiometric=*/true) << comparison << "\n";
            }
            return 0;
          }};
}

}  // namespace brdf::cli
