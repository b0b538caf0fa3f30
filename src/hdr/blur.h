// Blurs of the bloom stage (DESIGN §8), each defined by the standard deviation sigma (in
// pixels of the input) of its impulse response, so that filters can be compared at equal
// sigma. Borders repeat the edge pixel. All four channels are filtered.
//
//   box      three passes of the extended box filter of Gwosdek, Grewenig, Bruhn & Weickert,
//            "Theoretical foundations of Gaussian convolution by extended box filtering"
//            (SSVM 2011): a box of 2r+1 taps plus fractional end taps alpha, so that the
//            variance is exactly sigma^2 / passes per pass, not only for special widths.
//   gauss    separable sampled Gaussian, truncated at 4 sigma and renormalised.
//   kawase   Kawase, "Frame buffer postprocessing effects in DOUBLE-S.T.E.A.L (Wreckless)",
//            GDC 2003: passes of four bilinear taps at (+-(o), +-(o)) pixels. With o = i + 1/2
//            each tap averages a 2x2 block, so a pass adds o^2 + f(1-f) (f = frac(o) = 1/2)
//            to the variance per axis: offsets {0,1,2,2,3} (o = i + 1/2) sum to 28.5 px^2,
//            sigma 5.34 px. Runs at full resolution; a fractional last offset hits any sigma.
//   dual     dual filtering, Bjørge, "Bandwidth-efficient rendering", SIGGRAPH 2015: L
//            half-resolution steps (centre 2x2 average weight 1/2 and four diagonal bilinear
//            taps at +-1 source pixel, 1/8 each), then L doubling steps (taps at (+-1, 0),
//            (0, +-1) weight 1/12 and (+-1/2, +-1/2) weight 2/12, in source pixels). Per axis
//            the step down adds 3/4 and the step up 1/3 + 3/16 (taps plus the bilinear
//            interpolation at phase 1/4) source px^2, so level k contributes 17/6 * 4^k px^2
//            and sigma^2 = 17/18 (4^L - 1): 1.68 px (0.84 * 2) at L = 1, tending to 0.97 * 2^L.
//            Only whole levels exist, so the requested sigma is rounded to the nearest level
//            (in log scale).
#pragma once

#include <string>
#include <vector>

#include "hdr/image.h"

namespace brdf {

enum class BlurKind { kNone, kBox, kGaussian, kKawase, kDual };
// "none", "box", "gauss", "kawase", "dual"; throws UsageError otherwise.
BlurKind ParseBlurKind(const std::string& name);
const char* BlurKindName(BlurKind kind);

Image BoxBlur(const Image& image, double sigma, int passes = 3);
Image GaussianBlur(const Image& image, double sigma);

// Kawase passes with the given offsets o_k = i_k + 1/2 given as i_k (the usual notation), or
// any non-negative real i_k.
Image KawaseBlur(const Image& image, const std::vector<double>& offsets);
// Designed sigma of a pass sequence: sqrt(sum (i+1/2)^2 + f(1-f)), f = frac(i + 1/2).
double KawaseSigma(const std::vector<double>& offsets);
// Offsets 0, 1, 2, ... while the variance fits, then one fractional offset for the rest.
std::vector<double> KawaseOffsetsForSigma(double sigma);

Image DualFilterBlur(const Image& image, int levels);
// The dual filter in pieces, for a pipeline that fuses its first and last steps into passes of
// its own (pipeline.cpp); DualFilterBlur(image, L) is the first step (DualFilterDown, or its
// rows), then DualFilterFromHalf(., L), then the last doubling step (DualFilterUpRow per row).
Image DualFilterDown(const Image& source);
// Row y of the half-resolution step: rows[k] is source row 2y - 1 + k clamped to the image.
// Writes (source_width + 1) / 2 RGBA pixels.
void DualFilterDownRow(const float* const rows[4], int source_width, int source_height, int y,
                       float* out);
// The pixels [begin, end) of that row alone (each pixel's arithmetic is the same).
void DualFilterDownRow(const float* const rows[4], int source_width, int source_height, int y,
                       int begin, int end, float* out);
// From the half-resolution image: L - 1 more steps down and back up to the half resolution.
Image DualFilterFromHalf(Image half, int levels);
// Row y of the doubling step from `source` to a `width`-pixel-wide row: `width` RGBA pixels.
void DualFilterUpRow(const Image& source, int width, int y, float* out);
double DualFilterSigma(int levels);
int DualFilterLevelsForSigma(double sigma);

// The blur of `kind` designed for `sigma`; kNone returns the image unchanged.
Image Blur(const Image& image, BlurKind kind, double sigma);
// The sigma `Blur(kind, sigma)` really has (equal to `sigma` except for dual's whole levels).
double DesignedSigma(BlurKind kind, double sigma);

}  // namespace brdf
