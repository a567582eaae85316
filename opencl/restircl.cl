/* The whole program: headers in dependency order, then one file per pass. The host compiles it with -D feature
 * flags derived from the scene and the settings (features.py), so a scene builds only the code it needs. */
#include "types.h"
#include "rng.h"
#include "bvh.h"
#include "camera.h"
#include "lights.h"
#include "light_array.h"
#include "reservoir.h"
#include "shading.h"
#include "reproject.h"

#include "primary.cl"
#include "direct.cl"
#include "restir_initial.cl"
#include "restir_temporal.cl"
#include "restir_spatial.cl"
#include "restir_shade.cl"
#include "taa.cl"
