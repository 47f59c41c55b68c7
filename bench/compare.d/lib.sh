# Helpers for bench/compare (sourced). Statistics over whitespace-separated numbers, timing of
# whole processes with /usr/bin/time, and the render-only times each program prints.

# median / min / max of the numbers given as arguments
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {if (NR == 0) print "nan"; else print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
minof() { printf '%s\n' "$@" | sort -g | head -1; }
maxof() { printf '%s\n' "$@" | sort -g | tail -1; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{if (b == 0 || a == "nan" || b == "nan") print "nan"; else printf "%.3f", a/b}'; }
fmt2() { awk -v a="$1" 'BEGIN{printf "%.2f", a}'; }
fmt3() { awk -v a="$1" 'BEGIN{printf "%.3f", a}'; }
mib() { awk -v k="$1" 'BEGIN{printf "%.0f", k/1024}'; }
# "median (min–max)" of the arguments, with 2 decimals
spread() { printf '%s (%s–%s)' "$(fmt2 "$(median "$@")")" "$(fmt2 "$(minof "$@")")" "$(fmt2 "$(maxof "$@")")"; }

# timed <log> <cmd...>: runs cmd with stdout+stderr into <log>; sets T_WALL (s) and T_RSS (KiB).
timed() {
  local log=$1; shift
  /usr/bin/time -o "$log.time" -f '%e %M' "$@" >"$log" 2>&1 || {
    echo "compare: command failed (log: $log): $*" >&2
    tail -5 "$log" >&2
    return 1
  }
  read -r T_WALL T_RSS < <(tail -1 "$log.time")
}

# Render-only seconds from an anamorph render log ("... in 1.23 s, ...").
anamorph_render_s() { tr '\r' '\n' <"$1" | sed -n 's/.* in \([0-9.]*\) s, .*/\1/p' | tail -1; }
# Render-only seconds from a POV-Ray log ("Trace Time: ... (1.234 seconds)").
pov_render_s() { tr '\r' '\n' <"$1" | sed -n 's/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' | tail -1; }
# Threads POV-Ray used ("using 2 thread(s)").
pov_threads() { tr '\r' '\n' <"$1" | sed -n 's/.*using \([0-9]*\) thread(s).*/\1/p' | tail -1; }

# Display RMSE / mean absolute difference between two images (anamorph compare).
img_metric() { build/anamorph compare "$1" "$2" | awk -v k="$3" '$1 == k {print $2}'; }

# Installs the Debian packages given if dpkg does not list them as installed.
ensure_packages() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "compare: installing ${missing[*]}" >&2
  apt-get install -y -qq "${missing[@]}" >/dev/null 2>&1 ||
    { apt-get update -qq && apt-get install -y -qq "${missing[@]}" >/dev/null; }
}
