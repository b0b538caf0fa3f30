// Display encoding (DESIGN §8): the sRGB transfer curve (IEC 61966-2-1: linear below
// 0.0031308, a 1/2.4 power above), or a plain gamma, then 8 bits with rounding.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace brdf {

struct TransferCurve {
  enum class Kind { kSrgb, kGamma } kind = Kind::kSrgb;
  double gamma = 2.2;  // kGamma only; 1 is linear

  // "srgb", or a positive number (the gamma: "2.2", "1"); throws UsageError otherwise.
  static TransferCurve Parse(const std::string& text);
  std::string Name() const;

  double Encode(double linear) const;   // [0, 1] -> [0, 1]
  double Decode(double encoded) const;  // the inverse
};

double SrgbEncode(double linear);
double SrgbDecode(double encoded);

// Encodes with a transfer curve and rounds to 8 bits: round(255 * Encode(x)) for x in [0, 1]
// (clipped outside). Exact and fast: the 255 linear values where the rounded code changes,
// Decode((k + 1/2) / 255), are precomputed and searched, so no power is taken per pixel.
class Quantizer8 {
 public:
  explicit Quantizer8(const TransferCurve& curve);
  uint8_t operator()(float linear) const;

 private:
  std::array<float, 255> thresholds_;  // code k + 1 starts at thresholds_[k]
};

}  // namespace brdf
