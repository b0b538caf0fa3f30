// The project's one SIMD idiom (src/hdr/README.md, docs/performance.md): the build targets
// baseline x86-64 (4-wide SSE2) or any other processor, and nothing is tuned to the build
// machine. Loops are written so that the compiler vectorizes them; where a hand-written wider
// version earned its place by a measured gain, it is an AVX2 function (BRDF_AVX2: compiled for
// AVX2 alone by a function attribute, x86 intrinsics or the same lane code widened by the
// compiler) chosen at run time by Avx2Enabled(), beside its portable twin. Each does the float
// operations of its twin in the same order and with the same rounding (no fused multiply-add:
// FMA is not enabled for them), so the bytes are the same either way; the tests run both paths
// and compare.
#pragma once

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define BRDF_HAS_AVX2_PATHS 1
// Compiles one function for AVX2 (and the SSE levels below it), not for FMA.
#define BRDF_AVX2 __attribute__((target("avx2")))
#else
#define BRDF_HAS_AVX2_PATHS 0
#define BRDF_AVX2
#endif

namespace brdf {

// Whether the AVX2 paths run: the processor has AVX2 and they have not been switched off.
bool Avx2Enabled();
// Switches the AVX2 paths off (false) or back on where the processor has them; returns
// whether they were on. For tests and benchmarks that compare the paths; not thread-safe
// against work running at the same time.
bool SetAvx2Enabled(bool enabled);

}  // namespace brdf
