#!/usr/bin/env bash
# Fuzzes each libFuzzer harness of test/fuzz/ for a bounded time (not part of
# the default tests; CI runs it in a short mode, the ctest test
# fuzz_script_short of the sanitizer build). Uses the sanitizer build
# (./build-san, ASan + UBSan + libFuzzer, scripts/sanitize.sh) and builds the
# harnesses there if needed. Each harness starts from its seed corpus
# (test/fuzz/<name>/) and a working corpus that grows in
# build-san/fuzz/corpus/<name>; a crash, a timeout (an input over a second)
# or an out-of-memory (over 2 GB) leaves its input in build-san/fuzz/ and
# fails the run: copy it into test/fuzz/<name>/ as a regression input once
# fixed. A harness that leaves its scratch file behind (af_fuzz_*_<pid>.*
# in /dev/shm or /tmp: test/fuzz/fuzz_scratch.h removes them at exit) fails
# the run too. Prints executions per harness.
#
#   bash scripts/fuzz.sh [--seconds S] [--only NAME] [--jobs N] [--timeout T] [--seed N] [--no-build]
#
# --seconds: per harness (default 60); --jobs: harnesses run side by side
# (default 1); --timeout: seconds an input may take while fuzzing (default 1;
# libFuzzer's clock is the wall's, so on a loaded machine, e.g. fuzzing
# under `nice`, give more: every input reported as a timeout is run again
# on its own and fails the run only if it takes over a second then too);
# --seed: libFuzzer's random seed (default 0: a new one each run). CI's short
# mode gives --seed 1, so that its verdict depends on the code alone, not
# on which mutations a run happened to try; long runs keep the default.
# --no-build: use the build as it is.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export AF_BUILD_DIR=${AF_SAN_BUILD_DIR:-$root/build-san}
source "$root/scripts/env.sh"
seconds=60
only=""
jobs=1
timeout=1
seed=0
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a value}; shift 2 ;;
    --only) only=${2:?--only needs a name}; shift 2 ;;
    --jobs) jobs=${2:?--jobs needs a value}; shift 2 ;;
    --timeout) timeout=${2:?--timeout needs a value}; shift 2 ;;
    --seed) seed=${2:?--seed needs a value}; shift 2 ;;
    --no-build) build=0; shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
case "$seconds" in '' | *[!0-9]*) echo "fuzz.sh: --seconds '$seconds' is not a whole number" >&2; exit 2 ;; esac
case "$jobs" in '' | *[!0-9]* | 0) echo "fuzz.sh: --jobs '$jobs' is not a whole number >= 1" >&2; exit 2 ;; esac
case "$seed" in '' | *[!0-9]*) echo "fuzz.sh: --seed '$seed' is not a whole number" >&2; exit 2 ;; esac
case "$timeout" in '' | *[!0-9]* | 0) echo "fuzz.sh: --timeout '$timeout' is not a whole number >= 1" >&2; exit 2 ;; esac

names=()
for src in "$root"/test/fuzz/fuzz_*.c "$root"/test/fuzz/fuzz_*.cpp; do
  [ -e "$src" ] || continue
  n=$(basename "$src")
  n=${n%.*}
  n=${n#fuzz_}
  [ -z "$only" ] || [ "$n" = "$only" ] && names+=("$n")
done
[ "${#names[@]}" -gt 0 ] || { echo "fuzz.sh: no harness named '$only'" >&2; exit 2; }

if [ "$build" = 1 ]; then
  if [ ! -f "$AF_BUILD/CMakeCache.txt" ]; then
    export CC=clang-14 CXX=clang++-14
    export AF_CMAKE_ARGS="-DACOUSTIC_FIRMNESS_SANITIZE=address,undefined -DACOUSTIC_FIRMNESS_FUZZ=ON"
    bash "$root/scripts/build.sh" >/dev/null
  fi
  make -C "$AF_BUILD" -j"$(nproc)" $(printf 'fuzz_%s ' "${names[@]}") >/dev/null
fi

out="$AF_BUILD/fuzz"
mkdir -p "$out/previous"
# what an earlier run found is kept, out of the way of this run's count
for n in "${names[@]}"; do
  find "$out" -maxdepth 1 -type f -name "$n-*" -exec mv -f {} "$out/previous/" \;
done
export ASAN_OPTIONS="detect_leaks=1"
export LSAN_OPTIONS="suppressions=$root/test/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$root/test/sanitizers/ubsan.supp"

# The longest input each harness takes [bytes]: a few chunks, a window of
# audio, an argument list, a YAML file, a small bag, two short recordings, a WAV file,
# a lane's program (its chunks are made from a few bytes each).
max_len() {
  case "$1" in
    strike) echo 65536 ;; response) echo 16384 ;; cli) echo 1024 ;; yaml) echo 8192 ;; wav) echo 16384 ;;
    msgs) echo 65536 ;; bag) echo 65536 ;; analyze) echo 65536 ;; lane) echo 4096 ;; *) echo 4096 ;;
  esac
}

exe_of() {
  local exe="$AF_DEVEL/lib/acoustic_firmness/fuzz_$1"
  [ -x "$exe" ] || exe=$(find "$AF_BUILD" "$AF_DEVEL" -name "fuzz_$1" -type f -perm -u+x | head -1)
  echo "$exe"
}

run_one() {
  local n=$1 exe
  exe=$(exe_of "$n")
  [ -n "$exe" ] || { echo "$n: harness not built" >"$out/$n.log"; return 1; }
  mkdir -p "$out/corpus/$n"
  # -close_fd_mask=3: the harnesses' own output (analyze's JSON, refusal
  # lines) is discarded; libFuzzer's reports still show.
  # exec: the job's PID is the harness's, whose scratch files bear it
  exec "$exe" "$out/corpus/$n" "$root/test/fuzz/$n" -max_total_time="$seconds" -timeout="$timeout" -seed="$seed" \
    -rss_limit_mb=2048 -max_len="$(max_len "$n")" -print_final_stats=1 -close_fd_mask=3 \
    -artifact_prefix="$out/$n-" >"$out/$n.log" 2>&1
}

status=0
pids=()
declare -A pid_of code_of
# Waits for harness job $1 and keeps its exit code (under set -e a bare wait
# on a failed harness would end this script before the table and the others).
reap() {
  local code=0
  wait "$1" || code=$?
  code_of[$1]=$code
}
for n in "${names[@]}"; do
  run_one "$n" &
  pids+=($!)
  pid_of[$n]=$!
  if [ "${#pids[@]}" -ge "$jobs" ]; then
    reap "${pids[0]}"
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do
  reap "$p"
done

printf '%-10s %8s %12s %10s %8s  %s\n' harness seconds executions "exec/s" corpus result
for n in "${names[@]}"; do
  log="$out/$n.log"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  corpus=$(find "$out/corpus/$n" -type f | wc -l)
  # a timeout must show again on its own, within a second, to count
  moved=0
  for t in "$out/$n"-timeout-*; do
    [ -e "$t" ] || continue
    if "$(exe_of "$n")" -timeout=1 -rss_limit_mb=2048 "$t" >"$t.rerun" 2>&1; then
      mv -f "$t" "$t.rerun" "$out/previous/"
      moved=1
      echo "$n: $(basename "$t") ran within a second on its own: the run was starved of CPU" >&2
    fi
  done
  # LeakSanitizer's own tracer may fail at the fuzzer's exit ("LeakSanitizer has
  # encountered a fatal error", seen once, the input written empty): the input
  # must fail again on its own to count
  if grep -q 'LeakSanitizer has encountered a fatal error' "$log"; then
    for c in "$out/$n"-crash-*; do
      [ -e "$c" ] || continue
      if "$(exe_of "$n")" -rss_limit_mb=2048 "$c" >"$c.rerun" 2>&1; then
        mv -f "$c" "$c.rerun" "$out/previous/"
        moved=1
        echo "$n: $(basename "$c") passes on its own: LeakSanitizer failed at the fuzzer's exit" >&2
      fi
    done
  fi
  found=$(find "$out" -maxdepth 1 -name "$n-*" -type f | wc -l)
  result=ok
  # (a timeout or a crash that did not show again is no failure; its input was moved)
  if [ "$found" -gt 0 ] || grep -q -e 'ERROR: libFuzzer: deadly signal' -e 'out-of-memory' \
    -e 'ERROR: AddressSanitizer' -e 'runtime error:' -e 'ERROR: LeakSanitizer' "$log"; then
    result="FAILED ($found input(s) in $out; log $log)"
    status=1
  elif [ "${code_of[${pid_of[$n]}]}" != 0 ] && [ "$moved" = 0 ]; then
    result="FAILED (the harness exited ${code_of[${pid_of[$n]}]}; log $log)"
    status=1
  fi
  # a harness removes its scratch files when it exits (test/fuzz/fuzz_scratch.h)
  # (a machine without /dev/shm: find's complaint is no failure of the harness)
  left=$( (find /dev/shm /tmp -maxdepth 1 -name "af_fuzz_*_${pid_of[$n]}.*" 2>/dev/null || true) | wc -l)
  # (a harness that crashed never reached its exit handler: the crash is the
  # finding, and its scratch files are removed here)
  if [ "$left" -gt 0 ] && [ "$result" = ok ]; then
    result="FAILED ($left scratch file(s) af_fuzz_*_${pid_of[$n]}.* left in /dev/shm or /tmp)"
    status=1
  elif [ "$left" -gt 0 ]; then
    find /dev/shm /tmp -maxdepth 1 -name "af_fuzz_*_${pid_of[$n]}.*" -delete 2>/dev/null || true
  fi
  printf '%-10s %8s %12s %10s %8s  %s\n' "$n" "$seconds" "${execs:-?}" "${rate:-?}" "$corpus" "$result"
done
exit "$status"
