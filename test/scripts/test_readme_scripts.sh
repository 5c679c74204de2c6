#!/usr/bin/env bash
# The README's other script commands, in short modes, each on a master port
# of its own (the figures they print in full take minutes; see README):
#  - bash scripts/report_vs_node.sh N SEED: 6 strikes (seed 3) through the
#    node and through firmness_report must agree (exit 0, "the same apples");
#  - bash scripts/bench_node.sh --seconds S --floor: 4 s of input, every
#    strike reported, the CPU and latency lines printed, and af_bench_floor's
#    CPU line, having taken every chunk of the replay;
#  - bash scripts/rviz_shot.sh OUT.png: 2 strikes, a 1600x860 screenshot
#    that is not blank (rviz's panels, the rig and the markers give it
#    hundreds of colours; an empty Xvfb screen has one).
# Each must leave no process of its own running. Registered in ctest as
# scripts_readme_scripts.
set -euo pipefail
source "$(dirname "$0")/harness.sh"

af_run_script AF_REPORT_PORT 150 "$tmp/report.out" report_vs_node.sh 6 3
grep -qE '^report_vs_node: 6 strikes, [0-9]+ reliable; node and firmness_report: the same apples' \
  "$tmp/report.out" || bad "report_vs_node.sh: no line '6 strikes ... the same apples'"
af_check_stopped "$port" || fail=1

af_run_script AF_BENCH_PORT 150 "$tmp/bench.out" bench_node.sh --seconds 4 --floor
# 4 s of input: one strike every 0.5 s after 1.5 s of lead (bench_node.sh)
grep -qE '^bench: 5 strikes in 4\.0 s of input' "$tmp/bench.out" ||
  bad "bench_node.sh: not 5 strikes reported in 4 s of input"
grep -qE 'node CPU: [0-9.]+ s over the replay = [0-9.]+ % of one core' "$tmp/bench.out" ||
  bad "bench_node.sh: no CPU figure"
grep -qE 'strike latency, end to end .*: median [0-9.]+, 90 % [0-9.]+, max [0-9.]+ over 5' \
  "$tmp/bench.out" || bad "bench_node.sh: no latency over the 5 strikes"
grep -qE 'floor \(af_bench_floor: .*\): [0-9.]+ s = [0-9.]+ % of one core; idle before the replay [0-9.]+ %; the node above it -?[0-9.]+ %' \
  "$tmp/bench.out" || bad "bench_node.sh --floor: no floor CPU line"
# 4 s of strike_bag: 199,680 force samples at 50 kHz and 191,488 audio
# samples at 48 kHz in 1024-sample chunks, 5 apples: every one taken
grep -qE 'af_bench_floor: took 195 force, 187 audio and 5 apple messages' "$tmp/bench.out" ||
  bad "bench_node.sh --floor: af_bench_floor did not take the replay's 195 + 187 chunks and 5 apples"
af_check_stopped "$port" || fail=1

export AF_RVIZ_STRIKES=2
af_run_script AF_RVIZ_PORT 200 "$tmp/rviz.out" rviz_shot.sh "$tmp/shot.png"
if [ -s "$tmp/shot.png" ]; then
  size=$(identify -format '%wx%h' "$tmp/shot.png")
  colours=$(identify -format '%k' "$tmp/shot.png")
  echo "rviz_shot: $size, $colours colours"
  [ "$size" = "1600x860" ] || bad "rviz_shot.sh: screenshot $size, not 1600x860"
  [ "$colours" -ge 100 ] || bad "rviz_shot.sh: screenshot of $colours colours (blank?)"
else
  bad "rviz_shot.sh wrote no screenshot"
fi
af_check_stopped "$port" || fail=1
[ "$fail" -eq 0 ] && echo "test_readme_scripts: passed"
exit "$fail"
