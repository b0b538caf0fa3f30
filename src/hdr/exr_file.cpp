// OpenEXR through its C++ API (ImfInputFile / ImfOutputFile). OpenEXR converts between the
// file's channel type (half or float) and the float frame buffer, so one buffer layout serves
// both. Its exceptions are translated here, at the boundary, into the program's own (after tev).
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <ImfTileDescription.h>
#include <half.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <mutex>
#include <thread>

#include "core/atomic_file.h"
#include "core/enum_names.h"
#include "core/errors.h"
#include "core/text.h"
#include "hdr/image_files.h"

namespace brdf {
namespace {

// OpenEXR's messages may span lines; an error here is one line (DESIGN §3).
std::string OneLine(std::string message) {
  std::replace(message.begin(), message.end(), '\n', ' ');
  return message;
}

// OpenEXR compresses and decompresses line blocks in its own thread pool.
void UseAllCoresForExr() {
  static std::once_flag once;
  std::call_once(once, [] {
    Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  });
}

Imf::Slice FloatSlice(Image* image, int channel, int min_x, int min_y, double fill) {
  // OpenEXR addresses pixel (x, y) of the data window at base + x*xStride + y*yStride, a base
  // outside the buffer whenever the window does not start at (0, 0). Slice::Make computes it in
  // integers: the pointer arithmetic `data - min_x * xStride` is undefined behaviour (the
  // fuzzer's UBSan found it with a window starting at x = -2).
  const size_t x_stride = sizeof(float) * Image::kChannels;
  const size_t y_stride = x_stride * image->width;
  return Imf::Slice::Make(Imf::FLOAT, image->rgba.data() + channel, Imath::V2i(min_x, min_y),
                          image->width, image->height, x_stride, y_stride, 1, 1, fill);
}

// The byte where the header attribute `name` of `type` starts (headers are small: it is looked
// for in the first 64 kB), or 0 when it is not found there.
int64_t AttributeByte(const std::string& path, const std::string& name, const std::string& type) {
  std::string head(65536, '\0');
  std::ifstream stream(path, std::ios::binary);
  stream.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(std::max<std::streamsize>(0, stream.gcount())));
  const size_t attribute = head.find(name + std::string(1, '\0') + type + std::string(1, '\0'));
  return attribute == std::string::npos ? 0 : static_cast<int64_t>(attribute);
}

// A header may claim any data window; the pixels it promises must fit in the file before
// width x height float pixels are allocated. Uncompressed pixels take their full size; no
// lossless codec of OpenEXR packs more than about 1000:1 (deflate's limit is 1032:1; PIZ and
// RLE on constant data do less), so 4096:1 is a bound no real file reaches.
void CheckExrSize(const Imf::Header& header, int64_t pixels, int64_t file_size,
                  const std::string& path) {
  constexpr double kMaxCompressionRatio = 4096.0;
  double pixel_bytes = 0;
  for (auto channel = header.channels().begin(); channel != header.channels().end(); ++channel) {
    const Imf::Channel& info = channel.channel();
    const double samples =
        static_cast<double>(pixels) /
        (std::max(1, info.xSampling) * static_cast<double>(std::max(1, info.ySampling)));
    pixel_bytes += samples * (info.type == Imf::HALF ? 2 : 4);
  }
  const double ratio = header.compression() == Imf::NO_COMPRESSION ? 1.0 : kMaxCompressionRatio;
  if (pixel_bytes > ratio * static_cast<double>(file_size)) {
    throw ByteError(path, AttributeByte(path, "dataWindow", "box2i"),
                    "the header's data window promises " + std::to_string(pixels) + " pixels (" +
                        std::to_string(static_cast<int64_t>(pixel_bytes)) +
                        " bytes), more than a file of " + std::to_string(file_size) +
                        " bytes can hold");
  }
}

// A tiled file read as scan lines keeps one row of tiles per channel (width x tile height
// samples), and each tile in flight holds tile width x tile height: a hostile tile description
// (a tile 134 million rows high on a 4 x 3 image) makes OpenEXR allocate gigabytes before it
// reads a pixel. A tile larger than its image is legal (64 x 64 tiles on a 10 x 10 image are
// common), so the bound is four times the image or 2^24 pixels (64 MB of floats a channel),
// whichever is larger.
void CheckExrTiles(const Imf::Header& header, int64_t width, int64_t pixels,
                   const std::string& path) {
  if (!header.hasTileDescription()) return;
  const Imf::TileDescription& tiles = header.tileDescription();
  const int64_t bound = std::max<int64_t>(4 * pixels, int64_t{1} << 24);
  const int64_t tile_width = tiles.xSize, tile_height = tiles.ySize;
  std::string problem;
  if (tile_width < 1 || tile_height < 1) {
    problem = "a tile of " + std::to_string(tile_width) + "x" + std::to_string(tile_height);
  } else if (tile_width * tile_height > bound || width * tile_height > bound) {
    problem = "tiles of " + std::to_string(tile_width) + "x" + std::to_string(tile_height) +
              " pixels on an image " + std::to_string(width) + " pixels wide (at most " +
              std::to_string(bound) + " pixels a tile or a row of tiles)";
  } else if (tiles.mode >= Imf::NUM_LEVELMODES || tiles.roundingMode >= Imf::NUM_ROUNDINGMODES) {
    problem = "an unknown level mode " + std::to_string(static_cast<int>(tiles.mode)) +
              " or rounding mode " + std::to_string(static_cast<int>(tiles.roundingMode));
  }
  if (!problem.empty()) {
    throw ByteError(path, AttributeByte(path, "tiles", "tiledesc"),
                    "the header's tile description asks for " + problem);
  }
}

}  // namespace

Image ReadExr(const std::string& path) {
  const int64_t file_size = RegularFileSize(path);  // a directory or a device is named as such
  if (!std::ifstream(path)) throw InputError(path, "cannot open the file");
  UseAllCoresForExr();
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    // In 64 bits: a hostile header's corners may be any int32.
    const int64_t width64 = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height64 = int64_t{window.max.y} - window.min.y + 1;
    if (width64 <= 0 || height64 <= 0 || width64 > 65536 || height64 > 65536) {
      throw InputError(path, "data window " + std::to_string(width64) + "x" +
                                 std::to_string(height64) + " is not a plausible image size");
    }
    const int width = static_cast<int>(width64), height = static_cast<int>(height64);
    CheckImageSize(width, height, path);
    const Imf::ChannelList& channels = file.header().channels();
    CheckExrSize(file.header(), width64 * height64, file_size, path);
    CheckExrTiles(file.header(), width64, width64 * height64, path);
    const bool has_rgb =
        channels.findChannel("R") || channels.findChannel("G") || channels.findChannel("B");
    const bool has_y = channels.findChannel("Y") != nullptr;
    if (!has_rgb && !has_y) throw InputError(path, "no R, G, B or Y channel to read");

    Image image(width, height, 0.0f);  // every channel is read or filled (A with 1)
    Imf::FrameBuffer frame;
    if (has_rgb) {
      frame.insert("R", FloatSlice(&image, 0, window.min.x, window.min.y, 0.0));
      frame.insert("G", FloatSlice(&image, 1, window.min.x, window.min.y, 0.0));
      frame.insert("B", FloatSlice(&image, 2, window.min.x, window.min.y, 0.0));
    } else {
      frame.insert("Y", FloatSlice(&image, 0, window.min.x, window.min.y, 0.0));
    }
    frame.insert("A", FloatSlice(&image, 3, window.min.x, window.min.y, 1.0));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (!has_rgb) {
      for (int64_t i = 0; i < image.pixel_count(); ++i) {
        float* rgba = image.rgba.data() + i * Image::kChannels;
        rgba[1] = rgba[2] = rgba[0];
      }
    }
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& error) {
    throw InputError(path, "not a readable OpenEXR file: " + OneLine(error.what()));
  }
}

constexpr EnumName<ExrCompression> kExrCompressionNames[] = {
    {ExrCompression::kZip, "zip"},
    {ExrCompression::kPiz, "piz"},
    {ExrCompression::kRle, "rle"},
    {ExrCompression::kNone, "none"},
};

constexpr EnumName<ExrPixelType> kExrPixelTypeNames[] = {
    {ExrPixelType::kHalf, "half"},
    {ExrPixelType::kFloat, "float"},
};

ExrPixelType ParseExrPixelType(const std::string& name) {
  return ParseEnum(kExrPixelTypeNames, name, "OpenEXR pixel type");
}

ExrCompression ParseExrCompression(const std::string& name) {
  return ParseEnum(kExrCompressionNames, name, "OpenEXR compression");
}

int64_t WriteExr(const std::string& path, const Image& image, ExrPixelType type,
                 ExrCompression compression) {
  CheckImageSize(image.width, image.height, path);
  int64_t clamped_values = 0;
  UseAllCoresForExr();
  const Imf::PixelType pixel_type = type == ExrPixelType::kHalf ? Imf::HALF : Imf::FLOAT;
  WriteFileAtomicallyByName(path, [&](const std::string& temporary) {
    try {
      Imf::Header header(image.width, image.height);
      switch (compression) {
        case ExrCompression::kZip:
          header.compression() = Imf::ZIP_COMPRESSION;
          break;
        case ExrCompression::kPiz:
          header.compression() = Imf::PIZ_COMPRESSION;
          break;
        case ExrCompression::kRle:
          header.compression() = Imf::RLE_COMPRESSION;
          break;
        case ExrCompression::kNone:
          header.compression() = Imf::NO_COMPRESSION;
          break;
      }
      // zlib level 1: a preview is written once and read rarely; the default level 6 costs
      // several times the time for a few percent of size on noisy HDR data.
      header.zipCompressionLevel() = 1;
      for (const char* name : {"R", "G", "B", "A"}) {
        header.channels().insert(name, Imf::Channel(pixel_type));
      }
      Imf::OutputFile file(temporary.c_str(), header);
      Imf::FrameBuffer frame;
      const char* names[] = {"R", "G", "B", "A"};
      // OpenEXR converts types when reading but not when writing: a half file needs a half
      // frame buffer.
      std::vector<half> halves;
      if (type == ExrPixelType::kHalf) {
        // Beyond the largest half (65504) the conversion gives infinity: such values are
        // clamped to it (and counted for the caller's warning), finite as they were.
        halves.reserve(image.rgba.size());
        for (const float value : image.rgba) {
          const bool beyond = std::isfinite(value) && std::abs(value) > HALF_MAX;
          if (beyond) ++clamped_values;
          halves.emplace_back(beyond ? std::copysign(HALF_MAX, value) : value);
        }
        const size_t x_stride = sizeof(half) * Image::kChannels;
        for (int c = 0; c < Image::kChannels; ++c) {
          frame.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.data() + c),
                                            x_stride, x_stride * image.width));
        }
      } else {
        Image& pixels = const_cast<Image&>(image);  // OpenEXR's Slice takes char*; read only
        for (int c = 0; c < Image::kChannels; ++c) {
          frame.insert(names[c], FloatSlice(&pixels, c, 0, 0, 0.0));
        }
      }
      file.setFrameBuffer(frame);
      file.writePixels(image.height);
    } catch (const std::exception& error) {
      throw OutputError(path, "cannot write OpenEXR: " + OneLine(error.what()));
    }
  });
  return clamped_values;
}

}  // namespace brdf
