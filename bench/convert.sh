#!/usr/bin/env bash
# Benchmark of `gltf-pbr convert` against glTF-Transform `metalrough` (npm, installed into a cache
# folder by peers.sh), in one run on this machine, over every spec-gloss asset in ../shared/assets.
# Ours and the peer's runs alternate. Prints markdown: median wall and CPU time of RUNS runs and the
# ratio, peak memory, output bytes, and the error a core-only viewer and a full viewer see in each
# output (gltf-pbr compare); the same for Avocado with its maps resized to SIZES (sharp, from the
# peer's install) and the cost per added Mtexel; then error against time for each solver setting.
#   bench/convert.sh [SHARED_DIR]        (RUNS=5, SIZES=512,1024,2048,4096 by default; SIZES= skips;
#                                        the shared Avocado is a point of the growth table too)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$here/.."
shared="${1:-$root/../shared}"
command -v /usr/bin/time >/dev/null || { apt-get install -y -qq time >/dev/null; }
eval "$("$here/peers.sh")"
# A release build of our own, apart from the test builds.
cmake -S "$root" -B "$root/build-bench" -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLTF_PBR_TESTS=OFF >/dev/null
cmake --build "$root/build-bench" >/dev/null
GLTF_PBR="$root/build-bench/gltf-pbr" GLTF_TRANSFORM="$GLTF_TRANSFORM" GLTF_TRANSFORM_VERSION="$GLTF_TRANSFORM_VERSION" \
  GLTF_PBR_NODE_MODULES="$GLTF_PBR_NODE_MODULES" RUNS="${RUNS:-5}" SIZES="${SIZES-512,1024,2048,4096}" \
  node "$here/convert.mjs" "$shared/assets"
