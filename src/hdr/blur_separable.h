// Separable convolution with a short 1D kernel, shared by the Gaussian and Kawase blurs.
#pragma once

#include <vector>

#include "hdr/image.h"

namespace brdf {

// Weights for the integer offsets first_offset, first_offset + 1, ...
struct Kernel1D {
  int first_offset = 0;
  std::vector<float> weights;
  // Adds `weight` at the continuous offset `position`, split linearly between the two nearest
  // integer offsets, as a bilinear texture fetch does.
  void AddBilinearTap(double position, double weight);
};

// Convolves rows, then columns, with `kernel`; edges repeat the border pixel.
Image ConvolveSeparable(const Image& image, const Kernel1D& kernel);

}  // namespace brdf
