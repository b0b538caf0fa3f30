// MERL table: analytic write/read, the non-linear theta_h index, bit-exact copy, hostile files.
#include "io/merl.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>

#include "core/errors.h"
#include "fitters/fit.h"
#include "fitters/fit_arguments.h"
#include "fitters/fit_samples.h"
#include "io/formats.h"
#include "models/model_string.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::ScratchDir;

// Samples at every MERL cell centre whose directions are above the horizon, valued by `model`.
Measurement TabulateOnGrid(const Model& model) {
  Measurement measurement;
  for (int h = 0; h < MerlTable::kThetaHalfBins; ++h) {
    for (int d = 0; d < MerlTable::kThetaDiffBins; ++d) {
      for (int p = 0; p < MerlTable::kPhiDiffBins; ++p) {
        Sample sample;
        FromHalfDiff(MerlTable::CellCentre(h, d, p), &sample.wi, &sample.wo);
        if (sample.wi.z() <= 0 || sample.wo.z() <= 0) continue;
        sample.value = model.Eval(sample.wi, sample.wo);
        measurement.samples.push_back(sample);
      }
    }
  }
  return measurement;
}
// Every stored value drawn uniformly from [low, high) (negative ones are missing cells).
MerlTable RandomTable(uint64_t seed, double low, double high) {
  MerlTable table;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(low, high);
  for (int c = 0; c < 3; ++c) {
    for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) table.raw(c, cell) = uniform(random);
  }
  return table;
}

TEST(Merl, FileSizeIsTheDocumentedOne) { EXPECT_EQ(MerlTable::kFileBytes, 34992012); }

TEST(Merl, ThetaHalfIndexIsSquareRootWarped) {
  // index = floor(sqrt(theta_h / (pi/2)) * 90): 0.3 rad -> sqrt(0.190986) * 90 = 39.33 -> 39,
  // whereas a linear index would give floor(0.3 / (pi/2) * 90) = 17.
  EXPECT_EQ(MerlTable::ThetaHalfIndex(0.3), 39);
  EXPECT_EQ(MerlTable::ThetaHalfIndex(0.0), 0);
  EXPECT_EQ(MerlTable::ThetaHalfIndex(kPi / 2), 89);  // clamped
  // Bin k spans [(k/90)^2, ((k+1)/90)^2) * pi/2: its centre maps back to k.
  for (int k = 0; k < 90; ++k) {
    EXPECT_EQ(MerlTable::ThetaHalfIndex(MerlTable::CellCentre(k, 0, 0).theta_h), k);
  }
  EXPECT_EQ(MerlTable::ThetaDiffIndex(0.5), 28);      // 0.5 / (pi/2) * 90 = 28.65
  EXPECT_EQ(MerlTable::PhiDiffIndex(1.0), 57);        // 1.0 / pi * 180 = 57.3
  EXPECT_EQ(MerlTable::PhiDiffIndex(1.0 + kPi), 57);  // reciprocity fold
}

TEST(Merl, LookupLandsInTheRightCell) {
  MerlTable table;
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) {
    for (int c = 0; c < 3; ++c) table.raw(c, cell) = static_cast<double>(cell) + c * 0.25;
  }
  HalfDiff hd;
  hd.theta_h = 0.3;
  hd.phi_h = 1.1;  // isotropic: phi_h must not matter
  hd.theta_d = 0.5;
  hd.phi_d = 1.0;
  Vec3 wi, wo;
  FromHalfDiff(hd, &wi, &wo);
  const int64_t expected_cell = 57 + 180 * (28 + 90 * int64_t{39});
  EXPECT_EQ(MerlTable::CellOf(wi, wo), expected_cell);
  const Rgb value = table.Lookup(wi, wo);
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(value[c], (expected_cell + c * 0.25) * MerlTable::kScale[c]);
  }
}

TEST(Merl, MeasurementDirectionsAreTheCellCentres) {
  MerlTable table;
  for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) table.raw(0, cell) = 1.0;
  const Measurement measurement = table.ToMeasurement();
  for (int h : {0, 1, 17, 45, 89}) {
    for (int d : {0, 30, 89}) {
      for (int p : {0, 90, 179}) {
        Vec3 wi, wo;
        FromHalfDiff(MerlTable::CellCentre(h, d, p), &wi, &wo);
        const Sample& sample = measurement.samples[MerlTable::CellIndex(h, d, p)];
        EXPECT_NEAR((sample.wi - wi).norm(), 0.0, 1e-14);
        EXPECT_NEAR((sample.wo - wo).norm(), 0.0, 1e-14);
        EXPECT_EQ(MerlTable::CellOf(sample.wi, sample.wo), MerlTable::CellIndex(h, d, p));
      }
    }
  }
}

TEST(Merl, TabulateValuesEveryCellAtItsCentre) {
  const Model model = ParseModel("phong:rho_d=0.2,0.3,0.4:rho_s=0.3:n=20");
  const MerlTable table =
      MerlTable::Tabulate([&](const Vec3& wi, const Vec3& wo) { return model.Eval(wi, wo); });
  for (int h : {3, 40, 80}) {
    for (int d : {5, 50}) {
      for (int p : {10, 100}) {
        Vec3 wi, wo;
        FromHalfDiff(MerlTable::CellCentre(h, d, p), &wi, &wo);
        const Rgb expected = model.Eval(wi, wo);
        const Rgb looked_up = table.Lookup(wi, wo);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(looked_up[c], expected[c], 1e-12 * expected[c]);
      }
    }
  }
}

TEST(Merl, AnalyticTableSurvivesWriteAndRead) {
  ScratchDir dir;
  const Model model = ParseModel("blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.5:m=50");
  const Measurement grid = TabulateOnGrid(model);
  const std::string path = dir.File("analytic.binary");
  const WriteReport report = WriteMeasurement(grid, path);
  // On-grid data is not binned; only the below-horizon cells are empty.
  for (const std::string& warning : report.warnings) {
    EXPECT_EQ(warning.find("not at MERL cell centres"), std::string::npos) << warning;
  }
  const Measurement read = ReadMeasurement(path);
  EXPECT_EQ(read.format, "merl");
  ASSERT_EQ(read.samples.size(), static_cast<size_t>(MerlTable::kCells));
  size_t present = 0;
  for (const Sample& sample : read.samples) {
    if (sample.missing) continue;
    ++present;
    const Rgb expected = model.Eval(sample.wi, sample.wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sample.value[c], expected[c], 1e-12 * expected[c]);
  }
  EXPECT_EQ(present, grid.samples.size());
}

TEST(Merl, TheCellMeasureWeighsTheFitWithoutTheEvaluator) {
  // A fit reads the cell measure, not the table's values: `brdf fit` drops the evaluator after
  // reading, and the weights must not change.
  ScratchDir dir;
  const std::string path = dir.File("analytic.binary");
  WriteMeasurement(TabulateOnGrid(ParseModel("blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.5:m=50")),
                   path);
  Measurement read = ReadMeasurement(path);
  ASSERT_NE(read.tabulated, nullptr);
  ASSERT_NE(read.cell_measure, nullptr);
  const fitters::PreparedSamples with_table = fitters::PrepareSamples(read);
  read.tabulated.reset();
  const fitters::PreparedSamples without = fitters::PrepareSamples(read);
  EXPECT_EQ(without.weighting, with_table.weighting);
  EXPECT_NE(without.weighting.find("MERL cell measure"), std::string::npos) << without.weighting;
  ASSERT_EQ(without.samples.size(), with_table.samples.size());
  double sum = 0;
  for (size_t k = 0; k < without.samples.size(); ++k) {
    ASSERT_EQ(without.samples[k].weight, with_table.samples[k].weight) << k;
    sum += MerlTable::CellMeasure(without.samples[k].wi, without.samples[k].wo);
  }
  // The weights are the cell measures normalized to mean 1.
  const double mean = sum / without.samples.size();
  for (size_t k : {size_t{0}, without.samples.size() / 2, without.samples.size() - 1}) {
    const fitters::FitSample& sample = without.samples[k];
    EXPECT_NEAR(sample.weight, MerlTable::CellMeasure(sample.wi, sample.wo) / mean,
                1e-12 * sample.weight);
  }
}

TEST(Merl, NegativeValuesAreMissingNotData) {
  ScratchDir dir;
  MerlTable table;  // all -1
  const int64_t cell = MerlTable::CellIndex(10, 20, 30);
  for (int c = 0; c < 3; ++c) table.raw(c, cell) = 750.0;
  const std::string path = dir.File("sparse.binary");
  table.Write(path);
  const Measurement read = ReadMeasurement(path);
  const MeasurementSummary summary = Summarize(read);
  EXPECT_EQ(summary.missing, static_cast<size_t>(MerlTable::kCells - 1));
  EXPECT_EQ(summary.negative, 0u);
  EXPECT_DOUBLE_EQ(summary.max[0], 0.5);  // 750 / 1500
  EXPECT_DOUBLE_EQ(summary.max[2], 750 * 1.66 / 1500);
}

TEST(Merl, ConvertMerlToMerlIsBitExact) {
  ScratchDir dir;
  const MerlTable table = RandomTable(7, -0.5, 3000.0);
  const std::string original = dir.File("a.binary"), copy = dir.File("b.binary");
  table.Write(original);
  const testing::CommandResult result =
      testing::RunBrdf("convert --quiet '" + original + "' '" + copy + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  EXPECT_TRUE(testing::ReadFileText(original) == testing::ReadFileText(copy));
}

// `brdf convert MODEL X.binary` tabulates the model: read back, every cell the reader places at
// (wi, wo) holds the model's value there; a model has no samples of its own to write as CSV.
TEST(Merl, ConvertTabulatesAModel) {
  ScratchDir dir;
  const std::string spec = "ggx:rho_d=0.2,0.1,0.05:f0=0.04:alpha=0.15";
  const std::string path = dir.File("ggx.binary");
  const testing::CommandResult result =
      testing::RunBrdf("convert --quiet '" + spec + "' '" + path + "'");
  ASSERT_EQ(result.exit_status, 0) << result.err;
  const Model model = ParseModel(spec);
  const Measurement read = ReadMeasurement(path);
  size_t checked = 0;
  for (size_t k = 0; k < read.samples.size(); k += 997) {
    const Sample& sample = read.samples[k];
    if (sample.missing) continue;
    const Rgb expected = model.Eval(sample.wi, sample.wo);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(sample.value[c], expected[c], 1e-9 * std::max(1.0, expected[c])) << k;
    }
    ++checked;
  }
  EXPECT_GT(checked, 1000u);

  const testing::CommandResult csv =
      testing::RunBrdf("convert '" + spec + "' '" + dir.File("ggx.csv") + "'");
  EXPECT_EQ(csv.exit_status, 2);
  EXPECT_NE(csv.err.find("--schedule"), std::string::npos) << csv.err;
  const testing::CommandResult neither =
      testing::RunBrdf("convert '" + dir.File("absent") + "' '" + dir.File("x.csv") + "'");
  EXPECT_EQ(neither.exit_status, 2);
  EXPECT_NE(neither.err.find("not a model string"), std::string::npos) << neither.err;
}

// Read keeps the values in the file's mapped pages (core/mapped_file.h): every cell reads back
// as written, a write-back gives the same bytes, and changing a cell of the read table copies
// the values first and leaves the file as it was.
TEST(Merl, AReadTableHoldsTheFilesValuesAndChangesOnlyItsOwnCopy) {
  ScratchDir dir;
  const MerlTable written = RandomTable(7, -1.0, 4000.0);
  const std::string path = dir.File("random.binary");
  written.Write(path);
  MerlTable read = MerlTable::Read(path);
#if defined(__linux__)
  EXPECT_TRUE(read.InFilePages()) << "read into memory of its own, not mapped";
#endif
  const MerlTable& as_read = read;  // raw's const form reads the mapped values in place
  for (int c = 0; c < 3; ++c) {
    for (int64_t cell = 0; cell < MerlTable::kCells; ++cell) {
      ASSERT_EQ(as_read.raw(c, cell), written.raw(c, cell)) << "channel " << c << ", cell " << cell;
    }
  }
  const std::string copy = dir.File("copy.binary");
  read.Write(copy);
  EXPECT_EQ(testing::ReadFileText(copy), testing::ReadFileText(path));
#if defined(__linux__)
  EXPECT_TRUE(read.InFilePages());
#endif

  const int64_t cell = MerlTable::CellIndex(10, 20, 30);
  read.raw(1, cell) = 1234.5;
  EXPECT_FALSE(read.InFilePages());
  EXPECT_EQ(read.raw(1, cell), 1234.5);
  EXPECT_EQ(read.raw(2, cell), written.raw(2, cell));
  EXPECT_EQ(MerlTable::Read(path).raw(1, cell), written.raw(1, cell));
}

// The evaluator a read hands out has values of its own: the file rewritten in place afterwards
// (truncated first, as most programs write) changes nothing it answers.
TEST(Merl, TheEvaluatorOutlivesItsFile) {
  ScratchDir dir;
  const MerlTable written = RandomTable(11, 0.0, 2000.0);
  const std::string path = dir.File("rewritten.binary");
  written.Write(path);
  const Measurement read = ReadMeasurement(path);
  ASSERT_NE(read.tabulated, nullptr);
  ASSERT_NE(read.cell_measure, nullptr);
  {
    std::ofstream rewrite(path, std::ios::binary | std::ios::trunc);
    rewrite << "not a table any more";
  }
  for (int h = 0; h < MerlTable::kThetaHalfBins; h += 7) {
    Vec3 wi, wo;
    FromHalfDiff(MerlTable::CellCentre(h, 40, 20), &wi, &wo);
    const int64_t cell = MerlTable::CellIndex(h, 40, 20);
    EXPECT_EQ(read.tabulated->Eval(wi, wo)[0], written.raw(0, cell) * MerlTable::kScale[0]) << h;
  }
}

// A consumer that asks for the evaluator alone gets the table's lookup, cell measure and
// metadata as the whole read gives them, and none of the 1.46 million samples.
TEST(Merl, TheEvaluatorIsReadWithoutTheSamples) {
  ScratchDir dir;
  const std::string path = dir.File("random.binary");
  RandomTable(5, -100.0, 2000.0).Write(path);
  const Measurement whole = ReadMeasurement(path);
  const std::optional<Measurement> table = ReadEvaluator(path);
  ASSERT_TRUE(table.has_value());
  EXPECT_TRUE(table->samples.empty());
  EXPECT_EQ(whole.samples.size(), static_cast<size_t>(MerlTable::kCells));
  EXPECT_EQ(table->format, "merl");
  EXPECT_EQ(table->source, path);
  EXPECT_EQ(table->metadata, whole.metadata);
  ASSERT_NE(table->tabulated, nullptr);
  ASSERT_NE(table->cell_measure, nullptr);
  EXPECT_EQ(table->tabulated->Describe(), whole.tabulated->Describe());
  for (int64_t cell = 0; cell < MerlTable::kCells; cell += 9973) {
    const Sample& sample = whole.samples[cell];
    if (sample.wi.z() <= 0 || sample.wo.z() <= 0) continue;
    const Rgb a = table->tabulated->Eval(sample.wi, sample.wo);
    const Rgb b = whole.tabulated->Eval(sample.wi, sample.wo);
    for (int c = 0; c < 3; ++c) {
      // Both NaN in a missing cell, else the same stored value.
      EXPECT_TRUE(a[c] == b[c] || (std::isnan(a[c]) && std::isnan(b[c]))) << cell;
    }
    EXPECT_EQ(table->cell_measure->Measure(sample.wi, sample.wo),
              whole.cell_measure->Measure(sample.wi, sample.wo));
  }
  // A format whose samples are its data has no such read: the caller reads the whole file.
  const std::string csv = dir.File("samples.csv");
  WriteMeasurement(whole, csv, "native-csv");
  EXPECT_FALSE(ReadEvaluator(csv).has_value());
}

// An image-loss fit renders the evaluator and never reads a sample, so reading for it skips the
// samples; the fit is the same, bit for bit, as one of the whole read. Other losses fit the
// samples and get them, as does a caller that asks (`fit --plot`).
TEST(Merl, AnImageLossFitIsReadWithoutSamplesAndFitsTheSame) {
  ScratchDir dir;
  const std::string path = dir.File("ggx.binary");
  WriteMeasurement(TabulateOnGrid(ParseModel("ggx:rho_d=0.2,0.1,0.05:f0=0.04:alpha=0.2")), path);
  fitters::FitArguments arguments;
  arguments.model = "ggx";
  const Measurement lean = fitters::ReadForFit(path, arguments);
  const Measurement whole = fitters::ReadForFit(path, arguments, /*samples_wanted=*/true);
  EXPECT_TRUE(lean.samples.empty());
  EXPECT_EQ(whole.samples.size(), static_cast<size_t>(MerlTable::kCells));
  ASSERT_NE(lean.tabulated, nullptr);
  const fitters::FitOptions options = arguments.ToFitOptions(2);
  const fitters::FitResult from_lean = fitters::FitModel(lean, "ggx", options);
  const fitters::FitResult from_whole = fitters::FitModel(whole, "ggx", options);
  EXPECT_EQ(from_lean.loss, fitters::Loss::kImage);
  EXPECT_EQ(from_lean.samples, from_whole.samples);
  EXPECT_EQ(from_lean.model.ToString(17), from_whole.model.ToString(17));
  EXPECT_EQ(from_lean.metrics.rmse, from_whole.metrics.rmse);

  arguments.loss = "sqrt";
  const Measurement for_sqrt = fitters::ReadForFit(path, arguments);
  EXPECT_EQ(for_sqrt.samples.size(), static_cast<size_t>(MerlTable::kCells));
  EXPECT_EQ(for_sqrt.tabulated, nullptr);  // not rendered: let go before the fit
}

// A MERL table's samples written by another format (no cell measure of their own, no grid
// metadata) are recognised by where they sit and weighted by their cells, as the table's own
// read weighs them; one sample moved off its cell centre makes them scattered data again.
TEST(Merl, SamplesOnTheGridAreWeightedByTheirCells) {
  ScratchDir dir;
  const std::string path = dir.File("grid.binary");
  WriteMeasurement(TabulateOnGrid(ParseModel("blinn-phong:rho_d=0.3,0.2,0.1:rho_s=0.2:m=80")),
                   path);
  const Measurement table = ReadMeasurement(path);
  Measurement copy;
  copy.source = "copy";
  copy.samples = table.samples;
  EXPECT_TRUE(OnMerlGrid(copy.samples));
  const fitters::PreparedSamples from_table = fitters::PrepareSamples(table);
  const fitters::PreparedSamples from_copy = fitters::PrepareSamples(copy);
  EXPECT_EQ(from_copy.weighting, from_table.weighting);
  ASSERT_EQ(from_copy.samples.size(), from_table.samples.size());
  for (size_t k = 0; k < from_table.samples.size(); k += 101) {
    ASSERT_EQ(from_copy.samples[k].weight, from_table.samples[k].weight) << k;
  }
  size_t above = 0;
  while (copy.samples[above].missing) ++above;
  copy.samples[above].wo = (copy.samples[above].wo + Vec3(1e-4, 0, 0)).normalized();
  EXPECT_FALSE(OnMerlGrid(copy.samples));
  EXPECT_NE(fitters::PrepareSamples(copy).weighting, from_table.weighting);
}

TEST(Merl, HostileFilesNameTheByte) {
  ScratchDir dir;
  MerlTable table;
  const std::string good = dir.File("good.binary");
  table.Write(good);
  const std::string bytes = testing::ReadFileText(good);

  auto expect_error = [&](const std::string& name, const std::string& contents,
                          const std::string& fragment) {
    const std::string path = dir.Write(name, contents);
    try {
      MerlTable::Read(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const ByteError& error) {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  expect_error("empty.binary", "", "byte 0");
  expect_error("short-header.binary", bytes.substr(0, 7), "byte 7");
  expect_error("truncated.binary", bytes.substr(0, bytes.size() - 5),
               "byte " + std::to_string(bytes.size() - 5));
  std::string wrong_dims = bytes;
  const int32_t forty_five = 45;
  std::memcpy(wrong_dims.data() + 4, &forty_five, 4);
  expect_error("dims.binary", wrong_dims, "byte 4");
  std::string with_nan = bytes;
  const double nan = std::nan("");
  std::memcpy(with_nan.data() + 12 + 8 * 1000, &nan, 8);
  expect_error("nan.binary", with_nan, "byte " + std::to_string(12 + 8 * 1000));
  // Two bad values, far apart (the check runs in parallel parts): the first is the one named.
  const double infinite = std::numeric_limits<double>::infinity();
  std::string two_bad = with_nan;
  std::memcpy(two_bad.data() + 12 + 8 * (2 * MerlTable::kCells + 5), &infinite, 8);
  expect_error("two.binary", two_bad, "byte " + std::to_string(12 + 8 * 1000));
  std::string late_bad = bytes;
  std::memcpy(late_bad.data() + 12 + 8 * (2 * MerlTable::kCells + 5), &infinite, 8);
  expect_error("late.binary", late_bad,
               "byte " + std::to_string(12 + 8 * (2 * MerlTable::kCells + 5)));
}

}  // namespace
}  // namespace brdf
