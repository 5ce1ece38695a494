// The VPL visibility technique the gather was compiled with (renderer/gl/vpl_visibility.h): exactly one of
// VISIBILITY_CUBE and VISIBILITY_ISM is defined by the renderer.
#include "common/units.glsl"
#if defined(VISIBILITY_ISM)
#include "common/visibility_ism.glsl"
#elif defined(VISIBILITY_CUBE)
#include "common/visibility_cube.glsl"
#else
#error "no VPL visibility technique defined"
#endif
