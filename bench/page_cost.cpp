// What a fresh page costs on this machine, the fact behind core/pages.h and core/mapped_file.h
// (docs/performance.md, *Fresh pages*): milliseconds per MiB of a new anonymous mapping first
// written one byte a page, on one thread and on two; populated with MADV_POPULATE_WRITE and then
// touched; through PrefaultPages (the product's way, every core); advised for transparent huge
// pages; and a file read into a new buffer against the same file mapped (MappedFile). Each way
// runs `--rounds` times in turn with the others, after a pause of `--pause` seconds (on a
// virtual machine whose balloon reports free memory to the host, the host reclaims freed pages
// about two seconds after they are freed); the medians are printed, one CSV row a way.
//
//   page_cost [--mib N] [--rounds R] [--pause S] [--file PATH]
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "core/mapped_file.h"
#include "core/pages.h"

namespace {

using Clock = std::chrono::steady_clock;

// Writes one byte a page of [data, data + bytes) on `threads` threads, each a contiguous part.
void Touch(unsigned char* data, size_t bytes, int threads) {
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  std::vector<std::thread> workers;
  const size_t part = (bytes / threads + page - 1) / page * page;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([=] {
      const size_t end = std::min(bytes, (t + 1) * part);
      for (size_t offset = t * part; offset < end; offset += page) {
        reinterpret_cast<volatile unsigned char*>(data)[offset] = 1;
      }
    });
  }
  for (std::thread& worker : workers) worker.join();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  size_t mib = 128;
  int rounds = 5;
  double pause = 3.0;
  std::string file;
  for (int k = 1; k < argc; ++k) {
    const std::string argument = argv[k];
    auto value = [&](const char* name) -> const char* {
      if (k + 1 >= argc) {
        std::fprintf(stderr, "page_cost: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++k];
    };
    if (argument == "--mib") {
      mib = std::strtoul(value("--mib"), nullptr, 10);
    } else if (argument == "--rounds") {
      rounds = std::atoi(value("--rounds"));
    } else if (argument == "--pause") {
      pause = std::atof(value("--pause"));
    } else if (argument == "--file") {
      file = value("--file");
    } else {
      std::fprintf(stderr,
                   "usage: page_cost [--mib N] [--rounds R] [--pause S] [--file PATH]\n"
                   "  a file of about N MiB is written to a temporary path unless --file\n");
      return argument == "--help" ? 0 : 2;
    }
  }
  if (mib < 1 || rounds < 1 || pause < 0) {
    std::fprintf(stderr, "page_cost: --mib and --rounds must be at least 1, --pause >= 0\n");
    return 2;
  }
  const size_t bytes = mib << 20;
  std::string scratch;
  if (file.empty()) {
    char path[] = "/tmp/brdfkit-page-cost-XXXXXX";
    const int descriptor = mkstemp(path);
    if (descriptor < 0) {
      std::perror("page_cost: temporary file");
      return 1;
    }
    close(descriptor);
    scratch = file = path;
    std::ofstream out(file, std::ios::binary);
    const std::vector<char> block(1 << 20, 7);
    for (size_t k = 0; k < mib; ++k) out.write(block.data(), block.size());
  }

  // Each way gets a fresh anonymous mapping and returns the seconds it took to fault it in.
  using Way = std::function<double(unsigned char*)>;
  auto timed = [](const std::function<void()>& work) {
    const auto start = Clock::now();
    work();
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  const std::vector<std::pair<std::string, Way>> ways = {
      {"first write, 1 thread",
       [&](unsigned char* p) { return timed([&] { Touch(p, bytes, 1); }); }},
      {"first write, 2 threads",
       [&](unsigned char* p) { return timed([&] { Touch(p, bytes, 2); }); }},
      {"MADV_POPULATE_WRITE then first write, 1 thread",
       [&](unsigned char* p) {
         return timed([&] {
#if defined(MADV_POPULATE_WRITE)
           madvise(p, bytes, MADV_POPULATE_WRITE);
#endif
           Touch(p, bytes, 1);
         });
       }},
      {"PrefaultPages (every core)",
       [&](unsigned char* p) { return timed([&] { brdf::PrefaultPages(p, bytes); }); }},
      {"huge pages advised, PrefaultPages",
       [&](unsigned char* p) {
         return timed([&] {
           madvise(p, bytes, MADV_HUGEPAGE);
           brdf::PrefaultPages(p, bytes);
         });
       }},
      {"huge pages advised, first write, 1 thread",
       [&](unsigned char* p) {
         return timed([&] {
           madvise(p, bytes, MADV_HUGEPAGE);
           Touch(p, bytes, 1);
         });
       }},
  };
  std::map<std::string, std::vector<double>> seconds;
  for (int round = 0; round < rounds; ++round) {
    for (const auto& [name, way] : ways) {
      std::this_thread::sleep_for(std::chrono::duration<double>(pause));
      // 2 MiB of slack so that the huge-page way can start on a 2 MiB boundary.
      void* mapping = mmap(nullptr, bytes + (2 << 20), PROT_READ | PROT_WRITE,
                           MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (mapping == MAP_FAILED) {
        std::perror("page_cost: mmap");
        return 1;
      }
      const uintptr_t aligned =
          (reinterpret_cast<uintptr_t>(mapping) + (2 << 20) - 1) & ~uintptr_t((2 << 20) - 1);
      seconds[name].push_back(way(reinterpret_cast<unsigned char*>(aligned)));
      munmap(mapping, bytes + (2 << 20));
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(pause));
    seconds["file read into a new buffer"].push_back(timed([&] {
      std::vector<char> buffer;
      std::ifstream in(file, std::ios::binary | std::ios::ate);
      buffer.resize(static_cast<size_t>(in.tellg()));
      in.seekg(0);
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    }));
    std::this_thread::sleep_for(std::chrono::duration<double>(pause));
    seconds["file mapped (MappedFile) and read a byte a page"].push_back(timed([&] {
      const auto mapped = brdf::MappedFile::Open(file);
      if (mapped == nullptr) return;
      unsigned sum = 0;
      for (size_t offset = 0; offset < mapped->size(); offset += 4096)
        sum += mapped->data()[offset];
      asm volatile("" : : "r"(sum));  // keeps the reads
    }));
  }
  if (!scratch.empty()) std::remove(scratch.c_str());

  std::printf("way,ms_per_mib_median,rounds,mib,pause_s\n");
  auto row = [&](const std::string& name) {
    std::printf("\"%s\",%.3f,%d,%zu,%g\n", name.c_str(), 1e3 * Median(seconds[name]) / mib, rounds,
                mib, pause);
  };
  for (const auto& [name, way] : ways) row(name);
  row("file read into a new buffer");
  row("file mapped (MappedFile) and read a byte a page");
  return 0;
}
