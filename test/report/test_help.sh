#!/usr/bin/env bash
# Every command-line tool answers --help and -h (exit 0, stdout only) with
# every flag of its table, each with a unit and a default (or "required"),
# and a bad flag or a missing value with one line naming it, exit 2.
#   test_help.sh FIRMNESS_MODEL FIRMNESS_REPORT STRIKE_BAG CAPTURE_TO_BAG
# The flags expected are read from the C sources' tables (the af_option rows,
# cli_flags.c's model_options among them) by this script, not from the tools'
# output.
source "$(dirname "$0")/../cli/harness.sh" "$1"
REPORT=${2:?path to firmness_report}
SB=${3:?path to strike_bag}
C2B=${4:?path to capture_to_bag}
SRC=$(cd "$(dirname "$0")/../../src" && pwd)

# tool (as run) | source of its table | the table's name | takes the model flags
tools=(
  "$FM|tools/firmness_model.c|-|model"
  "$FM analyze|tools/analyze.c|analyze_options|-"
  "$FM design|tools/design.c|design_options|-"
  "$FM plot|tools/plot_cmd.c|plot_options|model"
  "$FM sweep|tools/sweep.c|sweep_options|model"
  "$FM bench|tools/bench.c|bench_options|model"
  "$FM paper|tools/paper.c|paper_options|-"
  "$REPORT|report/firmness_report.c|af_report_options|-"
  "$SB|demo/strike_bag.c|options|-"
  "$C2B|convert/capture_to_bag.c|af_c2b_options|-"
)

# The subcommands of firmness_model's table: each must be in the list above.
subs=$($PY - "$SRC/tools/firmness_model.c" <<'EOF'
import re, sys
src = open(sys.argv[1]).read()
table = re.search(r'subcommands\[\] = \{(.*?)\n\};', src, re.S).group(1)
print(' '.join(re.findall(r'\{"(\w+)", af_\w+_main', table)))
EOF
)
for s in $subs; do
  if printf '%s\n' "${tools[@]}" | grep -q "^$FM $s|"; then ok; else bad "subcommand $s is not tested"; fi
done
[ "$(wc -w <<<"$subs")" -ge 6 ] && ok || bad "found only subcommands '$subs' in firmness_model.c"

for row in "${tools[@]}"; do
  IFS='|' read -r cmd src table model <<<"$row"
  for h in --help -h; do
    # shellcheck disable=SC2086  # cmd is the tool and its subcommand
    $cmd $h >"$tmp/help" 2>"$tmp/err"
    code=$?
    if [ $code -eq 0 ] && [ ! -s "$tmp/err" ] && [ -s "$tmp/help" ]; then ok; else bad "'$cmd $h' exited $code, stderr: $(cat "$tmp/err")"; fi
  done
  # Every flag of the table (and the model flags) on a line of its own, with
  # a unit in [] when it takes a number and a default or "required".
  if $PY - "$SRC/$src" "$table" "$model" "$SRC/tools/cli_flags.c" "$tmp/help" <<'EOF'; then ok; else bad "'$cmd --help' lacks flags of its table"; fi
import re, sys
src, table, model, cli, help_path = sys.argv[1:]
flags = []  # (name, placeholder or None)
if table != '-':
    body = re.search(r'af_option ' + re.escape(table) + r'\[\] = \{(.*?)\n\};', open(src).read(), re.S)
    assert body, 'no table ' + table
    for m in re.finditer(r'(?:\{|AF_ROW\()\s*"(--[\w-]+)",\s*(NULL|"[^"]*")', body.group(1)):
        flags.append((m.group(1), None if m.group(2) == 'NULL' else m.group(2).strip('"')))
    assert flags, 'no flag in ' + table
if model != '-':
    body = re.search(r'af_option model_options\[\] = \{(.*?)\n\};', open(cli).read(), re.S).group(1)
    names = re.findall(r'(?:\{|CHOICE\()\s*"(--[\w-]+)",\s*("[^"]*")?', body)
    names = [(n, v.strip('"') if v else 'WORD') for n, v in names]
    assert len(names) >= 15, names
    flags += names
lines = open(help_path).read().splitlines()
text_values = ('FILE', 'DIR', 'NAME', 'WORD', 'NAME=VALUE', 'default|paper')
missing = []
for name, value in flags:
    head = '  ' + name + (' ' + value if value else '') + ' '
    line = next((l for l in lines if l.startswith(head)), None)
    if line is None:
        missing.append(name + ': no line starting ' + repr(head))
        continue
    if not re.search(r'\((default[ :]|required[,)])', line):
        missing.append(name + ': no default: ' + line)
    if value and value not in text_values and not re.search(r'\[[^\]]+\]', line):
        missing.append(name + ': no unit: ' + line)
if missing:
    print('\n'.join(missing), file=sys.stderr)
    sys.exit(1)
print('%s: %d flags' % (table, len(flags)))
EOF
  # A bad flag: one line naming it and what is accepted, exit 2.
  # shellcheck disable=SC2086
  $cmd --no-such-flag 7 >"$tmp/out" 2>"$tmp/err"
  code=$?
  if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q -- "--no-such-flag.*accepted: .*--" "$tmp/err"; then ok; else bad "'$cmd --no-such-flag' exited $code: $(cat "$tmp/err")"; fi
done

# A flag without its value: one line naming the flag and the value it needs.
expect_usage "--E2 needs a value" --E2
for row in "analyze|--mass|KG" "design|--plot|FILE" "plot|--out|FILE" "sweep|--steps|N" "bench|--seconds|S" "paper|--out|DIR"; do
  IFS='|' read -r sub flag value <<<"$row"
  expect_usage "$flag needs a value: $value" "$sub" "$flag"
done
for prog in "$REPORT|x.bag --csv|--csv needs a value: FILE" "$SB|--out|--out needs a value: FILE"; do
  IFS='|' read -r p args want <<<"$prog"
  # shellcheck disable=SC2086
  "$p" $args >"$tmp/out" 2>"$tmp/err"
  code=$?
  if [ $code -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q -- "$want" "$tmp/err"; then ok; else bad "'$p $args' exited $code: $(cat "$tmp/err")"; fi
done

# The top-level usage lists every subcommand and every flag of each.
"$FM" --help >"$tmp/top"
for row in "${tools[@]:1:6}"; do
  IFS='|' read -r cmd _ <<<"$row"
  sub=${cmd##* }
  if grep -q "^  $sub " "$tmp/top"; then ok; else bad "firmness_model --help does not list $sub"; fi
  # shellcheck disable=SC2086
  for flag in $($cmd --help | sed '/^model flags/,$d' | sed -n 's/^  \(--[a-zA-Z0-9-]*\).*/\1/p' | sort -u); do
    if grep -q -- "$flag" <<<"$(sed -n "/^  $sub /,/^  [a-z]/p" "$tmp/top")"; then ok; else bad "firmness_model --help: $sub lacks $flag"; fi
  done
done
# analyze's flags that the usage once missed.
for flag in --config --cultivar --set --equatorial-radius --force-channel --audio-scale; do
  if grep -q -- "$flag" "$tmp/top"; then ok; else bad "firmness_model --help lacks analyze's $flag"; fi
done

summary test_help
