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
    return Encode(linear, buckets_.data(), thresholds_.data(), max_codes_per_bucket_ - 1);
  }
  // `count` values at once, as operator() one by one: the table and the step count are read
  // into locals once (a byte store may alias anything, so a per-value call reloads them).
  // With AVX2 (simd.h), eight values at a time: the bucket table is read by gathers.
  void EncodeMany(const float* linear, int64_t count, uint8_t* out) const;
  // Three planes of `count` values each (red, green, blue) into `count` interleaved RGB byte
  // triples, as operator() value by value (the pipeline's AVX2 tone mapping writes planes).
  void EncodePlanes(const float* red, const float* green, const float* blue, int64_t count,
                    uint8_t* rgb) const;

 private:
  struct Bucket;
  // The rounding itself, given the tables; `extra_steps` more comparisons after the bucket's
  // first, a fixed number without branches (a data-dependent loop exit mispredicts): none for
  // the sRGB curve and gammas near it, where no bucket holds more than one code change.
  static uint8_t Encode(float linear, const Bucket* buckets, const float* thresholds,
                        int extra_steps);

  static constexpr int kBucketShift = 16;  // keeps sign, exponent and 7 mantissa bits
  static constexpr int kBuckets = (0x3f800000 >> kBucketShift) + 1;  // floats in [0, 1]
  // Code k + 1 starts at thresholds_[k]; thresholds_[255] = infinity stops the count at 255.
  std::array<float, 256> thresholds_;
  // The code at the start of a bucket and the threshold of the next one, side by side: one
  // load finds both (32-bit code: no padding, so a vector gather reads defined bytes).
  struct Bucket {
    float next;
    uint32_t start;
  };
  std::array<Bucket, kBuckets> buckets_;
  int max_codes_per_bucket_ = 0;  // most code changes inside one bucket
};

inline uint8_t Quantizer8::Encode(float linear, const Bucket* buckets, const float* thresholds,
                                  int extra_steps) {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  uint32_t bits;
  std::memcpy(&bits, &linear, sizeof(bits));
  const Bucket& bucket = buckets[bits >> kBucketShift];
  int code = static_cast<int>(bucket.start) + (linear >= bucket.next);
  for (int step = 0; step < extra_steps; ++step) code += linear >= thresholds[code];
  return static_cast<uint8_t>(code);
}

}  // namespace brdf
