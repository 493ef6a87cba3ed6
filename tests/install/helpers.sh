# Shell functions the install tests share.

# Prints the fenced code block that follows "<!-- example: NAME -->" in a Markdown file, so tests
# run the README's examples exactly as written.
#   readme_example FILE NAME
readme_example() {
  awk -v marker="<!-- example: $2 -->" '
    $0 == marker { found = 1; next }
    found && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$1"
}

# An installed program (the tool, or a program linking the installed library) with the installed
# image module moved away must fail on a WebP texture, say why, and load no other module (never
# the build tree's). The module is put back afterwards.
#   fails_without_its_image_module PREFIX WHAT COMMAND...   (COMMAND converts a WebP-textured asset)
fails_without_its_image_module() {
  local prefix=$1 what=$2
  shift 2
  local log="$prefix/loader-without.log"
  mv "$prefix/lib/gltf-pbr/libgltf_pbr_images.so" "$prefix/module.aside"
  if env -u GLTF_PBR_IMAGE_MODULE LD_DEBUG=files "$@" >/dev/null 2>"$log"; then
    echo "$what converted a WebP without its own image module" >&2
    return 1
  fi
  if grep -q "file=[^ ]*libgltf_pbr_images.so" "$log"; then
    echo "without its own module, $what loaded another:" >&2
    grep -o "file=[^ ]*libgltf_pbr_images.so" "$log" | sort -u >&2
    return 1
  fi
  grep -q "cannot load the image module" "$log" || { echo "$what did not say why the conversion failed" >&2; return 1; }
  mv "$prefix/module.aside" "$prefix/lib/gltf-pbr/libgltf_pbr_images.so"
}
