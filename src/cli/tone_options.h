// The tone options shared by `brdf tonemap` and `brdf render` (DESIGN §8), defined once: the
// command-line spelling and the help text with defaults (hdr/tone_arguments.h converts them).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "hdr/tone_arguments.h"

namespace brdf::cli {

// Registers --operator, --exposure, --ev, --key, --white, --bloom, --bloom-threshold,
// --bloom-strength, --bloom-sigma and --gamma on `app`.
void AddToneOptions(CLI::App* app, ToneArguments* arguments);

// Throws UsageError unless `path` ends in `extension` (".png", any case): the command writes
// that format only, and bytes of one format under another's name mislead every viewer.
void RequireExtension(const std::string& option, const std::string& path,
                      const std::string& extension);

}  // namespace brdf::cli
