// The `brdf energy --plot` chart: directional albedo against theta per channel, with the line
// a = 1 that a conserving material stays under. Drawn with OpenCV so the binary needs no Python.
#pragma once

#include <string>

#include "energy/albedo.h"

namespace brdf::cli {

// Writes the chart as a PNG, atomically (encoded in memory, then WriteFileAtomically).
// Throws OutputError when the image cannot be encoded or written.
void WriteAlbedoPlot(const AlbedoCurve& curve, const std::string& path);

}  // namespace brdf::cli
