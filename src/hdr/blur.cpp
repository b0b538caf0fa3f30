// Blur names and the dispatch by kind; the filters live in blur_*.cpp.
#include "hdr/blur.h"

#include "core/errors.h"

namespace brdf {

BlurKind ParseBlurKind(const std::string& name) {
  for (BlurKind kind :
       {BlurKind::kNone, BlurKind::kBox, BlurKind::kGaussian, BlurKind::kKawase, BlurKind::kDual}) {
    if (name == BlurKindName(kind)) return kind;
  }
  throw UsageError("unknown blur '" + name + "', expected none, box, gauss, kawase or dual");
}

const char* BlurKindName(BlurKind kind) {
  switch (kind) {
    case BlurKind::kNone:
      return "none";
    case BlurKind::kBox:
      return "box";
    case BlurKind::kGaussian:
      return "gauss";
    case BlurKind::kKawase:
      return "kawase";
    case BlurKind::kDual:
      return "dual";
  }
  return "none";
}

Image Blur(const Image& image, BlurKind kind, double sigma) {
  switch (kind) {
    case BlurKind::kNone:
      return image;
    case BlurKind::kBox:
      return BoxBlur(image, sigma);
    case BlurKind::kGaussian:
      return GaussianBlur(image, sigma);
    case BlurKind::kKawase:
      return KawaseBlur(image, KawaseOffsetsForSigma(sigma));
    case BlurKind::kDual:
      return DualFilterBlur(image, DualFilterLevelsForSigma(sigma));
  }
  return image;
}

double DesignedSigma(BlurKind kind, double sigma) {
  if (kind == BlurKind::kDual) return DualFilterSigma(DualFilterLevelsForSigma(sigma));
  if (kind == BlurKind::kNone) return 0.0;
  return sigma;
}

}  // namespace brdf
