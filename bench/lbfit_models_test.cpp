// The peer lbfit's models (lbfit_models.h) against closed forms worked by hand from libbsdf's
// formulas, and its output reader against a block printed by lbfit.
#include "lbfit_models.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/angles.h"
#include "core/errors.h"
#include "lbfit_output.h"

namespace brdf::lbfit {
namespace {

Vec3 LbfitTestDirection(double theta_deg, double phi_deg) {
  const double theta = DegToRad(theta_deg), phi = DegToRad(phi_deg);
  return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

TEST(LbfitModels, GgxAtNormalIncidenceAndViewIsColourOverFourPiAlphaSquared) {
  // wi = wo = n: h = n, F = c (Schlick at l.h = 1), G = 1, D = 1 / (pi alpha^2), and the
  // 1 / (4 cos_i cos_o) of the microfacet BRDF: f = c / (4 pi alpha^2), alpha = roughness^2.
  const Vec3 n(0, 0, 1);
  const GgxParameters p{Rgb(0.9, 0.5, 0.1), 0.3};
  const double alpha = 0.3 * 0.3;
  const Rgb f = EvalGgx(p, n, n);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f[c], p.color[c] / (4.0 * kPi * alpha * alpha), 1e-12 * f[c]) << c;
  }
}

TEST(LbfitModels, Ue4WithoutSpecularIsLambertian) {
  // metallic 0, specular 0: F0 = 0, so F = min(50 * 0, 1) Fc + (1 - Fc) 0 = 0 and
  // f = base / pi wherever the directions are (roughness 1 the least peaked lobe).
  const Ue4Parameters p{Rgb(0.7, 0.4, 0.2), 0.0, 0.0, 1.0};
  for (double theta_i : {0.0, 30.0, 70.0}) {
    for (double theta_o : {10.0, 45.0, 85.0}) {
      const Rgb f = EvalUe4(p, LbfitTestDirection(theta_i, 0), LbfitTestDirection(theta_o, 140));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], p.base_color[c] / kPi, 1e-15);
      EXPECT_TRUE(f.isApprox(EvalLambertian(p.base_color), 1e-14));
    }
  }
}

TEST(LbfitModels, Ue4AtNormalIncidenceAndView) {
  // wi = wo = n: Fc = 0 so F = F0 = lerp(0.08 specular, base, metallic); D = 1 / (pi alpha^2);
  // Vis = 0.5 / (1 + 1) = 1/4. f = base (1 - metallic) / pi + F0 / (4 pi alpha^2).
  const Vec3 n(0, 0, 1);
  const Ue4Parameters p{Rgb(0.6, 0.3, 0.1), 0.25, 0.5, 0.4};
  const double alpha = 0.4 * 0.4;
  const Rgb f = EvalUe4(p, n, n);
  for (int c = 0; c < 3; ++c) {
    const double f0 = 0.04 + (p.base_color[c] - 0.04) * 0.25;
    const double expected = p.base_color[c] * 0.75 / kPi + f0 / (4.0 * kPi * alpha * alpha);
    EXPECT_NEAR(f[c], expected, 1e-12 * expected) << c;
  }
}

TEST(LbfitModels, GgxIsReciprocalAndAnisotropicReducesToIsotropic) {
  const GgxParameters iso{Rgb(0.04, 0.05, 0.06), 0.35};
  const AnisotropicGgxParameters aniso{iso.color, 0.35, 0.35};
  const AnisotropicGgxParameters stretched{iso.color, 0.5, 0.2};
  for (double theta_i : {5.0, 40.0, 75.0}) {
    for (double phi_o : {0.0, 60.0, 180.0}) {
      const Vec3 wi = LbfitTestDirection(theta_i, 20), wo = LbfitTestDirection(50, phi_o);
      const Rgb f = EvalGgx(iso, wi, wo);
      EXPECT_TRUE(f.isApprox(EvalGgx(iso, wo, wi), 1e-12));
      EXPECT_TRUE(f.isApprox(EvalAnisotropicGgx(aniso, wi, wo), 1e-12));
      EXPECT_TRUE(EvalAnisotropicGgx(stretched, wi, wo)
                      .isApprox(EvalAnisotropicGgx(stretched, wo, wi), 1e-12));
    }
  }
  // Stretched along the tangent x: the highlight stays wider when the half vector tilts along x.
  const Vec3 wo(0, 0, 1);
  const Rgb along_x = EvalAnisotropicGgx(stretched, LbfitTestDirection(30, 0), wo);
  const Rgb along_y = EvalAnisotropicGgx(stretched, LbfitTestDirection(30, 90), wo);
  EXPECT_GT(along_x[0], 10.0 * along_y[0]);
}

// lbfit's stdout for blue-acrylic (MERL, NBRDF reconstruction), the values read by hand.
constexpr char kLbfitBlueAcrylic[] =
    "[Unreal Engine 4]\n"
    "Base color: 0.0148152 0.0388612 0.107134\n"
    "Metallic: 0\n"
    "Specular: 0.046546\n"
    "Roughness: 0.119299\n"
    "Error: 0.0156313\n"
    "\n"
    "[GGX (isotropic, no refractive index)]\n"
    "Color: 0.00146731 0.0012035 0.00126908\n"
    "Roughness: 0.0711496\n"
    "Error: 0.113643\n"
    "\n"
    "[GGX (anisotropic, no refractive index)]\n"
    "Color: 0.00143428 0.00117259 0.00123724\n"
    "Roughness X: 0.0758418\n"
    "Roughness Y: 0.065875\n"
    "Error: 0.113272\n"
    "\n"
    "[Lambertian]\n"
    "Color: 0.0195783 0.0434485 0.111921\n"
    "Error: 0.0202024\n";

TEST(LbfitOutput, ReadsEveryBlock) {
  const std::vector<PrintedFit> fits = ParseLbfitOutput("lbfit.txt", kLbfitBlueAcrylic);
  ASSERT_EQ(fits.size(), 4u);
  EXPECT_EQ(fits[0].kind->key, "ue4");
  EXPECT_EQ(fits[0].parameters.at("Base color"),
            (std::vector<double>{0.0148152, 0.0388612, 0.107134}));
  EXPECT_EQ(fits[0].parameters.at("Specular")[0], 0.046546);
  EXPECT_EQ(fits[0].lbfit_error, 0.0156313);
  EXPECT_EQ(fits[2].kind->key, "ggx_aniso");
  EXPECT_EQ(fits[2].parameters.at("Roughness Y")[0], 0.065875);
  EXPECT_EQ(fits[3].kind->key, "lambert");
  EXPECT_EQ(fits[3].parameters.at("Color")[2], 0.111921);
  // The Lambertian block's evaluator is c / pi everywhere.
  const Evaluator lambert = fits[3].kind->make_evaluator(fits[3].parameters);
  EXPECT_DOUBLE_EQ(lambert(Vec3(0, 0, 1), LbfitTestDirection(60, 10))[1], 0.0434485 / kPi);
}

int LbfitParseErrorLine(const std::string& text) {
  try {
    ParseLbfitOutput("lbfit.txt", text);
  } catch (const ParseError& error) {
    EXPECT_NE(std::string(error.what()).find("lbfit.txt: line "), std::string::npos);
    return static_cast<int>(error.line());
  }
  ADD_FAILURE() << "no ParseError for:\n" << text;
  return 0;
}

TEST(LbfitOutput, BrokenOutputNamesTheLine) {
  // A colour with two numbers.
  EXPECT_EQ(LbfitParseErrorLine("[Lambertian]\nColor: 0.1 0.2\nError: 0.1\n"), 2);
  // A block without its roughness: reported at its heading.
  EXPECT_EQ(LbfitParseErrorLine("[Lambertian]\nColor: 0.1 0.2 0.3\nError: 0.1\n\n"
                                "[GGX (isotropic, no refractive index)]\nColor: 1 1 1\n"
                                "Error: 0.2\n"),
            5);
  // A model lbfit does not print, a value that is not a number, a line before any heading.
  EXPECT_EQ(LbfitParseErrorLine("[Phong]\nColor: 1 1 1\n"), 1);
  EXPECT_EQ(LbfitParseErrorLine("[Lambertian]\nColor: 0.1 x 0.3\nError: 0.1\n"), 2);
  EXPECT_EQ(LbfitParseErrorLine("Failed to load: t.binary\n"), 1);
  EXPECT_THROW(ParseLbfitOutput("lbfit.txt", ""), InputError);
}

}  // namespace
}  // namespace brdf::lbfit
