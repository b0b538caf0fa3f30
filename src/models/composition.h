// A reflectance model as a composition (DESIGN §2): one diffuse term plus zero, one or two lobes,
// f = the sum of the terms' f. The terms (term.h) are types, so a composition is a type too and
// everything a fit or a render does with it is compiled per term, not switched on at run time:
//   Composition<Lambert, GgxLobe>            lambert+ggx, the model `ggx`
//   Composition<Lambert, GgxLobe, GgxLobe>   lambert+ggx+ggx, a base lobe under a clear coat
// The parameters are the terms' in order (the diffuse term's first, at slot 0); a lobe's
// parameter whose name an earlier term already uses takes the lobe's position, e.g. f0_2.
#pragma once

#include <array>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "models/term.h"

namespace brdf::models {

template <typename Diffuse, typename... Lobes>
struct Composition {
  static_assert(Diffuse::kDiffuse, "a composition starts with a diffuse term");
  static_assert((!Lobes::kDiffuse && ...), "only the first term is diffuse");
  static_assert(sizeof...(Lobes) <= 2, "at most two lobes");

  using DiffuseTerm = Diffuse;
  // What each term's ValueAndGradient shares at one point of the parameters (term.h).
  using Prepared = std::tuple<typename Diffuse::Prepared, typename Lobes::Prepared...>;
  // What each term's ValueAndGradient takes of a sample's directions (term.h).
  using Geometry = std::tuple<typename Diffuse::Geometry, typename Lobes::Geometry...>;
  static constexpr int kRhoD = 0;  // the diffuse term's albedo, every model's first parameter
  static constexpr int kLobes = sizeof...(Lobes);
  static constexpr int kTerms = 1 + kLobes;
  static constexpr int kNumParams = Diffuse::kNumParams + (0 + ... + Lobes::kNumParams);
  // Entries of a channel's d f / d params: one per row of the parameter table.
  static constexpr int kGradientSize = Diffuse::kGradientSize + (0 + ... + Lobes::kGradientSize);
  // The first slot of each term, the diffuse term's (0) first.
  static constexpr std::array<int, kTerms> kOffsets = [] {
    std::array<int, kTerms> offsets{};
    const int sizes[kTerms] = {Diffuse::kNumParams, Lobes::kNumParams...};
    for (int k = 1; k < kTerms; ++k) offsets[k] = offsets[k - 1] + sizes[k - 1];
    return offsets;
  }();

  // Term number `index` (0 the diffuse term, 1 and 2 the lobes) as a type.
  template <int Index>
  using Term = std::tuple_element_t<Index, std::tuple<Diffuse, Lobes...>>;

  // Calls f(Term{}, index) for every term in order (the diffuse term is index 0).
  template <typename F>
  static void ForEachTerm(F&& f) {
    f(Diffuse{}, std::integral_constant<int, 0>{});
    ForEachLobe([&](auto lobe, auto index) { f(lobe, index); });
  }
  // The same for the lobes alone (index 1, 2).
  template <typename F>
  static void ForEachLobe(F&& f) {
    ForEachLobeFrom<1, Lobes...>(f);
  }

  template <typename T, typename D>
  static RgbT<T> Eval(const T* params, const Vec3T<D>& wi, const Vec3T<D>& wo) {
    if (!AboveHorizon(wi, wo)) return RgbT<T>::Constant(T(0));
    RgbT<T> f = Diffuse::Colour(params, Diffuse::template Angular<T, D>(params, wi, wo));
    ForEachLobe([&](auto lobe, auto index) {
      using Lobe = decltype(lobe);
      const T* p = params + kOffsets[index];
      f = f + Lobe::Colour(p, Lobe::template Angular<T, D>(p, wi, wo));
    });
    return f;
  }

  // The parameter table, slots and names as a model string writes them.
  static std::vector<ParamInfo> Params() {
    std::vector<ParamInfo> table;
    ForEachTerm([&](auto term, auto index) {
      for (ParamInfo param : decltype(term)::Params()) {
        param.slot += kOffsets[index];
        for (const ParamInfo& earlier : table) {
          if (earlier.name == param.name) {
            param.name += "_" + std::to_string(static_cast<int>(index));
            break;
          }
        }
        table.push_back(std::move(param));
      }
    });
    return table;
  }
  // "lambert+ggx+ggx"
  static std::string TermNames() {
    std::string names = Diffuse::kName;
    ForEachLobe([&](auto lobe, auto) { names += std::string("+") + decltype(lobe)::kName; });
    return names;
  }
  // "rho_d/pi + rho_s (n+2)/(2pi) cos^n(alpha)"
  static std::string Formula() {
    std::string formula = Diffuse::kFormula;
    ForEachLobe([&](auto lobe, auto) { formula += std::string(" + ") + decltype(lobe)::kFormula; });
    return formula;
  }
  // How the energy bound is formed: "rho_d + A(e) rho_s"
  static std::string BoundFormula() {
    std::string formula = Diffuse::kBoundFormula;
    ForEachLobe(
        [&](auto lobe, auto) { formula += std::string(" + ") + decltype(lobe)::kBoundFormula; });
    return formula;
  }

 private:
  template <int Index, typename First, typename... Rest, typename F>
  static void ForEachLobeFrom(F& f) {
    f(First{}, std::integral_constant<int, Index>{});
    if constexpr (sizeof...(Rest) > 0) ForEachLobeFrom<Index + 1, Rest...>(f);
  }
  template <int Index, typename F>
  static void ForEachLobeFrom(F&) {}
};

}  // namespace brdf::models
