#include "render/lobe_sampler.h"

#include <algorithm>
#include <limits>

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
  if (!lobe.frame.half_vector) {
    const Frame frame = Frame::FromZ(lobe.frame.Axis(wo_double_).normalized());
    axis_frame_.row(0) = frame.x.cast<float>();
    axis_frame_.row(1) = frame.y.cast<float>();
    axis_frame_.row(2) = frame.z.cast<float>();
  }
}

template <bool kHalfVector>
BRDF_LANE_FUNCTION void LobeSampler::PowerCosineSample(float u0, float u1, float* x, float* y,
                                                       float* z) const {
  // About +z of the lobe's frame: 1 - cos(beta) = 1 - u^(1/(e+1)), keeping the digits of a
  // cosine near 1. u0 = 0 gives log 0 = -inf and 1 - cos = 1: the rim, as u^(1/(e+1)) = 0 does.
  const float log_u0 = u0 > 0.0f ? LogPositive(u0) : -std::numeric_limits<float>::infinity();
  const float one_minus_cos = -ExpMinusOne(log_u0 * inverse_exponent_plus_one_);
  const float sin_theta = std::sqrt(std::max(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
  float sin_phi, cos_phi;
  SinCosTurn(u1, &sin_phi, &cos_phi);
  const float axis_x = sin_theta * cos_phi, axis_y = sin_theta * sin_phi,
              axis_z = 1.0f - one_minus_cos;
  if constexpr (!kHalfVector) {
    // axis_frame_ transposed: its rows are the frame's axes.
    *x = axis_frame_(0, 0) * axis_x + axis_frame_(1, 0) * axis_y + axis_frame_(2, 0) * axis_z;
    *y = axis_frame_(0, 1) * axis_x + axis_frame_(1, 1) * axis_y + axis_frame_(2, 1) * axis_z;
    *z = axis_frame_(0, 2) * axis_x + axis_frame_(1, 2) * axis_y + axis_frame_(2, 2) * axis_z;
  } else {
    // The drawn axis is the half vector: reflect wo about it.
    const float twice_dot = 2.0f * (wo_.x() * axis_x + wo_.y() * axis_y + wo_.z() * axis_z);
    *x = twice_dot * axis_x - wo_.x(), *y = twice_dot * axis_y - wo_.y();
    *z = twice_dot * axis_z - wo_.z();
  }
}

template <bool kHalfVector>
BRDF_LANE_FUNCTION float LobeSampler::PowerCosineAxis(float x, float y, float z,
                                                      float* one_minus_cos) const {
  if constexpr (!kHalfVector) {
    // |wi - axis|^2 = 2 (1 - cos) for unit vectors; beyond 90 deg from the axis (1 - cos >= 1)
    // the density is 0.
    const float dx = x - axis_frame_(2, 0), dy = y - axis_frame_(2, 1), dz = z - axis_frame_(2, 2);
    *one_minus_cos = 0.5f * (dx * dx + dy * dy + dz * dz);
    return 1.0f;
  } else {
    const float sum_x = x + wo_.x(), sum_y = y + wo_.y(), sum_z = z + wo_.z();
    const float norm = std::sqrt(sum_x * sum_x + sum_y * sum_y + sum_z * sum_z);
    const float wo_dot_sum = wo_.x() * sum_x + wo_.y() * sum_y + wo_.z() * sum_z;
    // Not && (a branch): the loops over a batch vectorize only without control flow.
    const bool defined = (norm > 0.0f) & (sum_z > 0.0f) & (wo_dot_sum > 0.0f);
    const float safe_norm = defined ? norm : 1.0f;
    // With h = sum / |sum|: 1 - h_z = (h_x^2 + h_y^2) / (1 + h_z).
    *one_minus_cos =
        defined ? (sum_x * sum_x + sum_y * sum_y) / (safe_norm * (safe_norm + sum_z)) : 2.0f;
    // The half-vector Jacobian dω_h/dω_i = 1/(4 wo.h) (core/sampling.h).
    return defined ? 0.25f * safe_norm / wo_dot_sum : 0.0f;
  }
}

template <bool kHalfVector>
void LobeSampler::PowerCosineSamples(const float* u0, const float* u1, int count, float* x,
                                     float* y, float* z) const {
  // Into arrays of its own first: writes through x, y, z might alias this sampler's members,
  // and the run-time checks for that would be too many for the compiler to vectorize.
  constexpr int kChunk = 16;
  alignas(16) float drawn_x[kChunk], drawn_y[kChunk], drawn_z[kChunk];
  for (int first = 0; first < count; first += kChunk) {
    const int n = std::min(kChunk, count - first);
    for (int k = 0; k < n; ++k) {
      PowerCosineSample<kHalfVector>(u0[first + k], u1[first + k], &drawn_x[k], &drawn_y[k],
                                     &drawn_z[k]);
    }
    std::copy(drawn_x, drawn_x + n, x + first);
    std::copy(drawn_y, drawn_y + n, y + first);
    std::copy(drawn_z, drawn_z + n, z + first);
  }
}

template <bool kHalfVector>
BRDF_LANE_FUNCTION void LobeSampler::AxisMisPdfs(const float* x, const float* y, const float* z,
                                                 int count, float* mis_pdf) const {
  constexpr int kChunk = 16;
  alignas(16) float one_minus_cos[kChunk], jacobian[kChunk];
  const float core = core_one_minus_cos_;
  for (int first = 0; first < count; first += kChunk) {
    const int n = std::min(kChunk, count - first);
    int inside = 0;
    for (int k = 0; k < n; ++k) {
      jacobian[k] =
          PowerCosineAxis<kHalfVector>(x[first + k], y[first + k], z[first + k], &one_minus_cos[k]);
      inside += static_cast<int>(one_minus_cos[k] <= core);
    }
    // Most light and cosine samples of a narrow lobe fall outside its core: skip the
    // density for a batch that has none inside.
    if (inside == 0) {
      std::fill(mis_pdf + first, mis_pdf + first + n, 0.0f);
      continue;
    }
    if (lobe_.distribution == nullptr) {
      for (int k = 0; k < n; ++k) {
        const float pdf = PowerCosineDensity(one_minus_cos[k]) * jacobian[k];
        mis_pdf[first + k] = one_minus_cos[k] > core ? 0.0f : pdf;
      }
      continue;
    }
    // A distribution's density of h from the table (a gather: one at a time). Visible
    // normals: G1(wo) D(h) / (4 cos theta_o), D(h) = density / cos theta_h; else the
    // half-vector Jacobian.
    const bool visible = lobe_.distribution->visible_density != nullptr;
    for (int k = 0; k < n; ++k) {
      const float cos_theta_h = 1.0f - one_minus_cos[k];
      mis_pdf[first + k] = 0.0f;
      if (one_minus_cos[k] > core || !(cos_theta_h > 0.0f)) continue;
      const float density = technique_.TabulatedDensity(one_minus_cos[k]);
      mis_pdf[first + k] = density * (visible ? visible_scale_ / cos_theta_h : jacobian[k]);
    }
  }
}

Vec3f LobeSampler::Sample(float u0, float u1) const {
  Vec3f wi;
  SampleBatch(&u0, &u1, 1, &wi.x(), &wi.y(), &wi.z());
  return wi;
}

void LobeSampler::SampleBatch(const float* u0, const float* u1, int count, float* x, float* y,
                              float* z) const {
  if (lobe_.distribution != nullptr) {
    const bool in_float = visible_normals_ && lobe_.distribution->sample_visible_float != nullptr;
    // The normals first (for all of the batch at once), then wi: Reflect (core/sampling.h).
    if (in_float) lobe_.distribution->sample_visible_float(wo_, u0, u1, count, x, y, z, exponent_);
    for (int k = 0; k < count; ++k) {
      Vec3f wi;
      if (in_float) {
        const Vec3f h(x[k], y[k], z[k]);
        wi = 2.0f * wo_.dot(h) * h - wo_;
      } else {
        wi = SampleStrategy(lobe_, wo_double_, Point2(u0[k], u1[k])).cast<float>();
      }
      x[k] = wi.x(), y[k] = wi.y(), z[k] = wi.z();
    }
    return;
  }
  if (lobe_.frame.half_vector) return PowerCosineSamples<true>(u0, u1, count, x, y, z);
  PowerCosineSamples<false>(u0, u1, count, x, y, z);
}

float LobeSampler::AxisOneMinusCos(const Vec3f& wi) const {
  float one_minus_cos = 2.0f;
  if (lobe_.frame.half_vector) {
    PowerCosineAxis<true>(wi.x(), wi.y(), wi.z(), &one_minus_cos);
  } else {
    PowerCosineAxis<false>(wi.x(), wi.y(), wi.z(), &one_minus_cos);
  }
  return one_minus_cos;
}

float LobeSampler::MisPdf(const Vec3f& wi) const {
  float mis_pdf;
  MisPdfBatch(&wi.x(), &wi.y(), &wi.z(), 1, &mis_pdf);
  return mis_pdf;
}

void LobeSampler::MisPdfBatch(const float* x, const float* y, const float* z, int count,
                              float* mis_pdf) const {
  if (avx2_) return MisPdfsAvx2(x, y, z, count, mis_pdf);
  MisPdfsIn(x, y, z, count, mis_pdf);
}

void LobeSampler::MisPdfsAvx2(const float* x, const float* y, const float* z, int count,
                              float* mis_pdf) const {
  MisPdfsIn(x, y, z, count, mis_pdf);
}

BRDF_LANE_FUNCTION void LobeSampler::MisPdfsIn(const float* x, const float* y, const float* z,
                                               int count, float* mis_pdf) const {
  // The distributions are microfacet normals: half-vector lobes.
  if (lobe_.distribution != nullptr) {
    return AxisMisPdfs<true>(x, y, z, count, mis_pdf);
  }
  if (lobe_.frame.half_vector) return AxisMisPdfs<true>(x, y, z, count, mis_pdf);
  AxisMisPdfs<false>(x, y, z, count, mis_pdf);
}

float LobeSampler::Pdf(const Vec3f& wi) const {
  if (lobe_.distribution != nullptr) {
    if (lobe_.distribution->density_float == nullptr) {
      return static_cast<float>(StrategyPdf(lobe_, wo_double_, wi.cast<double>()));
    }
    const Vec3f sum = wi + wo_;
    const float norm_squared = sum.squaredNorm();
    if (!(norm_squared > 0.0f)) return 0.0f;
    const Vec3f half_vector = sum / std::sqrt(norm_squared);
    const float wo_dot_h = wo_.dot(half_vector);
    if (!(half_vector.z() > 0.0f) || !(wo_dot_h > 0.0f)) return 0.0f;
    const float density = lobe_.distribution->density_float(half_vector.z(), exponent_);
    // Visible normals: G1(wo) D(h) / (4 cos theta_o), D(h) = density / cos theta_h.
    if (visible_normals_) return visible_scale_ * density / half_vector.z();
    return density / (4.0f * wo_dot_h);
  }
  const float one_minus_cos = AxisOneMinusCos(wi);
  float jacobian = 1.0f;
  if (lobe_.frame.half_vector) {
    float unused;
    jacobian = PowerCosineAxis<true>(wi.x(), wi.y(), wi.z(), &unused);
  }
  return PowerCosineDensity(one_minus_cos) * jacobian;
}

double LobeSampler::PeakDensity(const LobeCoordinates& lobe) {
  const double at_axis = LobeDensity(lobe, 1.0);
  // A half vector at the normal, seen from the normal, has wo.h = 1: wi's density is a quarter.
  return lobe.frame.half_vector ? HalfVectorToIncidentPdf(at_axis, 1.0) : at_axis;
}

}  // namespace brdf
