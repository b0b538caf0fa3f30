#include "render/sphere.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <cstdio>

#include "core/colour.h"
#include "core/errors.h"
#include "core/progress.h"
#include "energy/monte_carlo.h"
#include "render/sampling.h"

namespace brdf {
namespace {

// Power heuristic with exponent 2 (Veach & Guibas 1995) for one sample of each technique; a
// technique that is not used has pdf 0.
double PowerHeuristic(double pdf_this, double pdf_other, double pdf_third = 0.0) {
  const double a = pdf_this * pdf_this;
  const double sum = a + pdf_other * pdf_other + pdf_third * pdf_third;
  return sum > 0.0 ? a / sum : 0.0;
}

Rgb FiniteOrZero(const Rgb& value, int64_t* missing) {
  if (value.allFinite()) return value;
  ++*missing;
  return Rgb::Zero();
}

}  // namespace

void RenderOptions::Validate() const {
  if (size <= 0 || size > 16384) {
    throw UsageError("--size " + std::to_string(size) + ": must lie in 1..16384 px");
  }
  if (spp <= 0 || spp > 1 << 20) {
    throw UsageError("--spp " + std::to_string(spp) + ": must lie in 1..1048576");
  }
}

std::string RenderResult::Summary() const {
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), "%dx%d, %lld sphere pixels", radiance.width,
                radiance.height, static_cast<long long>(sphere_pixels));
  std::string text = buffer;
  if (missing_lookups > 0) {
    text += ", " + std::to_string(missing_lookups) + " lookups without data (black)";
  }
  return text;
}

std::optional<Vec3> SphereNormal(int x, int y, int size) {
  const double u = (2.0 * x + 1.0) / size - 1.0;
  const double v = 1.0 - (2.0 * y + 1.0) / size;
  const double r2 = u * u + v * v;
  if (r2 >= 1.0) return std::nullopt;
  return Vec3(u, v, std::sqrt(1.0 - r2));
}

RenderResult RenderSphere(const Material& material, const std::vector<DirectionalLight>& lights,
                          const Environment* environment, const RenderOptions& options,
                          Progress* progress) {
  options.Validate();
  const int size = options.size;
  RenderResult result;
  result.radiance = Image(size, size, /*alpha=*/0.0f);
  result.luminance_std_error.assign(int64_t{size} * size, 0.0f);
  std::atomic<int64_t> sphere_pixels{0}, missing{0};
  const Vec3 wo_world(0.0, 0.0, 1.0);
  const std::optional<LobeCoordinates> lobe = material.SpecularLobe();
  // Density of the lobe technique at wi (0 when the material has no lobe).
  auto lobe_pdf = [&](const Vec3& wo, const Vec3& wi) {
    return lobe ? StrategyPdf(*lobe, wo, wi) : 0.0;
  };

  tbb::parallel_for(0, size, [&](int y) {
    int64_t row_pixels = 0, row_missing = 0;
    for (int x = 0; x < size; ++x) {
      const std::optional<Vec3> normal = SphereNormal(x, y, size);
      if (!normal) continue;
      ++row_pixels;
      const Frame frame = Frame::FromZ(*normal);
      const Vec3 wo = frame.ToLocal(wo_world);
      Rgb radiance = Rgb::Zero();

      // f in 1/sr, no cosine factor (DESIGN §1); E is the irradiance normal to the light.
      for (const DirectionalLight& light : lights) {
        const Vec3 wi = frame.ToLocal(light.direction);
        if (wi.z() <= 0.0) continue;
        radiance += FiniteOrZero(material.Eval(wi, wo), &row_missing) * light.irradiance * wi.z();
      }

      double std_error = 0.0;
      if (environment != nullptr) {
        const int64_t pixel = int64_t{y} * size + x;
        PixelRandom random(options.seed, static_cast<uint64_t>(pixel));
        Rgb sum = Rgb::Zero();
        double luminance_sum = 0.0, luminance_squares = 0.0;
        for (int s = 0; s < options.spp; ++s) {
          Rgb estimate = Rgb::Zero();
          // Environment (light) sampling.
          // Draws in separate statements: argument evaluation order is unspecified, and the
          // image must not depend on the compiler.
          const double v0 = random.Uniform();
          const double v1 = random.Uniform();
          const Environment::Sample light = environment->SampleDirection(v0, v1);
          const Vec3 wi_light = frame.ToLocal(light.direction);
          if (wi_light.z() > 0.0 && light.pdf > 0.0) {
            const double weight = PowerHeuristic(light.pdf, CosineHemispherePdf(wi_light.z()),
                                                 lobe_pdf(wo, wi_light));
            estimate += FiniteOrZero(material.Eval(wi_light, wo), &row_missing) * light.radiance *
                        (wi_light.z() * weight / light.pdf);
          }
          // Cosine (BRDF-proportional for the diffuse part) sampling.
          const double u0 = random.Uniform();
          const double u1 = random.Uniform();
          const Vec3 wi_cosine = SampleCosineHemisphere(Point2(u0, u1));
          const double pdf_cosine = CosineHemispherePdf(wi_cosine.z());
          if (pdf_cosine > 0.0) {
            const Vec3 world = frame.FromLocal(wi_cosine);
            double pdf_light = 0.0;
            const Rgb radiance_in = environment->RadianceAndPdf(world, &pdf_light);
            const double weight = PowerHeuristic(pdf_cosine, pdf_light, lobe_pdf(wo, wi_cosine));
            estimate += FiniteOrZero(material.Eval(wi_cosine, wo), &row_missing) * radiance_in *
                        (wi_cosine.z() * weight / pdf_cosine);
          }
          // Lobe sampling, for models with a specular lobe.
          if (lobe) {
            const double w0 = random.Uniform();
            const double w1 = random.Uniform();
            const Vec3 wi_lobe = SampleStrategy(*lobe, wo, Point2(w0, w1));
            const double pdf = lobe_pdf(wo, wi_lobe);
            if (wi_lobe.z() > 0.0 && pdf > 0.0) {
              double pdf_light = 0.0;
              const Rgb radiance_in =
                  environment->RadianceAndPdf(frame.FromLocal(wi_lobe), &pdf_light);
              const double weight =
                  PowerHeuristic(pdf, pdf_light, CosineHemispherePdf(wi_lobe.z()));
              estimate += FiniteOrZero(material.Eval(wi_lobe, wo), &row_missing) * radiance_in *
                          (wi_lobe.z() * weight / pdf);
            }
          }
          sum += estimate;
          const double luminance = Luminance(estimate);
          luminance_sum += luminance;
          luminance_squares += luminance * luminance;
        }
        const double n = options.spp;
        radiance += sum / n;
        if (options.spp > 1) {
          const double mean = luminance_sum / n;
          const double variance = std::max(0.0, (luminance_squares - n * mean * mean) / (n - 1));
          std_error = std::sqrt(variance / n);
        }
      }

      float* rgba = result.radiance.pixel(x, y);
      for (int c = 0; c < 3; ++c) rgba[c] = static_cast<float>(radiance[c]);
      rgba[3] = 1.0f;
      result.luminance_std_error[int64_t{y} * size + x] = static_cast<float>(std_error);
    }
    sphere_pixels += row_pixels;
    missing += row_missing;
    if (progress != nullptr) progress->Advance();
  });
  result.sphere_pixels = sphere_pixels;
  result.missing_lookups = missing;
  return result;
}

}  // namespace brdf
