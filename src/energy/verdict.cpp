#include "energy/verdict.h"

#include "core/enum_names.h"

namespace brdf {
namespace {

constexpr EnumName<Conservation> kConservationNames[] = {
    {Conservation::kConserving, "conserving"},
    {Conservation::kNotConserving, "not conserving"},
    {Conservation::kUndecided, "undecided"},
};

}  // namespace

const char* ConservationName(Conservation conservation) {
  return NameOf(kConservationNames, conservation);
}

}  // namespace brdf
