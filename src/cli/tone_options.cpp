#include "cli/tone_options.h"

#include <cctype>

#include "core/errors.h"

namespace brdf::cli {

void RequireExtension(const std::string& option, const std::string& path,
                      const std::string& extension) {
  std::string tail =
      path.size() >= extension.size() ? path.substr(path.size() - extension.size()) : std::string();
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (tail != extension) {
    std::string format = extension.substr(1);
    for (char& c : format) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    throw UsageError(option + " " + path + ": the file written is " + format + "; name it *" +
                     extension);
  }
}

void AddToneOptions(CLI::App* app, ToneArguments* arguments) {
  app->add_option("--operator", arguments->tone_operator,
                  "tone mapping on luminance, chroma kept: exposure (1 - exp(-x*exposure)), "
                  "reinhard (Reinhard 2002 global), reinhard-extended (with L_white), none")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--exposure", arguments->exposure,
                  "multiplier applied before everything else; auto brings the log-average "
                  "luminance to --key")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option_function<double>(
         "--ev",
         [arguments](double ev) {
           arguments->ev = ev;
           arguments->ev_given = true;
         },
         "exposure value: the multiplier is 2^EV (instead of --exposure)")
      ->group("Tone mapping");
  app->add_option("--key", arguments->key, "Reinhard key a: the grey the log-average maps to")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--white", arguments->white,
                  "reinhard-extended L_white in key-scaled units (Reinhard 2002 eq. 4); auto = "
                  "the scene maximum, which then maps to 1")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--bloom", arguments->bloom,
                  "bloom blur: none, box (3 extended boxes), gauss, kawase, dual (Bjorge 2015)")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--bloom-threshold", arguments->bloom_threshold,
                  "bright pass: luminance (after exposure) above which light blooms")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--bloom-strength", arguments->bloom_strength,
                  "weight of the blurred bright pass added back")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--bloom-sigma", arguments->bloom_sigma,
                  "bloom blur standard deviation in pixels (dual rounds to whole levels)")
      ->capture_default_str()
      ->group("Tone mapping");
  app->add_option("--gamma", arguments->gamma,
                  "display transfer: srgb (IEC 61966-2-1) or a plain gamma such as 2.2 or 1")
      ->capture_default_str()
      ->group("Tone mapping");
}

}  // namespace brdf::cli
