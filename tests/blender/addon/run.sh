#!/usr/bin/env bash
# Runs one of the add-on's headless tests in Debian's Blender (ctest: blender.addon.*).
# Usage: run.sh TEST.py REPO OUTDIR ANAMORPH_BINARY PYTHON_DIR
# Exits 77 (ctest: skipped) with a message when Blender is not installed. test_window*.py run
# Blender with its window on a virtual X server (xvfb-run; skipped without it).
set -euo pipefail
test=$1 repo=$2 out=$3 bin=$4 pydir=$5
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "skipped: '$blender' not found (scripts/install-deps installs Debian's blender)" >&2
  exit 77
fi
rm -rf "$out" && mkdir -p "$out"
# A user folder of the test's own: installing the zip must not touch the user's Blender.
export BLENDER_USER_CONFIG="$out/user/config" BLENDER_USER_SCRIPTS="$out/user/scripts"
export ANAMORPH_PYTHONPATH="$pydir"
# Temporary files (the engine's scene folders, the viewport's) inside the test's own folder:
# Blender quits with os._exit, which leaves them behind.
export TMPDIR="$out/tmp"
mkdir -p "$TMPDIR"
cd "$out"
case "$test" in
  test_window*)
    if ! command -v xvfb-run >/dev/null 2>&1; then
      echo "skipped: xvfb-run not found (Debian's xvfb package)" >&2
      exit 77
    fi
    # A window on a virtual screen; Mesa's software OpenGL draws it. The test quits Blender.
    exec timeout 240 xvfb-run -a -s "-screen 0 1100x1500x24" "$blender" --factory-startup \
      -noaudio --python-exit-code 1 --python "$repo/tests/blender/addon/$test" -- "$repo" \
      "$out" "$bin" ;;
esac
exec "$blender" -b --factory-startup -noaudio --python-exit-code 1 \
  --python "$repo/tests/blender/addon/$test" -- "$repo" "$out" "$bin"
