#include "hdr/transfer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/errors.h"

namespace brdf {

double SrgbEncode(double linear) {
  // IEC 61966-2-1: the linear segment 12.92 x meets 1.055 x^(1/2.4) - 0.055 at 0.0031308.
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double SrgbDecode(double encoded) {
  // 0.04045 = 12.92 * 0.0031308, the same knee seen from the encoded side.
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

TransferCurve TransferCurve::Parse(const std::string& text) {
  TransferCurve curve;
  if (text == "srgb") return curve;
  char* end = nullptr;
  const double gamma = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(gamma > 0.0) || !std::isfinite(gamma)) {
    throw UsageError("--gamma: expected 'srgb' or a positive number, got '" + text + "'");
  }
  curve.kind = Kind::kGamma;
  curve.gamma = gamma;
  return curve;
}

std::string TransferCurve::Name() const {
  if (kind == Kind::kSrgb) return "srgb";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "gamma %g", gamma);
  return buffer;
}

double TransferCurve::Encode(double linear) const {
  linear = std::clamp(linear, 0.0, 1.0);
  return kind == Kind::kSrgb ? SrgbEncode(linear) : std::pow(linear, 1.0 / gamma);
}

double TransferCurve::Decode(double encoded) const {
  encoded = std::clamp(encoded, 0.0, 1.0);
  return kind == Kind::kSrgb ? SrgbDecode(encoded) : std::pow(encoded, gamma);
}

void Quantizer8::EncodeMany(const float* linear, int64_t count, uint8_t* out) const {
  const Bucket* const buckets = buckets_.data();
  const float* const thresholds = thresholds_.data();
  const int extra_steps = max_codes_per_bucket_ - 1;
  for (int64_t i = 0; i < count; ++i) out[i] = Encode(linear[i], buckets, thresholds, extra_steps);
}

Quantizer8::Quantizer8(const TransferCurve& curve) {
  for (int k = 0; k < 255; ++k) {
    thresholds_[k] = static_cast<float>(curve.Decode((k + 0.5) / 255.0));
  }
  thresholds_[255] = std::numeric_limits<float>::infinity();
  // Number of thresholds at or below a value (a binary search, fine once per bucket).
  const auto codes_below = [&](float value) {
    return static_cast<int>(
        std::upper_bound(thresholds_.begin(), thresholds_.begin() + 255, value) -
        thresholds_.begin());
  };
  for (int bucket = 0; bucket < kBuckets; ++bucket) {
    const uint32_t first_bits = static_cast<uint32_t>(bucket) << kBucketShift;
    const uint32_t last_bits = first_bits + (1u << kBucketShift) - 1;
    float first, last;
    std::memcpy(&first, &first_bits, sizeof(first));
    std::memcpy(&last, &last_bits, sizeof(last));
    const int start = codes_below(first);
    buckets_[bucket] = {thresholds_[start], static_cast<uint8_t>(start)};
    max_codes_per_bucket_ =
        std::max(max_codes_per_bucket_, codes_below(std::min(last, 1.0f)) - codes_below(first));
  }
}

}  // namespace brdf
