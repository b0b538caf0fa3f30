#include "hdr/tone_arguments.h"

#include <cmath>
#include <cstdlib>

#include "core/errors.h"

namespace brdf {
namespace {

double ParsePositive(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(value > 0.0) || !std::isfinite(value)) {
    throw UsageError(option + ": expected 'auto' or a positive number, got '" + text + "'");
  }
  return value;
}

}  // namespace

ToneOptions ToneArguments::Resolve() const {
  ToneOptions options;
  options.tone_operator = ParseToneOperator(tone_operator);
  if (ev_given && exposure != "auto") {
    throw UsageError("exposure and ev both set the exposure; give one");
  }
  if (ev_given) options.exposure = std::exp2(ev);
  if (exposure != "auto") options.exposure = ParsePositive("exposure", exposure);
  options.key = key;
  options.white = white == "auto" ? 0.0 : ParsePositive("white", white);
  options.bloom = ParseBlurKind(bloom);
  options.bloom_threshold = bloom_threshold;
  options.bloom_strength = bloom_strength;
  options.bloom_sigma = bloom_sigma;
  options.transfer = TransferCurve::Parse(gamma);
  options.Validate();
  return options;
}

}  // namespace brdf
