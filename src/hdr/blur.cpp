// Blur names and the dispatch by kind; the filters live in blur_*.cpp.
#include "hdr/blur.h"

#include "core/enum_names.h"
#include "core/errors.h"

namespace brdf {

constexpr EnumName<BlurKind> kBlurNames[] = {
    {BlurKind::kNone, "none"},     {BlurKind::kBox, "box"},   {BlurKind::kGaussian, "gauss"},
    {BlurKind::kKawase, "kawase"}, {BlurKind::kDual, "dual"},
};

BlurKind ParseBlurKind(const std::string& name) { return ParseEnum(kBlurNames, name, "blur"); }

const char* BlurKindName(BlurKind kind) { return NameOf(kBlurNames, kind); }

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
