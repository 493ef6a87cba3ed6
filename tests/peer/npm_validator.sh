#!/usr/bin/env bash
# Sourced by the peer tests: installs the npm gltf-validator (2.0.0-dev.3.10, the reference run as a
# black box) into a cache folder, never into the repo, and sets GLTF_PBR_NODE_MODULES to its
# node_modules. npm's own error (an unreachable registry, a full disk) is printed, not silenced.
validator_cache="${GLTF_PBR_CACHE:-$HOME/.cache/gltf-pbr}/validator"
if [ ! -f "$validator_cache/node_modules/gltf-validator/package.json" ]; then
  if ! npm install --prefix "$validator_cache" --no-audit --no-fund --loglevel=error gltf-validator@2.0.0-dev.3.10 >&2; then
    echo "cannot install gltf-validator@2.0.0-dev.3.10 from npm into $validator_cache: see npm's error above" >&2
    exit 1
  fi
fi
export GLTF_PBR_NODE_MODULES="$validator_cache/node_modules"
