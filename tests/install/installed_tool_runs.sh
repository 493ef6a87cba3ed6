#!/usr/bin/env bash
# `cmake --install` into a fresh prefix, then the installed tool alone: it reports the build's
# version (--version and every report), and it converts an asset whose WebP texture needs the
# image module, which it must load from the installed tree (lib/gltf-pbr, found relative to the
# executable); with that module moved away it must fail, never reach for the build tree's.
#   installed_tool_runs.sh BUILD_DIR VERSION SOURCE_DIR
set -euo pipefail
# shellcheck source=helpers.sh
. "$(dirname "$0")/helpers.sh"
build=$1
version=$2
source=$3
prefix=$(realpath "$(mktemp -d)")  # as the loader prints it
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null

for installed in bin/gltf-pbr lib/gltf-pbr/libgltf_pbr_images.so share/gltf-pbr/rules/materials.json \
  share/gltf-pbr/rules/structure.json share/gltf-pbr/rules/mesh.json share/doc/gltf-pbr/README.md; do
  [ -e "$prefix/$installed" ] || { echo "not installed: $installed" >&2; exit 1; }
done

reported=$("$prefix/bin/gltf-pbr" --version)
[ "$reported" = "gltf-pbr $version" ] || { echo "--version says '$reported', the build is $version" >&2; exit 1; }

# The dynamic loader names every file it opens (LD_DEBUG=files): the module must be the installed one.
out="$prefix/converted"
env -u GLTF_PBR_IMAGE_MODULE LD_DEBUG=files "$prefix/bin/gltf-pbr" convert -q \
  "$source/tests/hostile_inputs/webp_data_uri.gltf" -o "$out/webp.gltf" --report "$out/report.json" \
  2>"$prefix/loader.log"
[ -s "$out/webp.gltf" ] || { echo "the installed tool wrote no output" >&2; exit 1; }
if ! grep -q "file=$prefix/lib/gltf-pbr/libgltf_pbr_images.so" "$prefix/loader.log"; then
  echo "the installed tool did not load the installed image module; it loaded:" >&2
  grep -o "file=[^ ]*libgltf_pbr_images.so" "$prefix/loader.log" | sort -u >&2 || echo "  (no image module)" >&2
  exit 1
fi
if grep -q "file=$build/libgltf_pbr_images.so" "$prefix/loader.log"; then
  echo "the installed tool loaded the build tree's image module" >&2
  exit 1
fi
# One version everywhere: the convert report, and validate's report and summary.
status=0
"$prefix/bin/gltf-pbr" validate -q --format json -o "$out/validated" "$source/tests/hostile_inputs/webp_data_uri.gltf" ||
  status=$?
# 1: the file has issues, which do not matter here; anything else (a crash, a leak report) does.
[ "$status" -le 1 ] || { echo "validate ended with status $status" >&2; exit 1; }
for report in "$out/report.json" "$out/validated/summary.json"; do
  grep -q "\"version\": *\"$version\"" "$report" || { echo "$report does not carry version $version" >&2; exit 1; }
done
grep -q "\"validatorVersion\": *\"gltf-pbr $version\"" "$out/validated/webp_data_uri.gltf.report.json" ||
  { echo "the validate report does not carry version $version" >&2; exit 1; }
# Without its own module the installed tool must fail, not fall back to the build tree's.
fails_without_its_image_module "$prefix" "the installed tool" "$prefix/bin/gltf-pbr" convert -q \
  "$source/tests/hostile_inputs/webp_data_uri.gltf" -o "$out/again/webp.gltf"
echo "installed into $prefix: --version and a WebP conversion through lib/gltf-pbr ran"
