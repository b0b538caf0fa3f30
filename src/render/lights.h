// Directional lights of the preview (DESIGN §8), given as irradiance or as illuminance.
//
// Command-line form: dir:theta=DEG:phi=DEG:lux=LX (or :irradiance=W_PER_M2, or :rgb=R,G,B in
// W/m^2 per channel). Directions are in the camera's world frame: +z toward the viewer, +x to
// the right, +y up; theta from +z, phi from +x toward +y, in degrees.
//
// Illuminance becomes irradiance through 683 lm/W (DESIGN §1), the luminous efficacy of
// 555 nm light: exact only for monochromatic green light. Real white light has a lower
// efficacy (about 93 lm/W for sunlight), so these irradiances are lower bounds on the physical
// W/m^2; the *relative* brightness of the presets, which is what a preview shows after
// exposure, is unaffected. The light is white (equal RGB), so its luminance equals the value.
#pragma once

#include <string>
#include <vector>

#include "core/vec.h"

namespace brdf {

struct DirectionalLight {
  Vec3 direction = Vec3(0, 0, 1);  // unit, world frame, toward the light
  Rgb irradiance = Rgb::Ones();    // W/m^2 on a surface facing the light
};

// Typical illuminances from the lecture's table (the usual photometry handbook values).
struct IlluminancePreset {
  std::string name;
  double lux = 0.0;
  std::string description;
};
const std::vector<IlluminancePreset>& IlluminancePresets();

double LuxToIrradiance(double lux);

// Parses the dir:... form; throws UsageError naming the text and the bad part.
DirectionalLight ParseDirectionalLight(const std::string& text);
// A preset's illuminance from theta = 45, phi = 45 degrees (upper right, in front); throws
// UsageError listing the presets for an unknown name.
DirectionalLight PresetLight(const std::string& name);

}  // namespace brdf
