#!/usr/bin/env bash
# P-mesh prediction study (docs/prediction.md): the P-mesh bytes of the three shared sequences
# (cfg/d3dmc-lossy.cfg with cfg/per-sequence/<seq>.cfg) at MotionQuantStep 1, 4 and 16, from
# 3dvo-enc's summary ("P meshes" in "bytes"), one line per run, labelled with LABEL:
#
#   bench/prediction_study.sh BUILD_DIR OUT_DIR LABEL [encoder options...]
#
# e.g. bench/prediction_study.sh build /tmp/study spatial
#      bench/prediction_study.sh build /tmp/study temporal --TemporalPrediction=1
# The options (a predictor's cfg key, --KeyframeCount=9, ...) apply to every run; the streams
# and encoder logs are kept in OUT_DIR.
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,11p' "$0"; exit 2; }
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "$1" && pwd)"
out="$2"
label="$3"
shift 3
mkdir -p "$out"
cd "$here"
printf "%-13s %3s %-12s %10s %10s %8s\n" sequence Q predictor "P bytes" "all bytes" "enc s"
for seq in samba pcow horse-gallop; do
  for q in 1 4 16; do
    name="$out/$seq-q$q-$label"
    "$build/bin/3dvo-enc" -c cfg/d3dmc-lossy.cfg -c "cfg/per-sequence/$seq.cfg" \
      --MotionQuantStep="$q" "$@" -o "$name.3dvo" > "$name.log"
    bytes="$(grep '^bytes ' "$name.log")"
    pbytes="$(sed -n 's/.*P meshes \([0-9]*\).*/\1/p' <<< "$bytes")"
    all="$(sed -n 's/^bytes *: \([0-9]*\).*/\1/p' <<< "$bytes")"
    secs="$(sed -n 's/^time *: \([0-9.]*\) s/\1/p' "$name.log")"
    printf "%-13s %3d %-12s %10d %10d %8.2f\n" "$seq" "$q" "$label" "$pbytes" "$all" "$secs"
  done
done
