// The virtual gonioreflectometer against microfacet theory (Westin, Arvo & Torrance 1992;
// Walter et al. 2007): a Gaussian height field of rms slope s under a smooth conductor, traced
// with Embree through `brdf measure`'s own path and fitted with `beckmann` by the fitter
// library, gives alpha = s (DESIGN §2). The conductor is silver-like: its exact Fresnel
// reflectance stays within 0.987–0.992 from 0° to 85°, so Schlick's form with the fitted f0
// represents it to 0.5 % and the fit compares the traced geometry (D, masking) with the model's.
// docs/gonio.md shows the same over 0.05 … 0.8 (bench/gonio_microfacet_bench), where multiple
// scattering, which the tracer has and the model lacks, makes them part.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fitters/fit.h"
#include "gonio/measure.h"
#include "gonio/surface_sample.h"
#include "gonio/traced_surface.h"
#include "gonio_test_util.h"
#include "test_util.h"

namespace brdf::gonio {
namespace {

using testing::IdealInstrument;

constexpr const char* kSilver = "conductor:ior=0.05:k=4.3";

std::string SurfaceJson(double rms_slope) {
  return R"({"heightfield": {"kind": "gaussian", "rms_slope": )" + std::to_string(rms_slope) +
         R"(, "resolution": 128, "seed": 3, "correlation": 2}, "base": ")" + kSilver +
         R"(", "rays_per_incidence": 50000})";
}

// The generated triangles have the slope statistics the JSON asks for: rms |∇h| = s, each axis
// s/√2, Gaussian (no excess kurtosis).
TEST(GonioFacetSlopes, GaussianFacetsHaveTheRequestedSlopeStatistics) {
  for (double slope : {0.1, 0.5}) {
    HeightFieldSpec spec;
    spec.rms_slope = slope;
    spec.resolution = 128;
    spec.correlation = 2;
    const testing::FacetSlopes facets = testing::MeasureFacetSlopes(MakeHeightField(spec));
    EXPECT_NEAR(facets.rms, slope, 1e-5 * slope);
    EXPECT_NEAR(facets.sigma_x, slope / std::sqrt(2.0), 0.02 * slope);
    EXPECT_NEAR(facets.sigma_y, slope / std::sqrt(2.0), 0.02 * slope);
    EXPECT_NEAR(facets.kurtosis, 0.0, 0.1);
  }
}

// Measured over the hemisphere (θi 0 … 80° in 20° steps, θo and φo every 5° and 15°) and fitted
// with beckmann (`brdf fit --loss log`): alpha within 5 % of the rms slope for s = 0.1, 0.3 and
// 0.5. The fit is weighted by solid angle only: the sigma column of a traced reading comes from
// its own hits, and weights that follow the readings' fluctuations pull a least-squares fit
// toward the low ones; the log loss keeps the grazing peaks (f grows as 1/cos theta_i) from
// outweighing the rest (docs/gonio.md). One test for the three slopes: the fitter's microfacet
// albedo table, built once per process, costs more than the three traces.
TEST(GonioMicrofacetTest, BeckmannFitRecoversTheRmsSlope) {
  const Schedule schedule = MakeSchedule("hemisphere:theta_i_step=20:theta_o_step=5:phi_o_step=15");
  for (double slope : {0.1, 0.3, 0.5}) {
    brdf::testing::ScratchDir dir;
    MeasureOptions options;
    options.sample = "surface:" + dir.Write("surface.json", SurfaceJson(slope));
    options.instrument = IdealInstrument();
    options.instrument.detector_solid_angle_sr = 0.003;
    Measurement measurement = Measure(options, schedule);
    ASSERT_GT(measurement.samples.size(), 2000u);
    measurement.sigma.clear();
    fitters::FitOptions fit_options;
    fit_options.loss = fitters::Loss::kLog;
    const fitters::FitResult fit = fitters::FitModel(measurement, "beckmann", fit_options);
    EXPECT_TRUE(fit.converged) << slope;
    EXPECT_NEAR(fit.model.Param("alpha"), slope, 0.05 * slope) << fit.model.ToString(4);
    // The conductor's Fresnel (0.987–0.992), read by Schlick's f0.
    EXPECT_NEAR(fit.model.Param("f0"), 0.99, 0.03) << fit.model.ToString(4);
  }
}

}  // namespace
}  // namespace brdf::gonio
