// The HDR pipeline of DESIGN §8 from a float image to 8-bit sRGB:
//   exposure -> bloom (bright pass, blur, add back) -> tone mapping on luminance -> transfer
//   curve -> 8 bits with rounding.
// Each stage is its own unit (exposure.h, bloom.h, blur.h, tone_map.h, transfer.h); this file
// only chains them with the user's options.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hdr/blur.h"
#include "hdr/image.h"
#include "hdr/image_files.h"
#include "hdr/tone_map.h"
#include "hdr/transfer.h"

namespace brdf {

struct ToneOptions {
  ToneOperator tone_operator = ToneOperator::kReinhardExtended;
  // Multiplier applied first; unset = automatic (log-average luminance -> `key`).
  std::optional<double> exposure;
  double key = 0.18;    // Reinhard's a, "middle grey"
  double delta = 1e-4;  // Reinhard's delta in the log-average
  double white = 0.0;   // L_white in key-scaled units; <= 0 = the scene maximum
  BlurKind bloom = BlurKind::kNone;
  double bloom_threshold = 1.0;  // luminance after exposure
  double bloom_strength = 0.1;
  double bloom_sigma = 13.0;  // px
  TransferCurve transfer;

  // Throws UsageError naming the option that is out of range.
  void Validate() const;
};

struct ToneResult {
  Image8 display;
  double exposure = 1.0;  // the multiplier used (chosen, when automatic)
  SceneLuminance scene;   // of the input, before exposure
  ToneMapping mapping;
  double bloom_sigma = 0.0;  // the blur's real sigma (dual filtering rounds to whole levels)
  // What the caller should tell the user (e.g. black pixels that moved the automatic exposure).
  std::vector<std::string> warnings;
  // e.g. "1920x1080, log-average luminance 0.0326 W/(m² sr) = 22.3 cd/m², max ..., exposure
  // 0.81, reinhard-extended L_white 42.1, bloom sigma 15.5 px". `radiometric`: the image holds
  // radiance in W/(m² sr) (a `brdf render`), so luminance is given in both units; otherwise its
  // scale is unknown (any photograph) and the numbers are said to be relative.
  std::string Summary(bool radiometric = false) const;
};

// Equal, byte for byte, to running the stages one after another on a copy of `image`; fused
// into fewer passes over it (pipeline.cpp says which).
ToneResult RunTonePipeline(const Image& image, const ToneOptions& options);

// The last stage alone: transfer curve and 8-bit rounding of RGB in [0, 1].
Image8 EncodeDisplay(const Image& image, const TransferCurve& transfer);

}  // namespace brdf
