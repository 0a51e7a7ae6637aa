// Constants of the CDT algorithm shared with C++: the other definition of each is in
// sim/cdt/CdtConstants.h, and tests/test_cdt_cpu.cpp fails if the two differ. Values only here.
const int CDT_MAX_LAYERS = 4;
const int CDT_MAX_TEXEL_RANGE = 16;
const float CDT_EMPTY_TEXEL = -1.0;
const uint CDT_MAX_ID = 16777216u;
const uint CDT_NO_PARTNER = 0xFFFFFFFFu;
const uint CDT_OFFSCREEN = 0xFFFFFFFFu;

const int CDT_FLAG_INTEGRATE = 1;
const int CDT_FLAG_TEXEL_POSITION = 2;
const int CDT_FLAG_ADAPTIVE_RANGE = 4;
const int CDT_FLAG_PAPER_RESPONSE = 8;
const int CDT_FLAG_TEXTURE_VALID = 16;

const int CDT_ATTRIB_POSITION_TIME = 0;
const int CDT_ATTRIB_VELOCITY = 1;
const int CDT_ATTRIB_ID = 2;
const int CDT_ATTRIB_ACCELERATION = 3;
const int CDT_PARAMS_BINDING = 0;
const int CDT_LAYER_UNIT = 0;
const int CDT_PEEL_DEPTH_UNIT = 4;
const int CDT_PEEL_INDEX_UNIT = 5;
const int CDT_IMAGE_COLOUR = 0;
const int CDT_IMAGE_DEPTH_KEY = 1;
const int CDT_IMAGE_INDEX_KEY = 2;
const int CDT_IMAGE_PREVIOUS_DEPTH = 3;
const int CDT_IMAGE_PREVIOUS_INDEX = 4;
const int CDT_PARTICLE_BINDING = 0;
const int CDT_WRITE_KEY_BINDING = 1;
const int CDT_WRITE_GROUP_SIZE = 64;
