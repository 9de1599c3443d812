#!/usr/bin/env bash
# Rendering quality by leaving one camera out (3dvo-render --Mode=leave-one-out): PSNR and SSIM
# inside the held-out camera's mask on the synthetic rig, nerf-lego and uu-4cam, each measured
# with a BEFORE and an AFTER configuration (below) and, for AFTER, again with the textures coded
# at the encoder's default TextureQP; writes docs/results-rendering.md. Run time on 2 cores
# shared with other jobs: 9 and 12.5 minutes with the four *_ARGS empty (AFTER is then BEFORE,
# measured once), 7.7 minutes with all four set (the load made the difference, not the
# arguments); allow 15 minutes.
#
#   tools/render/results.sh [BUILD_DIR]          (default: build)
#   AFTER_RENDER_ARGS=--Blending=ulr tools/render/results.sh      (any variable below, likewise)
#
# Needs the apps of BUILD_DIR (3dvo-synth, 3dvo-import, 3dvo-recon, 3dvo-enc, 3dvo-dec,
# 3dvo-render); for nerf-lego ../shared/data/multiview/nerf-lego plus Debian's python3-numpy,
# python3-scipy, python3-skimage (tools/render/carve_hull.py); for uu-4cam
# ../shared/data/multiview/uu-4cam. A data set that is absent is skipped, and the page says so.
# The *_ARGS variables hold several arguments: they are split on purpose.
# shellcheck disable=SC2086
set -euo pipefail

# --- The two configurations compared (issue 22): BEFORE is the renderer and reconstruction as
# they were, AFTER today's defaults.
# 3dvo-render keys of every leave-one-out run: the angle weights and the nearest-camera fallback
# before; Blending=ulr and Fallback=fill (the defaults) after.
BEFORE_RENDER_ARGS="${BEFORE_RENDER_ARGS---Blending=angle --Fallback=nearest}"
AFTER_RENDER_ARGS="${AFTER_RENDER_ARGS-}"
# 3dvo-recon keys added to each reconstruction: no calibration refinement before (it is on in
# cfg/recon/uu-4cam.cfg, off by default elsewhere); the cfg files as they are after.
BEFORE_RECON_ARGS="${BEFORE_RECON_ARGS---RefineCalibration=false}"
AFTER_RECON_ARGS="${AFTER_RECON_ARGS-}"
# uu-4cam frames reconstructed and measured (about 8 s of reconstruction per frame).
UU_FRAMES="${UU_FRAMES-6}"
# Coded textures: 3dvo-enc with D3DMC P meshes lossless on a 16-bit grid (geometry practically
# lossless) and the texture keys at their defaults; a reconstruction's GOMs from its encode.cfg.
CODE_ARGS=(-c cfg/d3dmc-lossless.cfg --GridBits=16)

root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
bin="$build/bin"
data="${DATA_DIR:-$root/../shared/data/multiview}"  # DATA_DIR=/nowhere: the synthetic rig only
out="$root/docs/results-rendering.md"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$root"
start=$SECONDS

render() { "$bin/3dvo-render" "$@"; }
# The pooled PSNR (the "all" row) of a leave-one-out run.
pooled() { render "$@" | awk -F'|' '/\*\*all\*\*/ { gsub(/ /, "", $4); print $4 }'; }
# A table of pooled PSNRs: rows k, columns axis and ray.
sweep() {
  echo "| sharpness k | axis (dB) | ray (dB) |"
  echo "|---:|---:|---:|"
  for k in "${@:2}"; do
    echo "| $k | $(pooled -i "$1" --Mode=leave-one-out --ViewDirection=axis --Sharpness="$k" \
      ${SWEEP_ARGS:-}) | $(pooled -i "$1" --Mode=leave-one-out --ViewDirection=ray \
      --Sharpness="$k" ${SWEEP_ARGS:-}) |"
  done
}

# loo NAME ARGS...: a leave-one-out run; its table in $work/NAME.md, its CSV in $work/NAME.csv.
loo() {
  local name="$1"
  shift
  echo "results: leave-one-out $name" >&2
  render --Mode=leave-one-out --Csv="$work/$name.csv" "$@" > "$work/$name.md"
}
# psnr NAME, ssim NAME: the all row's figures of run NAME ("-" when it did not run).
column() { if [ -f "$work/$2.csv" ]; then awk -F, -v c="$1" '$1 == "all" { print $c }' "$work/$2.csv"; else echo -; fi; }
psnr() { column 3 "$1"; }
ssim() { column 6 "$1"; }
table() { cat "$work/$1.md"; }

# recon NAME INPUT CFG FRAMES ARGS: 3dvo-recon into $work/NAME-recon, then the dataset $work/NAME:
# INPUT's cameras (the refined ones of the reconstruction's dataset.json when it refined them) and
# images, the reconstructed meshes, the reconstruction's silhouettes as masks.
recon() {
  local name="$1" input="$2" cfg="$3" frames="$4" args="$5"
  echo "results: 3dvo-recon $name ($cfg $args)" >&2
  "$bin/3dvo-recon" -c "$cfg" -i "$input" -o "$work/$name-recon" --FrameCount="$frames" \
    --WriteSilhouettes $args > "$work/$name-recon.log" 2>&1 || {
    cat "$work/$name-recon.log" >&2
    exit 1
  }
  /usr/bin/python3 - "$input" "$work/$name" "$work/$name-recon" "$frames" << 'EOF'
import json, os, sys
src, out, recon, frames = sys.argv[1:5]
if os.path.exists(os.path.join(recon, "dataset.json")):  # RefineCalibration's cameras
    src = recon
d = json.load(open(os.path.join(src, "dataset.json")))
for c in d["cameras"]:  # paths relative to the input's folder become absolute
    for key in ("images", "video", "background", "backgroundVideo"):
        if key in c and not os.path.isabs(c[key]):
            c[key] = os.path.join(os.path.abspath(src), c[key])
    c.pop("alphaMask", None)
    c["masks"] = os.path.join(recon, "silhouettes", c["name"], "%04d.png")
d["frames"]["count"] = int(frames)
d["meshes"] = os.path.join(recon, "%04d.obj")
d["description"] = "3dvo-recon of " + d.get("description", src)
os.makedirs(out)
json.dump(d, open(os.path.join(out, "dataset.json"), "w"), indent=2)
EOF
}
# What a reconstruction gave (its per-frame lines: "frame n gom g I v V f F IoU m (worst w) ...").
recon_line() {
  awk '/^frame +[0-9]/ { n++; for (i = 1; i < NF; i++) { if ($i == "v") v = $(i + 1); if ($i == "f") f = $(i + 1)
      if ($i == "IoU") { s += $(i + 1); w = $(i + 3); sub(/\)/, "", w); if (n == 1 || w + 0 < m) m = w + 0 } } }
    END { printf "%d frames, %s vertices / %s triangles in the last, reprojection IoU mean %.4f, worst view %.4f", n, v, f, s / n, m }' \
    "$work/$1-recon.log"
}

# coded NAME DATA STEP CFG ARGS...: every STEP-th camera of DATA (the encoder takes at most 64)
# coded by 3dvo-enc (CODE_ARGS, then CFG when not empty: a reconstruction's encode.cfg, for its
# GOMs; default TextureQP), decoded by 3dvo-dec, then leave-one-out with the decoded mesh and
# pictures against DATA's images and masks (--Reference); run NAME-coded.
coded() {
  local name="$1" dataset="$2" step="$3" cfg=()
  [ -n "$4" ] && cfg=(-c "$4")
  shift 4
  echo "results: 3dvo-enc / 3dvo-dec $name" >&2
  /usr/bin/python3 - "$dataset" "$work/$name-input" "$step" << 'EOF'
import json, os, sys
src, out, step = sys.argv[1], sys.argv[2], int(sys.argv[3])
d = json.load(open(os.path.join(src, "dataset.json")))
d["cameras"] = d["cameras"][::step]
for c in d["cameras"]:
    for key in ("images", "video", "masks", "background", "backgroundVideo"):
        if key in c and not os.path.isabs(c[key]):
            c[key] = os.path.join(os.path.abspath(src), c[key])
if "meshes" in d and not os.path.isabs(d["meshes"]):
    d["meshes"] = os.path.join(os.path.abspath(src), d["meshes"])
os.makedirs(out)
json.dump(d, open(os.path.join(out, "dataset.json"), "w"), indent=2)
EOF
  "$bin/3dvo-enc" "${CODE_ARGS[@]}" "${cfg[@]}" --Dataset="$work/$name-input" \
    --BitstreamFile="$work/$name.3dvo" > "$work/$name-enc.log" 2>&1 || {
    cat "$work/$name-enc.log" >&2
    exit 1
  }
  "$bin/3dvo-dec" -i "$work/$name.3dvo" -o "$work/$name-dec" > /dev/null
  loo "$name-coded" -i "$work/$name-dec" --Reference="$dataset" "$@"
}
# The texture bytes of an encoding per frame, all cameras (kB: 1000 bytes).
texture_size() {
  awk '/^frames / { n = $3 } /^bytes / { for (i = 1; i <= NF; i++) if ($i == "textures") t = $(i + 1) }
    END { sub(/\)/, "", t); printf "%.1f", t / n / 1000 }' "$work/$1-enc.log"
}

# measure NAME BEFORE_DATA AFTER_DATA ARGS...: the BEFORE run (NAME-before) and, when data or
# render arguments differ, the AFTER run (NAME-after; otherwise the same figures).
measure() {
  local name="$1" before="$2" after="$3"
  shift 3
  loo "$name-before" -i "$before" "$@" $BEFORE_RENDER_ARGS
  if [ "$(readlink -f "$before")" != "$(readlink -f "$after")" ] || [ "$BEFORE_RENDER_ARGS" != "$AFTER_RENDER_ARGS" ]; then
      loo "$name-after" -i "$after" "$@" $AFTER_RENDER_ARGS
  else
    cp "$work/$name-before.csv" "$work/$name-after.csv"
    cp "$work/$name-before.md" "$work/$name-after.md"
  fi
}
# reconstruct NAME INPUT CFG FRAMES: BEFORE and AFTER reconstructions ($work/NAME-before and
# NAME-after; one reconstruction when the recon arguments are the same).
reconstruct() {
  recon "$1-before" "$2" "$3" "$4" "$BEFORE_RECON_ARGS"
  if [ "$BEFORE_RECON_ARGS" != "$AFTER_RECON_ARGS" ]; then
    recon "$1-after" "$2" "$3" "$4" "$AFTER_RECON_ARGS"
  else
    ln -s "$work/$1-before" "$work/$1-after"
    ln -s "$work/$1-before-recon" "$work/$1-after-recon"
    ln -s "$work/$1-before-recon.log" "$work/$1-after-recon.log"
  fi
}
summary_row() {
  echo "| $1 | $(psnr "$2-before") | $(psnr "$2-after") | $(ssim "$2-before") | $(ssim "$2-after") |" \
    "$(psnr "$2-coded") | $(ssim "$2-coded") | ${3:--} |"
}

# --- Synthetic rig: ground-truth meshes, and 3dvo-recon's hull of the same rig.
echo "results: synthetic rig" >&2
"$bin/3dvo-synth" -o "$work/synth" > /dev/null
measure synth "$work/synth" "$work/synth"
coded synth "$work/synth" 1 "" $AFTER_RENDER_ARGS
synth_sweep="$(sweep "$work/synth" 1 2 4 8 16 32)"
reconstruct synth-recon "$work/synth" cfg/recon/synth.cfg 10
measure synth-recon "$work/synth-recon-before" "$work/synth-recon-after"
coded synth-recon "$work/synth-recon-after" 1 "$work/synth-recon-after-recon/encode.cfg" $AFTER_RENDER_ARGS
synth_recon_line="$(recon_line synth-recon-after)"

# --- nerf-lego: 25 of the 100 views; hulls from 3dvo-recon and from carve_hull.py.
lego_args=(--CameraStep=4)
if [ -d "$data/nerf-lego" ]; then
  echo "results: nerf-lego" >&2
  "$bin/3dvo-import" -i "$data/nerf-lego" -o "$work/lego" > /dev/null
  reconstruct lego "$work/lego" cfg/recon/lego.cfg 1
  measure lego "$work/lego-before" "$work/lego-after" "${lego_args[@]}"
  coded lego "$work/lego-after" 4 "$work/lego-after-recon/encode.cfg" $AFTER_RENDER_ARGS
  lego_recon_line="$(recon_line lego-after)"
  hull_line="$(/usr/bin/python3 "$root/tools/render/carve_hull.py" -i "$work/lego" \
    -o "$work/lego-hull" | sed 's/^carve_hull: //; s/ -> .*//')"
  measure lego-hull "$work/lego-hull" "$work/lego-hull" "${lego_args[@]}"
  lego_note=""
else
  lego_note="**Not run**: $data/nerf-lego is absent."
fi

# --- uu-4cam: the first UU_FRAMES frames through 3dvo-recon (cfg/recon/uu-4cam.cfg).
if [ -d "$data/uu-4cam" ]; then
  echo "results: uu-4cam" >&2
  "$bin/3dvo-import" -i "$data/uu-4cam" -o "$work/uu" --Up=0,0,-1 > /dev/null
  reconstruct uu "$work/uu" cfg/recon/uu-4cam.cfg "$UU_FRAMES"
  measure uu "$work/uu-before" "$work/uu-after"
  coded uu "$work/uu-after" 1 "$work/uu-after-recon/encode.cfg" $AFTER_RENDER_ARGS
  uu_recon_line="$(recon_line uu-after)"
  uu_note=""
else
  uu_note="**Not run**: $data/uu-4cam is absent."
fi

# --- Dino (Middlebury dinoSparseRing): reconstructed for its silhouette agreement only.
if [ -d "$data/middlebury-dinoSparseRing" ]; then
  for side in before after; do
    args=$BEFORE_RECON_ARGS
    [ $side = after ] && args=$AFTER_RECON_ARGS
    echo "results: 3dvo-recon dino-$side (cfg/recon/dino.cfg $args)" >&2
    "$bin/3dvo-recon" -c cfg/recon/dino.cfg -i "$data/middlebury-dinoSparseRing" \
      -o "$work/dino-$side-recon" $args > "$work/dino-$side-recon.log" 2>&1 || {
      cat "$work/dino-$side-recon.log" >&2
      exit 1
    }
  done
  echo "results: 3dvo-recon dino-refined (cfg/recon/dino.cfg --RefineCalibration=true)" >&2
  "$bin/3dvo-recon" -c cfg/recon/dino.cfg -i "$data/middlebury-dinoSparseRing" \
    -o "$work/dino-refined-recon" --RefineCalibration=true > "$work/dino-refined-recon.log" 2>&1 || {
    cat "$work/dino-refined-recon.log" >&2
    exit 1
  }
fi
# The reprojection IoU of a reconstruction: "mean (worst view)" over its frames, or "-".
iou() {
  [ -f "$work/$1-recon.log" ] || { echo -; return; }
  awk '/^frame +[0-9]/ { for (i = 1; i < NF; i++) if ($i == "IoU") { n++; s += $(i + 1); w = $(i + 3)
      sub(/\)/, "", w); if (n == 1 || w + 0 < m) m = w + 0 } }
    END { if (n) printf "%.4f (%.4f)", s / n, m; else printf "-" }' "$work/$1-recon.log"
}
iou_rows="| synthetic rig, \`cfg/recon/synth.cfg\`, 10 frames | $(iou synth-recon-before) | $(iou synth-recon-after) |
| nerf-lego, \`cfg/recon/lego.cfg\` | $(iou lego-before) | $(iou lego-after) |
| uu-4cam, \`cfg/recon/uu-4cam.cfg\`, $UU_FRAMES frames | $(iou uu-before) | $(iou uu-after) |
| dino, \`cfg/recon/dino.cfg\` | $(iou dino-before) | $(iou dino-after) |
| dino, \`cfg/recon/dino.cfg --RefineCalibration=true\` | $(iou dino-before) | $(iou dino-refined) |"

rows="$(summary_row "synthetic rig, ground-truth meshes" synth "$(texture_size synth)")
$(summary_row "synthetic rig, 3dvo-recon hull" synth-recon "$(texture_size synth-recon)")"
if [ -z "$lego_note" ]; then
  rows="$rows
$(summary_row "nerf-lego, 3dvo-recon hull, 25 views" lego "$(texture_size lego)")
$(summary_row "nerf-lego, carve_hull.py hull, 25 views (no recon arguments)" lego-hull)"
fi
[ -z "$uu_note" ] && rows="$rows
$(summary_row "uu-4cam, 3dvo-recon, $UU_FRAMES frames" uu "$(texture_size uu)")"
minutes=$(( (SECONDS - start + 30) / 60 ))

section() {  # section NAME NOTE: a data set's three tables, or its note when it did not run
  if [ -n "$2" ]; then
    echo "$2"
    return
  fi
  echo "Before:"
  echo
  table "$1-before"
  echo
  echo "After:"
  echo
  table "$1-after"
  if [ -f "$work/$1-coded.md" ]; then
    echo
    echo "After, textures coded at the default TextureQP (decoded mesh and pictures; reference:"
    echo "the original images and masks):"
    echo
    table "$1-coded"
  fi
}

cat > "$out.partial" << EOF
# Rendering results: leave one camera out

Generated by \`tools/render/results.sh\` (this page is its output; do not edit by hand; this run
took about $minutes minutes). Each held-out camera's viewpoint is rendered by \`3dvo-render\` from
the *other* cameras only and compared with that camera's real image inside its silhouette mask:
PSNR over R, G, B, peak 255, squared errors pooled over all frames and, in the **all** row, over
all cameras; SSIM (Wang et al. 2004: 11 × 11 Gaussian window, σ = 1.5, K1 = 0.01, K2 = 0.03) on
luma, with windows restricted to the mask, averaged over the mask's pixels (the **all** row over
every mask pixel of every frame and camera; [rendering.md](rendering.md)). "At own pose"
renders the same viewpoint with all cameras, the held-out one included (acceptance ≥ 40 dB on
the synthetic rig; tested in \`tests/render_test.cpp\`); where the mesh does not cover the mask
it is black, so an under-sized mesh shows there. "Fallback" is the share of mask pixels that no
other camera sees (coloured by the \`Fallback\`).

## Configurations

| | 3dvo-render arguments | 3dvo-recon arguments |
|---|---|---|
| before | \`${BEFORE_RENDER_ARGS:-(defaults)}\` | \`${BEFORE_RECON_ARGS:-(defaults)}\` |
| after | \`${AFTER_RENDER_ARGS:-(defaults)}\` | \`${AFTER_RECON_ARGS:-(defaults)}\` |

Renderer defaults: \`Blending=ulr\`, \`EdgeWidth=8\`, \`ResolutionPenalty=1\`,
\`ViewDirection=axis\`, \`Sharpness=4\`, \`DepthTolerance=0.01\`, \`Fallback=fill\`
([rendering.md](rendering.md), "Blending"). Reconstruction: the cfg files of \`cfg/recon/\`
(\`RefineCalibration true\` in \`uu-4cam.cfg\`; [reconstruction.md](reconstruction.md)). "Coded": the AFTER data set coded by \`3dvo-enc ${CODE_ARGS[*]}\` (D3DMC
P meshes lossless on a 16-bit grid, so the geometry is practically lossless; GOMs of 16 frames,
or a reconstruction's own from its \`encode.cfg\`; a texture GOP per GOM) with the texture keys
at their defaults (\`TextureQP 28\`, \`TextureMode bbox\`, \`TexturePadding mb128\`), decoded by
\`3dvo-dec\`, and rendered with AFTER's render arguments from the decoded mesh and pictures (each
source camera's shape is then the decoded alpha: the pixels the decoded mesh covers) against the
original images and masks (\`--Reference\`).

## Summary (the **all** rows)

| data set | before PSNR (dB) | after PSNR (dB) | before SSIM | after SSIM | after, coded textures: PSNR (dB) | SSIM | coded textures (kB per frame, all cameras) |
|---|---:|---:|---:|---:|---:|---:|---:|
$rows

${lego_note}
${uu_note}

## Reconstructions: silhouette agreement

3dvo-recon's reprojection IoU of the output meshes with the silhouettes it carved from, mean over
frames and cameras (worst view and frame in brackets), with the BEFORE and AFTER recon
arguments; a missing data set shows "-". Dino is not rendered here (its figures are in
[reconstruction.md](reconstruction.md)); its row with \`--RefineCalibration=true\` shows what the
refinement does to a good calibration: a pass that does not raise the IoU is undone, so it cannot
lower it.

| data set | before: IoU mean (worst) | after: IoU mean (worst) |
|---|---:|---:|
$iou_rows

## Synthetic rig (\`3dvo-synth\` defaults: 8 cameras on a ring, 320 × 240, 10 frames)

Ground-truth mesh; Lambert shading with a fixed light, so the surface looks the same from every
camera: what is lost is resampling (each texel is interpolated twice) and the cameras' 45°
spacing (foreshortened texels near the silhouette). The masks are the rig's own.

$(section synth "")

Weighting variants (pooled PSNR, all cameras held out in turn, BEFORE's data, no render
arguments):

$synth_sweep

### The same rig through 3dvo-recon

\`3dvo-recon -c cfg/recon/synth.cfg\` ($synth_recon_line); masks: the
reconstruction's silhouettes (here the rig's masks, given to it).

$(section synth-recon "")

## nerf-lego (25 of the 100 views: every 4th, \`--CameraStep=4\`)

No mesh ships with the set. The hull is carved from the alpha masks of all 100 views, so the
held-out view's silhouette helped make it (it is geometry known to the renderer, as the
synthetic rig's mesh is); the renderer's textures are those of the 25 views. A visual hull
fills the model's concavities (the cab, the space under the bucket arm, the tracks), so
texture from a neighbouring camera lands where the hull, not the model, is. The NeRF renders
have glossy reflections, so the surface is also somewhat view-dependent.

### 3dvo-recon hull

\`3dvo-recon -c cfg/recon/lego.cfg\` (${lego_recon_line:-not run}); masks: the reconstruction's
silhouettes (the alpha channel).

$(section lego "$lego_note")

### carve_hull.py hull

\`tools/render/carve_hull.py\` (voxel carving + marching cubes: ${hull_line:-not run}); masks:
the alpha channel. No recon arguments apply; not coded.

$(section lego-hull "$lego_note")

## uu-4cam (4 cameras, 644 × 486, frames 0 … $((UU_FRAMES - 1)))

Imported with \`3dvo-import --Up=0,0,-1\`, reconstructed by \`3dvo-recon -c cfg/recon/uu-4cam.cfg
--FrameCount=$UU_FRAMES\` (${uu_recon_line:-not run}): background subtraction, approximate
calibration and strong lens distortion. Masks: the reconstruction's silhouettes (background
subtraction), not the pixels the mesh covers: an over-sized hull puts the other cameras'
texture at wrong surface points inside the silhouette, and mask pixels an under-sized one misses
stay black, so both are punished.

$(section uu "$uu_note")
EOF
mv "$out.partial" "$out"
echo "results: wrote $out in $minutes minutes" >&2
