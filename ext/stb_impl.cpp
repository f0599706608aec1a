// The one translation unit that compiles stb's image writer (PNG output). Images are
// read by src/core/imagefile.cpp, not by stb_image: see there why.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
