/* The pair loop's chunk functions for the baseline instruction set (the
 * build's target): one per (dimension, kernel, partial-sum buffer, pass),
 * listed in rates_chunks_base for rates.c (rate_loop.h). */
#include "physics/rate_loop.h"

#define RATE_PATH base
#define RATE_PATH_ATTR
SPH_KERNELS(CHUNK_VARIANTS_OF_KERNEL)
const chunk_fn rates_chunks_base[N_KERNELS][3][2][2] = {SPH_KERNELS(CHUNK_ENTRY)};
