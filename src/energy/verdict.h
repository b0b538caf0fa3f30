// The answer of the energy-conservation check (DESIGN §7): a material conserves energy when its
// directional albedo is at most 1 at every incidence (DESIGN §1). A check that cannot tell says
// so: the verdict has three values, and each comes with the sentence, numbers included, that it
// rests on.
#pragma once

#include <string>

namespace brdf {

enum class Conservation {
  kConserving,     // the largest albedo, with twice its error estimate, stays at or below 1
  kNotConserving,  // an albedo exceeds 1 by more than twice its error estimate
  // The error estimate straddles 1, or the largest albedo lies where the data do not reach
  // (beyond the measured incidences, or in coverage holes): the data cannot decide.
  kUndecided,
};
// "conserving", "not conserving" or "undecided": the words of the JSON reports.
const char* ConservationName(Conservation conservation);

struct EnergyVerdict {
  Conservation conservation = Conservation::kUndecided;
  std::string reason;  // one sentence with the numbers it rests on

  const char* name() const { return ConservationName(conservation); }
  // "undecided: <reason>", for people.
  std::string Text() const { return std::string(name()) + ": " + reason; }
};

}  // namespace brdf
