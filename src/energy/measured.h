// Measured data as an albedo integrand, through interpolation:
//  - dense tables through the reader's evaluator (Measurement::tabulated: a MERL table's
//    nearest-cell lookup, where missing cells are holes; an RGL tensor's inverse warp);
//  - scattered samples (Cornell ASTM / pbrt-v2, Zemax, native CSV) by inverse-distance
//    weighting of the nearest samples in a space that uses the symmetries every isotropic BRDF
//    has (see ScatteredInterpolator below), with a coverage radius beyond which a value is
//    extrapolated and counted as a hole.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/measurement.h"
#include "energy/integrand.h"
#include "io/merl.h"

namespace brdf {

struct MeasuredBrdf {
  std::string source;  // the path, for reports
  BrdfFunction brdf;
  LobeCoordinates coordinates;  // where the quadrature integrates (half-vector space)
  // What the interpolation assumes and where the data end, for the report.
  std::vector<std::string> notes;
  // The largest incidence a present sample was measured at (counting the reciprocal of each
  // sample where the interpolation assumes reciprocity): the albedo beyond it is extrapolated.
  double largest_incidence_deg = 90.0;
};

MeasuredBrdf TabulatedMeasuredBrdf(std::shared_ptr<const TabulatedBrdf> tabulated,
                                   const std::string& source);
MeasuredBrdf MerlMeasuredBrdf(std::shared_ptr<const MerlTable> table, const std::string& source);

// Scattered, isotropic data. Throws InputError naming the source when no sample is usable.
MeasuredBrdf ScatteredMeasuredBrdf(const Measurement& measurement);

// The reader's evaluator when the measurement has one, else scattered interpolation.
MeasuredBrdf MeasuredBrdfOf(const Measurement& measurement);
// Reads a measurement file and wraps it as MeasuredBrdfOf does.
MeasuredBrdf LoadMeasuredBrdf(const std::string& path);

}  // namespace brdf
