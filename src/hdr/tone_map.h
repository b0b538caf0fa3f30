// Tone mapping on luminance, preserving chroma (DESIGN §8): the operator maps world luminance
// L_w to display luminance L_d in [0, 1]; RGB is scaled by L_d / L_w and clipped to [0, 1].
//
//   exposure           L_d = 1 - exp(-L_w * exposure): slope `exposure` at 0, never reaches 1.
//                      (The lecture prints 1 - exp(+x * exposure), which is negative; see
//                      docs/conventions.md.) In the pipeline the exposure stage has already
//                      multiplied L_w, so the operator runs with exposure 1.
//   reinhard           Reinhard, Stark, Shirley & Ferwerda, "Photographic tone reproduction
//                      for digital images", SIGGRAPH 2002: L = a / L_avg * L_w (eq. 2),
//                      L_d = L / (1 + L) (eq. 3).
//   reinhard-extended  eq. (4): L_d = L (1 + L / L_white^2) / (1 + L), L_white in the same
//                      key-scaled units as L; the default L_white is the scene maximum, which
//                      then maps to exactly 1.
//   none               L_d = L_w (clipped).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "hdr/exposure.h"
#include "hdr/image.h"

namespace brdf {

enum class ToneOperator { kExposure, kReinhard, kReinhardExtended, kNone };
// "exposure", "reinhard", "reinhard-extended", "none"; throws UsageError otherwise.
ToneOperator ParseToneOperator(const std::string& name);
const char* ToneOperatorName(ToneOperator tone_operator);

template <typename T>
T ExponentialMap(T luminance, T exposure) {
  return T(1) - std::exp(-luminance * exposure);
}
// `scaled` is the key-scaled luminance L of Reinhard 2002 eq. (2).
template <typename T>
T ReinhardMap(T scaled) {
  return scaled / (T(1) + scaled);
}
template <typename T>
T ReinhardExtendedMap(T scaled, T white) {
  return scaled * (T(1) + scaled / (white * white)) / (T(1) + scaled);
}

// What one tone-mapping run used, for the summary line.
struct ToneMapping {
  ToneOperator tone_operator = ToneOperator::kReinhardExtended;
  double key_scale = 1.0;  // a / L_avg (Reinhard); 1 otherwise
  double white = 0.0;      // L_white in key-scaled units (reinhard-extended)
};

// Chooses the key scale and L_white. `white` <= 0 means the scene maximum.
ToneMapping PlanToneMapping(ToneOperator tone_operator, const SceneLuminance& scene, double key,
                            double white);
// One pixel's mapping in float, as ApplyToneMapping does it (the fused pipeline maps pixels it
// never stores through the same arithmetic). The operator is a template argument so that the
// per-pixel loop carries no switch; ForToneOperator() picks the instance.
template <ToneOperator kOperator>
class PixelToneMap {
 public:
  static constexpr ToneOperator kToneOperator = kOperator;
  explicit PixelToneMap(const ToneMapping& mapping)
      : key_scale_(static_cast<float>(mapping.key_scale)),
        white_(static_cast<float>(mapping.white)) {}
  // The constants operator() uses, for a vector twin of it.
  float key_scale() const { return key_scale_; }
  float white() const { return white_; }
  // RGB of `in` mapped and clipped to [0, 1] into out[0..2]; `in` may be `out`.
  void operator()(const float* in, float* out) const {
    const float world = PixelLuminance(in);
    float ratio = 0.0f;  // L_d / L_w; black (or negative) luminance stays black
    if (world > 0.0f) {
      float display = world;
      if constexpr (kOperator == ToneOperator::kExposure) {
        display = ExponentialMap(world, 1.0f);
      } else if constexpr (kOperator == ToneOperator::kReinhard) {
        display = ReinhardMap(key_scale_ * world);
      } else if constexpr (kOperator == ToneOperator::kReinhardExtended) {
        display = ReinhardExtendedMap(key_scale_ * world, white_);
      }
      ratio = display / world;
    }
    for (int c = 0; c < 3; ++c) out[c] = std::clamp(in[c] * ratio, 0.0f, 1.0f);
  }

 private:
  float key_scale_;
  float white_;
};

// Calls visit(PixelToneMap<op>(mapping)) for the mapping's operator.
template <typename Visit>
void ForToneOperator(const ToneMapping& mapping, Visit&& visit) {
  switch (mapping.tone_operator) {
    case ToneOperator::kExposure:
      return visit(PixelToneMap<ToneOperator::kExposure>(mapping));
    case ToneOperator::kReinhard:
      return visit(PixelToneMap<ToneOperator::kReinhard>(mapping));
    case ToneOperator::kReinhardExtended:
      return visit(PixelToneMap<ToneOperator::kReinhardExtended>(mapping));
    case ToneOperator::kNone:
      return visit(PixelToneMap<ToneOperator::kNone>(mapping));
  }
}

// Maps every pixel in place; RGB ends in [0, 1]; alpha is kept.
void ApplyToneMapping(Image* image, const ToneMapping& mapping);

}  // namespace brdf
