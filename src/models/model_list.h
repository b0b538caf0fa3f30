// The one list of reflectance models, in the order of DESIGN §2 (the ladder `--model auto`
// climbs, simplest first). The registry, the model-string parser, the fitter's dispatch,
// `auto`'s candidates, the albedo integrators and the renderer all take the models from here;
// adding a model is one header and one entry below.
#pragma once

#include <string_view>
#include <utility>

#include "models/beckmann.h"
#include "models/blinn_phong.h"
#include "models/blinn_phong_exact.h"
#include "models/ggx.h"
#include "models/lambert.h"
#include "models/phong.h"

namespace brdf::models {

template <typename... Models>
struct ModelList {};

using AllModels = ModelList<Lambert, Phong, BlinnPhong, BlinnPhongExact, Ggx, Beckmann>;

// Calls f(M{}) for every model of the list, in order.
template <typename F, typename... Models>
void ForEachModel(ModelList<Models...>, F&& f) {
  (f(Models{}), ...);
}
template <typename F>
void ForEachModel(F&& f) {
  ForEachModel(AllModels{}, std::forward<F>(f));
}

// Calls visitor(M{}) for the model of the list named `name`; `unknown()` when there is none
// (it must throw).
template <typename Visitor, typename Unknown, typename First, typename... Rest>
decltype(auto) VisitModel(ModelList<First, Rest...>, std::string_view name, Visitor&& visitor,
                          Unknown&& unknown) {
  if constexpr (sizeof...(Rest) == 0) {
    if (name != First::kName) unknown();
    return visitor(First{});
  } else {
    if (name == First::kName) return visitor(First{});
    return VisitModel(ModelList<Rest...>{}, name, std::forward<Visitor>(visitor),
                      std::forward<Unknown>(unknown));
  }
}

}  // namespace brdf::models
