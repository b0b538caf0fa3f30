// The one list of reflectance models (DESIGN §2): the terms, and the compositions of them that
// have a name. The registry, the model-string parser, the fitter's dispatch, `auto`'s candidates,
// the albedo integrators and the renderer all take the models from here. A new term is one header
// (term.h says what it provides) and one entry in AllTerms; a composition that users can name is
// one entry below.
#pragma once

#include <string_view>
#include <utility>

#include "models/beckmann.h"
#include "models/blinn_phong.h"
#include "models/blinn_phong_exact.h"
#include "models/composition.h"
#include "models/eon.h"
#include "models/ggx.h"
#include "models/ggx_aniso.h"
#include "models/lambert.h"
#include "models/phong.h"
#include "models/retro.h"

namespace brdf::models {

template <typename... Types>
struct TypeList {};

// Every term, diffuse terms first.
using AllTerms = TypeList<Lambert, Eon, PhongLobe, BlinnPhongLobe, BlinnPhongExactLobe, GgxLobe,
                          BeckmannLobe, RetroLobe, GgxAnisoLobe>;

// The named models. kName is what a model string and a report call it (the shorthand of DESIGN
// §2: `ggx` = lambert+ggx), kAuto whether `--model auto` climbs it, in this order (the ladder,
// simplest first).
struct LambertModel : Composition<Lambert> {
  static constexpr const char* kName = "lambert";
  static constexpr bool kAuto = true;
};
struct Phong : Composition<Lambert, PhongLobe>, SingleLobeSlots {
  static constexpr const char* kName = "phong";
  static constexpr bool kAuto = true;
};
struct BlinnPhong : Composition<Lambert, BlinnPhongLobe>, SingleLobeSlots {
  static constexpr const char* kName = "blinn-phong";
  static constexpr bool kAuto = true;
};
// Not an `auto` candidate: it spans blinn-phong's family of lobes (the two differ by a factor of
// the exponent that rho_s absorbs, under the same energy bound), so it always reaches
// blinn-phong's cost, and a tie keeps the simpler, earlier name.
struct BlinnPhongExact : Composition<Lambert, BlinnPhongExactLobe>, SingleLobeSlots {
  static constexpr const char* kName = "blinn-phong-exact";
  static constexpr bool kAuto = false;
};
struct Ggx : Composition<Lambert, GgxLobe>, SingleLobeSlots {
  static constexpr const char* kName = "ggx";
  static constexpr bool kAuto = true;
};
struct Beckmann : Composition<Lambert, BeckmannLobe>, SingleLobeSlots {
  static constexpr const char* kName = "beckmann";
  static constexpr bool kAuto = true;
};

// Compositions beyond the ladder: named by their terms, fitted only on request.
struct LambertRetro : Composition<Lambert, RetroLobe> {
  static constexpr const char* kName = "lambert+retro";
  static constexpr bool kAuto = false;
};

struct EonModel : Composition<Eon> {
  static constexpr const char* kName = "eon";
  static constexpr bool kAuto = false;
};
struct EonGgx : Composition<Eon, GgxLobe> {
  static constexpr const char* kName = "eon+ggx";
  static constexpr bool kAuto = false;
};

// An anisotropic lobe (brushed metals): `ggx-aniso` is lambert+ggx-aniso, as `ggx` is lambert+ggx.
struct GgxAniso : Composition<Lambert, GgxAnisoLobe> {
  static constexpr const char* kName = "ggx-aniso";
  static constexpr bool kAuto = false;
};

// Two lobes: a base lobe under a clear coat (the coat's f0 grey), and a retro-reflector's
// back-scatter with the specular reflection of its cover.
struct LambertGgxGgx : Composition<Lambert, GgxLobe, GgxLobe> {
  static constexpr const char* kName = "lambert+ggx+ggx";
  static constexpr bool kAuto = true;
};
struct LambertRetroGgx : Composition<Lambert, RetroLobe, GgxLobe> {
  static constexpr const char* kName = "lambert+retro+ggx";
  static constexpr bool kAuto = false;
};

using AllModels =
    TypeList<LambertModel, Phong, BlinnPhong, BlinnPhongExact, Ggx, Beckmann, LambertRetro,
             EonModel, EonGgx, GgxAniso, LambertGgxGgx, LambertRetroGgx>;

// Calls f(M{}) for every type of the list, in order.
template <typename F, typename... Types>
void ForEachType(TypeList<Types...>, F&& f) {
  (f(Types{}), ...);
}
template <typename F>
void ForEachModel(F&& f) {
  ForEachType(AllModels{}, std::forward<F>(f));
}
template <typename F>
void ForEachTerm(F&& f) {
  ForEachType(AllTerms{}, std::forward<F>(f));
}

// Calls visitor(M{}) for the model of the list named `name` (its kName or its terms' names,
// e.g. "ggx" or "lambert+ggx"); `unknown()` when there is none (it must throw).
template <typename Visitor, typename Unknown, typename First, typename... Rest>
decltype(auto) VisitModel(TypeList<First, Rest...>, std::string_view name, Visitor&& visitor,
                          Unknown&& unknown) {
  const bool match = name == First::kName || name == First::TermNames();
  if constexpr (sizeof...(Rest) == 0) {
    if (!match) unknown();
    return visitor(First{});
  } else {
    if (match) return visitor(First{});
    return VisitModel(TypeList<Rest...>{}, name, std::forward<Visitor>(visitor),
                      std::forward<Unknown>(unknown));
  }
}

}  // namespace brdf::models
