/* The pair loop's chunk functions for x86-64-v4 (AVX-512, 512-bit vectors): one per
 * (dimension, kernel, partial-sum buffer, pass), listed in
 * rates_chunks_avx512 for rates.c (rate_loop.h). */
#include "physics/rate_loop.h"

#if RATE_WIDE_PATHS
#define RATE_PATH      avx512
#define RATE_PATH_ATTR TARGET_AVX512
SPH_KERNELS(CHUNK_VARIANTS_OF_KERNEL)
const chunk_fn rates_chunks_avx512[N_KERNELS][3][2][2] = {SPH_KERNELS(CHUNK_ENTRY)};
#else
/* no avx512 path in this build (ISO C wants a declaration) */
typedef int rates_avx512_absent;
#endif
