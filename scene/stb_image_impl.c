/* stb_image's implementation, compiled once (Debian's libstb-dev ships the
 * single header only).  Its own translation unit so that sanitizer builds can
 * exempt it from the two checks its code trips by design: a PNG with an empty
 * IDAT chunk first makes stb_image compute NULL + 0 and then memcpy 0 bytes
 * to NULL (stb_image.h, the IDAT case of stbi__parse_png_file and
 * stbi__getn), undefined in C but harmless; the fuzzer found it
 * (fuzz/regressions/texture/).  scene/CMakeLists.txt turns off
 * -fsanitize=pointer-overflow,nonnull-attribute for this file only; every
 * other check, ASan's included, stays. */
#define STB_IMAGE_IMPLEMENTATION
#include "stb_image_config.h"
