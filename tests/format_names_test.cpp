// The printf-style formatter (core/format.h) and the enum name tables (core/enum_names.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/colour.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/format.h"
#include "energy/albedo.h"
#include "export/export.h"
#include "fitters/fit.h"
#include "fitters/fit_samples.h"
#include "hdr/blur.h"
#include "hdr/image_files.h"
#include "hdr/tone_map.h"
#include "io/tensor_file.h"

namespace brdf {
namespace {

TEST(Format, MatchesSnprintf) {
  char expected[128];
  std::snprintf(expected, sizeof(expected), "%-12.6g|%10.4g|%.3f|%a|%zu|%s", 1.0 / 3, 2e-7, 0.5,
                0.1, size_t{42}, "text");
  EXPECT_EQ(Format("%-12.6g|%10.4g|%.3f|%a|%zu|%s", 1.0 / 3, 2e-7, 0.5, 0.1, size_t{42}, "text"),
            expected);
  EXPECT_EQ(Format("%s", ""), "");
}

TEST(Format, LongerThanItsFirstBuffer) {
  // Past the stack buffer the text is formatted a second time at its full length.
  for (size_t length : {255, 256, 257, 1000, 100000}) {
    const std::string text(length, 'x');
    const std::string formatted = Format("<%s|%d>", text.c_str(), 7);
    ASSERT_EQ(formatted.size(), length + 4);
    EXPECT_EQ(formatted, "<" + text + "|7>");
  }
}

enum class Colour { kRed, kGreen, kBlue };
constexpr EnumName<Colour> kColourNames[] = {
    {Colour::kRed, "red"}, {Colour::kGreen, "green"}, {Colour::kBlue, "blue"}};

TEST(EnumNames, RoundTripAndUnknownNames) {
  for (const EnumName<Colour>& entry : kColourNames) {
    EXPECT_EQ(ParseEnum(kColourNames, NameOf(kColourNames, entry.value), "colour"), entry.value);
  }
  EXPECT_STREQ(NameOf(kColourNames, static_cast<Colour>(7)), "?");
  EXPECT_EQ(KnownNames(kColourNames), "red, green, blue");
  EXPECT_FALSE(LookupEnum(kColourNames, "Red").has_value());
  EXPECT_EQ(LookupEnum(kColourNames, "Red", NameCase::kIgnore).value_or(Colour::kBlue),
            Colour::kRed);
  EXPECT_FALSE(LookupEnum(kColourNames, "re", NameCase::kIgnore).has_value());
  try {
    ParseEnum(kColourNames, "mauve\x01", "colour");
    FAIL() << "mauve was accepted";
  } catch (const UsageError& error) {
    // The message names what was parsed, the text (printable) and every accepted name.
    EXPECT_STREQ(error.what(), "unknown colour 'mauve?' (known: red, green, blue)");
  }
}

TEST(EnumNames, EveryConvertedEnumRoundTrips) {
  for (AlbedoMethod method :
       {AlbedoMethod::kQuadrature, AlbedoMethod::kMonteCarlo, AlbedoMethod::kImportance}) {
    EXPECT_EQ(ParseAlbedoMethod(AlbedoMethodName(method)), method);
  }
  for (exporters::Target target : exporters::AllTargets()) {
    EXPECT_EQ(exporters::ParseTarget(exporters::TargetName(target)), target);
  }
  EXPECT_EQ(exporters::AllTargets().size(), 3u);
  for (Illuminant illuminant : {Illuminant::kD65, Illuminant::kE}) {
    EXPECT_EQ(ParseIlluminant(IlluminantName(illuminant)), illuminant);
  }
  EXPECT_STREQ(TensorDtypeName(TensorDtype::kU8), "u8");
  EXPECT_STREQ(TensorDtypeName(TensorDtype::kF64), "f64");
  EXPECT_THROW(exporters::ParseTarget("mitsuba"), UsageError);
  for (fitters::Loss loss : {fitters::Loss::kL2, fitters::Loss::kLog, fitters::Loss::kCosineL2,
                             fitters::Loss::kSqrt, fitters::Loss::kImage, fitters::Loss::kAuto}) {
    EXPECT_EQ(fitters::ParseLoss(fitters::LossName(loss)), loss);
  }
  for (fitters::Robust robust :
       {fitters::Robust::kNone, fitters::Robust::kHuber, fitters::Robust::kCauchy}) {
    EXPECT_EQ(fitters::ParseRobust(fitters::RobustName(robust)), robust);
  }
  for (ToneOperator op : {ToneOperator::kExposure, ToneOperator::kReinhard,
                          ToneOperator::kReinhardExtended, ToneOperator::kNone}) {
    EXPECT_EQ(ParseToneOperator(ToneOperatorName(op)), op);
  }
  for (BlurKind kind :
       {BlurKind::kNone, BlurKind::kBox, BlurKind::kGaussian, BlurKind::kKawase, BlurKind::kDual}) {
    EXPECT_EQ(ParseBlurKind(BlurKindName(kind)), kind);
  }
  EXPECT_EQ(ParseExrCompression("piz"), ExrCompression::kPiz);
  EXPECT_EQ(ParseExrPixelType("float"), ExrPixelType::kFloat);
  // One message shape for every enum: what, the text given, the accepted names.
  try {
    ParseExrPixelType("double");
    ADD_FAILURE() << "no error";
  } catch (const UsageError& error) {
    EXPECT_STREQ(error.what(), "unknown OpenEXR pixel type 'double' (known: half, float)");
  }
  try {
    fitters::ParseLoss("l1");
    ADD_FAILURE() << "no error";
  } catch (const UsageError& error) {
    EXPECT_STREQ(error.what(), "unknown loss 'l1' (known: l2, log, cosine-l2, sqrt, image, auto)");
  }
}

}  // namespace
}  // namespace brdf
