#include "render/lobe_sampler.h"

#include <algorithm>

#include "core/sampling.h"

namespace brdf {

LobeTechnique::LobeTechnique(const LobeCoordinates& lobe_coordinates) : lobe(lobe_coordinates) {
  // The density of the axis variable (wi for the normal and the mirror, h for the half vector)
  // falls with the angle beta from the axis; the rim is where it reaches kCoreDensity.
  if (lobe.distribution == nullptr) {
    const double normalization = (lobe.exponent + 1.0) * 0.5 * kInvPi;
    if (normalization > kCoreDensity && lobe.exponent > 0.0) {
      core_one_minus_cos =
          static_cast<float>(-std::expm1(std::log(kCoreDensity / normalization) / lobe.exponent));
    }
    return;
  }
  // A distribution of its own: its table, then bisect in cos(beta) for the core (the rule
  // need not be exact, only fixed).
  density_table.resize(kTableSize);
  for (int i = 0; i < kTableSize; ++i) {
    const double root = static_cast<double>(i) / (kTableSize - 1);
    density_table[i] = static_cast<float>(LobeDensity(lobe, 1.0 - root * root));
  }
  if (LobeDensity(lobe, 1e-6) >= kCoreDensity) return;
  double inside = 1.0, outside = 1e-6;
  for (int step = 0; step < 60; ++step) {
    const double middle = 0.5 * (inside + outside);
    (LobeDensity(lobe, middle) >= kCoreDensity ? inside : outside) = middle;
  }
  core_one_minus_cos = static_cast<float>(1.0 - outside);
}

LobeSampler::LobeSampler(const LobeTechnique& technique, const Vec3f& wo)
    : technique_(technique),
      lobe_(technique.lobe),
      core_one_minus_cos_(technique.core_one_minus_cos),
      wo_(wo),
      wo_double_(wo.cast<double>()) {
  const LobeCoordinates& lobe = technique.lobe;
  // As energy/monte_carlo.cpp decides: visible normals only for wo above the surface.
  visible_normals_ =
      lobe.distribution != nullptr && lobe.distribution->sample_visible != nullptr && wo.z() > 0.0f;
  if (lobe.distribution != nullptr && lobe.distribution->visible_density != nullptr &&
      wo.z() > 0.0f) {
    // At h = +z (wi the mirror of wo): pdf = G1 D(1) / (4 cos theta_o) = scale density(1).
    const Vec3 mirror = MirrorDirection(wo_double_);
    visible_scale_ =
        static_cast<float>(StrategyPdf(lobe, wo_double_, mirror) / LobeDensity(lobe, 1.0));
  }
  exponent_ = static_cast<float>(lobe.exponent);
  normalization_ = static_cast<float>((lobe.exponent + 1.0) * 0.5 * kInvPi);
  inverse_exponent_plus_one_ = static_cast<float>(1.0 / (lobe.exponent + 1.0));
  if (lobe.frame == LobeFrame::kMirror) {
    const Frame frame = Frame::FromZ(MirrorDirection(wo_double_).normalized());
    mirror_frame_.row(0) = frame.x.cast<float>();
    mirror_frame_.row(1) = frame.y.cast<float>();
    mirror_frame_.row(2) = frame.z.cast<float>();
  }
}

Vec3f LobeSampler::SampleAboutAxis(float u0, float u1) const {
  // u0 = 0 gives log 0 = -inf and 1 - cos = 1: the rim, as u^(1/(e+1)) = 0 does.
  const float one_minus_cos = -ExpMinusOne(std::log(u0) * inverse_exponent_plus_one_);
  const float sin_theta = std::sqrt(std::max(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  float sin_phi, cos_phi;
  SinCosTurn(u1, &sin_phi, &cos_phi);
  return Vec3f(sin_theta * cos_phi, sin_theta * sin_phi, 1.0f - one_minus_cos);
}

Vec3f LobeSampler::Sample(float u0, float u1) const {
  if (lobe_.distribution != nullptr) {
    if (visible_normals_ && lobe_.distribution->sample_visible_float != nullptr) {
      // Reflect (core/sampling.h) about the drawn normal.
      const Vec3f h = lobe_.distribution->sample_visible_float(wo_, u0, u1, exponent_);
      return 2.0f * wo_.dot(h) * h - wo_;
    }
    return SampleStrategy(lobe_, wo_double_, Point2(u0, u1)).cast<float>();
  }
  const Vec3f about_axis = SampleAboutAxis(u0, u1);
  switch (lobe_.frame) {
    case LobeFrame::kNormal:
      return about_axis;
    case LobeFrame::kMirror:
      return mirror_frame_.transpose() * about_axis;
    case LobeFrame::kHalfVector:
      return 2.0f * wo_.dot(about_axis) * about_axis - wo_;
  }
  return about_axis;
}

float LobeSampler::AxisOneMinusCos(const Vec3f& wi) const {
  switch (lobe_.frame) {
    case LobeFrame::kNormal:
      return wi.z() > 0.0f ? (wi.x() * wi.x() + wi.y() * wi.y()) / (1.0f + wi.z()) : 2.0f;
    case LobeFrame::kMirror:
      return 0.5f * (wi - Vec3f(-wo_.x(), -wo_.y(), wo_.z())).squaredNorm();
    case LobeFrame::kHalfVector: {
      const Vec3f sum = wi + wo_;
      const float norm_squared = sum.squaredNorm();
      if (!(norm_squared > 0.0f) || !(sum.z() > 0.0f)) return 2.0f;
      // With h = sum / |sum|: 1 - h_z = (h_x^2 + h_y^2) / (1 + h_z).
      const float norm = std::sqrt(norm_squared);
      return (sum.x() * sum.x() + sum.y() * sum.y()) / (norm * (norm + sum.z()));
    }
  }
  return 2.0f;
}

float LobeSampler::MisPdf(const Vec3f& wi) const {
  const float one_minus_cos = AxisOneMinusCos(wi);
  if (one_minus_cos > core_one_minus_cos_) return 0.0f;
  if (lobe_.distribution == nullptr) return Pdf(wi);
  // Half vector (the distributions are microfacet normals).
  const Vec3f h = (wi + wo_).normalized();
  const float wo_dot_h = wo_.dot(h);
  if (!(h.z() > 0.0f) || !(wo_dot_h > 0.0f)) return 0.0f;
  const float density = technique_.TabulatedDensity(one_minus_cos);
  if (lobe_.distribution->visible_density != nullptr) return visible_scale_ * density / h.z();
  return density / (4.0f * wo_dot_h);
}

float LobeSampler::Pdf(const Vec3f& wi) const {
  if (lobe_.distribution != nullptr && lobe_.distribution->density_float == nullptr) {
    return static_cast<float>(StrategyPdf(lobe_, wo_double_, wi.cast<double>()));
  }
  switch (lobe_.frame) {
    case LobeFrame::kNormal: {
      if (!(wi.z() > 0.0f)) return 0.0f;
      return PowerCosineDensity((wi.x() * wi.x() + wi.y() * wi.y()) / (1.0f + wi.z()));
    }
    case LobeFrame::kMirror: {
      // |wi - m|^2 = 2 (1 - cos) for unit vectors.
      const Vec3f axis(-wo_.x(), -wo_.y(), wo_.z());
      if (!(wi.dot(axis) > 0.0f)) return 0.0f;
      return PowerCosineDensity(0.5f * (wi - axis).squaredNorm());
    }
    case LobeFrame::kHalfVector: {
      const Vec3f sum = wi + wo_;
      const float norm_squared = sum.squaredNorm();
      if (!(norm_squared > 0.0f)) return 0.0f;
      const Vec3f half_vector = sum / std::sqrt(norm_squared);
      const float wo_dot_h = wo_.dot(half_vector);
      if (!(half_vector.z() > 0.0f) || !(wo_dot_h > 0.0f)) return 0.0f;
      if (lobe_.distribution != nullptr) {
        const float density = lobe_.distribution->density_float(half_vector.z(), exponent_);
        // Visible normals: G1(wo) D(h) / (4 cos theta_o), D(h) = density / cos theta_h.
        if (visible_normals_) return visible_scale_ * density / half_vector.z();
        return density / (4.0f * wo_dot_h);
      }
      const float one_minus_cos =
          (half_vector.x() * half_vector.x() + half_vector.y() * half_vector.y()) /
          (1.0f + half_vector.z());
      // The half-vector Jacobian dω_h/dω_i = 1/(4 wo.h) (core/sampling.h).
      return PowerCosineDensity(one_minus_cos) / (4.0f * wo_dot_h);
    }
  }
  return 0.0f;
}

double LobeSampler::PeakDensity(const LobeCoordinates& lobe) {
  const double at_axis = LobeDensity(lobe, 1.0);
  // A half vector at the normal, seen from the normal, has wo.h = 1: wi's density is a quarter.
  return lobe.frame == LobeFrame::kHalfVector ? HalfVectorToIncidentPdf(at_axis, 1.0) : at_axis;
}

}  // namespace brdf
