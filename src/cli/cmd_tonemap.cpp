// brdf tonemap IN.exr|IN.hdr --out OUT.png [tone options]: the HDR pipeline alone (DESIGN §8)
// on any OpenEXR or Radiance image. NaN/Inf pixels are counted, reported and replaced by 0.
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/tone_options.h"
#include "hdr/image_files.h"
#include "hdr/pipeline.h"

namespace brdf::cli {

Command AddTonemapCommand(CLI::App& parent) {
  struct Options {
    std::string input, output;
    ToneArguments tone;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "tonemap", "Run the HDR pipeline (exposure, bloom, tone mapping, sRGB, 8 bits) on an image");
  app->add_option("IN", options->input, "HDR image: OpenEXR (.exr) or Radiance RGBE (.hdr)")
      ->required();
  app->add_option("--out", options->output, "8-bit sRGB PNG to write")->required();
  AddToneOptions(app, &options->tone);
  app->add_flag("--quiet", options->quiet, "print nothing on success");

  return {app, [options]() {
            RequireExtension("--out", options->output, ".png");
            const ToneOptions tone = options->tone.Resolve();
            Image image = ReadHdrImage(options->input);
            const int64_t broken = ReplaceNonFinite(&image);
            if (broken > 0) {
              std::cerr << "brdf tonemap: warning: " << options->input << ": " << broken
                        << " pixels with NaN or infinite values, replaced by 0\n";
            }
            const ToneResult result = RunTonePipeline(std::move(image), tone);
            for (const std::string& warning : result.warnings) {
              std::cerr << "brdf tonemap: warning: " << options->input << ": " << warning << "\n";
            }
            WritePng(options->output, result.display);
            if (!options->quiet) {
              std::cout << "wrote " << options->output << ": " << result.Summary() << "\n";
            }
            return 0;
          }};
}

}  // namespace brdf::cli
