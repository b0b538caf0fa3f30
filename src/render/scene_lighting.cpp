#include "render/scene_lighting.h"

namespace brdf {

SceneLighting MakeSceneLighting(const std::vector<std::string>& light_specs,
                                const std::vector<std::string>& preset_names,
                                const std::string& environment_spec) {
  SceneLighting lighting;
  for (const std::string& text : light_specs) {
    lighting.lights.push_back(ParseDirectionalLight(text));
  }
  for (const std::string& name : preset_names) lighting.lights.push_back(PresetLight(name));
  if (!environment_spec.empty()) {
    int64_t broken = 0;
    lighting.environment = Environment::Load(environment_spec, &broken);
    if (broken > 0) {
      lighting.warnings.push_back(environment_spec + ": " + std::to_string(broken) +
                                  " pixels with NaN or infinite values, replaced by 0");
    }
  }
  if (lighting.lights.empty() && !lighting.environment) {
    lighting.lights.push_back(PresetLight("office"));
  }
  return lighting;
}

}  // namespace brdf
