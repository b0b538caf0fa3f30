// The stated sigma of the virtual gonioreflectometer is honest: it carries the arms'
// positioning jitter (gonio/measure.h, PositioningSigma), so the residuals of the true BRDF
// over the stated sigma have unit rms at every angle, grazing included, and a fit of data made
// by the model it fits raises no "model mismatch" or "outliers" warning. The other side: a model
// that cannot follow the data still draws the warning.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/angles.h"
#include "fitters/fit.h"
#include "gonio/instrument.h"
#include "gonio/measure.h"
#include "gonio/schedule.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf::gonio {
namespace {

using brdf::testing::AllWarnings;
using brdf::testing::HasWarning;

Measurement MeasureMatte(const Instrument& instrument) {
  MeasureOptions options;
  options.sample = "model:lambert:rho_d=0.6,0.45,0.3";
  options.instrument = instrument;
  return Measure(options, MakeSchedule("hemisphere"));
}

// Before the positioning term the rms z of this sample grew from 1.0 below 45 deg to 2.6 at
// 85 deg. Bands of >= 2000 samples put the rms within sqrt(1/(2N)) ~ 1.6 % of 1 by chance.
TEST(GonioSigmaTest, TrueLambertResidualsHaveUnitRmsUpToGrazing) {
  const Measurement measurement = MeasureMatte(Instrument{});
  ASSERT_TRUE(measurement.has_sigma());
  const double bands_deg[] = {0, 45, 70, 80, 90};
  const double rho[] = {0.6, 0.45, 0.3};
  for (int band = 0; band < 4; ++band) {
    double sum_z2 = 0;
    int count = 0;
    for (size_t k = 0; k < measurement.samples.size(); ++k) {
      const double theta_o_deg = RadToDeg(std::acos(measurement.samples[k].wo.z()));
      if (theta_o_deg < bands_deg[band] || theta_o_deg >= bands_deg[band + 1]) continue;
      for (int c = 0; c < 3; ++c) {
        const double z =
            (measurement.samples[k].value[c] - rho[c] * kInvPi) / measurement.sigma[k][c];
        sum_z2 += z * z;
        ++count;
      }
    }
    ASSERT_GT(count, 2000) << "band " << bands_deg[band];
    EXPECT_NEAR(std::sqrt(sum_z2 / count), 1.0, 0.08)
        << "theta_o in [" << bands_deg[band] << ", " << bands_deg[band + 1] << ") deg";
  }
}

// For a Lambertian sample only the detector's cosine moves with the detector arm, and only along
// the polar axis: d cos(theta_o)/d theta_o = -sin(theta_o), so the jitter adds
// f tan(theta_o) sigma_jitter in quadrature to the detector noise. The light arm adds nothing
// (the irradiance weight is relative to the beam's own direction, instrument.h).
TEST(GonioSigmaTest, LambertJitterTermIsTheCosineSlope) {
  Instrument jittered;
  jittered.jitter_deg = 0.2;
  Instrument still = jittered;
  still.jitter_deg = 0;
  const Measurement a = MeasureMatte(jittered), b = MeasureMatte(still);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  const double sigma_jitter = DegToRad(jittered.jitter_deg);
  int checked = 0;
  for (size_t k = 0; k < a.samples.size(); ++k) {
    const double cos_theta_o = a.samples[k].wo.z();
    if (cos_theta_o > std::cos(DegToRad(60))) continue;  // where the term dominates
    const double f = 0.45 * kInvPi;
    const double expected =
        f * std::sqrt(1 - cos_theta_o * cos_theta_o) / cos_theta_o * sigma_jitter;
    const double added = std::sqrt(a.sigma[k][1] * a.sigma[k][1] - b.sigma[k][1] * b.sigma[k][1]);
    EXPECT_NEAR(added, expected, 0.03 * expected) << "theta_o " << RadToDeg(std::acos(cos_theta_o));
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(GonioSigmaTest, TruthFitsRaiseNoMismatchOrOutlierWarning) {
  fitters::FitOptions fit_options;
  const Measurement matte = MeasureMatte(Instrument{});
  const fitters::FitResult lambert = fitters::FitModel(matte, "lambert", fit_options);
  EXPECT_FALSE(HasWarning(lambert, "model mismatch")) << AllWarnings(lambert);
  EXPECT_FALSE(HasWarning(lambert, "outliers")) << AllWarnings(lambert);

  MeasureOptions options;
  options.sample = "sphere:blinn-phong:rho_d=0.25,0.05,0.04:rho_s=0.2:m=200";
  const Measurement sphere = Measure(options, MakeSchedule("inplane:step=30"));
  const fitters::FitResult truth = fitters::FitModel(sphere, "blinn-phong", fit_options);
  EXPECT_FALSE(HasWarning(truth, "model mismatch")) << AllWarnings(truth);
  EXPECT_FALSE(HasWarning(truth, "outliers")) << AllWarnings(truth);
  // The other side: a diffuse model cannot follow the plastic's highlight, and says so.
  const fitters::FitResult diffuse = fitters::FitModel(sphere, "lambert", fit_options);
  EXPECT_TRUE(HasWarning(diffuse, "model mismatch")) << AllWarnings(diffuse);

  // The microfacet rungs on flat samples of themselves, over the hemisphere.
  for (const char* name : {"ggx", "beckmann"}) {
    options.sample = std::string("model:") + name + ":rho_d=0.2,0.1,0.05:f0=0.04:alpha=0.3";
    const Measurement flat =
        Measure(options, MakeSchedule("hemisphere:theta_i_step=20:theta_o_step=10:phi_o_step=30"));
    const fitters::FitResult fit = fitters::FitModel(flat, name, fit_options);
    EXPECT_FALSE(HasWarning(fit, "model mismatch")) << name << ": " << AllWarnings(fit);
    EXPECT_FALSE(HasWarning(fit, "outliers")) << name << ": " << AllWarnings(fit);
    EXPECT_NEAR(fit.model.Param("alpha"), 0.3, 3e-3) << name;
  }
}

}  // namespace
}  // namespace brdf::gonio
