#include "hdr/tone_map.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/enum_names.h"
#include "core/errors.h"

namespace brdf {

constexpr EnumName<ToneOperator> kToneOperatorNames[] = {
    {ToneOperator::kExposure, "exposure"},
    {ToneOperator::kReinhard, "reinhard"},
    {ToneOperator::kReinhardExtended, "reinhard-extended"},
    {ToneOperator::kNone, "none"},
};

ToneOperator ParseToneOperator(const std::string& name) {
  return ParseEnum(kToneOperatorNames, name, "tone operator");
}

const char* ToneOperatorName(ToneOperator tone_operator) {
  return NameOf(kToneOperatorNames, tone_operator);
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
  ForToneOperator(mapping, [&](const auto& map) {
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, image->pixel_count()),
                      [&](const tbb::blocked_range<int64_t>& range) {
                        for (int64_t i = range.begin(); i < range.end(); ++i) {
                          float* rgba = image->rgba.data() + i * Image::kChannels;
                          map(rgba, rgba);
                        }
                      });
  });
}

}  // namespace brdf
