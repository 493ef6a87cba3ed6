#!/usr/bin/env bash
# KTX2 images from a real encoder: ktx2-encoder (npm, basis_universal) encodes the textures of shared
# assets as a pipeline would, and encoded_images.py checks what gltf-pbr validate says of them.
#   encoded_images.sh GLTF_PBR_CLI SHARED_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../peer/ktx2_encoder.sh"
# The script keeps its scratch folder itself: exec leaves no shell to run an EXIT trap.
exec /usr/bin/python3 "$here/encoded_images.py" "$1" "$2" "$here/../peer/ktx2_encode.mjs"
