// Format detection by signature, and the PNG writer.
#include "hdr/image_files.h"

#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text.h"

namespace brdf {
namespace {

// OpenEXR files begin with the magic number 20000630 (little-endian 76 2f 31 01); Radiance
// files with "#?" followed by the program name (usually RADIANCE or RGBE).
constexpr char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};

}  // namespace

Image ReadHdrImage(const std::string& path) {
  RegularFileSize(path);  // a directory or a device is named as such, not misread
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, "cannot open the file");
  char head[4] = {0, 0, 0, 0};
  file.read(head, sizeof(head));
  if (file.gcount() == 4 && std::memcmp(head, kExrMagic, 4) == 0) return ReadExr(path);
  if (file.gcount() >= 2 && head[0] == '#' && head[1] == '?') return ReadRadiance(path);
  throw ByteError(path, 0,
                  "neither an OpenEXR file (magic 76 2f 31 01) nor a Radiance RGBE file ('#?')");
}

void WritePng(const std::string& path, const Image8& image) {
  CheckImageSize(image.width, image.height, path);
  // OpenCV stores colour as BGR.
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", bgr, bytes)) throw OutputError(path, "PNG encoding failed");
  WriteFileAtomically(
      path,
      [&](std::ostream& stream) {
        stream.write(reinterpret_cast<const char*>(bytes.data()),
                     static_cast<std::streamsize>(bytes.size()));
      },
      /*binary=*/true);
}

}  // namespace brdf
