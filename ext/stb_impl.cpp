// The one translation unit that compiles stb's image reader and writer.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image.h>
#include <stb_image_write.h>

/// Clears stb_image's last failure reason. stb keeps it from one failure to the next and
/// some failures set none, so a caller that does not clear it may report a stale reason.
void noriClearStbFailureReason() {
    stbi__g_failure_reason = nullptr;
}
