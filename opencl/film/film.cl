/* The film program: the kernels that sum a still's samples and passes, whose code reads no feature flag. The host
 * builds it once per device (python/restircl/core/program.py film_program) and every renderer's Kernels launches
 * these from it, so that the renderer's program, built per set of feature flags, does not compile them again. A
 * kernel that needs a feature flag belongs in restircl.cl. */
#include "types.h"

#include "still/accumulate.cl"
#include "still/holdout.cl"
#include "still/layers.cl"
#include "film/cryptomatte.cl"
