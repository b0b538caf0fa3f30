// BRDF slice image (DESIGN §4): the 2D slice of an isotropic BRDF that Burley's BRDF Explorer
// shows and that ALTA's `data_brdf_slice` plugin (belcour/alta, sources/plugins/) writes as an
// OpenEXR image: one R, G, B pixel per cell of a square grid, no header of its own. The EXR
// says nothing about its parameterization, so this reader assumes one and states it in the
// metadata:
// - columns i = 0..N-1 are theta_h = (i + 0.5)/N * 90 deg, and rows from the BOTTOM of the
//   image are theta_d = (N - 1 - y + 0.5)/N * 90 deg (y = 0 is the top scan line), at
//   phi_d = 90 deg and phi_h = 0 (Rusinkiewicz 1998 angles): ALTA's RUSIN_TH_TD slice, the
//   plugin's first default. Then wi = (sin th cos td, sin td, cos th cos td) and wo = (sin th
//   cos td, -sin td, cos th cos td): every cell lies above the horizon.
// - values are the BRDF in sr^-1, RGB, as ALTA stores what it reads from a MERL table.
// The shared red-fabric slice (ALTA's documents/data/data-example-01.exr, described as its
// later STARK_2D default) was checked against this: read so, it agrees with the published NBRDF
// network of MERL red-fabric (Sztrajman et al. 2021) to a median ratio of 0.99, 0.98, 0.97
// (r, g, b; rms log ratio 0.31 over 6000 random cells), while a STARK_2D reading (columns the
// projected half vector, rows |B|, as in ALTA's params.cpp) misses by an rms log ratio of 1.2
// (docs/formats.md). Cells that are negative (MERL's mark of a missing sample) or not finite
// are flagged missing.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/errors.h"
#include "core/text.h"
#include "io/formats.h"

namespace brdf {
namespace {

constexpr char kExrMagic[] = {0x76, 0x2f, 0x31, 0x01};
// ALTA writes 512 x 512; a grid this fine is already 1,048,576 samples (about 80 MB in memory).
constexpr int kMaxCells = 1024;
// No lossless OpenEXR codec packs more than about 1000:1 (deflate's limit is 1032:1): a header
// that promises more pixels than that is refused before anything is allocated.
constexpr double kMaxCompressionRatio = 4096.0;

// OpenEXR's messages may span lines and quote the file's bytes: one printable line (DESIGN §3).
std::string OneLine(const std::string& message) {
  std::string line = PrintableText(message);
  std::replace(line.begin(), line.end(), '\n', ' ');
  return line;
}

}  // namespace

// A slice is a square image: the header's dataWindow (box2i: x_min, y_min, x_max, y_max, little-
// endian int32) says so before any pixel is read. The header's attributes follow the 8-byte magic
// and version as name\0 type\0 int32 size, then the value, up to an empty name.
bool SniffAltaSlice(std::string_view head, int64_t) {
  if (head.size() < 8 || !std::equal(std::begin(kExrMagic), std::end(kExrMagic), head.begin())) {
    return false;
  }
  size_t at = 8;
  while (at < head.size() && head[at] != '\0') {
    const size_t name_end = head.find('\0', at);
    if (name_end == std::string_view::npos) return false;
    const size_t type_end = head.find('\0', name_end + 1);
    if (type_end == std::string_view::npos || type_end + 5 > head.size()) return false;
    const std::string_view name = head.substr(at, name_end - at);
    const std::string_view type = head.substr(name_end + 1, type_end - name_end - 1);
    uint32_t size = 0;
    for (int k = 3; k >= 0; --k)
      size = size << 8 | static_cast<unsigned char>(head[type_end + 1 + k]);
    const size_t value = type_end + 5;
    if (size > head.size() - value) return false;
    if (name == "dataWindow" && type == "box2i" && size == 16) {
      int32_t box[4];
      for (int c = 0; c < 4; ++c) {
        uint32_t word = 0;
        for (int k = 3; k >= 0; --k) {
          word = word << 8 | static_cast<unsigned char>(head[value + 4 * c + k]);
        }
        box[c] = static_cast<int32_t>(word);
      }
      return int64_t{box[2]} - box[0] == int64_t{box[3]} - box[1] && box[2] >= box[0];
    }
    at = value + size;
  }
  return false;
}

Measurement ReadAltaSlice(const std::string& path, const ReadOptions&) {
  const int64_t file_size = RegularFileSize(path);
  std::vector<float> rgb[3];
  int cells = 0;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height = int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0 || width != height) {
      throw ByteError(path, 0,
                      "an OpenEXR image of " + std::to_string(width) + " x " +
                          std::to_string(height) +
                          " pixels, not a BRDF slice (a square grid of theta_h x theta_d cells)");
    }
    if (width > kMaxCells) {
      throw ByteError(path, 0,
                      "a " + std::to_string(width) + " x " + std::to_string(height) +
                          " slice is finer than brdfkit reads (at most " +
                          std::to_string(kMaxCells) + " x " + std::to_string(kMaxCells) + ")");
    }
    const char* const names[3] = {"R", "G", "B"};
    for (const char* name : names) {
      const Imf::Channel* channel = header.channels().findChannel(name);
      if (channel == nullptr) {
        throw ByteError(path, 0,
                        std::string("an OpenEXR image without a ") + name +
                            " channel, not a BRDF slice (expected R, G and B)");
      }
      if (channel->xSampling != 1 || channel->ySampling != 1) {
        throw ByteError(path, 0,
                        std::string("channel ") + name +
                            " is subsampled, not a BRDF slice (one value per cell)");
      }
    }
    cells = static_cast<int>(width);
    const double pixels = static_cast<double>(width) * static_cast<double>(height);
    const double ratio = header.compression() == Imf::NO_COMPRESSION ? 1.0 : kMaxCompressionRatio;
    if (pixels * 3 * 2 > static_cast<double>(file_size) * ratio) {
      throw ByteError(path, 0,
                      "the header promises " + std::to_string(width) + " x " +
                          std::to_string(height) + " pixels, more than a " +
                          std::to_string(file_size) + "-byte file can hold (truncated?)");
    }
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c) {
      rgb[c].assign(static_cast<size_t>(width * height), 0.0f);
      frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, rgb[c].data(), window, sizeof(float),
                                              sizeof(float) * static_cast<size_t>(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& error) {
    throw InputError(path, "not a readable OpenEXR BRDF slice: " + OneLine(error.what()));
  }

  Measurement measurement;
  measurement.samples.reserve(static_cast<size_t>(cells) * cells);
  int64_t missing = 0;
  for (int y = 0; y < cells; ++y) {
    const double theta_d = (cells - 1 - y + 0.5) / cells * (kPi / 2);
    for (int i = 0; i < cells; ++i) {
      const double theta_h = (i + 0.5) / cells * (kPi / 2);
      Sample sample;
      FromHalfDiff({theta_h, 0.0, theta_d, kPi / 2}, &sample.wi, &sample.wo);
      const size_t pixel = static_cast<size_t>(y) * cells + i;
      for (int c = 0; c < 3; ++c) sample.value[c] = rgb[c][pixel];
      if (!sample.value.allFinite() || (sample.value < 0).any()) {
        sample.missing = true;
        ++missing;
      }
      measurement.samples.push_back(sample);
    }
  }
  auto& metadata = measurement.metadata;
  const std::string n = std::to_string(cells);
  metadata["parameterization"] = "ASSUMED ALTA RUSIN_TH_TD slice (the file does not say): " + n +
                                 " x " + n + " cells, column i at theta_h = (i + 0.5)/" + n +
                                 " x 90 deg, row y (0 = top) at theta_d = (" + n +
                                 " - 1 - y + 0.5)/" + n + " x 90 deg, phi_h = 0, phi_d = 90 deg";
  metadata["units"] = "ASSUMED BRDF in sr^-1, RGB (what ALTA stores from a MERL table)";
  metadata["isotropy"] = "ASSUMED isotropic: one slice phi_d = 90 deg of an isotropic BRDF";
  metadata["missing"] = std::to_string(missing) +
                        " cells negative (MERL's missing mark) or not finite, flagged missing";
  return measurement;
}

}  // namespace brdf
