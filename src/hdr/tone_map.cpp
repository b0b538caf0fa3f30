#include "hdr/tone_map.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"

namespace brdf {

ToneOperator ParseToneOperator(const std::string& name) {
  for (ToneOperator op : {ToneOperator::kExposure, ToneOperator::kReinhard,
                          ToneOperator::kReinhardExtended, ToneOperator::kNone}) {
    if (name == ToneOperatorName(op)) return op;
  }
  throw UsageError("unknown tone operator '" + name +
                   "', expected exposure, reinhard, reinhard-extended or none");
}

const char* ToneOperatorName(ToneOperator tone_operator) {
  switch (tone_operator) {
    case ToneOperator::kExposure:
      return "exposure";
    case ToneOperator::kReinhard:
      return "reinhard";
    case ToneOperator::kReinhardExtended:
      return "reinhard-extended";
    case ToneOperator::kNone:
      return "none";
  }
  return "none";
}

ToneMapping PlanToneMapping(ToneOperator tone_operator, const SceneLuminance& scene, double key,
                            double white) {
  ToneMapping mapping;
  mapping.tone_operator = tone_operator;
  const bool reinhard =
      tone_operator == ToneOperator::kReinhard || tone_operator == ToneOperator::kReinhardExtended;
  if (reinhard && scene.log_average > 0.0) mapping.key_scale = key / scene.log_average;
  if (tone_operator == ToneOperator::kReinhardExtended) {
    mapping.white = white > 0.0 ? white : mapping.key_scale * scene.max;
    // A black scene: any positive L_white gives the same (black) picture.
    if (!(mapping.white > 0.0)) mapping.white = 1.0;
  }
  return mapping;
}

void ApplyToneMapping(Image* image, const ToneMapping& mapping) {
  const float key_scale = static_cast<float>(mapping.key_scale);
  const float white = static_cast<float>(mapping.white);
  const ToneOperator op = mapping.tone_operator;
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, image->pixel_count()),
                    [&](const tbb::blocked_range<int64_t>& range) {
                      for (int64_t i = range.begin(); i < range.end(); ++i) {
                        float* rgba = image->rgba.data() + i * Image::kChannels;
                        const float world = PixelLuminance(rgba);
                        float ratio = 0.0f;  // L_d / L_w; black (or negative) luminance stays black
                        if (world > 0.0f) {
                          const float scaled = key_scale * world;
                          float display = world;
                          switch (op) {
                            case ToneOperator::kExposure:
                              display = ExponentialMap(world, 1.0f);
                              break;
                            case ToneOperator::kReinhard:
                              display = ReinhardMap(scaled);
                              break;
                            case ToneOperator::kReinhardExtended:
                              display = ReinhardExtendedMap(scaled, white);
                              break;
                            case ToneOperator::kNone:
                              break;
                          }
                          ratio = display / world;
                        }
                        for (int c = 0; c < 3; ++c)
                          rgba[c] = std::clamp(rgba[c] * ratio, 0.0f, 1.0f);
                      }
                    });
}

}  // namespace brdf
