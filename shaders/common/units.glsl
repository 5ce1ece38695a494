// Texture units and buffer binding points of the preview's passes: the same numbers as renderer/gl/texture_units.h (a
// test compares the two).
#define UNIT_G_POSITION 0
#define UNIT_G_NORMAL 1
#define UNIT_G_BASE_COLOR 2
#define UNIT_G_EMISSION 3
#define UNIT_G_GEO_NORMAL 4
#define UNIT_SCENE_TEXTURES 5
#define UNIT_PASS_INPUT0 6
#define UNIT_PASS_INPUT1 7
#define UNIT_PASS_INPUT2 8
#define UNIT_PASS_INPUT3 9
#define UNIT_G_MERGE_KEY 10
#define UNIT_PASS_INPUT4 11
#define UNIT_PASS_INPUT5 12
#define UNIT_PASS_INPUT6 13
#define UNIT_PASS_INPUT7 14
#define UNIT_VISIBILITY 15
#define UNIT_LIGHT_SHADOWS 16
#define UNIT_DIRECTIONAL_SHADOWS 17
#define BINDING_SCENE_POSITIONS 0
#define BINDING_SCENE_NORMALS 1
#define BINDING_SCENE_UVS 2
#define BINDING_SCENE_TRIANGLES 3
#define BINDING_SCENE_MATERIALS 4
#define BINDING_SHADOW_CASTERS 6
#define BINDING_DIRECT_LIGHTS 7
#define BINDING_VPLS 8
