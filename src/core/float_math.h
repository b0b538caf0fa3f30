// Single-precision pieces of the preview's hot loop (render/sphere.cpp, and the models' float
// evaluation and draws it calls: ClampedPow in models/common.h, ggx's visible normals): the
// vector types, the sine and cosine of a fraction of a turn, atan2, exp and log, as polynomials
// without libm's argument reduction for arbitrary inputs. Coefficients from S. L. Moshier's Cephes
// library (sinf.c, cosf.c, atanf.c, expf.c, logf.c; "Methods and Programs for Mathematical
// Functions", 1989), accurate to a few float ulps on their reduced ranges; the tests check them
// against libm in double.
//
// Why float and not libm: one preview takes about 40 million directions, each needing a sine and
// cosine to be drawn and an atan2 and an arccosine to be looked up in the environment; libm's
// double versions were a quarter of the render. An error of 1e-7 rad moves a direction by a
// thousandth of the smallest environment pixel, far below the noise. Inline and without
// branches, these vectorize in a loop over a batch (libm's float exp and log, behind a call,
// do not: they were a tenth of a glossy render).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/angles.h"
#include "core/vec.h"

namespace brdf {

// A function of one lane of a batch loop: inlined whatever its size, since a call keeps the
// loop scalar.
#if defined(__GNUC__)
#define BRDF_LANE_FUNCTION inline __attribute__((always_inline))
#else
#define BRDF_LANE_FUNCTION inline
#endif

using Vec3f = Vec3T<float>;
using RgbF = RgbT<float>;

inline constexpr float kPiF = static_cast<float>(kPi);
inline constexpr float kInvPiF = static_cast<float>(kInvPi);

// The selects below multiply by 0 or 1 (exact for finite values) instead of branching: the
// directions are random, and a mispredicted branch costs as much as the polynomial.

// sin(2 pi t) and cos(2 pi t) for t in [0, 1] (a fraction of a turn, as random numbers are):
// t is split exactly into a quarter-turn count and a remainder in [-pi/4, pi/4], where the
// Cephes polynomials hold.
inline void SinCosTurn(float t, float* sine, float* cosine) {
  const float quarters = 4.0f * t;  // exact
  const int quadrant = static_cast<int>(quarters + 0.5f);
  const float x = (quarters - static_cast<float>(quadrant)) * (0.5f * kPiF);
  const float x2 = x * x;
  const float s =
      x + x * x2 * (-1.6666654611e-1f + x2 * (8.3321608736e-3f + x2 * -1.9515295891e-4f));
  const float c =
      1.0f - 0.5f * x2 +
      x2 * x2 *
          (4.166664568298827e-2f + x2 * (-1.388731625493765e-3f + x2 * 2.443315711809948e-5f));
  // sin(k pi/2 + x), cos(k pi/2 + x) for quadrant k: (s, c), (c, -s), (-s, -c), (-c, s).
  const float swap = static_cast<float>(quadrant & 1);
  const float sine_sign = 1.0f - static_cast<float>(quadrant & 2);
  const float cosine_sign = 1.0f - static_cast<float>((quadrant + 1) & 2);
  *sine = sine_sign * (swap * c + (1.0f - swap) * s);
  *cosine = cosine_sign * (swap * s + (1.0f - swap) * c);
}

// atan2(y, x) in [-pi, pi], 0 for (0, 0). The ratio t of the smaller to the larger magnitude
// lies in [0, 1]; above tan(pi/8) it is mapped by atan(t) = pi/4 + atan((t - 1)/(t + 1)) into
// [-tan(pi/8), tan(pi/8)], where Cephes' odd polynomial holds; the octant is then restored.
inline float Atan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float larger = std::max(ax, ay), smaller = std::min(ax, ay);
  const float shifted = static_cast<float>(smaller > 0.41421356f * larger);
  // (0, 0): 0 / FLT_MIN = 0.
  const float t =
      (smaller - shifted * larger) / std::max(larger + shifted * smaller, 1.17549435e-38f);
  const float z = t * t;
  const float first_octant =
      (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z -
       3.33329491539e-1f) *
          z * t +
      t + shifted * (0.25f * kPiF);
  // |y| > |x|: pi/2 - angle; then x < 0: pi - angle; then the sign of y.
  const float steep = std::copysign(1.0f, ax - ay);
  const float quadrant_angle = (1.0f - steep) * (0.25f * kPiF) + steep * first_octant;
  const float left = std::copysign(1.0f, x);
  return std::copysign((1.0f - left) * (0.5f * kPiF) + left * quadrant_angle, y);
}

// The bits of a float and back (a copy the compiler turns into a register move).
inline int32_t FloatBits(float x) {
  int32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}
inline float BitsFloat(int32_t bits) {
  float x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

// exp(x) for x <= 0 (Cephes expf.c): x = n ln 2 + r with |r| <= ln(2)/2 (ln 2 split in two so
// that n ln 2 is exact), a degree-7 polynomial for exp(r), and 2^n written into the exponent
// bits; 0 below -87.3, where exp(x) leaves the normal floats.
inline float ExpNonPositive(float x) {
  const float clamped = std::max(x, -87.0f);
  // Truncating t - 1/2 for t <= 0 rounds t to a nearest integer.
  const int n = static_cast<int>(clamped * 1.44269504088896341f - 0.5f);
  const float n_float = static_cast<float>(n);
  const float r = (clamped - n_float * 0.693359375f) - n_float * -2.12194440e-4f;
  const float r2 = r * r;
  const float polynomial =
      (((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r +
         4.1665795894e-2f) *
            r +
        1.6666665459e-1f) *
           r +
       5.0000001201e-1f) *
          r2 +
      r + 1.0f;
  const float result =
      polynomial * BitsFloat(static_cast<int32_t>(static_cast<uint32_t>(n + 127) << 23));
  return static_cast<float>(x >= -87.0f) * result;
}

// log(x) for a positive normal float (Cephes logf.c): x = 2^e m with m in [sqrt(1/2), sqrt(2)),
// a degree-9 polynomial in m - 1, and e ln 2 added in two parts.
inline float LogPositive(float x) {
  const int32_t bits = FloatBits(x);
  int exponent = ((bits >> 23) & 0xff) - 126;
  float m = BitsFloat((bits & 0x807fffff) | 0x3f000000);  // in [1/2, 1)
  const float below = static_cast<float>(m < 0.707106781186547524f);
  exponent -= static_cast<int>(below);
  m = m + below * m - 1.0f;
  const float m2 = m * m;
  float y = ((((((((7.0376836292e-2f * m - 1.1514610310e-1f) * m + 1.1676998740e-1f) * m -
                  1.2420140846e-1f) *
                     m +
                 1.4249322787e-1f) *
                    m -
                1.6668057665e-1f) *
                   m +
               2.0000714765e-1f) *
                  m -
              2.4999993993e-1f) *
                 m +
             3.3333331174e-1f) *
            m * m2;
  const float e = static_cast<float>(exponent);
  y += -2.12194440e-4f * e;
  y += -0.5f * m2;
  return (m + y) + 0.693359375f * e;
}

// log(1 - d) for d in [0, 1), with the digits of d kept when d is tiny (Goldberg, "What every
// computer scientist should know about floating-point arithmetic", 1991, theorem 4: with
// w = 1 - d rounded, log(w) d / (1 - w) is accurate although w itself has lost d's digits).
inline float LogOneMinus(float d) {
  const float w = 1.0f - d;
  const float lost = 1.0f - w;  // 0 when w rounds to 1: then log(1 - d) = -d to float precision
  const float exact = static_cast<float>(lost == 0.0f);
  return exact * -d + (1.0f - exact) * (LogPositive(w) * (d / (lost + exact)));
}

// exp(x) - 1 for x <= 0 without the cancellation near 0: the Taylor series to x^7 above
// x = -1/2 (relative error under 2e-7 there), exp(x) - 1 below (where it is at least 0.39 in
// magnitude and nothing cancels); -1 at -inf.
inline float ExpMinusOne(float x) {
  const float series =
      x * (1.0f + x * (0.5f + x * (1.0f / 6 +
                                   x * (1.0f / 24 +
                                        x * (1.0f / 120 + x * (1.0f / 720 + x * (1.0f / 5040)))))));
  // Both computed, one selected (x = -inf makes the series NaN, which a select ignores).
  return x < -0.5f ? ExpNonPositive(x) - 1.0f : series;
}

}  // namespace brdf
