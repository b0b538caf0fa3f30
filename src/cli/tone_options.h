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

}  // namespace brdf::cli
