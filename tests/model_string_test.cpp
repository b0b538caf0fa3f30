// Model strings on the command line (DESIGN §2): NAME[:key=value]..., RGB values as three
// numbers or one for grey, defaults for what is not named, an exact round trip through
// Model::ToString(), and errors that name the offending part.
#include "models/model_string.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "models/registry.h"

namespace brdf {
namespace {

// The slots of a one-lobe model (rho_d, rho_s, exponent).
using LobedSlots = models::Phong;

// Expects ParseModel(text) to throw UsageError whose message contains every one of `parts`.
void ExpectUsageError(const std::string& text, const std::vector<std::string>& parts) {
  try {
    const Model model = ParseModel(text);
    ADD_FAILURE() << "'" << text << "' parsed as " << model.ToString();
  } catch (const UsageError& error) {
    const std::string message = error.what();
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "'" << text << "': message \"" << message << "\" does not mention \"" << part << "\"";
    }
  }
}

TEST(ModelString, ParsesTheDesignExample) {
  const Model model = ParseModel("blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200");
  EXPECT_EQ(model.name(), "blinn-phong");
  EXPECT_EQ(&model.info(), &FindModel("blinn-phong"));
  std::vector<double> expected(LobedSlots::kNumParams);
  expected[LobedSlots::kRhoD + 0] = 0.5;
  expected[LobedSlots::kRhoD + 1] = 0.1;
  expected[LobedSlots::kRhoD + 2] = 0.1;
  expected[LobedSlots::kRhoS + 0] = 0.04;  // grey: one number fills all three channels
  expected[LobedSlots::kRhoS + 1] = 0.04;
  expected[LobedSlots::kRhoS + 2] = 0.04;
  expected[LobedSlots::kExponent] = 200.0;
  EXPECT_EQ(model.params(), expected);
  EXPECT_EQ(model.Param("rho_d", 0), 0.5);
  EXPECT_EQ(model.Param("rho_d", 2), 0.1);
  EXPECT_EQ(model.Param("m"), 200.0);
  EXPECT_THROW(model.Param("n"), UsageError);         // phong's name for the exponent
  EXPECT_THROW(model.Param("rho_d", 3), UsageError);  // RGB has channels 0..2
  EXPECT_THROW(model.Param("m", 1), UsageError);      // a scalar has channel 0 only
  // It prints back in the same form (grey rho_s as one number).
  EXPECT_EQ(model.ToString(), "blinn-phong:rho_d=0.5,0.1,0.1:rho_s=0.04:m=200");
}

TEST(ModelString, GreyShorthandFillsEveryChannel) {
  const Model model = ParseModel("lambert:rho_d=0.25");
  EXPECT_EQ(model.params(), (std::vector<double>{0.25, 0.25, 0.25}));
  EXPECT_EQ(ParseModel("lambert:rho_d=0.25,0.25,0.25").params(), model.params());
  EXPECT_EQ(model.ToString(), "lambert:rho_d=0.25");
}

TEST(ModelString, RoundedFormIsForPeople) {
  const Model model = ParseModel("phong:rho_d=0.123456789,0.5,1e-7:rho_s=0.04:n=123456.7");
  EXPECT_EQ(model.ToString(4), "phong:rho_d=0.1235,0.5,1e-07:rho_s=0.04:n=1.235e+05");
  EXPECT_EQ(ParseModel(model.ToString()).params(), model.params());  // the default round-trips
}

TEST(ModelString, OmittedKeysTakeTheRegistryDefaults) {
  for (const ModelInfo& info : ModelRegistry()) {
    EXPECT_EQ(ParseModel(info.name).params(), info.DefaultParams()) << info.name;
  }
  // Documented defaults (phong.h, blinn_phong.h): rho_d 0.5, rho_s 0.04, exponent 100.
  EXPECT_EQ(ParseModel("phong").params(),
            (std::vector<double>{0.5, 0.5, 0.5, 0.04, 0.04, 0.04, 100.0}));
  const Model partial = ParseModel("blinn-phong-exact:m=20");
  EXPECT_EQ(partial.params(), (std::vector<double>{0.5, 0.5, 0.5, 0.04, 0.04, 0.04, 20.0}));
  // Keys may come in any order.
  EXPECT_EQ(ParseModel("phong:n=7:rho_d=0.1").params(), ParseModel("phong:rho_d=0.1:n=7").params());
}

// Model::ToString promises that ParseModel reads back the same doubles, bit for bit: a fit
// report's parameters must survive being pasted onto a command line.
TEST(ModelString, ToStringRoundTripIsExact) {
  const double awkward[] = {0.1,
                            1e-7,
                            1.0 / 3.0,
                            0.1 + 0.2,
                            2.0 / 3.0 * 1e-300,
                            std::numeric_limits<double>::denorm_min(),
                            123456.789012345678,
                            0.0};
  for (double value : awkward) {
    const Model model(FindModel("phong"), {value, 0.5, value, value, value, value, 1e6});
    const Model parsed = ParseModel(model.ToString());
    EXPECT_EQ(parsed.params(), model.params()) << model.ToString();
  }
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> albedo(0.0, 1.5);
  std::uniform_real_distribution<double> log_exponent(-3.0, 6.0);
  for (const ModelInfo& info : ModelRegistry()) {
    for (int trial = 0; trial < 200; ++trial) {
      // Each parameter within its own table's range: albedos up to 1.5, exponents log-uniform
      // over 1e-3 ... 1e6, bounded parameters (f0, alpha) uniform over their range.
      std::vector<double> params(info.num_params);
      for (const ParamInfo& param : info.params) {
        for (int c = 0; c < param.channels; ++c) {
          double& p = params[param.slot + c];
          if (std::isinf(param.upper)) {
            p = albedo(rng);
          } else if (param.upper >= 1e6) {
            p = std::pow(10.0, log_exponent(rng));
          } else {
            p = std::uniform_real_distribution<double>(param.lower, param.upper)(rng);
          }
        }
      }
      const Model model(info, params);
      const std::string text = model.ToString();
      const Model parsed = ParseModel(text);
      EXPECT_EQ(parsed.name(), info.name);
      EXPECT_EQ(parsed.params(), params) << text;
      EXPECT_EQ(parsed.ToString(), text);
    }
  }
}

TEST(ModelString, UnknownModelListsTheKnownModels) {
  ExpectUsageError("blinn:m=10", {"blinn", "lambert", "phong", "blinn-phong", "blinn-phong-exact"});
  ExpectUsageError("", {"lambert"});
}

TEST(ModelString, UnknownKeyListsTheValidKeys) {
  ExpectUsageError("phong:m=10", {"'m'", "rho_d", "rho_s", "n"});
  ExpectUsageError("blinn-phong:n=10", {"'n'", "rho_d", "rho_s", "m"});
  ExpectUsageError("lambert:rho_s=0.1", {"'rho_s'", "rho_d"});
  ExpectUsageError("phong:=0.1", {"phong"});
}

TEST(ModelString, MissingEqualsNamesThePart) {
  ExpectUsageError("phong:rho_d", {"rho_d", "key=value"});
  ExpectUsageError("phong:rho_d=0.1:", {"key=value"});  // trailing ':' is an empty part
  ExpectUsageError("phong::n=3", {"key=value"});
}

TEST(ModelString, NonNumberNamesTheValue) {
  ExpectUsageError("phong:n=abc", {"n", "'abc'"});
  ExpectUsageError("phong:n=5x", {"n", "'5x'"});
  ExpectUsageError("phong:n=", {"n", "''"});
  ExpectUsageError("phong:rho_d=0.1,,0.3", {"rho_d", "''"});
  ExpectUsageError("phong:rho_d=0.1,0.2,abc", {"rho_d", "'abc'"});
}

TEST(ModelString, WrongNumberOfValuesNamesTheCount) {
  ExpectUsageError("phong:rho_d=0.1,0.2", {"rho_d", "2"});
  ExpectUsageError("phong:rho_s=0.1,0.2,0.3,0.4", {"rho_s", "4"});
  ExpectUsageError("phong:n=1,2,3", {"n", "3"});  // a scalar takes exactly one
}

TEST(ModelString, OutOfRangeValuesNameTheParameter) {
  ExpectUsageError("phong:rho_s=-0.1", {"rho_s", "-0.1"});
  ExpectUsageError("lambert:rho_d=0.5,-0.01,0.5", {"rho_d", "-0.01"});
  ExpectUsageError("blinn-phong:m=-1", {"m", "-1"});
  ExpectUsageError("blinn-phong:m=2e6", {"m"});
}

TEST(ModelString, NonFiniteValuesAreRejected) {
  ExpectUsageError("phong:n=nan", {"n", "nan"});
  ExpectUsageError("phong:rho_d=NaN", {"rho_d", "NaN"});
  ExpectUsageError("phong:rho_s=inf", {"rho_s", "inf"});
  ExpectUsageError("lambert:rho_d=0.1,nan,0.1", {"rho_d", "nan"});
}

TEST(ModelString, KeyGivenTwiceIsAnError) {
  ExpectUsageError("phong:n=5:n=6", {"'n'", "twice"});
  ExpectUsageError("phong:rho_d=0.1:rho_s=0.1:rho_d=0.2", {"'rho_d'", "twice"});
}

TEST(ModelString, ErrorMessageQuotesTheWholeString) {
  ExpectUsageError("phong:rho_d=0.1:n=oops", {"phong:rho_d=0.1:n=oops"});
}

// A fitted albedo driven to its bound arrives at ~1e-17, not 0: the text for people reads 0,
// the round-trip text keeps every digit, and a value near but off the bound is left alone.
TEST(ModelString, ValuesAtTheirBoundReadAsTheBoundForPeople) {
  const Model model = ParseModel("phong:rho_d=4.18e-18,0.082,1e-7:rho_s=0.0171:n=6122");
  EXPECT_EQ(model.ToString(4), "phong:rho_d=0,0.082,1e-07:rho_s=0.0171:n=6122");
  EXPECT_EQ(ParseModel(model.ToString()).params(), model.params());
  const ParamInfo& rho_d = *model.info().FindParam("rho_d");
  EXPECT_TRUE(rho_d.AtBound(4.18e-18));
  EXPECT_TRUE(rho_d.AtBound(0.0));
  EXPECT_FALSE(rho_d.AtBound(1e-7));
  EXPECT_EQ(rho_d.Displayed(-1e-12), 0.0);
}

}  // namespace
}  // namespace brdf

namespace brdf {
namespace {

TEST(ModelString, ChannelsEqualToTheDigitsShownAreOneGreyValue) {
  // A monochrome file fitted per channel: the three channels differ in the last bit only.
  const Model model =
      ParseModel("lambert:rho_d=0.2699260473095003,0.2699260473095004,0.2699260473095003");
  EXPECT_EQ(model.ToString(7), "lambert:rho_d=0.269926");
  // The full form keeps every bit, so channels that differ are written out.
  EXPECT_EQ(ParseModel(model.ToString()).params(), model.params());
  EXPECT_NE(model.ToString().find(','), std::string::npos);
  // Channels that differ at the digits shown stay three numbers.
  EXPECT_EQ(ParseModel("lambert:rho_d=0.3,0.1,0.1").ToString(7), "lambert:rho_d=0.3,0.1,0.1");
}

TEST(ModelString, PrintedStringReproducesTheFitToTheDigitsShown) {
  // A MERL round trip's fit: rho_d 0.1 by way of 0.09999999999999998, and a bound value.
  const Model fit = ParseModel(
      "ggx:rho_d=0.3,0.09999999999999998,0.1234567890123:f0=2.9748775049246083e-18,0.0220544715,"
      "0.11169612:alpha=0.16768361234");
  const std::string printed = fit.ToString(7);
  EXPECT_EQ(printed, "ggx:rho_d=0.3,0.1,0.1234568:f0=0,0.02205447,0.1116961:alpha=0.1676836");
  const Model reread = ParseModel(printed);
  for (size_t k = 0; k < fit.params().size(); ++k) {
    EXPECT_NEAR(reread.params()[k], fit.params()[k], 5e-7 * std::max(1e-3, fit.params()[k])) << k;
  }
  // The BRDF itself agrees to about the digits shown, in and out of the highlight.
  const Vec3 wi = SphericalDirection(0.35, 0.2);
  for (const Vec3& wo : {SphericalDirection(0.35, 0.2 + kPi), SphericalDirection(0.9, 2.0)}) {
    const Rgb a = fit.Eval(wi, wo);
    const Rgb b = reread.Eval(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], a[c], 2e-6 * a[c]) << c;
  }
}

}  // namespace
}  // namespace brdf
