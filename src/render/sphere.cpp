#include "render/sphere.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>

#include "core/colour.h"
#include "core/errors.h"
#include "core/float_math.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/simd.h"
#include "render/lobe_sampler.h"

namespace brdf {
namespace {

Rgb FiniteOrZero(const Rgb& value, int64_t* missing) {
  if (value.allFinite()) return value;
  ++*missing;
  return Rgb::Zero();
}
BRDF_LANE_FUNCTION RgbF FiniteOrZero(const RgbF& value, int64_t* missing) {
  if (value.allFinite()) return value;
  ++*missing;
  return RgbF::Zero();
}

// The lobe technique earns its cost only where the lobe is narrower than the cosine technique
// resolves: where the lobe's largest density of wi exceeds the cosine's, 1/pi, by this factor
// (measured in docs/performance.md: below it the lobe's samples cost more time than the noise
// they remove). Any set of techniques keeps the estimate unbiased; this only trades noise for
// time.
constexpr double kLobeOverCosineDensity = 8.0;

std::optional<LobeTechnique> ChooseLobeTechnique(const Material& material) {
  const std::optional<LobeCoordinates> lobe = material.SpecularLobe();
  if (!lobe || LobeSampler::PeakDensity(*lobe) < kLobeOverCosineDensity * kInvPi) {
    return std::nullopt;
  }
  return LobeTechnique(*lobe);
}

// Samples are drawn, looked up and shaded this many at a time: the loops over a batch that
// compute directions and environment pixels vectorize (four floats at a time), and the
// environment entries of a batch are prefetched before the first is read, so that their cache
// misses overlap.
constexpr int kBatch = 16;

// Directions of a batch, one array per coordinate (so that loops over them vectorize).
struct DirectionBatch {
  alignas(16) float x[kBatch];
  alignas(16) float y[kBatch];
  alignas(16) float z[kBatch];
};

// The environment term of one pixel (sphere.h) in single precision. Per sample s, in this
// order: a light direction from the environment's distribution (64 random bits and a float),
// a cosine-distributed one (two floats), and, when the lobe technique is on, one from the lobe
// (two floats) or, for dense tables, one from the material's own sampler (Material::MakeSampler,
// the same two floats); combined with the power heuristic, whose weight p_t^2 / sum p^2 divided
// by the technique's own pdf p_t is p_t / sum p^2.
class EnvironmentEstimator {
 public:
  EnvironmentEstimator(const Material& material, const Environment& environment,
                       std::optional<LobeTechnique> lobe, const DirectionSampler* sampler, int spp)
      : material_(material),
        environment_(environment),
        lobe_(lobe),
        sampler_(lobe ? nullptr : sampler),
        spp_(spp) {}

  struct Estimate {
    Rgb radiance = Rgb::Zero();
    double luminance_std_error = 0.0;
  };
  // The loops over a batch take 8 lanes where the processor has AVX2 (the pixel compiled a
  // second time for it, without FMA: the same float operations in the same order, so the same
  // numbers), else 4.
  Estimate Pixel(const Frame& frame, uint64_t seed, uint64_t pixel, int64_t* missing) const {
    return avx2_ ? PixelAvx2(frame, seed, pixel, missing) : PixelIn(frame, seed, pixel, missing);
  }

 private:
  BRDF_AVX2 Estimate PixelAvx2(const Frame& frame, uint64_t seed, uint64_t pixel,
                               int64_t* missing) const {
    return PixelIn(frame, seed, pixel, missing);
  }
  BRDF_LANE_FUNCTION Estimate PixelIn(const Frame& frame, uint64_t seed, uint64_t pixel,
                                      int64_t* missing) const {
    Eigen::Matrix3f to_local;
    to_local.row(0) = frame.x.cast<float>();
    to_local.row(1) = frame.y.cast<float>();
    to_local.row(2) = frame.z.cast<float>();
    const Vec3f wo = to_local.col(2);  // the viewer, +z in the world
    std::optional<LobeSampler> lobe;
    if (lobe_) lobe.emplace(*lobe_, wo);
    // The third technique: the lobe's, or the material's own sampler.
    const bool third = lobe || sampler_ != nullptr;
    Rng random(pixel, seed);

    // Zeroed: a batch's unused lanes must hold finite numbers.
    uint64_t light_bits[kBatch] = {};
    alignas(16) float light_v_in_pixel[kBatch] = {}, light_u[kBatch] = {}, light_v[kBatch] = {};
    alignas(16) float light_sin_theta[kBatch] = {}, cosine_sin_theta[kBatch] = {};
    alignas(16) float cosine_u0[kBatch] = {}, cosine_u1[kBatch] = {}, lobe_sin_theta[kBatch] = {};
    uint32_t light_pixel[kBatch] = {}, cosine_pixel[kBatch] = {}, lobe_pixel[kBatch] = {};
    DirectionBatch light_world = {}, light_local = {}, cosine_local = {}, cosine_world = {},
                   lobe_local = {}, lobe_world = {};
    alignas(16) float lobe_u0[kBatch] = {}, lobe_u1[kBatch] = {};
    // The lobe's pdf as the weights count it (MisPdf: zero outside its core, lobe_sampler.h),
    // at each technique's samples.
    alignas(16) float light_lobe_pdf[kBatch] = {}, cosine_lobe_pdf[kBatch] = {},
                      lobe_lobe_pdf[kBatch] = {};
    RgbF light_f[kBatch], cosine_f[kBatch], lobe_f[kBatch];
    Rgb sum = Rgb::Zero();
    double luminance_sum = 0.0, luminance_squares = 0.0;
    for (int first = 0; first < spp_; first += kBatch) {
      const int count = std::min(kBatch, spp_ - first);
      // Draws in separate statements: argument evaluation order is unspecified, and the image
      // must not depend on the compiler. The loops below run over the whole batch (their lanes
      // beyond `count` hold stale numbers and are not used), so that they vectorize.
      for (int k = 0; k < count; ++k) {
        light_bits[k] = random.Bits();
        light_v_in_pixel[k] = random.UniformFloat();
        environment_.Prefetch(environment_.SlotOf(light_bits[k]));
        cosine_u0[k] = random.UniformFloat();
        cosine_u1[k] = random.UniformFloat();
        if (third) {
          lobe_u0[k] = random.UniformFloat();
          lobe_u1[k] = random.UniformFloat();
        }
      }
      if (lobe) {
        lobe->SampleBatch(lobe_u0, lobe_u1, kBatch, lobe_local.x, lobe_local.y, lobe_local.z);
      } else if (sampler_ != nullptr) {
        sampler_->SampleBatch(wo, lobe_u0, lobe_u1, kBatch, lobe_local.x, lobe_local.y,
                              lobe_local.z);
      }
      // SampleCosineHemisphere (core/sampling.h) in float: the polar map.
      for (int k = 0; k < kBatch; ++k) {
        const float radius = std::sqrt(cosine_u0[k]);
        float sin_phi, cos_phi;
        SinCosTurn(cosine_u1[k], &sin_phi, &cos_phi);
        cosine_local.x[k] = radius * cos_phi;
        cosine_local.y[k] = radius * sin_phi;
        cosine_local.z[k] = std::sqrt(std::max(0.0f, 1.0f - cosine_u0[k]));
      }
      Transform(to_local.transpose(), cosine_local, &cosine_world);
      Locate(cosine_world, cosine_pixel, cosine_sin_theta);
      if (third) {
        Transform(to_local.transpose(), lobe_local, &lobe_world);
        Locate(lobe_world, lobe_pixel, lobe_sin_theta);
      }
      for (int k = 0; k < count; ++k) {
        environment_.Prefetch(cosine_pixel[k]);
        if (third) environment_.Prefetch(lobe_pixel[k]);
      }
      for (int k = 0; k < count; ++k) {
        light_pixel[k] = environment_.DrawFloat(environment_.SlotOf(light_bits[k]), light_bits[k],
                                                light_v_in_pixel[k], &light_u[k], &light_v[k]);
        environment_.Prefetch(light_pixel[k]);
      }
      for (int k = 0; k < kBatch; ++k) {
        Environment::DirectionAt(light_u[k], light_v[k], &light_world.x[k], &light_world.y[k],
                                 &light_world.z[k], &light_sin_theta[k]);
      }
      Transform(to_local, light_world, &light_local);
      // The material at every sample of the batch (some are not shaded: below the horizon,
      // outside the lobe's core; those cost an early return).
      material_.EvalFloatBatch(light_local.x, light_local.y, light_local.z, wo, count, light_f);
      material_.EvalFloatBatch(cosine_local.x, cosine_local.y, cosine_local.z, wo, count, cosine_f);
      if (lobe) {
        material_.EvalFloatBatch(lobe_local.x, lobe_local.y, lobe_local.z, wo, count, lobe_f);
        lobe->MisPdfBatch(light_local.x, light_local.y, light_local.z, kBatch, light_lobe_pdf);
        lobe->MisPdfBatch(cosine_local.x, cosine_local.y, cosine_local.z, kBatch, cosine_lobe_pdf);
        lobe->MisPdfBatch(lobe_local.x, lobe_local.y, lobe_local.z, kBatch, lobe_lobe_pdf);
      } else if (sampler_ != nullptr) {
        material_.EvalFloatBatch(lobe_local.x, lobe_local.y, lobe_local.z, wo, count, lobe_f);
        sampler_->PdfBatch(wo, light_local.x, light_local.y, light_local.z, count, light_lobe_pdf);
        sampler_->PdfBatch(wo, cosine_local.x, cosine_local.y, cosine_local.z, count,
                           cosine_lobe_pdf);
        sampler_->PdfBatch(wo, lobe_local.x, lobe_local.y, lobe_local.z, count, lobe_lobe_pdf);
      }

      for (int k = 0; k < count; ++k) {
        RgbF estimate = RgbF::Zero();
        {
          const Vec3f wi(light_local.x[k], light_local.y[k], light_local.z[k]);
          const Environment::Texel& texel = environment_.texel(light_pixel[k]);
          const float pdf = Environment::PdfFloat(texel, light_sin_theta[k]);
          if (wi.z() > 0.0f && pdf > 0.0f) {
            const float pdf_lobe = light_lobe_pdf[k];
            estimate +=
                Shade(light_f[k], wi, texel, pdf, pdf, {pdf, wi.z() * kInvPiF, pdf_lobe}, missing);
          }
        }
        {
          const Vec3f wi(cosine_local.x[k], cosine_local.y[k], cosine_local.z[k]);
          if (wi.z() > 0.0f) {
            const Environment::Texel& texel = environment_.texel(cosine_pixel[k]);
            const float pdf = wi.z() * kInvPiF;
            const float pdf_light = Environment::PdfFloat(texel, cosine_sin_theta[k]);
            const float pdf_lobe = cosine_lobe_pdf[k];
            estimate +=
                Shade(cosine_f[k], wi, texel, pdf, pdf, {pdf_light, pdf, pdf_lobe}, missing);
          }
        }
        if (lobe) {
          const Vec3f wi(lobe_local.x[k], lobe_local.y[k], lobe_local.z[k]);
          const float weighted = wi.z() > 0.0f ? lobe_lobe_pdf[k] : 0.0f;
          const float pdf = weighted > 0.0f ? lobe->PdfInCore(wi, weighted) : 0.0f;
          if (pdf > 0.0f) {
            const Environment::Texel& texel = environment_.texel(lobe_pixel[k]);
            const float pdf_light = Environment::PdfFloat(texel, lobe_sin_theta[k]);
            estimate += Shade(lobe_f[k], wi, texel, pdf, weighted,
                              {pdf_light, wi.z() * kInvPiF, weighted}, missing);
          }
        } else if (sampler_ != nullptr) {
          // The sampler's density is exact everywhere: it weighs and divides alike.
          const Vec3f wi(lobe_local.x[k], lobe_local.y[k], lobe_local.z[k]);
          const float pdf = wi.z() > 0.0f ? lobe_lobe_pdf[k] : 0.0f;
          if (pdf > 0.0f) {
            const Environment::Texel& texel = environment_.texel(lobe_pixel[k]);
            const float pdf_light = Environment::PdfFloat(texel, lobe_sin_theta[k]);
            estimate +=
                Shade(lobe_f[k], wi, texel, pdf, pdf, {pdf_light, wi.z() * kInvPiF, pdf}, missing);
          }
        }
        const Rgb value = estimate.cast<double>();
        sum += value;
        const double luminance = Luminance(value);
        luminance_sum += luminance;
        luminance_squares += luminance * luminance;
      }
    }
    Estimate result;
    const double n = spp_;
    result.radiance = sum / n;
    if (spp_ > 1) {
      const double mean = luminance_sum / n;
      const double variance = std::max(0.0, (luminance_squares - n * mean * mean) / (n - 1));
      result.luminance_std_error = std::sqrt(variance / n);
    }
    return result;
  }

  // out = matrix * in, direction by direction.
  BRDF_LANE_FUNCTION static void Transform(const Eigen::Matrix3f& matrix, const DirectionBatch& in,
                                           DirectionBatch* out) {
    for (int k = 0; k < kBatch; ++k) {
      out->x[k] = matrix(0, 0) * in.x[k] + matrix(0, 1) * in.y[k] + matrix(0, 2) * in.z[k];
      out->y[k] = matrix(1, 0) * in.x[k] + matrix(1, 1) * in.y[k] + matrix(1, 2) * in.z[k];
      out->z[k] = matrix(2, 0) * in.x[k] + matrix(2, 1) * in.y[k] + matrix(2, 2) * in.z[k];
    }
  }
  // The environment pixel of each world direction, and the sine of its polar angle.
  BRDF_LANE_FUNCTION void Locate(const DirectionBatch& world, uint32_t* pixel,
                                 float* sin_theta) const {
    for (int k = 0; k < kBatch; ++k) {
      pixel[k] = environment_.LocateFloat(world.x[k], world.y[k], world.z[k], &sin_theta[k]);
    }
  }

  // f L cos(theta_i) w_t / p_t with the power heuristic's w_t = q_t^2 / sum q^2 over the
  // weights' pdfs q = (q_light, q_cosine, q_lobe) (an unused technique's is 0): the sample of
  // technique t, drawn with pdf p_t, whose weight pdf is q_t; `material` is f(wi, wo).
  BRDF_LANE_FUNCTION static RgbF Shade(const RgbF& material, const Vec3f& wi,
                                       const Environment::Texel& texel, float pdf, float weight_pdf,
                                       const std::array<float, 3>& weight_pdfs, int64_t* missing) {
    const float sum_squares = weight_pdfs[0] * weight_pdfs[0] + weight_pdfs[1] * weight_pdfs[1] +
                              weight_pdfs[2] * weight_pdfs[2];
    const RgbF f = FiniteOrZero(material, missing);
    const RgbF radiance(texel.rgb[0], texel.rgb[1], texel.rgb[2]);
    return f * radiance * (wi.z() * (weight_pdf / sum_squares) * (weight_pdf / pdf));
  }

  const Material& material_;
  const Environment& environment_;
  std::optional<LobeTechnique> lobe_;
  const DirectionSampler* sampler_;  // null, or the material's own (when it has no lobe)
  int spp_;
  bool avx2_ = Avx2Enabled();
};

}  // namespace

void RenderOptions::Validate() const {
  if (size <= 0 || size > kMaxSize) {
    throw UsageError("image size " + std::to_string(size) + " px: must lie in 1.." +
                     std::to_string(kMaxSize));
  }
  if (spp <= 0 || spp > kMaxSpp) {
    throw UsageError(std::to_string(spp) + " samples per pixel: must lie in 1.." +
                     std::to_string(kMaxSpp));
  }
}

std::string RenderResult::Summary() const {
  std::string text = Format("%dx%d, %lld sphere pixels", radiance.width, radiance.height,
                            static_cast<long long>(sphere_pixels));
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
  // Dense tables bring a sampler built from their values (needed only under an environment).
  const std::unique_ptr<DirectionSampler> sampler =
      environment == nullptr ? nullptr : material.MakeSampler();
  const std::optional<EnvironmentEstimator> estimator =
      environment == nullptr ? std::nullopt
                             : std::optional<EnvironmentEstimator>(
                                   std::in_place, material, *environment,
                                   ChooseLobeTechnique(material), sampler.get(), options.spp);

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
      if (estimator) {
        const int64_t pixel = int64_t{y} * size + x;
        const EnvironmentEstimator::Estimate estimate =
            estimator->Pixel(frame, options.seed, static_cast<uint64_t>(pixel), &row_missing);
        radiance += estimate.radiance;
        std_error = estimate.luminance_std_error;
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
