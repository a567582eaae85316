/* The TAA program (python/restircl/core/side_programs.py TAA): temporal accumulation, built with only the defines
 * its code reads (the surface and material tests of its history), so that feature variants which differ in others
 * share it. */
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/eval.h"
#include "surface/surface.h"
#include "guards.h"
#include "camera/reproject.h"
#include "surface/view_dependence.h"
#include "taa/sweep.h"
#include "taa/fresh_fill.h"
#include "taa/clip_box.h"
#include "taa/taa.cl"
