#include "energy/integrand.h"

#include <algorithm>

namespace brdf {

AlbedoEstimate& AlbedoEstimate::operator+=(const AlbedoEstimate& other) {
  albedo += other.albedo;
  error += other.error;  // estimates of bounds: they add
  coverage = std::min(coverage, other.coverage);
  evaluations += other.evaluations;
  return *this;
}

}  // namespace brdf
