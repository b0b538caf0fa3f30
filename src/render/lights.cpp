#include "render/lights.h"

#include <charconv>
#include <cmath>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "core/text.h"

namespace brdf {
namespace {

[[noreturn]] void Fail(const std::string& text, const std::string& what) {
  throw UsageError("light '" + text + "': " + what);
}

double ParseValue(const std::string& text, std::string_view field, const std::string& key) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || error != std::errc() || end != field.data() + field.size() ||
      !std::isfinite(value)) {
    Fail(text, "expected a number for " + key + ", found '" + std::string(field) + "'");
  }
  return value;
}

// Camera world frame: +z toward the viewer, theta from +z, phi from +x toward +y.
Vec3 WorldDirection(double theta_deg, double phi_deg) {
  return SphericalDirection(DegToRad(theta_deg), DegToRad(phi_deg));
}

}  // namespace

const std::vector<IlluminancePreset>& IlluminancePresets() {
  static const std::vector<IlluminancePreset> presets = {
      {"sun", 100000.0, "direct sunlight"},
      {"sunny", 20000.0, "full daylight, not in direct sun"},
      {"cloudy", 1000.0, "overcast day"},
      {"office", 500.0, "office lighting"},
      {"home", 50.0, "living room"},
      {"street", 10.0, "street lighting at night"},
      {"full-moon", 0.25, "full moon, clear night"},
      {"moonless", 0.001, "clear moonless night sky"},
  };
  return presets;
}

double LuxToIrradiance(double lux) { return lux / kLumensPerWattAt555nm; }

DirectionalLight ParseDirectionalLight(const std::string& text) {
  const std::vector<std::string_view> parts = SplitFields(text, ":", /*collapse=*/false);
  if (parts.empty() || parts[0] != "dir") Fail(text, "expected dir:theta=..:phi=..:lux=..");
  double theta = 0.0, phi = 0.0;
  bool power_given = false;
  DirectionalLight light;
  for (size_t k = 1; k < parts.size(); ++k) {
    const size_t equals = parts[k].find('=');
    if (equals == std::string_view::npos) {
      Fail(text, "expected key=value, found '" + std::string(parts[k]) + "'");
    }
    const std::string key(parts[k].substr(0, equals));
    const std::string_view value = parts[k].substr(equals + 1);
    if (key == "theta") {
      theta = ParseValue(text, value, key);
      if (theta < 0.0 || theta > 180.0) Fail(text, "theta must lie in [0, 180] degrees");
    } else if (key == "phi") {
      phi = ParseValue(text, value, key);
    } else if (key == "lux" || key == "irradiance" || key == "rgb") {
      if (power_given) Fail(text, "give one of lux, irradiance, rgb");
      power_given = true;
      if (key == "rgb") {
        const std::vector<std::string_view> channels = SplitFields(value, ",", false);
        if (channels.size() != 3) Fail(text, "rgb takes three numbers r,g,b");
        for (int c = 0; c < 3; ++c) light.irradiance[c] = ParseValue(text, channels[c], key);
      } else {
        const double amount = ParseValue(text, value, key);
        light.irradiance = Rgb::Constant(key == "lux" ? LuxToIrradiance(amount) : amount);
      }
      if ((light.irradiance < 0.0).any()) Fail(text, key + " must be >= 0");
    } else {
      Fail(text, "unknown key '" + key + "' (expected theta, phi, lux, irradiance or rgb)");
    }
  }
  if (!power_given) Fail(text, "give its strength: lux=, irradiance= or rgb=");
  light.direction = WorldDirection(theta, phi);
  return light;
}

DirectionalLight PresetLight(const std::string& name) {
  std::string names;
  for (const IlluminancePreset& preset : IlluminancePresets()) {
    if (preset.name == name) {
      DirectionalLight light;
      light.direction = WorldDirection(45.0, 45.0);
      light.irradiance = Rgb::Constant(LuxToIrradiance(preset.lux));
      return light;
    }
    names += (names.empty() ? "" : ", ") + preset.name;
  }
  throw UsageError("unknown preset '" + name + "' (expected one of " + names + ")");
}

}  // namespace brdf
