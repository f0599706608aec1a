#!/usr/bin/env bash
# Installs the Debian 12 packages needed to build and render, skipping those already
# installed (so it is quick to run again). Run as root or with sudo.
#   scripts/install-deps.sh          what building and rendering need
#   scripts/install-deps.sh --test   also the test tools: Catch2, clang with libFuzzer, Slurm,
#                                    Chromium, Blender
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail

packages=(
    build-essential cmake   # compiler and build system
    ninja-build             # the build tool: recompiles a file only when its command changes
    libeigen3-dev           # vectors, matrices, colours
    libpugixml-dev          # XML scene files
    libstb-dev              # PNG writing
    libpng-dev              # PNG reading (textures)
    libjpeg62-turbo-dev     # JPEG reading (textures)
    libtinyexr-dev          # EXR reading and writing
    libtbb-dev              # parallel render loop
    libfmt-dev              # message formatting
    pkg-config libcpp-httplib-dev  # the HTTP server of the browser preview (--preview)
    libnanovdb-dev          # NanoVDB grid files of heterogeneous media (header-only)
    libcli11-dev            # the programs' command lines (header-only)
    zlib1g-dev              # compressed meshes: .ply.gz, Mitsuba's serialized files
    libtinygltf-dev         # glTF 2.0 assets (the gltf shape)
)
if [ "${1:-}" = "--test" ]; then
    packages+=(
        catch2              # unit and statistical tests
        clang               # the fuzz targets' compiler ...
        libclang-rt-14-dev  # ... and its libFuzzer, ASan and UBSan runtimes
        util-linux          # prlimit: the bad-input corpus's out-of-memory case, failed writes
        slurm-wlm munge     # the split-render test's one-node Slurm cluster
        chromium chromium-driver python3-selenium  # the preview's headless-browser test
        blender             # the exporter's test: Blender builds, exports and renders (Cycles)
    )
elif [ -n "${1:-}" ]; then
    echo "usage: $0 [--test]" >&2
    exit 2
fi

missing=()
for package in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done

if ((${#missing[@]} > 0)); then
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        sudo="sudo"
    fi
    echo "Installing: ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
