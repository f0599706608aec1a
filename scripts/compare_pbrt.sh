#!/usr/bin/env bash
# Renders pbrt-v4 scenes with pbrt-v4 and with nori from the same file, and compares them
# region by region (nori-imgtool compare --grid 4: the whole image and a 4 × 4 grid, per
# channel, in standard errors of nori's render; pbrt-v4's, at 4× the samples, is taken
# as the reference).
#   scripts/compare_pbrt.sh PBRT [--size N] [--spp N] [--grey] SCENE.pbrt...
# --size N  renders at N × N pixels (default 100; the scene's aspect is not kept)
# --spp N   nori's samples per pixel (default 256; pbrt-v4 renders 4N)
# --grey    also renders a grey copy of each scene, every "rgb" colour replaced by its
#           luminance: what remains of a difference there is not spectral against RGB
# Prints, per scene, the compare tool's table. Needs python3 for --grey.
# --help (or -h) prints the comment above and exits.
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
set -euo pipefail
pbrt=$(realpath "$1")
shift
size=100 spp=256 grey=0 scenes=()
while (($#)); do
    case "$1" in
    --size) size=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --grey) grey=1; shift ;;
    *) scenes+=("$(realpath "$1")"); shift ;;
    esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
nori=$root/build/nori imgtool=$root/build/nori-imgtool
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

compare() { # NAME FILE: a renderer that fails is reported, and the next scene follows
    local name=$1 file=$2 status=0
    echo "== $name"
    "$pbrt" --quiet --nthreads 2 --spp $((4 * spp)) --seed 1 --outfile "$work/$name-pbrt.exr" \
        "$file" || status=$?
    if ((status)); then echo "pbrt-v4 failed (exit status $status)"; return; fi
    "$nori" "$file" --spp "$spp" --aovs variance --no-progress -o "$work/$name-nori" \
        >"$work/$name-nori.log" 2>&1 || status=$?
    if ((status)); then echo "nori failed (exit status $status):"; cat "$work/$name-nori.log"; return; fi
    "$imgtool" compare "$work/$name-nori.exr" "$work/$name-pbrt.exr" --grid 4 || true
}

for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .pbrt)
    # A copy at the size asked for, in a folder that links to everything beside the
    # scene (meshes, spectra, textures), so that its relative names resolve.
    copy=$work/$name
    mkdir -p "$copy"
    for entry in "$(dirname "$scene")"/*; do
        [[ "$entry" == "$scene" ]] || ln -sf "$entry" "$copy/"
    done
    small=$copy/$name.pbrt
    sed -e "s/\"integer xresolution\" *\[ *[0-9]* *\]/\"integer xresolution\" [$size]/" \
        -e "s/\"integer yresolution\" *\[ *[0-9]* *\]/\"integer yresolution\" [$size]/" \
        "$scene" >"$small"
    compare "$name" "$small"
    if ((grey)); then
        python3 - "$small" <<'EOF'
import re, sys
path = sys.argv[1]
text = open(path).read()
def luminance(match):
    r, g, b = (float(x) for x in match.group(2).split())
    y = 0.2126 * r + 0.7152 * g + 0.0722 * b
    return f'{match.group(1)} [ {y:.6g} {y:.6g} {y:.6g} ]'
text = re.sub(r'("rgb [A-Za-z_.]+")\s*\[\s*([-0-9.eE+]+\s+[-0-9.eE+]+\s+[-0-9.eE+]+)\s*\]', luminance, text)
open(path, 'w').write(text)
EOF
        compare "$name-grey" "$small"
    fi
done
