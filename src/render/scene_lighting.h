// The lighting of a preview as `brdf render` and `brdfkit.render` take it (DESIGN §8): the
// --light specs, the --preset names and the --env spec, with the default a user gets when none
// is given (the office preset).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "render/environment.h"
#include "render/lights.h"

namespace brdf {

struct SceneLighting {
  std::vector<DirectionalLight> lights;
  std::optional<Environment> environment;
  // What the caller should tell the user (an environment's NaN/Inf pixels made black).
  std::vector<std::string> warnings;

  const Environment* environment_or_null() const { return environment ? &*environment : nullptr; }
};

// Lights in the order given (specs, then presets); the office preset when there is neither a
// light nor an environment. Throws UsageError / InputError naming the bad spec or file.
SceneLighting MakeSceneLighting(const std::vector<std::string>& light_specs,
                                const std::vector<std::string>& preset_names,
                                const std::string& environment_spec);

}  // namespace brdf
