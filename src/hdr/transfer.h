// Display encoding (DESIGN §8): the sRGB transfer curve (IEC 61966-2-1: linear below
// 0.0031308, a 1/2.4 power above), or a plain gamma, then 8 bits with rounding.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
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
// Decode((k + 1/2) / 255), are precomputed, so no power is taken per pixel. A binary search
// over them mispredicts a branch per level; instead the float's exponent and top 7 mantissa
// bits index a table of the code at the start of that bucket (relative width 2^-7, so at most
// a few codes further), and a fixed, branch-free number of comparisons finishes.
class Quantizer8 {
 public:
  explicit Quantizer8(const TransferCurve& curve);
  uint8_t operator()(float linear) const {
    if (!(linear > 0.0f)) return 0;  // also NaN
    if (linear >= 1.0f) return 255;
    uint32_t bits;
    std::memcpy(&bits, &linear, sizeof(bits));
    const Bucket& bucket = buckets_[bits >> kBucketShift];
    int code = bucket.start + (linear >= bucket.next);
    // A fixed number of further steps without branches (a data-dependent loop exit
    // mispredicts); none for the sRGB curve and gammas near it, where no bucket holds more
    // than one code change.
    for (int step = 1; step < max_codes_per_bucket_; ++step) code += linear >= thresholds_[code];
    return static_cast<uint8_t>(code);
  }

 private:
  static constexpr int kBucketShift = 16;  // keeps sign, exponent and 7 mantissa bits
  static constexpr int kBuckets = (0x3f800000 >> kBucketShift) + 1;  // floats in [0, 1]
  // Code k + 1 starts at thresholds_[k]; thresholds_[255] = infinity stops the count at 255.
  std::array<float, 256> thresholds_;
  // The code at the start of a bucket and the threshold of the next one, side by side: one
  // load finds both.
  struct Bucket {
    float next;
    uint8_t start;
  };
  std::array<Bucket, kBuckets> buckets_;
  int max_codes_per_bucket_ = 0;  // most code changes inside one bucket
};

}  // namespace brdf
