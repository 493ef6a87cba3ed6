#!/usr/bin/env bash
# Sourced by the meshopt tests: installs gltfpack from npm (1.3.0, meshoptimizer's own packer, the
# maker of EXT_meshopt_compression test assets) into a cache folder, never into the repo, and sets
# GLTF_PBR_GLTFPACK to its command. npm's own error is printed, not silenced.
gltfpack_cache="${GLTF_PBR_CACHE:-$HOME/.cache/gltf-pbr}/gltfpack"
if [ ! -x "$gltfpack_cache/node_modules/.bin/gltfpack" ]; then
  if ! npm install --prefix "$gltfpack_cache" --no-audit --no-fund --loglevel=error gltfpack@1.3.0 >&2; then
    echo "cannot install gltfpack@1.3.0 from npm into $gltfpack_cache: see npm's error above" >&2
    exit 1
  fi
fi
export GLTF_PBR_GLTFPACK="$gltfpack_cache/node_modules/.bin/gltfpack"
