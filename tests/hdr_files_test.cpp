// HDR image files: OpenEXR round trips (half, float), the real Radiance and OpenEXR copies of
// Debevec's Memorial Church read to the same picture, and broken files rejected by name.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

#include "core/errors.h"
#include "hdr/image_files.h"
#include "test_util.h"

namespace brdf {
namespace {

using testing::DataPath;
using testing::ScratchDir;

Image RandomHdrImage(int width, int height, unsigned seed) {
  Image image(width, height);
  std::mt19937 random(seed);
  // Log-uniform over 8 decades (half reaches 65504; its normal range starts at 6e-5).
  std::uniform_real_distribution<float> exponent(-4.0f, 4.0f);
  for (float& value : image.rgba) value = std::pow(10.0f, exponent(random));
  return image;
}

TEST(ExrFile, DataWindowAwayFromTheOriginReadsIntoPlace) {
  // A data window from (-2, 3) to (1, 5): 4 x 3 pixels whose top-left one is at x = -2 (the
  // window the fuzzer used to expose undefined pointer arithmetic in the reader).
  ScratchDir dir;
  const Imath::Box2i window(Imath::V2i(-2, 3), Imath::V2i(1, 5));
  std::vector<float> values(12);
  for (int i = 0; i < 12; ++i) values[i] = 0.5f * i + 0.25f;
  {
    Imf::Header header(window, window);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(dir.File("offset.exr").c_str(), header);
    Imf::FrameBuffer frame;
    frame.insert(
        "Y", Imf::Slice::Make(Imf::FLOAT, values.data(), window, sizeof(float), 4 * sizeof(float)));
    file.setFrameBuffer(frame);
    file.writePixels(3);
  }
  Image image = ReadExr(dir.File("offset.exr"));
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 3);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      const float* rgba = image.pixel(x, y);
      EXPECT_EQ(rgba[0], values[y * 4 + x]) << x << "," << y;
      EXPECT_EQ(rgba[2], values[y * 4 + x]);  // luminance-only: grey
      EXPECT_EQ(rgba[3], 1.0f);               // no alpha channel: opaque
    }
  }
}

TEST(RadianceFile, BrokenScanLinesNameTheByte) {
  ScratchDir dir;
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n";  // 45 bytes
  struct Case {
    std::string name, pixels;
    int64_t byte;
  };
  const Case cases[] = {
      // A run of 9 in a line of 8 pixels: the count byte after the 4-byte marker.
      {"long-run.hdr", std::string("\x02\x02\x00\x08\x89\x10", 6) + std::string(26, '\0'), 49},
      // A line 16 wide in an image 8 wide.
      {"wide.hdr", std::string("\x02\x02\x00\x10", 4) + std::string(28, '\0'), 45},
      // Red a run of 8, green two literals of 4, blue one literal of 4 and then a count of 4
      // with only 2 bytes left: the file ends at byte 67, inside the line.
      {"truncated.hdr",
       std::string("\x02\x02\x00\x08\x88\x01\x04\x01\x02\x03\x04", 11) + std::string(13, '\x04'),
       67},
  };
  for (const Case& c : cases) {
    const std::string path = dir.Write(c.name, header + c.pixels);
    try {
      ReadRadiance(path);
      ADD_FAILURE() << c.name << " was accepted";
    } catch (const ByteError& error) {
      EXPECT_EQ(error.offset(), c.byte) << error.what();
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    }
  }
}

// A tiled file whose tile description asks for tiles 134,217,730 rows high on a 4 x 3 image (a
// fuzzer's find): OpenEXR would allocate a 2 GB row of tiles before reading a pixel. It is
// rejected at the byte of the tiles attribute, read by hand from the file: 276.
TEST(ExrFile, HostileTileDescriptionNamesItsByte) {
  const std::string path = testing::TestPath("fuzz/regressions/fuzz_exr/tall-tiles.exr");
  try {
    ReadExr(path);
    ADD_FAILURE() << "accepted";
  } catch (const ByteError& error) {
    EXPECT_EQ(error.offset(), 276) << error.what();
    EXPECT_NE(std::string(error.what()).find("134217730"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
}

TEST(ExrFile, FloatRoundTripIsExact) {
  ScratchDir dir;
  const Image image = RandomHdrImage(37, 23, 1);
  WriteExr(dir.File("a.exr"), image, ExrPixelType::kFloat);
  const Image back = ReadExr(dir.File("a.exr"));
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.rgba, image.rgba);
  EXPECT_EQ(dir.CountEntries(), 1);  // no temporary left behind
}

TEST(ExrFile, HalfRoundTripWithinHalfPrecision) {
  ScratchDir dir;
  const Image image = RandomHdrImage(64, 32, 2);
  WriteExr(dir.File("a.exr"), image, ExrPixelType::kHalf);
  const Image back = ReadHdrImage(dir.File("a.exr"));  // detected by its magic number
  ASSERT_EQ(back.rgba.size(), image.rgba.size());
  for (size_t i = 0; i < image.rgba.size(); ++i) {
    const float value = image.rgba[i];
    // half has an 11-bit significand (relative rounding error <= 2^-11) for normal values
    // (>= 2^-14); below that the spacing is fixed at 2^-24.
    const float tolerance = std::max(value * std::ldexp(1.0f, -11), std::ldexp(1.0f, -25));
    ASSERT_NEAR(back.rgba[i], value, tolerance) << i;
  }
}

TEST(RadianceFile, MemorialChurchReadsLikeItsExrCopy) {
  const Image radiance = ReadHdrImage(DataPath("hdr/memorial.hdr"));
  const Image exr = ReadHdrImage(DataPath("hdr/memorial.exr"));
  ASSERT_EQ(radiance.width, 512);
  ASSERT_EQ(radiance.height, 768);
  ASSERT_EQ(exr.width, radiance.width);
  ASSERT_EQ(exr.height, radiance.height);
  // RGBE keeps 8 bits of mantissa per channel under a shared exponent: the channels agree to
  // about 1% of the pixel's largest channel.
  int64_t agreeing = 0;
  for (int64_t i = 0; i < radiance.pixel_count(); ++i) {
    const float* a = &radiance.rgba[i * 4];
    const float* b = &exr.rgba[i * 4];
    const float largest = std::max({a[0], a[1], a[2], 1e-6f});
    bool close = true;
    for (int c = 0; c < 3; ++c) close = close && std::abs(a[c] - b[c]) <= 0.01f * largest;
    agreeing += close;
    EXPECT_EQ(a[3], 1.0f);
  }
  EXPECT_GT(agreeing, 0.99 * radiance.pixel_count());
}

TEST(RadianceFile, RealEnvironmentMapIsTwoToOne) {
  const Image image = ReadRadiance(DataPath("hdr/venice_sunset_1k.hdr"));
  EXPECT_EQ(image.width, 1024);
  EXPECT_EQ(image.height, 512);
  float largest = 0.0f;
  for (int64_t i = 0; i < image.pixel_count(); ++i) {
    largest = std::max(largest, PixelLuminance(&image.rgba[i * 4]));
  }
  EXPECT_GT(largest, 100.0f);  // the sun: far beyond display white
}

TEST(HdrFiles, BrokenFilesAreInputErrorsNamingTheFile) {
  ScratchDir dir;
  const std::string missing = dir.File("missing.exr");
  const std::string garbage = dir.Write("garbage.hdr", "P6 not an hdr image");
  const std::string truncated_exr =
      dir.Write("cut.exr", testing::ReadFileText(DataPath("hdr/memorial.exr")).substr(0, 2000));
  const std::string truncated_hdr =
      dir.Write("cut.hdr", testing::ReadFileText(DataPath("hdr/memorial.hdr")).substr(0, 3000));
  for (const std::string& path : {missing, garbage, truncated_exr, truncated_hdr}) {
    try {
      ReadHdrImage(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(path + ": ", 0), 0u) << error.what();
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos) << error.what();
    }
  }
}

TEST(HdrFiles, NonFinitePixelsAreCountedAndReplaced) {
  Image image(4, 1);
  image.pixel(1, 0)[0] = std::nanf("");
  image.pixel(1, 0)[1] = 0.5f;
  image.pixel(2, 0)[2] = INFINITY;
  image.pixel(3, 0)[1] = -INFINITY;
  image.pixel(3, 0)[2] = std::nanf("");
  EXPECT_EQ(ReplaceNonFinite(&image), 3);
  for (float value : image.rgba) EXPECT_TRUE(std::isfinite(value));
  for (int x = 1; x < 4; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(image.pixel(x, 0)[c], 0.0f);
  }
  EXPECT_EQ(ReplaceNonFinite(&image), 0);
}

TEST(PngFile, WritesWhatIsGivenAtomically) {
  ScratchDir dir;
  Image8 image;
  image.width = 2;
  image.height = 1;
  image.rgb = {255, 0, 10, 1, 2, 3};
  WritePng(dir.File("a.png"), image);
  const std::string bytes = testing::ReadFileText(dir.File("a.png"));
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(dir.CountEntries(), 1);
  EXPECT_THROW(WritePng(dir.path(), image), OutputError);  // a directory
}

TEST(PngFile, DecodesToThePixelsWrittenWithAnyThreadCount) {
  // Several strips of the parallel encoder, the last one short, and an odd width.
  Image8 image;
  image.width = 333;
  image.height = 3 * 64 + 17;
  image.rgb.resize(size_t{333} * image.height * 3);
  std::mt19937 random(11);
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    // Smooth ramps (long runs after the Sub filter) with noise in a band (short ones).
    const size_t pixel = i / 3;
    const int x = static_cast<int>(pixel % image.width), y = static_cast<int>(pixel / image.width);
    image.rgb[i] = static_cast<uint8_t>(y > 100 && y < 140 ? random() : (x + 2 * y + i % 3) % 256);
  }
  ScratchDir dir;
  WritePng(dir.File("a.png"), image);
  const cv::Mat decoded = cv::imread(dir.File("a.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(decoded.type(), CV_8UC3);
  ASSERT_EQ(decoded.cols, image.width);
  ASSERT_EQ(decoded.rows, image.height);
  int64_t differing = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const cv::Vec3b bgr = decoded.at<cv::Vec3b>(y, x);
      const uint8_t* rgb = image.rgb.data() + (int64_t{y} * image.width + x) * 3;
      differing += bgr[2] != rgb[0] || bgr[1] != rgb[1] || bgr[0] != rgb[2];
    }
  }
  EXPECT_EQ(differing, 0);
  const std::string many = EncodePng(image, "a.png");
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_TRUE(EncodePng(image, "a.png") == many);
}

// The PNG writer's strips, decoded by libpng (through OpenCV), on the cases a Huffman coder
// finds hardest: one pixel; one colour (two literal codes: the value and the end of block);
// all 256 byte values; and filtered bytes of Fibonacci frequencies, whose Huffman tree is
// deeper than deflate's 15-bit limit.
TEST(PngFile, HardHuffmanCasesDecodeToThePixelsWritten) {
  const auto image_of = [](int width, int height, const std::vector<uint8_t>& filtered) {
    // Undo the Sub filter: the row bytes whose filtered values are `filtered` (cycled).
    Image8 image;
    image.width = width;
    image.height = height;
    image.rgb.resize(size_t{3} * width * height);
    for (int y = 0; y < height; ++y) {
      uint8_t* row = image.rgb.data() + size_t{3} * width * y;
      for (int i = 0; i < 3 * width; ++i) {
        const uint8_t f = filtered[(size_t{3} * width * y + i) % filtered.size()];
        row[i] = static_cast<uint8_t>(i < 3 ? f : row[i - 3] + f);
      }
    }
    return image;
  };
  std::vector<uint8_t> fibonacci;
  for (int value = 0, a = 1, b = 1; value < 24; ++value) {
    fibonacci.insert(fibonacci.end(), a, static_cast<uint8_t>(value * 7));
    const int next = a + b;
    a = b;
    b = next;
  }
  std::shuffle(fibonacci.begin(), fibonacci.end(), std::mt19937(3));
  std::vector<uint8_t> all(256 * 5);
  std::mt19937 random(9);
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint8_t>(i < 256 ? i : random());
  const std::vector<Image8> images = {image_of(1, 1, {77}), image_of(50, 70, {0}),
                                      image_of(97, 130, all), image_of(1000, 70, fibonacci)};
  ScratchDir dir;
  for (const Image8& image : images) {
    WritePng(dir.File("a.png"), image);
    const cv::Mat decoded = cv::imread(dir.File("a.png"), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(decoded.type(), CV_8UC3) << image.width << "x" << image.height;
    ASSERT_EQ(decoded.cols, image.width);
    ASSERT_EQ(decoded.rows, image.height);
    int64_t differing = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const cv::Vec3b bgr = decoded.at<cv::Vec3b>(y, x);
        const uint8_t* rgb = image.rgb.data() + (int64_t{y} * image.width + x) * 3;
        differing += bgr[2] != rgb[0] || bgr[1] != rgb[1] || bgr[0] != rgb[2];
      }
    }
    EXPECT_EQ(differing, 0) << image.width << "x" << image.height;
  }
}

}  // namespace
}  // namespace brdf
