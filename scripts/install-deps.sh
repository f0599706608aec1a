#!/usr/bin/env bash
# Installs the Debian 12 packages needed to build and test the renderer, skipping
# those already installed (so it is quick to run again). Run as root or with sudo.
set -euo pipefail

packages=(
    build-essential cmake   # compiler and build system
    libeigen3-dev           # vectors, matrices, colours
    libpugixml-dev          # XML scene files
    libstb-dev              # PNG/JPEG/HDR reading, PNG writing
    libtinyexr-dev          # EXR reading and writing
    libtbb-dev              # parallel render loop
    libfmt-dev              # message formatting
    catch2                  # unit and statistical tests
)

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
