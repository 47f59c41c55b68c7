#!/bin/sh
# A small vision dataset from sequence.toml (docs/vision.md): frames 0..8 of a rolling-shutter
# fisheye with RGB, ray distance, z-depth, normals, instance ids, forward and backward flow (with
# occlusion), Cycles-style motion vectors, and the camera's calibration for OpenCV, COLMAP and
# Kalibr (the shutter set to 0: calibration files have no rolling shutter).
# Usage: examples/vision/make_dataset.sh [OUT_DIR] [ANAMORPH] [FIRST:LAST] [SIZE]
#   defaults: vision_out, anamorph, 0:8 and the scene's 320 (SIZE: the square image's side, px)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-vision_out}
bin=${2:-anamorph}
frames=${3:-0:8}
size=""
if [ -n "${4:-}" ]; then
  case $4 in
    *[!0-9]*) echo "make_dataset.sh: SIZE must be a whole number, not '$4'" >&2; exit 2 ;;
  esac
  size="--width $4 --height $4"
fi
mkdir -p "$out/colmap"
# shellcheck disable=SC2086 # $size: empty or two options
"$bin" render "$here/sequence.toml" $size --frames "$frames" -o "$out/frame_%04d.png" -q \
  --aov distance,depth_z,normal,id,flow_forward,flow_backward,motion
for f in "opencv camera_opencv.yml" "kalibr camchain.yaml" "colmap colmap"; do
  # shellcheck disable=SC2086
  "$bin" calib "$here/sequence.toml" $size --set 'camera.shutter=[0, 0]' \
    --set camera.rolling_shutter=none --format "${f% *}" -o "$out/${f#* }"
done
echo "wrote $out: frame_NNNN.png (RGB) and frame_NNNN.exr (layers)," \
  "camera_opencv.yml, camchain.yaml, colmap/"
