// The vector paths of the HDR pipeline's hot loops (docs/hdr.md, *Vector paths*). The build
// targets baseline x86-64 (4-wide SSE2); where the processor has AVX2, the loops that dominate
// the pipeline take 8-wide versions compiled for AVX2 alone (a function attribute) and chosen
// at run time. Each does the float operations of its scalar twin in the same order and with
// the same rounding (no fused multiply-add: FMA is not enabled for them), so the bytes are the
// same either way; the tests run both paths and compare.
#pragma once

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define BRDF_HDR_HAS_AVX2_PATHS 1
// Compiles one function for AVX2 (and the SSE levels below it), not for FMA.
#define BRDF_HDR_AVX2 __attribute__((target("avx2")))
#else
#define BRDF_HDR_HAS_AVX2_PATHS 0
#define BRDF_HDR_AVX2
#endif

namespace brdf {

// Whether the AVX2 paths run: the processor has AVX2 and they have not been switched off.
bool HdrAvx2Enabled();
// Switches the AVX2 paths off (false) or back on where the processor has them; returns
// whether they were on. For tests and benchmarks that compare the paths; not thread-safe
// against a pipeline running at the same time.
bool SetHdrAvx2Enabled(bool enabled);

}  // namespace brdf
