// Every bloom blur against its design (DESIGN §8): the impulse response sums to 1, is centred,
// and its measured standard deviation matches the designed sigma within 2%.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "hdr/blur.h"

namespace brdf {
namespace {

struct Moments {
  double sum = 0, mean_x = 0, mean_y = 0, sigma_x = 0, sigma_y = 0;
};

// Moments of channel `c` of an image, in pixel coordinates.
Moments Measure(const Image& image, int c) {
  Moments m;
  double sx = 0, sy = 0, sxx = 0, syy = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double w = image.pixel(x, y)[c];
      m.sum += w;
      sx += w * x;
      sy += w * y;
      sxx += w * x * x;
      syy += w * y * y;
    }
  }
  m.mean_x = sx / m.sum;
  m.mean_y = sy / m.sum;
  m.sigma_x = std::sqrt(sxx / m.sum - m.mean_x * m.mean_x);
  m.sigma_y = std::sqrt(syy / m.sum - m.mean_y * m.mean_y);
  return m;
}

void ExpectImpulseResponse(const std::string& name, double designed_sigma,
                           const std::function<Image(const Image&)>& blur) {
  // An impulse in the middle of a field wide enough that no tap reaches the border.
  const int size = 2 * static_cast<int>(std::ceil(8 * designed_sigma)) + 33;
  Image impulse(size, size, /*alpha=*/0.0f);
  const int centre = size / 2;
  for (int c = 0; c < 4; ++c) impulse.pixel(centre, centre)[c] = 1.0f;
  const Image response = blur(impulse);
  ASSERT_EQ(response.width, size);
  ASSERT_EQ(response.height, size);
  for (int c = 0; c < 4; ++c) {
    const Moments m = Measure(response, c);
    SCOPED_TRACE(name + " channel " + std::to_string(c));
    EXPECT_NEAR(m.sum, 1.0, 1e-4);
    EXPECT_NEAR(m.mean_x, centre, 1e-3);
    EXPECT_NEAR(m.mean_y, centre, 1e-3);
    EXPECT_NEAR(m.sigma_x, designed_sigma, 0.02 * designed_sigma);
    EXPECT_NEAR(m.sigma_y, designed_sigma, 0.02 * designed_sigma);
  }
}

TEST(Blur, BoxImpulseResponse) {
  for (double sigma : {0.8, 2.0, 4.5, 13.0}) {
    ExpectImpulseResponse("box " + std::to_string(sigma), sigma,
                          [&](const Image& image) { return BoxBlur(image, sigma); });
  }
}

TEST(Blur, GaussianImpulseResponse) {
  for (double sigma : {1.0, 2.0, 4.5, 13.0}) {
    ExpectImpulseResponse("gauss " + std::to_string(sigma), sigma,
                          [&](const Image& image) { return GaussianBlur(image, sigma); });
  }
}

TEST(Blur, KawaseCanonicalOffsetsGiveSigma534) {
  const std::vector<double> offsets = {0, 1, 2, 2, 3};
  // Per axis: sum of (i + 1/2)^2 + 1/4 = 28.5 px^2.
  EXPECT_NEAR(KawaseSigma(offsets), std::sqrt(28.5), 1e-12);
  ExpectImpulseResponse("kawase {0,1,2,2,3}", KawaseSigma(offsets),
                        [&](const Image& image) { return KawaseBlur(image, offsets); });
}

TEST(Blur, KawaseDesignedForAnySigma) {
  for (double sigma : {0.6, 2.0, 5.0, 13.0}) {
    const std::vector<double> offsets = KawaseOffsetsForSigma(sigma);
    EXPECT_NEAR(KawaseSigma(offsets), sigma, 1e-9);
    ExpectImpulseResponse("kawase " + std::to_string(sigma), sigma,
                          [&](const Image& image) { return KawaseBlur(image, offsets); });
  }
}

TEST(Blur, DualFilterImpulseResponse) {
  for (int levels = 1; levels <= 4; ++levels) {
    ExpectImpulseResponse("dual L=" + std::to_string(levels), DualFilterSigma(levels),
                          [&](const Image& image) { return DualFilterBlur(image, levels); });
  }
  // The designed sigma does not depend on where the impulse falls in the 2^L pixel grid.
  for (int shift = 0; shift < 8; ++shift) {
    Image impulse(96, 96, /*alpha=*/0.0f);
    impulse.pixel(44 + shift, 40)[0] = 1.0f;
    const Moments m = Measure(DualFilterBlur(impulse, 3), 0);
    EXPECT_NEAR(m.sigma_x, DualFilterSigma(3), 0.02 * DualFilterSigma(3)) << shift;
    EXPECT_NEAR(m.mean_x, 44 + shift, 1e-3) << shift;
  }
}

TEST(Blur, DualFilterLevelsFollowSigma) {
  // About 0.84 * 2 px at one level, approaching 0.97 * 2^L.
  EXPECT_NEAR(DualFilterSigma(1), std::sqrt(17.0 / 6.0), 1e-12);
  for (int levels = 1; levels <= 6; ++levels) {
    EXPECT_EQ(DualFilterLevelsForSigma(DualFilterSigma(levels)), levels);
  }
  EXPECT_EQ(DualFilterLevelsForSigma(13.0), 4);  // 15.5 px is nearer (in log) than 7.7 px
}

TEST(Blur, DispatchUsesTheDesignedSigma) {
  EXPECT_EQ(ParseBlurKind("gauss"), BlurKind::kGaussian);
  EXPECT_EQ(DesignedSigma(BlurKind::kKawase, 5.0), 5.0);
  EXPECT_EQ(DesignedSigma(BlurKind::kDual, 13.0), DualFilterSigma(4));
  EXPECT_THROW(ParseBlurKind("bokeh"), std::exception);
}

}  // namespace
}  // namespace brdf
