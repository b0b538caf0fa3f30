// RGL-EPFL tensor files (io/tensor_file.h, io/rgl_bsdf.h, io/warp_2d.h) against the real
// files in data/rgl-bsdf/: the field table read by hand from a hex dump, evaluation at the
// stored grid nodes, the warp's round trip, reciprocity and the albedo of white paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "core/angles.h"
#include "core/colour.h"
#include "core/errors.h"
#include "energy/albedo.h"
#include "energy/measured.h"
#include "fitters/fit_samples.h"
#include "io/formats.h"
#include "io/rgl_bsdf.h"
#include "io/tensor_file.h"
#include "io/warp_2d.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;

const char* const kPaper = "rgl-bsdf/paper_white_rgb.bsdf";

// `xxd data/rgl-bsdf/paper_white_rgb.bsdf | head -28`, the header and the field table:
//   00000000: 7465 6e73 6f72 5f66 696c 6500 0100 0b00  tensor_file.....
//   00000010: 0000 0700 7665 7273 696f 6e01 0005 a001  ....version.....
//   00000020: 0000 0000 0000 0200 0000 0000 0000 0b00  ................
//   00000030: 6465 7363 7269 7074 696f 6e01 0001 a801  description.....
//   00000040: 0000 0000 0000 1800 0000 0000 0000 0500  ................
//   00000050: 7068 695f 6901 000a c001 0000 0000 0000  phi_i...........
//   00000060: 0100 0000 0000 0000 0700 7468 6574 615f  ..........theta_
//   00000070: 6901 000a c801 0000 0000 0000 0800 0000  i...............
//   00000080: 0000 0000 0500 7369 676d 6102 000a e801  ......sigma.....
//   00000090: 0000 0000 0000 0200 0000 0000 0000 8000  ................
//   000000a0: 0000 0000 0000 0300 6e64 6602 000a e805  ........ndf.....
//   000000b0: 0000 0000 0000 0200 0000 0000 0000 8000  ................
//   000000c0: 0000 0000 0000 0400 766e 6466 0400 0ae8  ........vndf....
//   000000d0: 0900 0000 0000 0001 0000 0000 0000 0008  ................
//   000000e0: 0000 0000 0000 0080 0000 0000 0000 0080  ................
//   000000f0: 0000 0000 0000 0009 006c 756d 696e 616e  .........luminan
//   00000100: 6365 0400 0ae8 0908 0000 0000 0001 0000  ce..............
//   00000110: 0000 0000 0008 0000 0000 0000 0020 0000  ............. ..
//   00000120: 0000 0000 0020 0000 0000 0000 0003 0072  ..... .........r
//   00000130: 6762 0500 0ae8 8908 0000 0000 0001 0000  gb..............
//   00000140: 0000 0000 0008 0000 0000 0000 0003 0000  ................
//   00000150: 0000 0000 0020 0000 0000 0000 0020 0000  ..... ....... ..
//   00000160: 0000 0000 0008 006a 6163 6f62 6961 6e01  .......jacobian.
//   00000170: 0001 e809 0a00 0000 0000 0100 0000 0000  ................
//   00000180: 0000 0500 7661 6c69 6401 0001 f009 0a00  ....valid.......
//   00000190: 0000 0000 0004 0000 0000 0000 0000 0000  ................
//   000001a0: 0100 0000 0000 0000 5768 6974 6520 4134  ........White A4
//   000001b0: 2070 6170 6572 2028 3136 3020 6773 6d29   paper (160 gsm)
//   000001c0: 0000 0000 0000 0000 0000 0000 413e f73e  ............A>.>
// Read by hand: version 01 00, 0x0b = 11 fields. "version": ndim 1, dtype 05 (u32), offset
// 0x1a0, shape [2]; "description": u8 at 0x1a8, [0x18 = 24]; "phi_i": f32 (0x0a) at 0x1c0, [1];
// "theta_i": f32 at 0x1c8, [8]; "sigma": f32 at 0x1e8, [2, 0x80]; "ndf": f32 at 0x5e8,
// [2, 128]; "vndf": f32 at 0x9e8, [1, 8, 128, 128]; "luminance": f32 at 0x809e8, [1, 8, 32, 32];
// "rgb": f32 at 0x889e8, [1, 8, 3, 32, 32]; "jacobian": u8 at 0xa09e8, [1]; "valid": u8 at
// 0xa09f0, [0x400]. Data: version (1, 0) at 0x1a0; phi_i = 0 (00000000 at 0x1c0); theta_i[0] = 0
// (at 0x1c8), theta_i[1] = 0x3ef73e41 = 0.48289683 rad (bytes 41 3e f7 3e at 0x1cc).
TEST(TensorFile, FieldTableOfPaperWhiteMatchesTheHexDump) {
  const TensorFile file = TensorFile::Read(DataPath(kPaper));
  EXPECT_EQ(file.version_major(), 1);
  EXPECT_EQ(file.version_minor(), 0);
  EXPECT_EQ(file.size(), 658928);
  struct Expected {
    const char* name;
    TensorDtype dtype;
    uint64_t offset;
    std::vector<uint64_t> shape;
  };
  const std::vector<Expected> expected = {
      {"version", TensorDtype::kU32, 0x1a0, {2}},
      {"description", TensorDtype::kU8, 0x1a8, {24}},
      {"phi_i", TensorDtype::kF32, 0x1c0, {1}},
      {"theta_i", TensorDtype::kF32, 0x1c8, {8}},
      {"sigma", TensorDtype::kF32, 0x1e8, {2, 128}},
      {"ndf", TensorDtype::kF32, 0x5e8, {2, 128}},
      {"vndf", TensorDtype::kF32, 0x9e8, {1, 8, 128, 128}},
      {"luminance", TensorDtype::kF32, 0x809e8, {1, 8, 32, 32}},
      {"rgb", TensorDtype::kF32, 0x889e8, {1, 8, 3, 32, 32}},
      {"jacobian", TensorDtype::kU8, 0xa09e8, {1}},
      {"valid", TensorDtype::kU8, 0xa09f0, {0x400}},
  };
  ASSERT_EQ(file.fields().size(), expected.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    const TensorField& field = file.fields()[k];
    EXPECT_EQ(field.name, expected[k].name);
    EXPECT_EQ(field.dtype, expected[k].dtype) << field.name;
    EXPECT_EQ(field.data_offset, expected[k].offset) << field.name;
    EXPECT_EQ(field.shape, expected[k].shape) << field.name;
  }
  EXPECT_EQ(file.fields()[0].entry_offset, 0x12);  // right after the 18-byte header
  EXPECT_EQ(file.Text(*file.Find("description")), "White A4 paper (160 gsm)");
  EXPECT_EQ(file.Values(*file.Find("version")), (std::vector<double>{1, 0}));
  const std::vector<double> theta_i = file.Values(*file.Find("theta_i"));
  EXPECT_EQ(theta_i[0], 0.0);
  EXPECT_EQ(static_cast<float>(theta_i[1]), 0.48289683f);
  EXPECT_EQ(file.Values(*file.Find("jacobian")), (std::vector<double>{1}));
}

// A bilinear lookup written out for the test, over a rows x cols table (x along the columns).
double Bilinear(const std::vector<double>& table, int rows, int cols, const Vec2& u) {
  const double x = u.x() * (cols - 1), y = u.y() * (rows - 1);
  const int px = std::min(static_cast<int>(x), cols - 2),
            py = std::min(static_cast<int>(y), rows - 2);
  const double tx = x - px, ty = y - py;
  auto at = [&](int r, int c) { return table[r * cols + c]; };
  return (1 - ty) * ((1 - tx) * at(py, px) + tx * at(py, px + 1)) +
         ty * ((1 - tx) * at(py + 1, px) + tx * at(py + 1, px + 1));
}

// At a stored node the inverse warp lands back on the node, so the evaluation is the file's
// own value times ndf(u_wm) / (4 sigma(u_wi)) (f cos(theta_o)). theta_i = 0 and the
// column u = 0 (theta_m = 0, the mirror direction) are left out: there the tables depend on
// the azimuth convention (every phi is the same direction).
TEST(RglBsdf, EvaluationAtGridNodesIsTheStoredValueTimesTheJacobianFactor) {
  const TensorFile file = TensorFile::Read(DataPath(kPaper));
  const std::shared_ptr<const RglBrdf> brdf = RglBrdf::FromTensor(file);
  const std::vector<double> rgb = file.Values(*file.Find("rgb"));
  const std::vector<double> ndf = file.Values(*file.Find("ndf"));
  const std::vector<double> sigma = file.Values(*file.Find("sigma"));
  const std::vector<double> theta_i = file.Values(*file.Find("theta_i"));
  const int n = 32;
  int checked = 0;
  for (int t = 1; t < 7; ++t) {
    for (int row = 0; row < n; row += 3) {
      for (int col = 1; col < n; col += 2) {
        const RglBrdf::Node node = brdf->GridNode(0, t, row, col);
        if (node.wo.z() < 0.05) continue;
        EXPECT_NEAR(Theta(node.wi), theta_i[t], 1e-12);
        const Vec2 u_wi(std::sqrt(theta_i[t] * 2 / kPi), 0.5);  // phi_i = 0
        const double factor =
            Bilinear(ndf, 2, 128, node.u_wm) / (4 * Bilinear(sigma, 2, 128, u_wi));
        // In the file's orientation, f cos(theta_o); brdfkit's f divides it by cos(theta_o),
        // wi the tensor's incidence (the reference reading).
        const Rgb value = brdf->EvalCosine(node.wi, node.wo);
        const Rgb f = brdf->Eval(node.wi, node.wo);
        for (int c = 0; c < 3; ++c) {
          const double stored = rgb[((t * 3 + c) * n + row) * n + col];
          const double expected = std::max(0.0, stored) * factor;
          EXPECT_NEAR(f[c], expected / node.wo.z(), 1e-7 * expected / node.wo.z() + 1e-12);
          EXPECT_NEAR(value[c], expected, 1e-7 * expected + 1e-12)
              << "theta_i " << t << " row " << row << " col " << col << " channel " << c;
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 500);
}

// Local extrema of a sequence: the turns of a curve that should fall monotonically.
int Turns(const std::vector<double>& values) {
  int turns = 0;
  for (size_t k = 2; k < values.size(); ++k) {
    turns += (values[k] - values[k - 1]) * (values[k - 1] - values[k - 2]) < 0;
  }
  return turns;
}

// The preview evaluator of an RGL file keeps every node's value (f at the nodes is the
// reference's) and interpolates f cos(theta_o) between them, so it draws no ring that the
// nodes do not have. On cc_ibiza_sunset at the incidence node 29.6 deg, the nodes on the light's
// side of the plane of incidence fall monotonically from the normal to 65 deg (0.030 to 3e-5);
// the reference's interpolation of the stored value times ndf(wm) turns 12 times there (the
// rings on a sphere), the preview's not once.
TEST(RglBsdf, PreviewKeepsTheNodesAndDrawsNoRingsBetweenThem) {
  const TensorFile file = TensorFile::Read(DataPath("rgl-bsdf/cc_ibiza_sunset_rgb.bsdf"));
  const std::shared_ptr<const RglBrdf> brdf = RglBrdf::FromTensor(file);
  const std::shared_ptr<const TabulatedBrdf> preview = brdf->PreviewEvaluator();
  ASSERT_NE(preview, nullptr);
  int checked = 0;
  for (int t = 1; t < 7; ++t) {
    for (int row = 0; row < brdf->rows(); row += 3) {
      for (int col = 1; col < brdf->cols(); col += 2) {
        const RglBrdf::Node node = brdf->GridNode(0, t, row, col);
        if (node.wo.z() < 0.05) continue;
        const Rgb reference = brdf->Eval(node.wi, node.wo), drawn = preview->Eval(node.wi, node.wo);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(drawn[c], reference[c], 1e-7 * reference[c] + 1e-12)
              << "theta_i " << t << " row " << row << " col " << col << " channel " << c;
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 500);
  const double theta_i = brdf->theta_i()[1];
  ASSERT_NEAR(RadToDeg(theta_i), 29.62, 0.01);
  const Vec3 wi = SphericalDirection(theta_i, 0);
  std::vector<double> reference, drawn;
  for (int k = 0; k <= 400; ++k) {
    const Vec3 wo = SphericalDirection(DegToRad(65.0 * k / 400), 0);
    reference.push_back(brdf->EvalCosine(wi, wo)[0]);
    drawn.push_back(preview->Eval(wi, wo)[0] * wo.z());
  }
  EXPECT_GE(Turns(reference), 10);
  EXPECT_EQ(Turns(drawn), 0);
}

// The measurement's samples are those nodes: same directions, the file's values divided by
// cos(theta_o).
TEST(RglBsdf, TheCellMeasureWeighsTheFitWithoutTheEvaluator) {
  Measurement read = ReadMeasurement(DataPath("rgl-bsdf/paper_white_rgb.bsdf"));
  ASSERT_NE(read.cell_measure, nullptr);
  const fitters::PreparedSamples with_table = fitters::PrepareSamples(read);
  read.tabulated.reset();
  const fitters::PreparedSamples without = fitters::PrepareSamples(read);
  EXPECT_EQ(without.weighting, with_table.weighting);
  ASSERT_EQ(without.samples.size(), with_table.samples.size());
  for (size_t k = 0; k < without.samples.size(); ++k) {
    ASSERT_EQ(without.samples[k].weight, with_table.samples[k].weight) << k;
  }
}

TEST(RglBsdf, SamplesAreTheGridNodes) {
  const Measurement measurement = ReadMeasurement(DataPath(kPaper));
  EXPECT_EQ(measurement.format, "rgl-bsdf");
  ASSERT_EQ(measurement.samples.size(), 8u * 32 * 32);
  ASSERT_NE(measurement.tabulated, nullptr);
  EXPECT_EQ(measurement.metadata.at("description"), "White A4 paper (160 gsm)");
  const Sample& sample = measurement.samples[(3 * 32 + 10) * 32 + 7];
  ASSERT_FALSE(sample.missing);
  const Rgb evaluated = measurement.tabulated->Eval(sample.wi, sample.wo);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(evaluated[c], sample.value[c], 1e-7 * sample.value[c]);
  // The reciprocal reading, on request, is reciprocal by construction (the more grazing
  // direction is read as the light); the reference reading is not.
  ReadOptions reciprocal;
  reciprocal.reciprocal = true;
  const Measurement symmetric = ReadMeasurement(DataPath(kPaper), reciprocal);
  const Rgb forward = symmetric.tabulated->Eval(sample.wi, sample.wo);
  EXPECT_EQ(Luminance(symmetric.tabulated->Eval(sample.wo, sample.wi)), Luminance(forward));
}

// The satin's table is far from reciprocal near grazing; the reference reading reproduces the
// values of the format's authors' evaluator and Mitsuba 3's `measured` plugin (wi the tensor's
// incidence, f = the stored f cos(theta_o) / cos(theta_o)), read from them at these directions:
// f(68.8 -> 79.4 deg, mirror side) = 1.38, f(78.7 -> 68.8) = 40.9 and f(68.8 -> 78.7) = 1.57 sr^-1,
// where the reciprocal reading gives 40.1 for the first. The red channel here is 1.419 and 1.626
// for the first and last (within 4 %, the middle one too: the quoted values' channel is not
// stated); what the test pins is the reading (a grazing view is not read as the light) and the
// order of magnitude it makes.
TEST(RglBsdf, ReferenceReadingGivesTheReferenceValuesOfTheSatin) {
  const auto satin =
      RglBrdf::FromTensor(TensorFile::Read(DataPath("rgl-bsdf/satin_rosaline_rgb.bsdf")));
  const auto f = [&](double theta_i, double theta_o) {
    return satin->Eval(SphericalDirection(DegToRad(theta_i), 0.0),
                       SphericalDirection(DegToRad(theta_o), kPi))[0];
  };
  EXPECT_NEAR(f(68.8, 79.4), 1.38, 0.04 * 1.38);
  EXPECT_NEAR(f(78.7, 68.8), 40.9, 0.04 * 40.9);
  EXPECT_NEAR(f(68.8, 78.7), 1.57, 0.04 * 1.57);
  ReadOptions reciprocal;
  reciprocal.reciprocal = true;
  const auto symmetric = RglBrdf::FromTensor(
      TensorFile::Read(DataPath("rgl-bsdf/satin_rosaline_rgb.bsdf")), reciprocal);
  const double symmetric_f = symmetric->Eval(SphericalDirection(DegToRad(68.8), 0.0),
                                             SphericalDirection(DegToRad(79.4), kPi))[0];
  EXPECT_GT(symmetric_f, 20.0);  // 40.1: the grazing view read as the light
}

// Sample and Invert are inverse maps, and the density integrates to one, on the real vndf
// tables (interpolated between two incidence slices).
TEST(Warp2D, SampleAndInvertAreInverseOnTheRealVndf) {
  const TensorFile file = TensorFile::Read(DataPath(kPaper));
  const std::vector<double> theta_i = file.Values(*file.Find("theta_i"));
  const Warp2D warp(128, 128, file.Values(*file.Find("vndf")), {{0.0}, theta_i}, true);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const double parameters[2] = {0.0, 0.3 + 0.9 * uniform(random)};
    const Vec2 u(uniform(random), uniform(random));
    double pdf_forward = 0, pdf_inverse = 0;
    const Vec2 point = warp.Sample(u, parameters, &pdf_forward);
    const Vec2 back = warp.Invert(point, parameters, &pdf_inverse);
    EXPECT_NEAR(back.x(), u.x(), 1e-9);
    EXPECT_NEAR(back.y(), u.y(), 1e-9);
    EXPECT_NEAR(pdf_inverse, pdf_forward, 1e-9 * pdf_forward);
    EXPECT_NEAR(warp.Eval(point, parameters), pdf_forward, 1e-9 * pdf_forward);
  }
  // Midpoint rule on a grid finer than the table: the density integrates to 1.
  const double parameters[2] = {0.0, theta_i[3]};
  double integral = 0;
  const int cells = 1024;
  for (int y = 0; y < cells; ++y) {
    for (int x = 0; x < cells; ++x) {
      integral += warp.Eval(Vec2((x + 0.5) / cells, (y + 0.5) / cells), parameters);
    }
  }
  EXPECT_NEAR(integral / (cells * cells), 1.0, 1e-3);
}

// Median over random direction pairs of |f(wi, wo) - f(wo, wi)| / mean, on luminance, with f
// read in the file's own orientation both ways: f(wi, wo) = EvalCosine(wi, wo) / cos(theta_o).
double MedianReciprocityError(const RglBrdf& brdf, uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> errors;
  while (errors.size() < 4000) {
    // theta up to 80 deg, away from the 90-degree incidence node.
    const Vec3 wi = SphericalDirection(
        std::acos(1 - uniform(random) * (1 - std::cos(DegToRad(80)))), 2 * kPi * uniform(random));
    const Vec3 wo = SphericalDirection(
        std::acos(1 - uniform(random) * (1 - std::cos(DegToRad(80)))), 2 * kPi * uniform(random));
    const double forward = Luminance(brdf.EvalCosine(wi, wo)) / wo.z();
    const double backward = Luminance(brdf.EvalCosine(wo, wi)) / wi.z();
    if (!(forward + backward > 0)) continue;
    errors.push_back(std::abs(forward - backward) / (0.5 * (forward + backward)));
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

// Measured data are only approximately reciprocal. Dupuy & Jakob's paper reports about 1.4 %
// median for paper; here, over 4000 random pairs below 80 deg, paper_white gives a median
// relative difference of 1.7 % (docs/formats.md lists all seven). A wrong convention (the stored f
// cos(theta_o) taken for f, or the azimuth of wm not taken relative to wi) breaks this by an order
// of magnitude.
TEST(RglBsdf, ReciprocityHoldsWithinTheMeasurementsOwnTolerance) {
  const auto paper = RglBrdf::FromTensor(TensorFile::Read(DataPath(kPaper)));
  const double paper_error = MedianReciprocityError(*paper, 1);
  EXPECT_LT(paper_error, 0.03);
  const auto paint =
      RglBrdf::FromTensor(TensorFile::Read(DataPath("rgl-bsdf/colodur_napoli_4f_rgb.bsdf")));
  EXPECT_LT(MedianReciprocityError(*paint, 1), 0.04);
  RecordProperty("paper_white_median_reciprocity", std::to_string(paper_error));
  // The other five, printed for docs/formats.md; only the colour-shifting films exceed 15 %.
  for (const char* name : {"cc_ibiza_sunset", "cc_iris_purple_gem", "cg_sunflower",
                           "satin_rosaline", "vch_golden_yellow"}) {
    const auto brdf = RglBrdf::FromTensor(
        TensorFile::Read(DataPath("rgl-bsdf/" + std::string(name) + "_rgb.bsdf")));
    const double error = MedianReciprocityError(*brdf, 1);
    std::printf("median reciprocity difference: %s %.4f\n", name, error);
    if (std::string(name).rfind("cc_", 0) != 0) {
      EXPECT_LT(error, 0.15) << name;
    }
  }
  std::printf("median reciprocity difference: paper_white %.4f\n", paper_error);
}

// Directional albedo a(wi) = ∫ f cos(theta_o) dwo by the midpoint rule on a 90 x 360 grid.
Rgb Albedo(const RglBrdf& brdf, double theta_i_deg) {
  const Vec3 wi = SphericalDirection(DegToRad(theta_i_deg), 0.0);
  const int n_theta = 90, n_phi = 360;
  const double d_theta = 0.5 * kPi / n_theta, d_phi = 2 * kPi / n_phi;
  Rgb sum = Rgb::Zero();
  for (int i = 0; i < n_theta; ++i) {
    const double theta = (i + 0.5) * d_theta;
    for (int j = 0; j < n_phi; ++j) {
      sum += brdf.EvalCosine(wi, SphericalDirection(theta, (j + 0.5) * d_phi)) * std::sin(theta) *
             d_theta * d_phi;
    }
  }
  return sum;
}

// `brdf energy`'s directional albedo of measured data integrates the stored f cos(theta_o) over
// the outgoing hemisphere at a held incidence, as the reference does: against the midpoint rule
// above (independent of the energy library's quadrature) on the satin, whose table is not
// reciprocal, and the ibiza film. The reference values (read from the authors' evaluator):
// satin 0.744 at 60 deg, ibiza 0.319 at 30 deg (red).
TEST(RglBsdf, MeasuredAlbedoHoldsTheIncidenceAndIntegratesTheView) {
  for (const auto& [name, theta, reference] :
       {std::tuple{"satin_rosaline", 60.0, 0.744}, std::tuple{"cc_ibiza_sunset", 30.0, 0.319}}) {
    const std::string path = DataPath("rgl-bsdf/" + std::string(name) + "_rgb.bsdf");
    const auto brdf = RglBrdf::FromTensor(TensorFile::Read(path));
    const Rgb midpoint = Albedo(*brdf, theta);
    const AlbedoEstimate integrated =
        MeasuredDirectionalAlbedo(LoadMeasuredBrdf(path), DegToRad(theta), AlbedoOptions{});
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(integrated.albedo[c], midpoint[c], 0.01 * midpoint[c]) << name << " " << c;
    }
    EXPECT_NEAR(integrated.albedo[0], reference, 0.01) << name;
  }
}

// White 160 gsm office paper reflects most light, diffusely: its albedo should be high and
// change little with incidence. Measured here: luminance albedo 0.836 at 10 deg, 0.854 at 40,
// 0.873 at 60 deg, within 5 % of each other (see docs/real-data.md).
TEST(RglBsdf, PaperWhiteAlbedoIsHighAndNearlyConstant) {
  const TensorFile file = TensorFile::Read(DataPath(kPaper));
  const std::shared_ptr<const RglBrdf> brdf = RglBrdf::FromTensor(file);
  std::vector<double> albedo;
  for (double theta : {10.0, 40.0, 60.0}) albedo.push_back(Luminance(Albedo(*brdf, theta)));
  std::printf("paper_white albedo (luminance) at 10, 40, 60 deg: %.4f %.4f %.4f\n", albedo[0],
              albedo[1], albedo[2]);
  for (double a : albedo) {
    EXPECT_GT(a, 0.6);
    EXPECT_LT(a, 1.0);
  }
  const auto [low, high] = std::minmax_element(albedo.begin(), albedo.end());
  EXPECT_LT(*high / *low, 1.1);
}

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

// A tensor_file written field by field (layout in io/tensor_file.h).
class TensorWriter {
 public:
  void Add(const std::string& name, TensorDtype dtype, std::vector<uint64_t> shape,
           std::string data) {
    fields_.push_back({name, dtype, std::move(shape), std::move(data)});
  }
  template <typename T>
  static std::string Bytes(const std::vector<T>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  std::string Build() const {
    uint64_t table = 18;
    for (const Field& f : fields_) table += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
    std::string header("tensor_file\0", 12), data;
    header += std::string("\x01\x00", 2);
    Append<uint32_t>(&header, static_cast<uint32_t>(fields_.size()));
    for (const Field& f : fields_) {
      Append<uint16_t>(&header, static_cast<uint16_t>(f.name.size()));
      header += f.name;
      Append<uint16_t>(&header, static_cast<uint16_t>(f.shape.size()));
      Append<uint8_t>(&header, static_cast<uint8_t>(f.dtype));
      Append<uint64_t>(&header, table + data.size());
      for (uint64_t extent : f.shape) Append<uint64_t>(&header, extent);
      data += f.data;
    }
    return header + data;
  }

 private:
  struct Field {
    std::string name;
    TensorDtype dtype;
    std::vector<uint64_t> shape;
    std::string data;
  };
  template <typename T>
  static void Append(std::string* bytes, T value) {
    bytes->append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  std::vector<Field> fields_;
};

// A spectral file with constant tables, in mixed dtypes: the warp is the identity, the
// spectrum is flat (v at both wavelengths, so RGB (v, v, v) under any illuminant, core/colour.h),
// ndf / (4 sigma) = 2 / (4 * 0.25) = 2, so f cos(theta_o) = 2 v everywhere above the horizon.
TEST(RglBsdf, SpectralFileWithConstantTablesGivesTheClosedForm) {
  const double v = 0.1;
  TensorWriter writer;
  writer.Add("description", TensorDtype::kU8, {4}, "flat");
  writer.Add("theta_i", TensorDtype::kF32, {2}, TensorWriter::Bytes<float>({0.0f, 1.0f}));
  writer.Add("phi_i", TensorDtype::kF64, {1}, TensorWriter::Bytes<double>({0.0}));
  // 2.0 in binary16 is 0x4000.
  writer.Add("ndf", TensorDtype::kF16, {2, 2},
             TensorWriter::Bytes<uint16_t>({0x4000, 0x4000, 0x4000, 0x4000}));
  writer.Add("sigma", TensorDtype::kF64, {2, 2},
             TensorWriter::Bytes<double>({0.25, 0.25, 0.25, 0.25}));
  writer.Add("vndf", TensorDtype::kF32, {1, 2, 2, 2},
             TensorWriter::Bytes<float>(std::vector<float>(8, 1.0f)));
  writer.Add("spectra", TensorDtype::kF32, {1, 2, 2, 3, 3},
             TensorWriter::Bytes<float>(std::vector<float>(36, static_cast<float>(v))));
  writer.Add("wavelengths", TensorDtype::kU16, {2}, TensorWriter::Bytes<uint16_t>({400, 700}));
  writer.Add("jacobian", TensorDtype::kU8, {1}, std::string(1, '\x01'));
  const TensorFile file = TensorFile::Parse("flat.bsdf", writer.Build());
  const std::shared_ptr<const RglBrdf> brdf = RglBrdf::FromTensor(file);
  EXPECT_NE(brdf->colour_source().find("spectra field (2 wavelengths"), std::string::npos);
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Vec3 wi = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    const Vec3 wo = SphericalDirection(std::acos(uniform(random)), 2 * kPi * uniform(random));
    const Rgb value = brdf->EvalCosine(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], 2 * static_cast<float>(v), 1e-4);
    const Rgb f = brdf->Eval(wi, wo);
    EXPECT_NEAR(f[1], 2 * static_cast<float>(v) / wo.z(), 1e-3 * f[1]);
  }
}

}  // namespace
}  // namespace brdf
