# Lookup of the system packages (Debian 12). Each area of src/ links the ones it uses
# (src/CMakeLists.txt).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(pugixml REQUIRED)
find_package(TBB REQUIRED)
find_package(fmt REQUIRED)
find_package(tinyexr REQUIRED)
find_path(STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb REQUIRED)
# Image decoding: libpng and libjpeg-turbo rather than stb_image (see src/image/imagefile.cpp).
find_package(PNG REQUIRED)
find_package(JPEG REQUIRED)
find_package(Threads REQUIRED)
# zlib: compressed meshes (.ply.gz, Mitsuba's `serialized` files).
find_package(ZLIB REQUIRED)
# tinygltf: glTF 2.0 assets (the `gltf` shape); its JSON parsing and buffer fetching.
find_package(TinyGLTF REQUIRED)
# CLI11 (header-only): the programs' command lines.
find_package(CLI11 2 REQUIRED)
# The HTTP server of the browser preview (nori --preview). Debian builds cpp-httplib as a
# shared library whose classes change with its feature macros (OpenSSL, zlib, Brotli), so
# its flags come from its pkg-config file rather than being guessed.
find_package(PkgConfig REQUIRED)
# NanoVDB (libnanovdb-dev, header-only): heterogeneous media read its grid files.
find_path(NANOVDB_INCLUDE_DIR nanovdb/NanoVDB.h REQUIRED)
add_library(nori_nanovdb INTERFACE)
target_include_directories(nori_nanovdb SYSTEM INTERFACE ${NANOVDB_INCLUDE_DIR})
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)

# stb's image writer is compiled once, here, with our own flags.
add_library(nori_stb STATIC ${CMAKE_CURRENT_LIST_DIR}/stb_impl.cpp)
target_include_directories(nori_stb SYSTEM PUBLIC ${STB_INCLUDE_DIR})
# stb_image_write's JPEG encoder (used by the tests to make JPEG files) left-shifts
# negative values, which UBSan reports; that is stb's arithmetic, not ours.
target_compile_options(nori_stb PRIVATE -w -fno-sanitize=shift)
