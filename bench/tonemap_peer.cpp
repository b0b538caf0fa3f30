// The whole-process peer of `brdf tonemap` (docs/performance.md): the same job written with
// Debian's OpenCV as a user would write it, run as its own process by bench/performance.
//
//   tonemap_peer IN.exr OUT.png          imread (EXR), bright pass by a luminance threshold,
//                                        GaussianBlur sigma 13 px, add back at 0.1, OpenCV's
//                                        Reinhard, 8 bits, imwrite (PNG)
//   tonemap_peer --make-input SRC OUT.exr
//                                        the benchmark's 1080p input: SRC (.hdr or .exr) resized
//                                        bilinearly to 1920x1080, written as half-float PIZ
//                                        OpenEXR (deterministic: same bytes on every run)
//
// Not product code: a measuring stick, built only with the benchmarks.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <string>

#include "hdr/image_files.h"

namespace {

constexpr int kWidth = 1920, kHeight = 1080;

int MakeInput(const std::string& source, const std::string& target) {
  const brdf::Image image = brdf::ReadHdrImage(source);
  const cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
  cv::Mat resized;
  cv::resize(rgba, resized, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_LINEAR);
  brdf::Image frame(kWidth, kHeight);
  std::memcpy(frame.rgba.data(), resized.ptr<float>(), frame.rgba.size() * sizeof(float));
  brdf::WriteExr(target, frame, brdf::ExrPixelType::kHalf, brdf::ExrCompression::kPiz);
  return 0;
}

int Tonemap(const std::string& input, const std::string& output) {
  cv::Mat bgr = cv::imread(input, cv::IMREAD_UNCHANGED);
  if (bgr.type() == CV_32FC4) cv::cvtColor(bgr, bgr, cv::COLOR_BGRA2BGR);
  if (bgr.empty() || bgr.type() != CV_32FC3) {
    std::fprintf(stderr, "tonemap_peer: %s: not a 3-channel float image\n", input.c_str());
    return 2;
  }
  cv::Mat luminance, mask, bright, blurred, bloomed, mapped, display;
  cv::cvtColor(bgr, luminance, cv::COLOR_BGR2GRAY);
  cv::threshold(luminance, mask, 1.0, 1.0, cv::THRESH_BINARY);
  cv::cvtColor(mask, mask, cv::COLOR_GRAY2BGR);
  cv::multiply(bgr, mask, bright);
  cv::GaussianBlur(bright, blurred, cv::Size(0, 0), 13.0);
  cv::addWeighted(bgr, 1.0, blurred, 0.1, 0.0, bloomed);
  cv::createTonemapReinhard()->process(bloomed, mapped);
  mapped.convertTo(display, CV_8UC3, 255.0);
  if (!cv::imwrite(output, display)) {
    std::fprintf(stderr, "tonemap_peer: %s: cannot write\n", output.c_str());
    return 2;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Debian's OpenCV reads and writes OpenEXR only when asked to.
  setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 1);
  // OpenCV 4.6 warns on every run that MatExpr's multi-channel handling may change.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  try {
    if (argc == 4 && std::string(argv[1]) == "--make-input") return MakeInput(argv[2], argv[3]);
    if (argc == 3) return Tonemap(argv[1], argv[2]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tonemap_peer: %s\n", error.what());
    return 2;
  }
  std::fprintf(stderr, "usage: tonemap_peer IN.exr OUT.png | --make-input SRC OUT.exr\n");
  return 2;
}
