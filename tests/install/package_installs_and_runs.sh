#!/usr/bin/env bash
# `cpack -G DEB` in the build folder: the package holds the installed layout under /usr, declares
# the shared libraries the tool and its image module link (dpkg-shlibdeps), and its unpacked tree
# runs on its own: --version, and a WebP conversion through its own image module.
#   package_installs_and_runs.sh BUILD_DIR VERSION SOURCE_DIR PYTHON_MODULE_BUILT(ON|OFF)
set -euo pipefail
build=$1 version=$2 source=$3 python_module=$4
work=$(realpath "$(mktemp -d)")  # as the loader prints it
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log" >&2; exit 1; }
deb=$(ls "$work"/gltf-pbr_"$version"_*.deb)

control=$(dpkg-deb -f "$deb")
for field in "Package: gltf-pbr" "Version: $version"; do
  grep -qx "$field" <<<"$control" || { echo "control lacks '$field':" >&2; echo "$control" >&2; exit 1; }
done
# What the tool and the module link, as Debian names it: each must be a declared dependency.
depends=$(dpkg-deb -f "$deb" Depends)
for library in libspng0 libdeflate0 libturbojpeg0 libdraco7 libyaml-cpp0.7 libopenimageio2.4 libstdc++6; do
  grep -q "\b$library\b" <<<"$depends" || { echo "Depends lacks $library: $depends" >&2; exit 1; }
done
# The Python module needs the interpreter it was built for; the tool does not.
recommends=$(dpkg-deb -f "$deb" Recommends)
if [ "$python_module" = ON ]; then
  grep -q "python3 (>= 3\.[0-9]*), python3 (<< 3\.[0-9]*)" <<<"$recommends" ||
    { echo "Recommends lacks the Python the module was built for: '$recommends'" >&2; exit 1; }
fi
contents=$(dpkg-deb -c "$deb")
packaged=(./usr/bin/gltf-pbr ./usr/lib/gltf-pbr/libgltf_pbr_images.so ./usr/share/gltf-pbr/rules/materials.json
  ./usr/share/doc/gltf-pbr/README.md ./usr/include/gltf_pbr/gltf_pbr.hpp "./usr/lib/libgltf_pbr.so.$version"
  ./usr/lib/cmake/gltf_pbr/gltf_pbrConfig.cmake)
[ "$python_module" = ON ] && packaged+=("./usr/lib/python3/dist-packages/gltf_pbr.cpython-.*.so")  # a pattern: grep reads each entry as one
for file in "${packaged[@]}"; do
  grep -q " $file\$" <<<"$contents" || { echo "the package lacks $file" >&2; exit 1; }
done

dpkg-deb -x "$deb" "$work/root"
tool="$work/root/usr/bin/gltf-pbr"
reported=$("$tool" --version)
[ "$reported" = "gltf-pbr $version" ] || { echo "the packaged tool says '$reported', not $version" >&2; exit 1; }
env -u GLTF_PBR_IMAGE_MODULE LD_DEBUG=files "$tool" convert -q "$source/tests/hostile_inputs/webp_data_uri.gltf" \
  -o "$work/out/webp.gltf" 2>"$work/loader.log"
[ -s "$work/out/webp.gltf" ] || { echo "the packaged tool wrote no output" >&2; exit 1; }
grep -q "file=$work/root/usr/lib/gltf-pbr/libgltf_pbr_images.so" "$work/loader.log" ||
  { echo "the packaged tool did not load the packaged image module" >&2; exit 1; }
echo "$(basename "$deb"): control, dependencies and contents as expected; the unpacked tool ran"
