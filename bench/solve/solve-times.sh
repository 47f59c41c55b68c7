#!/usr/bin/env bash
# The `anamorph solve` times of docs/performance.md: examples/solve/{dome_specimen,focus_context,
# dome_horizon}.toml and the demo's 3-pin solve (examples/demo.toml with a coin on the right
# sphere; pins of the three spheres where fov 50 and look_at [0.1, 0.7, 0] show them, through
# `anamorph project`; look_at and fov free from the demo's own), two binaries alternated in one
# hyperfine run per scene.
#   bench/solve/solve-times.sh OLD_BIN NEW_BIN [runs]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$(realpath "$1") new=$(realpath "$2") runs=${3:-5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ln -s "$root/examples/models" "$tmp/models"
coin=$'\n[[camera.coin]]\nposition = [1.6, 0.8, 0.6]\nstrength = 0.4\nradius = 0.15\n'
{ cat "$root/examples/demo.toml"; printf '%s' "$coin"; } > "$tmp/truth.toml"
{
  cat "$tmp/truth.toml"
  printf '\n[[camera.free]]\nkey = "camera.look_at"\n[[camera.free]]\nkey = "camera.fov"\n'
  for p in -1.6,0.8,0.6 0.0,0.8,-0.6 1.6,0.8,0.6; do
    read -r _ px _ py < <("$new" project "$tmp/truth.toml" --set camera.fov=50 \
      --set 'camera.look_at=[0.1, 0.7, 0]' --point "$p")
    printf '[[camera.constraint]]\nkind = "pin"\npoint = [%s]\nuv = [%.10f, %.10f]\n' \
      "${p//,/, }" "$(echo "$px / 960" | bc -l)" "$(echo "$py / 540" | bc -l)"
  done
} > "$tmp/demo_pins.toml"
for scene in "$root"/examples/solve/dome_specimen.toml "$root"/examples/solve/focus_context.toml \
  "$tmp/demo_pins.toml" "$root"/examples/solve/dome_horizon.toml; do
  echo "== $(basename "$scene")"
  for bin in "$old" "$new"; do "$bin" solve "$scene" | head -1; done
  # (each binary three times, alternating: old new old new old new)
  hyperfine -N -w 1 -r "$runs" -L bin "$old,$new,$old,$new,$old,$new" \
    "{bin} solve $scene -o $tmp/out.toml"
done
