// Measured data as an albedo integrand, through interpolation:
//  - a MERL table by its own cell lookup (nearest cell; missing cells are holes);
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
};

MeasuredBrdf MerlMeasuredBrdf(std::shared_ptr<const MerlTable> table, const std::string& source);

// Scattered, isotropic data. Throws InputError naming the source when no sample is usable.
MeasuredBrdf ScatteredMeasuredBrdf(const Measurement& measurement);

// Reads a measurement file (MERL straight into its table, every other format through
// ReadMeasurement) and wraps it as above.
MeasuredBrdf LoadMeasuredBrdf(const std::string& path);

}  // namespace brdf
