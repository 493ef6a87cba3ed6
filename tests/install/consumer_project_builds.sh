#!/usr/bin/env bash
# The README's "Use it from C++" example as a project of its own, configured with
# find_package(gltf_pbr) against a `cmake --install` tree, built and run on a real spec-gloss asset,
# then on a WebP-textured one, whose image module must come from the installed tree. The installed
# headers name no third-party library. When the Python module is built, the installed copy must
# import from the prefix, with the prefix's library.
#   consumer_project_builds.sh BUILD_DIR VERSION SOURCE_DIR SHARED_DIR CXX_FLAGS PYTHON_OR_EMPTY
set -euo pipefail
build=$1 version=$2 source=$3 shared=$4 cxx_flags=$5 python=$6
# shellcheck source=helpers.sh
. "$(dirname "$0")/helpers.sh"
prefix=$(realpath "$(mktemp -d)")  # as the loader prints it
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null

for installed in include/gltf_pbr/gltf_pbr.hpp include/gltf_pbr/error.hpp include/gltf_pbr/export.hpp \
  lib/libgltf_pbr.so "lib/libgltf_pbr.so.$version" lib/cmake/gltf_pbr/gltf_pbrConfig.cmake \
  lib/cmake/gltf_pbr/gltf_pbrConfigVersion.cmake lib/cmake/gltf_pbr/gltf_pbrTargets.cmake; do
  [ -e "$prefix/$installed" ] || { echo "not installed: $installed" >&2; exit 1; }
done
if grep -nE '#include *[<"](tiny_gltf|OpenImageIO|nlohmann|glm|draco|CGAL)' "$prefix"/include/gltf_pbr/*; then
  echo "a public header includes a third-party library" >&2
  exit 1
fi

project="$prefix/consumer"
mkdir -p "$project"
readme_example "$source/README.md" consumer/CMakeLists.txt >"$project/CMakeLists.txt"
readme_example "$source/README.md" consumer/main.cpp >"$project/main.cpp"
[ -s "$project/CMakeLists.txt" ] && [ -s "$project/main.cpp" ] || { echo "the README lost its C++ example" >&2; exit 1; }
cmake -S "$project" -B "$project/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_FLAGS="$cxx_flags" \
  >"$project/configure.log" 2>&1 || { cat "$project/configure.log" >&2; exit 1; }
cmake --build "$project/build" >"$project/build.log" 2>&1 || { cat "$project/build.log" >&2; exit 1; }
example="$project/build/convert_one"
linked=$(ldd "$example")  # whole, before grep: grep -q may stop reading early (SIGPIPE under pipefail)
grep -q "libgltf_pbr.so.* => $prefix/lib/libgltf_pbr.so" <<<"$linked" ||
  { echo "the example does not link the installed library:" >&2; echo "$linked" >&2; exit 1; }

# Duck: one spec-gloss material, converted; the result has no validation error (its texture's
# albedo and its mesh's self-intersections are warnings of the asset's own).
"$example" "$shared/assets/Duck/specgloss/Duck.gltf" "$prefix/out/Duck.gltf" >"$prefix/duck.txt"
head -1 "$prefix/duck.txt" | grep -qx "converted 1 materials" ||
  { echo "the example printed:" >&2; cat "$prefix/duck.txt" >&2; exit 1; }
grep -q '"outcome": "metalness"' "$prefix/duck.txt" || { echo "no metalness outcome in the report" >&2; exit 1; }
grep -qxE "validated: 0 errors, [0-9]+ warnings" "$prefix/duck.txt" ||
  { echo "the converted Duck has validation errors:" >&2; tail -1 "$prefix/duck.txt" >&2; exit 1; }

# A WebP texture needs the image module: the installed library must find the installed one.
env -u GLTF_PBR_IMAGE_MODULE LD_DEBUG=files "$example" "$source/tests/hostile_inputs/webp_data_uri.gltf" \
  "$prefix/out/webp.gltf" >"$prefix/webp.txt" 2>"$prefix/webp-loader.log" ||
  { echo "the example failed on a WebP texture:" >&2; grep -v "^ *[0-9]*:" "$prefix/webp-loader.log" >&2; exit 1; }
grep -q "file=$prefix/lib/gltf-pbr/libgltf_pbr_images.so" "$prefix/webp-loader.log" ||
  { echo "the installed library did not load the installed image module" >&2; exit 1; }

# Without its own module the installed library must fail, not reach for the build tree's.
fails_without_its_image_module "$prefix" "the installed library" "$example" \
  "$source/tests/hostile_inputs/webp_data_uri.gltf" "$prefix/out/webp-again.gltf"

# Bad input: InputError with the file and the reason, exit 1.
status=0
"$example" "$prefix/missing.gltf" "$prefix/out/missing.gltf" 2>"$prefix/missing.txt" || status=$?
[ "$status" -eq 1 ] && grep -q "^$prefix/missing.gltf: " "$prefix/missing.txt" ||
  { echo "a missing input gave status $status and:" >&2; cat "$prefix/missing.txt" >&2; exit 1; }

if [ -n "$python" ]; then
  # The module's version, then the files mapped into the process: the library must be the prefix's.
  env PYTHONPATH="$prefix/lib/python3/dist-packages" "$python" -c \
    'import gltf_pbr; print(gltf_pbr.__version__); print(open("/proc/self/maps").read())' >"$prefix/python.txt"
  reported=$(head -1 "$prefix/python.txt")
  [ "$reported" = "$version" ] || { echo "the installed module says '$reported', not $version" >&2; exit 1; }
  grep -q " $prefix/lib/libgltf_pbr.so" "$prefix/python.txt" ||
    { echo "the installed Python module did not load the installed library" >&2; exit 1; }
  grep -q " $prefix/lib/python3/dist-packages/gltf_pbr" "$prefix/python.txt" ||
    { echo "python3 imported another gltf_pbr module" >&2; exit 1; }
fi
echo "the README's C++ example built against $prefix and ran${python:+; the installed Python module imported}"
