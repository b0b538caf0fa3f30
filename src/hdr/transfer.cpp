#include "hdr/transfer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>

#include "core/errors.h"
#include "core/format.h"
#include "core/simd.h"

#if BRDF_HAS_AVX2_PATHS
#include <immintrin.h>
#endif

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
    throw UsageError("gamma: expected 'srgb' or a positive number, got '" + text + "'");
  }
  curve.kind = Kind::kGamma;
  curve.gamma = gamma;
  return curve;
}

std::string TransferCurve::Name() const {
  if (kind == Kind::kSrgb) return "srgb";
  return Format("gamma %g", gamma);
}

double TransferCurve::Encode(double linear) const {
  linear = std::clamp(linear, 0.0, 1.0);
  return kind == Kind::kSrgb ? SrgbEncode(linear) : std::pow(linear, 1.0 / gamma);
}

double TransferCurve::Decode(double encoded) const {
  encoded = std::clamp(encoded, 0.0, 1.0);
  return kind == Kind::kSrgb ? SrgbDecode(encoded) : std::pow(encoded, gamma);
}

#if BRDF_HAS_AVX2_PATHS
namespace {

// A quantizer's tables as the vector code reads them: bucket b's next threshold is the float
// at words[2b], its first code the 32-bit integer at words[2b + 1].
struct QuantizerTables {
  const void* buckets;
  const float* thresholds;
  int extra_steps;
  int last_bucket;
};

// Quantizer8::Encode on eight values: the same comparisons, the bucket and threshold tables
// read by gathers; codes as 32-bit integers.
BRDF_AVX2 inline __m256i Codes8(__m256 linear, const QuantizerTables& tables) {
  // Values outside (0, 1) (and NaN) get a clamped, valid index; their code is replaced below.
  const __m256i index = _mm256_min_epu32(_mm256_srli_epi32(_mm256_castps_si256(linear), 16),
                                         _mm256_set1_epi32(tables.last_bucket));
  const __m256 next = _mm256_i32gather_ps(static_cast<const float*>(tables.buckets), index, 8);
  const __m256i start =
      _mm256_i32gather_epi32(static_cast<const int*>(tables.buckets) + 1, index, 8);
  // A true comparison is all ones (-1): subtracting it adds 1.
  __m256i code =
      _mm256_sub_epi32(start, _mm256_castps_si256(_mm256_cmp_ps(linear, next, _CMP_GE_OQ)));
  for (int step = 0; step < tables.extra_steps; ++step) {
    const __m256 threshold = _mm256_i32gather_ps(tables.thresholds, code, 4);
    code =
        _mm256_sub_epi32(code, _mm256_castps_si256(_mm256_cmp_ps(linear, threshold, _CMP_GE_OQ)));
  }
  const __m256 one = _mm256_set1_ps(1.0f);
  code = _mm256_blendv_epi8(code, _mm256_set1_epi32(255),
                            _mm256_castps_si256(_mm256_cmp_ps(linear, one, _CMP_GE_OQ)));
  const __m256 positive = _mm256_cmp_ps(linear, _mm256_setzero_ps(), _CMP_GT_OQ);
  return _mm256_and_si256(code, _mm256_castps_si256(positive));
}

// The values of whole groups of eight; returns how many were encoded.
BRDF_AVX2 int64_t EncodeManyAvx2(const float* linear, int64_t count, uint8_t* out,
                                 const QuantizerTables& tables) {
  int64_t i = 0;
  for (; i + 8 <= count; i += 8) {
    const __m256i codes = Codes8(_mm256_loadu_ps(linear + i), tables);
    const __m128i words =
        _mm_packus_epi32(_mm256_castsi256_si128(codes), _mm256_extracti128_si256(codes, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(words, words));
  }
  return i;
}

BRDF_AVX2 int64_t EncodePlanesAvx2(const float* red, const float* green, const float* blue,
                                   int64_t count, uint8_t* rgb, const QuantizerTables& tables) {
  // Within each 128-bit half: r0..r3 g0..g3 b0..b3 (then zeros) to r0 g0 b0 r1 ... b3.
  const __m256i interleave =
      _mm256_setr_epi8(0, 4, 8, 1, 5, 9, 2, 6, 10, 3, 7, 11, -128, -128, -128, -128, 0, 4, 8, 1, 5,
                       9, 2, 6, 10, 3, 7, 11, -128, -128, -128, -128);
  int64_t i = 0;
  for (; i + 8 <= count; i += 8) {
    const __m256i r = Codes8(_mm256_loadu_ps(red + i), tables);
    const __m256i g = Codes8(_mm256_loadu_ps(green + i), tables);
    const __m256i b = Codes8(_mm256_loadu_ps(blue + i), tables);
    const __m256i bytes = _mm256_packus_epi16(_mm256_packus_epi32(r, g),
                                              _mm256_packus_epi32(b, _mm256_setzero_si256()));
    const __m256i pixels = _mm256_shuffle_epi8(bytes, interleave);
    const __m128i low = _mm256_castsi256_si128(pixels);        // pixels 0..3, 12 bytes
    const __m128i high = _mm256_extracti128_si256(pixels, 1);  // pixels 4..7
    uint8_t* out = rgb + 3 * i;
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_or_si128(low, _mm_slli_si128(high, 12)));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 16), _mm_srli_si128(high, 4));
  }
  return i;
}

}  // namespace
#endif

void Quantizer8::EncodeMany(const float* linear, int64_t count, uint8_t* out) const {
  const Bucket* const buckets = buckets_.data();
  const float* const thresholds = thresholds_.data();
  const int extra_steps = max_codes_per_bucket_ - 1;
  int64_t i = 0;
#if BRDF_HAS_AVX2_PATHS
  static_assert(sizeof(Bucket) == 8 && offsetof(Bucket, next) == 0 && offsetof(Bucket, start) == 4,
                "the vector path reads a bucket as two 32-bit words");
  if (Avx2Enabled()) {
    i = EncodeManyAvx2(linear, count, out, {buckets, thresholds, extra_steps, kBuckets - 1});
  }
#endif
  for (; i < count; ++i) out[i] = Encode(linear[i], buckets, thresholds, extra_steps);
}

void Quantizer8::EncodePlanes(const float* red, const float* green, const float* blue,
                              int64_t count, uint8_t* rgb) const {
  const Bucket* const buckets = buckets_.data();
  const float* const thresholds = thresholds_.data();
  const int extra_steps = max_codes_per_bucket_ - 1;
  int64_t i = 0;
#if BRDF_HAS_AVX2_PATHS
  if (Avx2Enabled()) {
    i = EncodePlanesAvx2(red, green, blue, count, rgb,
                         {buckets, thresholds, extra_steps, kBuckets - 1});
  }
#endif
  for (; i < count; ++i) {
    rgb[3 * i] = Encode(red[i], buckets, thresholds, extra_steps);
    rgb[3 * i + 1] = Encode(green[i], buckets, thresholds, extra_steps);
    rgb[3 * i + 2] = Encode(blue[i], buckets, thresholds, extra_steps);
  }
}

Quantizer8::Quantizer8(const TransferCurve& curve) {
  for (int k = 0; k < 255; ++k) {
    thresholds_[k] = static_cast<float>(curve.Decode((k + 0.5) / 255.0));
  }
  thresholds_[255] = std::numeric_limits<float>::infinity();
  // Number of thresholds at or below a value, for values that never decrease from one call to
  // the next (the buckets' first and last floats in turn): a sweep over the sorted thresholds,
  // where a binary search per bucket was 1 % of a 1080p pipeline.
  int below = 0;
  const auto codes_below = [&](float value) {
    while (below < 255 && thresholds_[below] <= value) ++below;
    return below;
  };
  for (int bucket = 0; bucket < kBuckets; ++bucket) {
    const uint32_t first_bits = static_cast<uint32_t>(bucket) << kBucketShift;
    const uint32_t last_bits = first_bits + (1u << kBucketShift) - 1;
    float first, last;
    std::memcpy(&first, &first_bits, sizeof(first));
    std::memcpy(&last, &last_bits, sizeof(last));
    const int start = codes_below(first);
    buckets_[bucket] = {thresholds_[start], static_cast<uint32_t>(start)};
    max_codes_per_bucket_ =
        std::max(max_codes_per_bucket_, codes_below(std::min(last, 1.0f)) - start);
  }
}

}  // namespace brdf
