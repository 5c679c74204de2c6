#!/usr/bin/env bash
# Every input the fuzzers found a failure with (test/fuzz/<name>/regress_*),
# through the real tool as a user would give it: exit 2 (bad input) with one
# line on stderr, never a hang. (The sanitizer stage also runs each through
# its harness: ctest fuzz_<name>_corpus.) Usage: test_fuzz_regressions.sh
# /path/to/firmness_model (firmness_report beside it).
source "$(dirname "$0")/harness.sh" "$@"
fuzz="$(cd "$(dirname "$0")/../fuzz" && pwd)"
report="$(dirname "$FM")/firmness_report"

# cli: the input is the argument list, NUL-separated (fuzz_cli.c)
for f in "$fuzz"/cli/regress_*; do
  [ -e "$f" ] || continue
  mapfile -d '' args <"$f"
  expect_bounded 2 "firmness_model" "${args[@]}"
done
# yaml: the input is a settings file (fuzz_yaml.c); design reads it as the cultivar's
for f in "$fuzz"/yaml/regress_*; do
  [ -e "$f" ] || continue
  expect_bounded 2 "$(basename "$f")" design --cultivar "$f"
done
# bag: the input is the file (fuzz_bag.c); firmness_report reads it
if [ -x "$report" ]; then
  for f in "$fuzz"/bag/regress_*; do
    [ -e "$f" ] || continue
    FM=$report expect_bounded 2 "$(basename "$f")" "$f"
  done
else
  bad "firmness_report not found beside $FM"
fi
summary test_fuzz_regressions
