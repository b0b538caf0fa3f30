// Drawing primitives the command line's PNG charts share (`brdf energy --plot`,
// `brdf fit --plot`): "nice" tick steps, tick labels, text, and the atomic PNG write. The charts
// are drawn with OpenCV so that the binary needs no Python at run time.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace brdf::cli::chart {

// OpenCV stores pixels as BGR.
inline const cv::Scalar kBlack(0, 0, 0), kGrey(170, 170, 170), kLightGrey(225, 225, 225);
inline const cv::Scalar kWhite(255, 255, 255);
// One colour per RGB channel, and a cycle for several curves on one chart.
inline const cv::Scalar kChannelColours[3] = {cv::Scalar(40, 40, 220), cv::Scalar(40, 160, 40),
                                              cv::Scalar(220, 80, 30)};
inline const cv::Scalar kCurveColours[6] = {cv::Scalar(200, 90, 30),  cv::Scalar(40, 40, 210),
                                            cv::Scalar(40, 150, 40),  cv::Scalar(160, 60, 160),
                                            cv::Scalar(20, 140, 200), cv::Scalar(110, 110, 110)};

// Smallest "nice" step (1, 2 or 5 times a power of ten) giving at most `ticks` ticks over
// `range`.
double TickStep(double range, int ticks);
// A tick value without the binary noise of repeated addition (0.6000000000000001 -> 0.6).
std::string TickLabel(double value);
// Text in black, anti-aliased, baseline at `origin`.
void Label(cv::Mat* image, const std::string& text, cv::Point origin, double scale = 0.5);
// Cuts `text` to `max_chars` for a chart (core/text.h ShortLabel: a path keeps its file name).
std::string Shorten(const std::string& text, size_t max_chars);
// Writes the (BGR, 8-bit) image as a PNG atomically. Throws OutputError naming the path when
// the encoding or the write fails.
void WritePng(const cv::Mat& image, const std::string& path);

}  // namespace brdf::cli::chart
