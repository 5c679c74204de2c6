#!/usr/bin/env bash
# Runs a libFuzzer harness once over every file of its corpus folder (the
# seeds and every input that once failed): the ctest test fuzz_<name>_corpus.
# Each input must finish within a second (-timeout=1) without a sanitizer
# report or a crash. Usage: run_corpus.sh HARNESS FOLDER
set -euo pipefail
harness=$1
dir=$2
mapfile -t files < <(find "$dir" -type f | sort)
if [ "${#files[@]}" -eq 0 ]; then
  echo "run_corpus: no inputs in $dir" >&2
  exit 1
fi
# -timeout applies to each input; -rss_limit_mb bounds what one may allocate.
"$harness" -timeout=1 -rss_limit_mb=2048 "${files[@]}" 2>&1 | tail -3
echo "run_corpus: ${#files[@]} inputs of $dir passed"
