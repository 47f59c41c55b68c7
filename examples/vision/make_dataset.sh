#!/bin/sh
# A small vision dataset from sequence.toml (docs/vision.md): frames 0..8 of a rolling-shutter
# fisheye with RGB, ray distance, z-depth, normals, instance ids, forward and backward flow (with
# occlusion), Cycles-style motion vectors, and the camera's calibration for OpenCV, COLMAP and
# Kalibr (the shutter set to 0: calibration files have no rolling shutter).
# Usage: examples/vision/make_dataset.sh [OUT_DIR] [ANAMORPH]   (default: vision_out, anamorph)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-vision_out}
bin=${2:-anamorph}
mkdir -p "$out/colmap"
"$bin" render "$here/sequence.toml" --frames 0:8 -o "$out/frame_%04d.png" -q \
  --aov distance,depth_z,normal,id,flow_forward,flow_backward,motion
"$bin" calib "$here/sequence.toml" --set 'camera.shutter=[0, 0]' --set camera.rolling_shutter=none \
  --format opencv -o "$out/camera_opencv.yml"
"$bin" calib "$here/sequence.toml" --set 'camera.shutter=[0, 0]' --set camera.rolling_shutter=none \
  --format kalibr -o "$out/camchain.yaml"
"$bin" calib "$here/sequence.toml" --set 'camera.shutter=[0, 0]' --set camera.rolling_shutter=none \
  --format colmap -o "$out/colmap"
echo "wrote $out: frame_NNNN.png (RGB) and frame_NNNN.exr (layers), camera_opencv.yml, camchain.yaml, colmap/"
