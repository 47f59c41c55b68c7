# Sourced by scripts/build, scripts/test and scripts/fuzz: the machine-wide build lock and the
# CMake arguments every build directory shares.

# One build at a time on this machine, whichever checkout asks: a C++ build takes every core, and
# two at once only make both slower (and can run a small machine out of memory). The lock is
# machine-wide on purpose; a caller that has to wait says so, and names the checkout that holds it.
# Usage: build_lock FD
build_lock() {
  local fd=$1 lock="${TMPDIR:-/tmp}/anamorph-build.lock"
  eval "exec $fd>>\"$lock\""
  if ! flock -n "$fd"; then
    echo "waiting for another anamorph build on this machine to finish" \
      "($(cat "$lock.holder" 2>/dev/null || echo 'unknown checkout'); lock: $lock)" >&2
    flock "$fd"
  fi
  echo "$root (pid $$)" >"$lock.holder"
}

# ccache, when the machine has it, makes rebuilds and second checkouts cheap; nothing needs it.
cmake_launcher_args() {
  if command -v ccache >/dev/null; then echo "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"; fi
}
