#!/usr/bin/env bash
# The error models judged under environments neither was built around (issue 12): Blender's eight
# studio-light worlds (city, courtyard, forest, interior, night, studio, sunrise, sunset; CC0,
# Poly Haven, from Debian's blender-data, installed when missing), beside the built-in sky and the
# neutral white furnace. Each runs gltf-pbr-appearance-bench: the shared assets and the grey
# spheres drawn before and after both models' conversions, lit by that environment alone.
# Usage: bench/preview/appearance_environments.sh [BUILD_DIR] [SIZE]   (default build-bench, 256)
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build-bench}
size=${2:-256}
worlds=/usr/share/blender/datafiles/studiolights/world
if [ ! -d "$worlds" ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq blender-data >/dev/null
fi
cmake --build "$build" -j2 --target gltf-pbr-appearance-bench >/dev/null
for environment in sky neutral "$worlds"/*.exr; do
  echo "## $(basename "$environment")"
  "$build/preview/gltf-pbr-appearance-bench" "$root/../shared/assets" "$size" "$environment"
  echo
done
