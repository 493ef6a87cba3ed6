#!/usr/bin/env bash
# Times the peer converter (glTF-Transform `metalrough`) on every shared
# spec-gloss input and prints a markdown table: median wall time and median
# peak RSS of RUNS runs, and the output's total size (the .gltf/.glb plus every
# file it references). This is the target our own converter is measured against.
#
#   bench/peer_baseline.sh [ASSETS_DIR] > table.md      (RUNS=5 by default)
#
# The last column is the Khronos validator's errors/warnings/infos/hints on the output.
# Needs GNU time (/usr/bin/time, Debian package `time`) for peak RSS.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
assets="${1:-$here/../../shared/assets}"
runs="${RUNS:-5}"
eval "$("$here/peers.sh")"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Median of the numbers on stdin, one per line (the upper one for even counts).
median() { sort -g | awk '{ v[NR] = $1 } END { print v[int(NR / 2) + 1] }'; }

# Bytes of a .gltf/.glb and of every non-data URI it references (buffers, images).
total_bytes() {
  node -e '
    const fs = require("fs"), path = require("path");
    const file = process.argv[1];
    let bytes = fs.statSync(file).size, json;
    const data = fs.readFileSync(file);
    if (file.endsWith(".glb")) {  // JSON chunk: length at byte 12, payload from byte 20
      json = JSON.parse(data.subarray(20, 20 + data.readUInt32LE(12)).toString());
    } else {
      json = JSON.parse(data.toString());
    }
    for (const item of [...(json.buffers || []), ...(json.images || [])]) {
      if (item.uri && !item.uri.startsWith("data:"))
        bytes += fs.statSync(path.resolve(path.dirname(file), decodeURIComponent(item.uri))).size;
    }
    console.log(bytes);' "$1"
}

# "E/W/I/H" counts from tests/peer/validate.mjs for one file.
validator_counts() {
  GLTF_PBR_NODE_MODULES="$GLTF_PBR_NODE_MODULES" node "$GLTF_VALIDATOR_JS" "$1" | node -e '
    const r = Object.values(JSON.parse(require("fs").readFileSync(0, "utf8")))[0];
    console.log([r.numErrors, r.numWarnings, r.numInfos, r.numHints].join("/"));'
}

echo "| input | input bytes | median wall s | median peak RSS MB | output bytes | output E/W/I/H |"
echo "|---|---|---|---|---|---|"
for input in "$assets"/*/specgloss/*.gltf \
             "$assets"/CesiumMilkTruck/specgloss-glb-generated/*.glb \
             "$assets"/2CylinderEngine/specgloss-draco-generated/*.gltf; do
  name="${input#"$assets"/}"
  extension="${input##*.}"
  : >"$work/times"
  for run in $(seq "$runs"); do
    out="$work/$run/out.$extension"  # a fresh folder per run: no stale textures counted
    mkdir -p "$work/$run"
    /usr/bin/time -f "%e %M" -o "$work/time" "$GLTF_TRANSFORM" metalrough "$input" "$out" >/dev/null 2>&1 ||
      { echo "peer_baseline.sh: gltf-transform failed on $input" >&2; exit 1; }
    cat "$work/time" >>"$work/times"
  done
  wall="$(cut -d' ' -f1 "$work/times" | median)"
  rss_mb="$(cut -d' ' -f2 "$work/times" | median | awk '{ printf "%.0f", $1 / 1024 }')"
  echo "| $name | $(total_bytes "$input") | $wall | $rss_mb | $(total_bytes "$out") | $(validator_counts "$out") |"
  rm -rf "${work:?}"/[0-9]*
done
