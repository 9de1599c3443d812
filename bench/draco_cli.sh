#!/usr/bin/env bash
# I-mesh coding next to Draco's own command-line tools (Debian package `draco`) on the meshes
# pmesh_bench uses: frame 0 of horse-gallop and samba from ../shared/data when present, else
# the generated blob (3dvo-sample, 5 subdivisions). Draco's CLI is run at compression level 10
# with 12 quantisation bits (what 3dvo-enc's DracoSpeed 0 on a 12-bit grid corresponds to);
# the times are the ones the CLI prints (coding only, no file parsing), median of 5 runs.
# 3DVO's own figures for the same meshes come from pmesh_bench (IMeshEncode / IMeshDecode).
#
#   bench/draco_cli.sh [BUILD_DIR]        (default: build)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:-$here/../build}" && pwd)"
data="$here/../../shared/data/meshseq"
for tool in draco_encoder draco_decoder; do
  command -v "$tool" > /dev/null || { echo "$tool not found (apt-get install draco)"; exit 1; }
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

meshes=()
if [ -f "$data/horse-gallop/0001.obj.gz" ]; then
  zcat "$data/horse-gallop/0001.obj.gz" > "$work/horse-gallop.obj"
  meshes+=(horse-gallop)
fi
if [ -f "$data/samba/mesh_0000.obj.gz" ]; then
  zcat "$data/samba/mesh_0000.obj.gz" > "$work/samba.obj"
  meshes+=(samba)
fi
if [ ${#meshes[@]} -eq 0 ]; then
  "$build/bin/3dvo-sample" -o "$work/blob" --Subdivisions=5 --FrameCount=1 > /dev/null
  cp "$work/blob/0000.obj" "$work/blob.obj"
  meshes+=(blob)
fi

median() { sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

printf '%-14s %9s %12s %14s %14s\n' mesh vertices "CLI bytes" "CLI enc (ms)" "CLI dec (ms)"
for m in "${meshes[@]}"; do
  enc=() dec=()
  for run in 1 2 3 4 5; do
    enc+=("$(draco_encoder -i "$work/$m.obj" -o "$work/$m.drc" -cl 10 -qp 12 |
      sed -n 's/.*(\([0-9]*\) ms to encode).*/\1/p')")
    dec+=("$(draco_decoder -i "$work/$m.drc" -o "$work/$m.out.obj" |
      sed -n 's/.*(\([0-9]*\) ms to decode).*/\1/p')")
  done
  printf '%-14s %9d %12d %14s %14s\n' "$m" "$(grep -c '^v ' "$work/$m.obj")" \
    "$(stat -c %s "$work/$m.drc")" "$(printf '%s\n' "${enc[@]}" | median)" \
    "$(printf '%s\n' "${dec[@]}" | median)"
done
echo
echo "3DVO I meshes (pmesh_bench, CPU time; IMeshEncode includes the closed-loop decode and"
echo "the vertex-order recovery):"
"$build/bin/pmesh_bench" --benchmark_filter='^IMesh' --benchmark_repetitions=5 \
  --benchmark_report_aggregates_only=true 2>&1 | grep -E '^IMesh.*_median'
