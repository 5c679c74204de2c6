#!/usr/bin/env bash
# Every example of README.md and doc/*.md re-run against the build under
# test, its output compared with the one the page shows, so that a figure
# pasted into the docs cannot go stale. An example is a code block line
# starting with "$ " (a command; a line ending in "\" continues it); the
# lines after it, up to the next "$ " line or the end of the block, are its
# output (stdout and stderr together), compared line by line: exactly, except
# that a line "..." stands for any number of lines and "..." within a line
# for any text (a path of the checkout, say). A comment "# exit N" on the
# command gives its exit status (default 0). The commands of one page run in
# order in one scratch folder (a bag made by one is read by the next; "bash
# scripts/..." runs in the package's root; the package's files, its example
# captures in test/data included, are named through `rospack find`: an
# example naming ../shared, outside the package, fails); scripts/run.sh gets
# a free master port of its own. Blocks without "$ " lines (synopses, measured timings) are not examples. Also
# checks that every code block is closed and that every relative link of the
# pages (file and heading) resolves. Registered in ctest as
# scripts_doc_examples. Usage: test_doc_examples.sh [PAGE.md...]
# AF_DOC_UPDATE=1 (scripts/docs.sh --examples): an example whose output
# differs has its output lines rewritten in the page with what it printed
# (the scratch folder and the checkout's path as "..."); the run still fails,
# so that every rewrite is looked at before it is committed.
set -euo pipefail
source "$(dirname "$0")/harness.sh"
if [ "$#" -gt 0 ]; then
  pages=("$@")
else
  # doc/paper.md is left out: `firmness_model paper` writes it (figures and
  # all; cli_test_paper runs that), and its designer example names the
  # absolute path of the checkout it was made in.
  pages=("$AF_ROOT/README.md")
  for page in "$AF_ROOT"/doc/*.md; do
    [ "$page" = "$AF_ROOT/doc/paper.md" ] || pages+=("$page")
  done
fi

# One file per example: $tmp/ex/<n>.{where,cmd,want,exit}.
mkdir -p "$tmp/ex"
/usr/bin/python3 - "$tmp/ex" "${pages[@]}" <<'PY'
import os, re, sys
out, pages = sys.argv[1], sys.argv[2:]
n = 0
for page in pages:
    lines = open(page, encoding='utf-8').read().split('\n')
    in_code, cur, i = False, None, 0

    def close():
        global cur, n
        if cur:
            n += 1
            base = os.path.join(out, '%03d' % n)
            for key in ('where', 'cmd', 'want', 'exit', 'span'):
                with open(base + '.' + key, 'w', encoding='utf-8') as f:
                    f.write(cur[key] if key != 'want' else ''.join(l + '\n' for l in cur[key]))
        cur = None

    while i < len(lines):
        line = lines[i]
        if line.lstrip().startswith('```'):
            close()
            in_code = not in_code
        elif in_code and line.startswith('$ '):
            close()
            no, cmd = i + 1, line[2:]
            while cmd.endswith('\\') and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1] + ' ' + lines[i].strip()
            if '../shared' in cmd:
                sys.exit('FAIL: %s:%d: an example reads ../shared, outside the package '
                         '(the captures are in test/data)' % (page, no))
            status = re.search(r'#\s*exit (\d+)\s*$', cmd)
            cur = {'where': '%s:%d' % (page, no), 'cmd': cmd,
                   'exit': status.group(1) if status else '0', 'want': [],
                   'span': '%s\n%d\n' % (page, i + 1)}
        elif in_code and cur is not None:
            cur['want'].append(line)
        i += 1
    close()
    if in_code:
        sys.exit('FAIL: %s: a code block is not closed (an odd number of ``` lines)' % page)


# Every relative link of the pages names a file that exists, and a heading
# of it when it names one (GitHub's anchors: lower case, punctuation dropped,
# spaces as dashes).
def anchors(path):
    return {re.sub(r'[^\w\- ]', '', l.lstrip('#').strip().lower()).replace(' ', '-')
            for l in open(path, encoding='utf-8') if l.startswith('#')}


broken = []
for page in pages:
    for link in re.findall(r'\]\(([^)\s]+)\)', open(page, encoding='utf-8').read()):
        if re.match(r'[a-z]+:', link):
            continue
        path, _, anchor = link.partition('#')
        target = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        if not os.path.exists(target):
            broken.append('%s: link to %s: no such file' % (page, link))
        elif anchor and target.endswith('.md') and anchor not in anchors(target):
            broken.append('%s: link to %s: no such heading' % (page, link))
if broken:
    sys.exit('\n'.join('FAIL: ' + b for b in broken))
PY

# Compares output $1 with the expected $2 ("..." lines: any lines); exit 1
# printing the first difference.
cat >"$tmp/compare.py" <<'PY'
import re, sys
got = open(sys.argv[1], encoding='utf-8', errors='replace').read().rstrip('\n').split('\n')
want = open(sys.argv[2], encoding='utf-8').read().rstrip('\n').split('\n')
if want == ['']:
    sys.exit(0)  # no output shown: only the exit status is checked
def same(g, w):
    if '...' not in w:
        return g == w
    return re.fullmatch('.*'.join(re.escape(part) for part in w.split('...')), g) is not None
def match(g, w):
    if not w:
        return not g
    if w[0] == '...':
        return any(match(g[k:], w[1:]) for k in range(len(g) + 1))
    return bool(g) and same(g[0], w[0]) and match(g[1:], w[1:])
if not match(got, want):
    fixed = [w for w in want if w != '...']
    missing = next((w for w in fixed if not any(same(g, w) for g in got)), None)
    print('  expected line not printed: %r' % missing if missing else '  lines out of order or extra lines')
    print('  the output was:')
    print('\n'.join('    ' + g for g in got[:60]))
    sys.exit(1)
PY

# The page's lines kept where they still match (a "..." line keeps standing
# for the lines it skipped, a line with "..." inside keeps its wildcard), the
# printed lines where they differ or were added.
cat >"$tmp/merge.py" <<'PY'
import difflib, re, sys
want = open(sys.argv[1], encoding='utf-8').read().rstrip('\n').split('\n')
got = open(sys.argv[2], encoding='utf-8', errors='replace').read().rstrip('\n').split('\n')
def same(g, w):
    if '...' not in w:
        return g == w
    return re.fullmatch('.*'.join(re.escape(part) for part in w.split('...')), g) is not None
def near(g, w):  # the same line with other figures or words
    return same(g, w) or difflib.SequenceMatcher(None, g, w.replace('...', '')).ratio() >= 0.6
def find(w, j, limit, test):
    return next((k for k in range(j, min(len(got), limit)) if test(got[k], w)), None)
out, j = [], 0
for i, w in enumerate(want):
    if w == '...':
        nxt = next((x for x in want[i + 1:] if x != '...'), None)
        k = len(got) if nxt is None else find(nxt, j, len(got), same)
        if k is None:
            k = find(nxt, j, len(got), near)
        out.append('...')
        j = k if k is not None else j
        continue
    k = find(w, j, j + 20, same)
    if k is None:
        k = find(w, j, j + 20, near)
        if k is None:  # gone: the next printed line takes its place
            if j < len(got):
                out.append(got[j])
                j += 1
            continue
        out.extend(got[j:k + 1])  # added lines, then the changed one
        j = k + 1
        continue
    out.extend(got[j:k])
    out.append(w)
    j = k + 1
if not (want and want[-1] == '...'):
    out.extend(got[j:])
print('\n'.join(out))
PY

ran=0 page="" port=""
for want in "$tmp"/ex/*.want; do
  [ -e "$want" ] || break
  base=${want%.want}
  where=$(cat "$base.where") cmd=$(cat "$base.cmd") expect=$(cat "$base.exit")
  if [ "${where%%:*}" != "$page" ]; then
    page=${where%%:*}
    rm -rf "$tmp/cwd" && mkdir -p "$tmp/cwd"
  fi
  ran=$((ran + 1))
  echo "${where#"$AF_ROOT"/}: $cmd"
  status=0
  port=$(af_free_port)
  dir=$tmp/cwd
  case "$cmd" in bash\ scripts/*) dir=$AF_ROOT ;; esac
  (cd "$dir" && AF_DEMO_PORT=$port timeout -k 5 200 bash -c "$cmd") >"$tmp/out" 2>&1 ||
    status=$?
  af_check_stopped "$port" || fail=1
  if [ "$status" -ne "$expect" ]; then
    tail -5 "$tmp/out" >&2
    bad "${where#"$AF_ROOT"/}: exited $status, expected $expect"
  elif ! /usr/bin/python3 "$tmp/compare.py" "$tmp/out" "$want" >&2; then
    bad "${where#"$AF_ROOT"/}: the output differs from the page's"
    if [ "${AF_DOC_UPDATE:-0}" = 1 ]; then
      # page, first output line (0-based), how many, then the new lines
      sed -e "s|$tmp/cwd|...|g" -e "s|$AF_ROOT|...|g" "$tmp/out" >"$tmp/out.clean"
      { cat "$base.span"; wc -l <"$want"; /usr/bin/python3 "$tmp/merge.py" "$want" "$tmp/out.clean"; } \
        >"$tmp/ex/$(basename "$base").update"
    fi
  fi
done
if [ "${AF_DOC_UPDATE:-0}" = 1 ]; then
  # Bottom-up per page, so that earlier line numbers stay right.
  /usr/bin/python3 - "$tmp"/ex/*.update <<'PY'
import collections, sys
by_page = collections.defaultdict(list)
for path in sys.argv[1:]:
    try:
        page, start, n, *new = open(path, encoding='utf-8').read().rstrip('\n').split('\n')
    except (FileNotFoundError, ValueError):
        continue
    by_page[page].append((int(start), int(n), new))
for page, edits in by_page.items():
    lines = open(page, encoding='utf-8').read().split('\n')
    for start, n, new in sorted(edits, reverse=True):
        lines[start:start + n] = new
    with open(page, 'w', encoding='utf-8') as f:
        f.write('\n'.join(lines))
    print('rewrote %d examples of %s' % (len(edits), page))
PY
fi
[ "$ran" -gt 0 ] || bad "no example found"
[ "$fail" -eq 0 ] && echo "test_doc_examples: $ran examples passed"
exit "$fail"
