// Tests for core/colour: the CIE tables against published values, and the spectrum -> RGB
// conversion against the properties core/colour.h promises.
#include "core/colour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/errors.h"

namespace brdf {
namespace {

constexpr int kCount = CieTables::kCount;

int IndexOf(double lambda_nm) {
  return static_cast<int>(std::lround((lambda_nm - CieTables::kFirstNm) / CieTables::kStepNm));
}

double WavelengthAt(int k) { return CieTables::kFirstNm + CieTables::kStepNm * k; }

int ArgMax(const double* table) {
  int best = 0;
  for (int k = 1; k < kCount; ++k) {
    if (table[k] > table[best]) best = k;
  }
  return best;
}

double Sum(const double* table) {
  double sum = 0.0;
  for (int k = 0; k < kCount; ++k) sum += table[k];
  return sum;
}

std::vector<double> CieGrid() {
  std::vector<double> grid(kCount);
  for (int k = 0; k < kCount; ++k) grid[k] = WavelengthAt(k);
  return grid;
}

TEST(Colour, GridIs360To830Every5nm) {
  EXPECT_EQ(kCount, 95);
  EXPECT_DOUBLE_EQ(WavelengthAt(0), 360.0);
  EXPECT_DOUBLE_EQ(WavelengthAt(kCount - 1), 830.0);
}

// The area under ybar = V(lambda): sum over the CIE 1931 table, 360..830 nm at 5 nm, times
// 5 nm is 106.857 (the CIE data set CIE_xyz_1931_2deg rows at 5 nm; at 1 nm it is 106.857 to
// the same 3 decimals). A wrong or missing row would move it by far more than 1e-3.
TEST(Colour, YBarAreaIsCieValue) {
  EXPECT_NEAR(Sum(CieTables::kYBar) * CieTables::kStepNm, 106.857, 1e-3);
}

// The 1931 functions are scaled so that illuminant E has chromaticity (1/3, 1/3), i.e. equal
// areas under xbar, ybar and zbar; the tabulation meets it to 4e-4.
TEST(Colour, EqualEnergyWhiteIsAchromatic) {
  const double x = Sum(CieTables::kXBar), y = Sum(CieTables::kYBar), z = Sum(CieTables::kZBar);
  EXPECT_NEAR(x / (x + y + z), 1.0 / 3.0, 1e-4);
  EXPECT_NEAR(y / (x + y + z), 1.0 / 3.0, 1e-4);
  EXPECT_NEAR(x / y, 1.0, 4e-4);
  EXPECT_NEAR(z / y, 1.0, 4e-4);
}

// Peaks on the 5 nm grid, as printed in the CIE 1931 table.
TEST(Colour, ColourMatchingFunctionPeaks) {
  EXPECT_EQ(WavelengthAt(ArgMax(CieTables::kYBar)), 555.0);
  EXPECT_EQ(CieTables::kYBar[IndexOf(555)], 1.0);
  EXPECT_EQ(WavelengthAt(ArgMax(CieTables::kXBar)), 600.0);
  EXPECT_DOUBLE_EQ(CieTables::kXBar[IndexOf(600)], 1.0622);
  EXPECT_EQ(WavelengthAt(ArgMax(CieTables::kZBar)), 445.0);
  EXPECT_DOUBLE_EQ(CieTables::kZBar[IndexOf(445)], 1.7826);
  // xbar's secondary (blue) lobe: 0.34828 at 440 nm.
  EXPECT_DOUBLE_EQ(CieTables::kXBar[IndexOf(440)], 0.34828);
}

// Spot values from the CIE 1931 table (first and last rows included, where a shifted table
// would show) and the zero tail of zbar.
TEST(Colour, ColourMatchingFunctionSpotValues) {
  EXPECT_DOUBLE_EQ(CieTables::kXBar[0], 0.0001299);
  EXPECT_DOUBLE_EQ(CieTables::kYBar[0], 0.000003917);
  EXPECT_DOUBLE_EQ(CieTables::kZBar[0], 0.0006061);
  EXPECT_DOUBLE_EQ(CieTables::kYBar[IndexOf(500)], 0.323);
  EXPECT_DOUBLE_EQ(CieTables::kXBar[IndexOf(700)], 0.01135916);
  EXPECT_DOUBLE_EQ(CieTables::kXBar[kCount - 1], 0.000001251141);
  EXPECT_DOUBLE_EQ(CieTables::kYBar[kCount - 1], 0.00000045181);
  for (int k = IndexOf(650); k < kCount; ++k) EXPECT_EQ(CieTables::kZBar[k], 0.0) << k;
}

TEST(Colour, D65SpotValues) {
  EXPECT_EQ(CieTables::kD65[IndexOf(560)], 100.0);
  EXPECT_DOUBLE_EQ(CieTables::kD65[0], 46.6383);             // 360 nm
  EXPECT_DOUBLE_EQ(CieTables::kD65[IndexOf(460)], 117.812);  // the maximum
  EXPECT_DOUBLE_EQ(CieTables::kD65[IndexOf(760)], 46.4182);  // the O2 A-band dip
  EXPECT_DOUBLE_EQ(CieTables::kD65[kCount - 1], 60.3125);    // 830 nm
  EXPECT_EQ(WavelengthAt(ArgMax(CieTables::kD65)), 460.0);
}

// CIE 015 tabulates the D65 white computed from the 5 nm tables over 380..780 nm as
// X = 95.04, Y = 100, Z = 108.88, chromaticity (0.31272, 0.32903). This ties the D65 and the
// colour matching function tables together.
TEST(Colour, D65WhitePointMatchesCie015) {
  double x = 0.0, y = 0.0, z = 0.0;
  for (int k = IndexOf(380); k <= IndexOf(780); ++k) {
    x += CieTables::kD65[k] * CieTables::kXBar[k];
    y += CieTables::kD65[k] * CieTables::kYBar[k];
    z += CieTables::kD65[k] * CieTables::kZBar[k];
  }
  EXPECT_NEAR(100.0 * x / y, 95.04, 0.005);
  EXPECT_NEAR(100.0 * z / y, 108.88, 0.005);
  EXPECT_NEAR(x / (x + y + z), 0.31272, 5e-6);
  EXPECT_NEAR(y / (x + y + z), 0.32903, 5e-6);
}

// The derived matrix agrees with the 4-decimal one printed in IEC 61966-2-1.
TEST(Colour, XyzToLinearSrgbMatchesIec61966Matrix) {
  const double printed[3][3] = {
      {3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  for (int column = 0; column < 3; ++column) {
    const Rgb rgb = XyzToLinearSrgb(Vec3::Unit(column));
    for (int row = 0; row < 3; ++row) {
      EXPECT_NEAR(rgb[row], printed[row][column], 5e-4) << row << "," << column;
    }
  }
}

TEST(Colour, XyzToLinearSrgbMapsD65WhiteToOne) {
  // The commonly quoted D65 white (1 nm CIE tables).
  const Rgb rgb = XyzToLinearSrgb(Vec3(0.95047, 1.0, 1.08883));
  EXPECT_NEAR(rgb[0], 1.0, 1e-3);
  EXPECT_NEAR(rgb[1], 1.0, 1e-3);
  EXPECT_NEAR(rgb[2], 1.0, 1e-3);
  // The sRGB white itself, (x, y) = (0.3127, 0.3290), maps to 1 to rounding error.
  const Rgb exact = XyzToLinearSrgb(Vec3(0.3127 / 0.3290, 1.0, (1 - 0.3127 - 0.3290) / 0.3290));
  EXPECT_NEAR(exact[0], 1.0, 1e-12);
  EXPECT_NEAR(exact[1], 1.0, 1e-12);
  EXPECT_NEAR(exact[2], 1.0, 1e-12);
}

TEST(Colour, XyzToLinearSrgbKeepsLuminance) {
  // The Rec.709 luminance weights are the Y row of RGB -> XYZ, so Luminance(rgb) == Y.
  const Vec3 xyz(0.3, 0.4, 0.2);
  EXPECT_NEAR(Luminance(XyzToLinearSrgb(xyz)), 0.4, 1e-4);
}

TEST(Colour, FlatSpectrumIsNeutralUnderBothIlluminants) {
  const std::vector<double> wavelengths = {380.0, 450.0, 520.0, 600.0, 700.0, 780.0};
  for (Illuminant illuminant : {Illuminant::kD65, Illuminant::kE}) {
    const SpectrumToRgb to_rgb(wavelengths, illuminant);
    for (double v : {0.0, 1.0, 0.25, 3.5}) {
      const std::vector<double> flat(wavelengths.size(), v);
      const Rgb rgb = to_rgb(flat.data());
      EXPECT_NEAR(rgb[0], v, 1e-12 * (1 + v)) << IlluminantName(illuminant);
      EXPECT_NEAR(rgb[1], v, 1e-12 * (1 + v)) << IlluminantName(illuminant);
      EXPECT_NEAR(rgb[2], v, 1e-12 * (1 + v)) << IlluminantName(illuminant);
      EXPECT_NEAR(Luminance(rgb), v, 1e-12 * (1 + v)) << IlluminantName(illuminant);
    }
  }
}

// A spike at 610 nm is an orange-red: XYZ proportional to (1.0026, 0.503, 0.00034).
TEST(Colour, NarrowBandAt610nmIsRed) {
  const std::vector<double> wavelengths = {605.0, 610.0, 615.0};
  const std::vector<double> spike = {0.0, 1.0, 0.0};
  for (Illuminant illuminant : {Illuminant::kD65, Illuminant::kE}) {
    const Rgb rgb = SpectrumToRgb(wavelengths, illuminant)(spike.data());
    EXPECT_GT(rgb[0], 0.0);
    EXPECT_GT(rgb[0], rgb[1]);
    EXPECT_GT(rgb[0], rgb[2]);
    // Out of the sRGB gamut: the spectral locus at 610 nm needs negative green and blue.
    EXPECT_LT(rgb[2], 0.0);
  }
  // Under D65 only the grid term at 610 nm contributes: XYZ = S(610) cmf(610) / sum S ybar.
  // The class also adapts the 5 nm-tabulated D65 white onto the sRGB white (a ~1e-4 change).
  double norm = 0.0;
  for (int k = 0; k < kCount; ++k) norm += CieTables::kD65[k] * CieTables::kYBar[k];
  const int k610 = IndexOf(610);
  const Vec3 xyz = CieTables::kD65[k610] / norm *
                   Vec3(CieTables::kXBar[k610], CieTables::kYBar[k610], CieTables::kZBar[k610]);
  const Rgb expected = XyzToLinearSrgb(xyz);
  const Rgb rgb = SpectrumToRgb(wavelengths, Illuminant::kD65)(spike.data());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], expected[c], 1e-3 * expected.abs().maxCoeff());
}

// Linear interpolation inside the sampled range and end values held outside it: a spectrum
// given at 500 and 600 nm converts like the same function sampled on the whole CIE grid.
TEST(Colour, InterpolatesLinearlyAndHoldsEnds) {
  const double low = 0.2, high = 0.9;
  const auto f = [&](double lambda) {
    if (lambda <= 500.0) return low;
    if (lambda >= 600.0) return high;
    return low + (high - low) * (lambda - 500.0) / 100.0;
  };
  const std::vector<double> grid = CieGrid();
  std::vector<double> sampled(kCount);
  for (int k = 0; k < kCount; ++k) sampled[k] = f(grid[k]);
  const std::vector<double> two = {low, high};
  for (Illuminant illuminant : {Illuminant::kD65, Illuminant::kE}) {
    const Rgb coarse = SpectrumToRgb({500.0, 600.0}, illuminant)(two.data());
    const Rgb fine = SpectrumToRgb(grid, illuminant)(sampled.data());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(coarse[c], fine[c], 1e-12) << c;
    // Rising towards the red: more red than blue.
    EXPECT_GT(coarse[0], coarse[2]);
  }
  // Input wavelengths off the 5 nm grid and beyond its ends are fine too.
  const std::vector<double> off_grid = {300.0, 502.5, 1000.0};
  const std::vector<double> ones = {1.0, 1.0, 1.0};
  const Rgb rgb = SpectrumToRgb(off_grid, Illuminant::kE)(ones.data());
  EXPECT_NEAR(rgb[0], 1.0, 1e-12);
  EXPECT_NEAR(rgb[1], 1.0, 1e-12);
  EXPECT_NEAR(rgb[2], 1.0, 1e-12);
}

TEST(Colour, SpectrumToRgbIsLinear) {
  const std::vector<double> wavelengths = {400.0, 500.0, 600.0, 700.0};
  const std::vector<double> a = {0.1, 0.5, 0.3, 0.8}, b = {0.7, 0.2, 0.4, 0.05};
  std::vector<double> sum(4);
  for (int i = 0; i < 4; ++i) sum[i] = 2.0 * a[i] + b[i];
  const SpectrumToRgb to_rgb(wavelengths, Illuminant::kD65);
  const Rgb expected = 2.0 * to_rgb(a.data()) + to_rgb(b.data());
  const Rgb actual = to_rgb(sum.data());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], 1e-12);
  EXPECT_EQ(to_rgb.illuminant(), Illuminant::kD65);
}

TEST(Colour, RejectsBadWavelengths) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SpectrumToRgb({}, Illuminant::kD65), UsageError);
  EXPECT_THROW(SpectrumToRgb({550.0}, Illuminant::kD65), UsageError);
  EXPECT_THROW(SpectrumToRgb({500.0, 500.0}, Illuminant::kD65), UsageError);
  EXPECT_THROW(SpectrumToRgb({600.0, 500.0}, Illuminant::kE), UsageError);
  EXPECT_THROW(SpectrumToRgb({400.0, nan, 600.0}, Illuminant::kE), UsageError);
  EXPECT_THROW(SpectrumToRgb({400.0, inf}, Illuminant::kE), UsageError);
  EXPECT_NO_THROW(SpectrumToRgb({400.0, 400.5}, Illuminant::kE));
}

TEST(Colour, ParseIlluminant) {
  EXPECT_EQ(ParseIlluminant("D65"), Illuminant::kD65);
  EXPECT_EQ(ParseIlluminant("d65"), Illuminant::kD65);
  EXPECT_EQ(ParseIlluminant("E"), Illuminant::kE);
  EXPECT_EQ(ParseIlluminant("e"), Illuminant::kE);
  EXPECT_STREQ(IlluminantName(Illuminant::kD65), "D65");
  EXPECT_STREQ(IlluminantName(Illuminant::kE), "E");
  EXPECT_EQ(ParseIlluminant(IlluminantName(Illuminant::kE)), Illuminant::kE);
  EXPECT_THROW(ParseIlluminant(""), UsageError);
  EXPECT_THROW(ParseIlluminant("D65 "), UsageError);
  try {
    ParseIlluminant("D50");
    FAIL() << "D50 was accepted";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("D50"), std::string::npos) << message;
    EXPECT_NE(message.find("D65"), std::string::npos) << message;
    EXPECT_NE(message.find("E"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace brdf
