// The C++ side of the Python calling-overhead benchmark (bench/python_api, docs/python.md): the
// plain loop over Model::Eval that brdfkit.Model.eval wraps, on the same direction pairs.
//
// Usage: bench_model_eval MODEL PAIRS.f64 REPEATS
//   PAIRS.f64: N rows of (wi, wo), six float64 each, native byte order (numpy's tofile).
// Prints the wall time of each repeat in seconds, one per line, and last the sum of every f
// (so the loop cannot be optimised away, and so that Python can check it evaluated the same).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "models/model_source.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: bench_model_eval MODEL PAIRS.f64 REPEATS\n";
    return 2;
  }
  const brdf::Model model = brdf::LoadModel(argv[1]);
  std::ifstream in(argv[2], std::ios::binary | std::ios::ate);
  const std::streamsize bytes = in.tellg();
  in.seekg(0);
  std::vector<double> pairs(static_cast<size_t>(bytes) / sizeof(double));
  in.read(reinterpret_cast<char*>(pairs.data()), bytes);
  const size_t count = pairs.size() / 6;
  std::vector<double> f(3 * count);
  const int repeats = std::stoi(argv[3]);
  for (int repeat = 0; repeat < repeats; ++repeat) {
    const auto start = std::chrono::steady_clock::now();
    for (size_t k = 0; k < count; ++k) {
      const double* row = &pairs[6 * k];
      const brdf::Rgb value =
          model.Eval(brdf::Vec3(row[0], row[1], row[2]), brdf::Vec3(row[3], row[4], row[5]));
      for (int c = 0; c < 3; ++c) f[3 * k + c] = value[c];
    }
    std::printf("%.9f\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  double sum = 0;
  for (double value : f) sum += value;
  std::printf("%.17g\n", sum);
  return 0;
}
