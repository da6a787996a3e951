/* The pair loop's chunk functions for x86-64-v3 (AVX2, FMA): one per
 * (dimension, kernel, partial-sum buffer, pass), listed in
 * rates_chunks_avx2 for rates.c (rate_loop.h). */
#include "physics/rate_loop.h"

#if RATE_WIDE_PATHS
#define RATE_PATH      avx2
#define RATE_PATH_ATTR TARGET_AVX2
SPH_KERNELS(CHUNK_VARIANTS_OF_KERNEL)
const chunk_fn rates_chunks_avx2[N_KERNELS][3][2][2] = {SPH_KERNELS(CHUNK_ENTRY)};
#else
/* no avx2 path in this build (ISO C wants a declaration) */
typedef int rates_avx2_absent;
#endif
