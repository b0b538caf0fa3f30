// Format detection by signature, and the PNG writer.
#include "hdr/image_files.h"

#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

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

namespace {

// PNG (ISO/IEC 15948) written here in parallel: every row gets the Sub filter (each byte
// minus the one a pixel to its left), and strips of kPngStripRows rows are deflated
// independently, each ending on a byte boundary (as zlib's Z_SYNC_FLUSH does it) so that the
// strips concatenate into one zlib stream; the strips' Adler-32 checksums (zlib) combine into
// the stream's. Huffman coding alone (no string matching): on tone-mapped 1080p photographs
// zlib's Huffman-only mode measured 25 % faster than OpenCV's setting (level 1, run-length
// matching) for 0.2 % more bytes, and both beat libpng's adaptive filters
// (docs/performance.md). The Huffman coder is our own (RFC 1951, one dynamic block of literals
// per strip): on one thread the whole PNG of that frame (filter, coding, checksums) takes a
// quarter to a third of the time zlib's Huffman-only deflate alone takes on the same bytes
// (bench_hdr BM_Png_*). The strips are
// fixed, so the bytes do not depend on the thread count.
constexpr int kPngStripRows = 64;

void AppendBigEndian(uint32_t value, std::string* out) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<char>(value >> shift));
}

void AppendChunk(const char type[4], const std::string& data, std::string* out) {
  AppendBigEndian(static_cast<uint32_t>(data.size()), out);
  const size_t start = out->size();
  out->append(type, 4);
  out->append(data);
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(out->data() + start),
                          out->size() - start);
  AppendBigEndian(static_cast<uint32_t>(crc), out);
}

// Deflate's bit order: least significant bit first, into whole bytes. Each Put stores eight
// bytes at once and moves on by the whole bytes it filled, so the buffer needs eight bytes to
// spare past the end.
class BitWriter {
 public:
  explicit BitWriter(uint8_t* out) : begin_(out), out_(out) {}
  // The low `count` bits of `bits`; at most 56 bits in one call.
  void Put(uint64_t bits, int count) {
    buffer_ |= bits << filled_;
    filled_ += count;
    std::memcpy(out_, &buffer_, sizeof(buffer_));
    out_ += filled_ >> 3;
    buffer_ = (filled_ & ~7) == 64 ? 0 : buffer_ >> (filled_ & ~7);
    filled_ &= 7;
  }
  // Pads with zero bits to a byte boundary.
  void Flush() {
    if (filled_ > 0) Put(0, 8 - filled_);
  }
  size_t bytes() const { return static_cast<size_t>(out_ - begin_); }

 private:
  uint8_t* begin_;
  uint8_t* out_;
  uint64_t buffer_ = 0;
  int filled_ = 0;  // bits in buffer_ not yet counted in out_, fewer than 8 between calls
};

// Code lengths of a Huffman code for `frequency` (0 = unused symbol), none longer than
// `limit` bits. A Huffman tree first (two queues over the sorted leaves); lengths beyond the
// limit are cut to it and the Kraft sum is restored by lengthening the deepest codes that
// still fit; lengths then go to the symbols in order of frequency, the shortest to the most
// frequent. At least two symbols must be used.
std::vector<int> HuffmanLengths(const std::vector<uint32_t>& frequency, int limit) {
  std::vector<int> symbols;
  for (int s = 0; s < static_cast<int>(frequency.size()); ++s) {
    if (frequency[s] > 0) symbols.push_back(s);
  }
  std::stable_sort(symbols.begin(), symbols.end(),
                   [&](int a, int b) { return frequency[a] < frequency[b]; });
  const int n = static_cast<int>(symbols.size());
  // Nodes 0..n-1 are the leaves (ascending weight), n.. the internal nodes in creation order
  // (ascending weight too): two queues, no heap.
  std::vector<uint64_t> weight(2 * n);
  std::vector<int> parent(2 * n, -1);
  for (int k = 0; k < n; ++k) weight[k] = frequency[symbols[k]];
  int leaf = 0, node = n, next = n;
  const auto take = [&]() {
    if (leaf < n && (node >= next || weight[leaf] <= weight[node])) return leaf++;
    return node++;
  };
  for (; next < 2 * n - 1; ++next) {
    const int a = take(), b = take();
    weight[next] = weight[a] + weight[b];
    parent[a] = parent[b] = next;
  }
  // Depths: the root is the last node.
  std::vector<int> depth(2 * n, 0);
  for (int k = 2 * n - 3; k >= 0; --k) depth[k] = depth[parent[k]] + 1;
  std::vector<int> count(std::max(limit, 64) + 1, 0);  // codes per length
  for (int k = 0; k < n; ++k) ++count[std::min(depth[k], limit)];
  uint64_t kraft = 0;  // in units of 2^-limit
  for (int length = 1; length <= limit; ++length)
    kraft += static_cast<uint64_t>(count[length]) << (limit - length);
  while (kraft > (uint64_t{1} << limit)) {
    // One code of the longest length goes; a shorter code splits into two one bit longer.
    --count[limit];
    for (int length = limit - 1; length > 0; --length) {
      if (count[length] > 0) {
        --count[length];
        count[length + 1] += 2;
        break;
      }
    }
    --kraft;
  }
  std::vector<int> lengths(frequency.size(), 0);
  int k = n - 1;  // most frequent first
  for (int length = 1; length <= limit; ++length) {
    for (int c = 0; c < count[length]; ++c) lengths[symbols[k--]] = length;
  }
  return lengths;
}

// Canonical codes for `lengths` (RFC 1951 3.2.2), bit-reversed for the LSB-first writer.
std::vector<uint32_t> CanonicalCodes(const std::vector<int>& lengths) {
  int count[17] = {0};
  for (int length : lengths) ++count[length];
  count[0] = 0;
  uint32_t next[17] = {0};
  for (int length = 1, code = 0; length <= 16; ++length) {
    code = (code + count[length - 1]) << 1;
    next[length] = code;
  }
  std::vector<uint32_t> codes(lengths.size(), 0);
  for (size_t s = 0; s < lengths.size(); ++s) {
    const int length = lengths[s];
    if (length == 0) continue;
    const uint32_t code = next[length]++;
    uint32_t reversed = 0;
    for (int bit = 0; bit < length; ++bit) reversed |= ((code >> bit) & 1u) << (length - 1 - bit);
    codes[s] = reversed;
  }
  return codes;
}

// One dynamic-Huffman deflate block of literals (no matches) holding `data`; `final` sets
// BFINAL. Appends to `writer` (not byte-aligned at the end).
void DeflateLiterals(const uint8_t* data, size_t size, bool final, BitWriter* writer) {
  constexpr int kEndOfBlock = 256;
  std::vector<uint32_t> frequency(257, 0);
  {
    // Four histograms in turn: consecutive equal bytes do not wait on one counter.
    std::vector<uint32_t> partial(4 * 256, 0);
    size_t i = 0;
    for (; i + 4 <= size; i += 4) {
      for (int k = 0; k < 4; ++k) ++partial[256 * k + data[i + k]];
    }
    for (; i < size; ++i) ++partial[data[i]];
    for (int b = 0; b < 256; ++b) {
      frequency[b] = partial[b] + partial[256 + b] + partial[512 + b] + partial[768 + b];
    }
  }
  frequency[kEndOfBlock] = 1;
  // A single literal value still needs a two-symbol code with the end of block.
  const std::vector<int> lengths = HuffmanLengths(frequency, 15);
  const std::vector<uint32_t> codes = CanonicalCodes(lengths);

  // The code lengths of the 257 literal/length codes and of one unused distance code, as
  // code-length symbols: 0..15 themselves, 16 repeats the previous 3..6 times, 17 and 18
  // repeat zero 3..10 and 11..138 times.
  std::vector<int> sequence(lengths);
  // Two distance codes of one bit, never used: what zlib writes for a block without matches
  // (a lone code of zero bits is legal too, but some decoders reject it).
  sequence.insert(sequence.end(), {1, 1});
  struct Symbol {
    int symbol, extra, extra_bits;
  };
  std::vector<Symbol> runs;
  for (size_t i = 0; i < sequence.size();) {
    const int value = sequence[i];
    size_t run = 1;
    while (i + run < sequence.size() && sequence[i + run] == value) ++run;
    size_t left = run;
    if (value == 0) {
      while (left >= 11) {
        const int take = static_cast<int>(std::min<size_t>(left, 138));
        runs.push_back({18, take - 11, 7});
        left -= take;
      }
      if (left >= 3) {
        runs.push_back({17, static_cast<int>(left) - 3, 3});
        left = 0;
      }
      for (; left > 0; --left) runs.push_back({0, 0, 0});
    } else {
      runs.push_back({value, 0, 0});
      --left;
      while (left >= 3) {
        const int take = static_cast<int>(std::min<size_t>(left, 6));
        runs.push_back({16, take - 3, 2});
        left -= take;
      }
      for (; left > 0; --left) runs.push_back({value, 0, 0});
    }
    i += run;
  }
  std::vector<uint32_t> length_frequency(19, 0);
  for (const Symbol& run : runs) ++length_frequency[run.symbol];
  // At least two code-length symbols are in use: 257 literal/length codes cannot all be of
  // one length, and when some are unused their zeros and the distance codes' ones differ.
  const std::vector<int> length_lengths = HuffmanLengths(length_frequency, 7);
  const std::vector<uint32_t> length_codes = CanonicalCodes(length_lengths);
  static constexpr int kOrder[19] = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                     11, 4,  12, 3, 13, 2, 14, 1, 15};
  int hclen = 19;
  while (hclen > 4 && length_lengths[kOrder[hclen - 1]] == 0) --hclen;

  writer->Put(final ? 1 : 0, 1);
  writer->Put(2, 2);  // BTYPE 10: dynamic Huffman codes
  writer->Put(0, 5);  // HLIT: 257 literal/length codes
  writer->Put(1, 5);  // HDIST: 2 distance codes
  writer->Put(hclen - 4, 4);
  for (int k = 0; k < hclen; ++k) writer->Put(length_lengths[kOrder[k]], 3);
  for (const Symbol& run : runs) {
    writer->Put(length_codes[run.symbol], length_lengths[run.symbol]);
    if (run.extra_bits > 0) writer->Put(run.extra, run.extra_bits);
  }
  // The literals: a code and its length in one table entry, three literals per Put
  // (3 x 15 bits).
  std::vector<uint32_t> table(256);
  for (int b = 0; b < 256; ++b) table[b] = codes[b] | static_cast<uint32_t>(lengths[b]) << 16;
  size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const uint32_t a = table[data[i]], b = table[data[i + 1]], c = table[data[i + 2]];
    const int length_a = static_cast<int>(a >> 16), length_b = static_cast<int>(b >> 16);
    writer->Put((a & 0xffff) | uint64_t{b & 0xffff} << length_a |
                    uint64_t{c & 0xffff} << (length_a + length_b),
                length_a + length_b + static_cast<int>(c >> 16));
  }
  for (; i < size; ++i)
    writer->Put(table[data[i]] & 0xffff, static_cast<int>(table[data[i]] >> 16));
  writer->Put(codes[kEndOfBlock], lengths[kEndOfBlock]);
}

struct Strip {
  std::string deflated;
  uLong adler = 1;
  uLong length = 0;  // filtered bytes
};

Strip DeflateStrip(const Image8& image, int y0, int y1, bool last) {
  const int64_t row_bytes = int64_t{image.width} * 3;
  std::vector<uint8_t> filtered(static_cast<size_t>((row_bytes + 1) * (y1 - y0)));
  for (int y = y0; y < y1; ++y) {
    const uint8_t* in = image.rgb.data() + int64_t{y} * row_bytes;
    uint8_t* out = filtered.data() + (row_bytes + 1) * (y - y0);
    out[0] = 1;  // filter type Sub
    for (int64_t i = 0; i < 3 && i < row_bytes; ++i) out[1 + i] = in[i];
    for (int64_t i = 3; i < row_bytes; ++i) out[1 + i] = static_cast<uint8_t>(in[i] - in[i - 3]);
  }
  Strip strip;
  strip.length = static_cast<uLong>(filtered.size());
  strip.adler =
      adler32(adler32(0L, Z_NULL, 0), filtered.data(), static_cast<uInt>(filtered.size()));
  // Room for the worst case: 15 bits a byte, the block header, the stored block, and the
  // eight bytes the writer stores past its end.
  std::unique_ptr<uint8_t[]> deflated(new uint8_t[filtered.size() * 2 + 1024]);
  BitWriter writer(deflated.get());
  DeflateLiterals(filtered.data(), filtered.size(), last, &writer);
  if (!last) {
    // An empty stored block, as Z_SYNC_FLUSH ends a strip: the next starts on a byte.
    writer.Put(0, 3);
    writer.Flush();
    writer.Put(0xffff0000u, 32);  // LEN 0, NLEN = ~LEN
  } else {
    writer.Flush();
  }
  strip.deflated.assign(reinterpret_cast<const char*>(deflated.get()), writer.bytes());
  return strip;
}

}  // namespace

std::string EncodePng(const Image8& image, const std::string& path) {
  CheckImageSize(image.width, image.height, path);
  if (image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    throw OutputError(path, "PNG encoding failed: pixel buffer does not match the image size");
  }
  const int strips = (image.height + kPngStripRows - 1) / kPngStripRows;
  std::vector<Strip> parts(strips);
  tbb::parallel_for(0, strips, [&](int k) {
    parts[k] = DeflateStrip(image, k * kPngStripRows,
                            std::min(image.height, (k + 1) * kPngStripRows), k == strips - 1);
  });
  std::string header;
  AppendBigEndian(static_cast<uint32_t>(image.width), &header);
  AppendBigEndian(static_cast<uint32_t>(image.height), &header);
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, filters, no interlace
  std::string data = "\x78\x01";                     // zlib header: deflate, 32 KiB window, fastest
  uLong adler = 1;
  for (const Strip& part : parts) {
    data += part.deflated;
    adler = adler32_combine(adler, part.adler, static_cast<z_off_t>(part.length));
  }
  AppendBigEndian(static_cast<uint32_t>(adler), &data);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  AppendChunk("IHDR", header, &png);
  AppendChunk("IDAT", data, &png);
  AppendChunk("IEND", "", &png);
  return png;
}

void WritePng(const std::string& path, const Image8& image) {
  const std::string png = EncodePng(image, path);
  WriteFileAtomically(
      path,
      [&](std::ostream& stream) {
        stream.write(png.data(), static_cast<std::streamsize>(png.size()));
      },
      /*binary=*/true);
}

}  // namespace brdf
