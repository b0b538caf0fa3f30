#include "export/targets.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"
#include "models/microfacet.h"

namespace brdf::exporters {
namespace {

// Grid of blend weights tried on (max f0, 1]: the objective is smooth in w, and 48 points put the
// chosen one within 1/48 of the interval of the best, far inside what a renderer shows.
constexpr int kBlendWeightSteps = 48;
// The smallest blend weight written: below it the conductor would need a specular scale past
// 1000 to keep the fit's lobe.
constexpr double kMinBlendWeight = 1e-3;
// A conductor's normal-incidence reflectance stays below 1 (k finite), as pbrt-v4 clamps it.
constexpr double kMaxConductorReflectance = 0.9999;
// cos theta_d points the conductor's Fresnel is matched on, and the eta grid before refinement.
constexpr int kFresnelGrid = 64;
constexpr int kEtaGrid = 32;

}  // namespace

std::string Num(double value) { return Format("%.6g", value); }

void MapToExactDiffuse(const Rgb& rho_d, ExportedMaterial* material) {
  material->material = "diffuse";
  material->exact = true;
  material->parameters = {{"type", "diffuse"}, {"reflectance", {rho_d[0], rho_d[1], rho_d[2]}}};
  material->notes.push_back("diffuse reflectance = rho_d: exact (f = reflectance/pi)");
  material->eval = [rho_d](const Vec3& wi, const Vec3& wo) -> Rgb {
    return wi.z() > 0 && wo.z() > 0 ? Rgb(rho_d * kInvPi) : Rgb(Rgb::Zero());
  };
}

double MappingLogRmse(const std::function<Rgb(const Vec3&, const Vec3&)>& renderer,
                      const MappingInput& input) {
  double sum = 0, weight = 0;
  for (size_t k = 0; k < input.samples.size(); ++k) {
    const fitters::FitSample& sample = input.samples[k];
    const Rgb f = renderer(sample.wi, sample.wo);
    const double c = sample.cos_theta_i();
    const Rgb difference = (1.0 + f * c).log() - (1.0 + input.fit_values[k] * c).log();
    sum += sample.weight * difference.square().sum();
    weight += 3 * sample.weight;
  }
  return weight > 0 ? std::sqrt(sum / weight) : 0.0;
}

Rgb FitDiffuseScale(const MappingInput& input,
                    const std::function<double(const Vec3&, const Vec3&)>& diffuse_shape,
                    const std::function<Rgb(const Vec3&, const Vec3&)>& rest) {
  Rgb numerator = Rgb::Zero(), denominator = Rgb::Zero();
  for (size_t k = 0; k < input.samples.size(); ++k) {
    const fitters::FitSample& sample = input.samples[k];
    const double a = diffuse_shape(sample.wi, sample.wo);
    const Rgb s = rest(sample.wi, sample.wo);
    const double c = sample.cos_theta_i();
    const Rgb& f = input.fit_values[k];
    const Rgb w = sample.weight * (c / (1.0 + f * c)).square();
    numerator += w * a * (f - s);
    denominator += w * a * a;
  }
  Rgb scale = Rgb::Zero();
  for (int c = 0; c < 3; ++c) {
    if (denominator[c] > 0) scale[c] = std::clamp(numerator[c] / denominator[c], 0.0, 1.0);
  }
  return scale;
}

ConductorIndex FitConductorIndex(double f0, double scale) {
  const double r = std::min(f0 * scale, kMaxConductorReflectance);
  const double root = std::sqrt(r);
  const double largest_eta = (1.0 + root) / (1.0 - root);
  auto k_for = [&](double eta) {
    const double k2 = (r * (eta + 1) * (eta + 1) - (eta - 1) * (eta - 1)) / (1.0 - r);
    return std::sqrt(std::max(k2, 0.0));
  };
  // rms and max of the difference over the cos theta_d grid.
  auto difference = [&](double eta, double* largest) {
    const double k = k_for(eta);
    double sum = 0;
    *largest = 0;
    for (int j = 0; j < kFresnelGrid; ++j) {
      const double cos_d = (j + 0.5) / kFresnelGrid;
      const double target = std::min(1.0, scale * models::SchlickFresnel(cos_d, f0));
      const double d = models::FresnelReflectance(cos_d, eta, k) - target;
      // Relative: a lobe's value is proportional to F, so a 0.01 error on F = 0.05 is as
      // visible as a 0.2 error on F = 1.
      sum += (d / target) * (d / target);
      *largest = std::max(*largest, std::abs(d));
    }
    return sum;
  };
  ConductorIndex best;
  double best_sum = difference(1.0, &best.max_difference);
  best.k = k_for(1.0);
  double lo = 1.0, hi = largest_eta;
  // A coarse log-spaced grid, then golden-section refinement around the best point.
  for (int step = 0; step <= kEtaGrid; ++step) {
    const double eta = std::exp(std::log(largest_eta) * step / kEtaGrid);
    double largest = 0;
    const double sum = difference(eta, &largest);
    if (sum < best_sum) {
      best_sum = sum;
      best = {eta, k_for(eta), largest};
      lo = std::exp(std::log(largest_eta) * std::max(step - 1, 0) / kEtaGrid);
      hi = std::exp(std::log(largest_eta) * std::min(step + 1, kEtaGrid) / kEtaGrid);
    }
  }
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
    double unused = 0;
    if (difference(a, &unused) < difference(b, &unused)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  double largest = 0;
  const double eta = 0.5 * (lo + hi);
  if (difference(eta, &largest) < best_sum) best = {eta, k_for(eta), largest};
  return best;
}

Rgb DiffuseConductorBlend::Eval(const Vec3& wi, const Vec3& wo) const {
  const HalfVectorGeometry g = Geometry(wi, wo);
  if (!g.above) return Rgb::Zero();
  Rgb f = Rgb::Zero();
  if (weight < 1) f += (1.0 - weight) * reflectance * kInvPi;
  if (weight > 0) {
    f += (weight * specular_scale) * ConductorFresnel(g.cos_theta_d, eta, k) * lobe.Eval(g);
  }
  return f;
}

DiffuseConductorBlend FitDiffuseConductorBlend(const MappingInput& input,
                                               const MicrofacetLobe& lobe,
                                               bool has_specular_scale) {
  const MicrofacetSource& source = input.source;
  auto with_conductor = [&](double weight, double specular_scale) {
    DiffuseConductorBlend blend;
    blend.weight = weight;
    blend.specular_scale = specular_scale;
    blend.lobe = lobe;
    for (int c = 0; c < 3; ++c) {
      const ConductorIndex index = FitConductorIndex(source.f0[c], 1.0 / (weight * specular_scale));
      blend.eta[c] = index.eta;
      blend.k[c] = index.k;
    }
    return blend;
  };
  if (source.rho_d.maxCoeff() <= 0) return with_conductor(1.0, 1.0);
  if (has_specular_scale) {
    const double weight = std::max(std::min(0.5, 1.0 - source.rho_d.maxCoeff()), kMinBlendWeight);
    DiffuseConductorBlend blend = with_conductor(weight, 1.0 / weight);
    blend.reflectance = (source.rho_d / (1.0 - weight)).min(1.0);
    return blend;
  }
  auto blend_for = [&](double weight) {
    DiffuseConductorBlend blend = with_conductor(weight, 1.0);
    if (weight < 1) {
      DiffuseConductorBlend lobe_only = blend;
      lobe_only.reflectance = Rgb::Zero();
      blend.reflectance = FitDiffuseScale(
          input,
          [&](const Vec3& wi, const Vec3& wo) {
            return wi.z() > 0 && wo.z() > 0 ? (1.0 - weight) * kInvPi : 0.0;
          },
          [&](const Vec3& wi, const Vec3& wo) { return lobe_only.Eval(wi, wo); });
    }
    return blend;
  };
  DiffuseConductorBlend best = blend_for(1.0);
  double best_error =
      MappingLogRmse([&](const Vec3& wi, const Vec3& wo) { return best.Eval(wi, wo); }, input);
  const double lowest = std::min(source.f0.maxCoeff(), kMaxConductorReflectance);
  for (int step = 0; step < kBlendWeightSteps; ++step) {
    const double weight = lowest + (1.0 - lowest) * (step + 0.5) / kBlendWeightSteps;
    const DiffuseConductorBlend candidate = blend_for(weight);
    const double error = MappingLogRmse(
        [&](const Vec3& wi, const Vec3& wo) { return candidate.Eval(wi, wo); }, input);
    if (error < best_error) {
      best_error = error;
      best = candidate;
    }
  }
  return best;
}

TermDifferences MeasureTermDifferences(
    const MappingInput& input, const MicrofacetLobe& renderer_lobe,
    const std::function<Rgb(double cos_theta_d)>& renderer_fresnel) {
  const MicrofacetSource& source = input.source;
  const Distribution ours = source.distribution;
  TermDifferences differences;
  for (const fitters::FitSample& sample : input.samples) {
    const HalfVectorGeometry g = Geometry(sample.wi, sample.wo);
    if (!g.above) continue;
    const double g_ours = MaskingShadowing(Masking::kHeightCorrelated, ours, g.cos_theta_i,
                                           g.cos_theta_o, source.alpha);
    const double g_renderer = renderer_lobe.G(g);
    if (g_ours > 0) {
      differences.max_g_relative =
          std::max(differences.max_g_relative, std::abs(g_renderer - g_ours) / g_ours);
    }
    const Rgb f_renderer = renderer_fresnel(g.cos_theta_d);
    for (int c = 0; c < 3; ++c) {
      const double f_ours = models::SchlickFresnel(g.cos_theta_d, source.f0[c]);
      differences.max_fresnel = std::max(differences.max_fresnel, std::abs(f_renderer[c] - f_ours));
    }
  }
  return differences;
}

}  // namespace brdf::exporters
