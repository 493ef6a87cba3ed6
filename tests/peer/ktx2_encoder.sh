#!/usr/bin/env bash
# Sourced by the KTX2 tests: installs ktx2-encoder from npm (0.6.0: Binomial's basis_universal encoder
# built to WebAssembly, the one glTF-Transform's ktx2 transform can use) into a cache folder, never
# into the repo, and sets GLTF_PBR_KTX2_ENCODER to its Node entry point. npm's own error is printed.
ktx2_cache="${GLTF_PBR_CACHE:-$HOME/.cache/gltf-pbr}/ktx2-encoder"
export GLTF_PBR_KTX2_ENCODER="$ktx2_cache/node_modules/ktx2-encoder/dist/node/index.js"
if [ ! -f "$GLTF_PBR_KTX2_ENCODER" ]; then
  if ! npm install --prefix "$ktx2_cache" --no-audit --no-fund --loglevel=error ktx2-encoder@0.6.0 >&2; then
    echo "cannot install ktx2-encoder@0.6.0 from npm into $ktx2_cache: see npm's error above" >&2
    exit 1
  fi
fi
