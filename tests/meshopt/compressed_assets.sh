#!/usr/bin/env bash
# EXT_meshopt_compression on real assets: gltfpack (npm) packs every shared spec-gloss asset twice,
# with and without compression, and compressed_assets.py checks that gltf-pbr validates, previews
# and converts the compressed one as it does its uncompressed twin.
#   compressed_assets.sh GLTF_PBR_CLI SHARED_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../peer/gltfpack.sh"
# The script keeps its scratch folder itself: exec leaves no shell to run an EXIT trap.
exec /usr/bin/python3 "$here/compressed_assets.py" "$1" "$2" "$GLTF_PBR_GLTFPACK"
