// What the preview renders: a reflectance model (a model string or a fit report, through
// LoadModel) or a measurement file through interpolation (DESIGN §8).
//
// Measured data:
//   * Dense tables go through the reader's evaluator for previews (TabulatedBrdf::
//     PreviewEvaluator, else Measurement::tabulated): MERL trilinear in its own grid with
//     missing cells filled from the nearest valid one (io/merl_preview.h), RGL-EPFL through the
//     inverse VNDF warp with f cos(theta_o) interpolated between the nodes (io/rgl_bsdf.h). Under
//     an environment they are importance-sampled by a sampler built from those values
//     (render/table_sampler.h): they have no lobe formula.
//   * Scattered measurements (Cornell, Zemax, native CSV) use the same inverse-distance
//     interpolant as `brdf energy` (energy/measured.h), tabulated once at the cell centres of
//     the isotropic half/difference space (theta_h, theta_d in [0, pi/2], phi_d folded into
//     [0, pi) by reciprocity) cut into 32 x 32 x 32 cells; a lookup is then a trilinear blend
//     of eight cell values. A lobe narrower than a cell (2.8 deg in theta_h) is smeared.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/float_math.h"
#include "core/measurement.h"
#include "core/vec.h"
#include "energy/integrand.h"
#include "models/registry.h"

namespace brdf {

// Directions wi drawn for a view wo, and their density, a batch at a time (local frame, float,
// for the renderer's hot loop): the importance sampler of data without a lobe formula.
class DirectionSampler {
 public:
  virtual ~DirectionSampler() = default;
  // wi from uniforms (u0, u1) in [0, 1)^2, one per k < count; a wi below the horizon carries
  // no weight.
  virtual void SampleBatch(const Vec3f& wo, const float* u0, const float* u1, int count, float* x,
                           float* y, float* z) const = 0;
  // The density of each wi in solid angle (sr^-1), exact for what SampleBatch draws.
  virtual void PdfBatch(const Vec3f& wo, const float* x, const float* y, const float* z, int count,
                        float* pdf) const = 0;
};

class Material {
 public:
  virtual ~Material() = default;
  // f(wi, wo) in sr^-1 in the local shading frame (DESIGN §1); NaN where the data has no value.
  virtual Rgb Eval(const Vec3& wi, const Vec3& wo) const = 0;
  // The same in single precision, for the renderer's hot loop (render/sphere.cpp): models
  // evaluate their templated formula in float unless the lobe is too sharp for it (see
  // material.cpp), the tabulated interpolant looks up a float table; the default converts to
  // Eval.
  virtual RgbF EvalFloat(const Vec3f& wi, const Vec3f& wo) const {
    return Eval(wi.cast<double>(), wo.cast<double>()).cast<float>();
  }
  // EvalFloat at `count` directions wi (one array per coordinate) for one wo, into
  // f[0, count): the renderer shades a batch of samples at a time. The default calls
  // EvalFloat for each; the tabulated interpolant locates the whole batch in a loop that
  // vectorizes.
  virtual void EvalFloatBatch(const float* wi_x, const float* wi_y, const float* wi_z,
                              const Vec3f& wo, int count, RgbF* f) const;
  // What it is, for the summary line: a model string or "FILE (format, interpolation)".
  virtual std::string Describe() const = 0;
  // The specular lobe the renderer draws directions from, besides the environment and the
  // cosine (a lobe far narrower than either would otherwise be found only by chance: one
  // bright pixel in thousands). Models give their own lobe; scattered measurements one read
  // off their table; MERL tables and lobe-free models none.
  virtual std::optional<LobeCoordinates> SpecularLobe() const { return std::nullopt; }
  // A sampler built from the material's own values, for dense tables that have no lobe
  // formula: the renderer asks for it once per render under an environment and draws from it
  // instead of a lobe. None for models and scattered data (they have SpecularLobe).
  virtual std::unique_ptr<DirectionSampler> MakeSampler() const { return nullptr; }
};

// A model string or FIT.json (LoadModel), else a measurement file. Throws UsageError /
// InputError naming the argument.
std::unique_ptr<Material> LoadMaterial(const std::string& spec);
// The same for a model and for a measurement in memory (the reader's evaluator when it has
// one, else the tabulated inverse-distance interpolant). Throws InputError naming the source
// when no sample is usable.
std::unique_ptr<Material> ModelMaterialOf(Model model);
std::unique_ptr<Material> MeasurementMaterialOf(const Measurement& measurement);

}  // namespace brdf
