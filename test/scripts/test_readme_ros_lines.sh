#!/usr/bin/env bash
# Every `rosrun acoustic_firmness ...` and `roslaunch acoustic_firmness ...`
# line of README.md and doc/*.md (in code blocks, or inline in backticks),
# against the build under test, so that a documented line that no longer
# works fails CI. Example lines starting with "$ " are left to
# test_doc_examples.sh, which also compares their output.
#  - rosrun of a CLI (firmness_model, strike_bag) runs, with no master, and
#    must exit 0, or N when its comment says "exit N";
#  - rosrun of the node (firmness_node) runs under a master of the test's
#    own (a free port) and must still be running after 3 s;
#  - roslaunch lines are resolved as roslaunch would (package, file, args,
#    includes, parameter files) and every node they start must be found;
#    they are not run (the node runs until stopped; the demo test runs
#    replay.launch end to end).
# Synopsis placeholders are filled: [optional] groups dropped, N -> 3,
# S -> 1, NAME -> lane1, FILE and <any text> -> a scratch file, /path/to/X
# -> config/X of the package (cultivar.yaml -> config/jonagold.yaml) or a
# scratch file.
# Also checks that a page's `source .../setup.bash` names the devel space
# scripts/build.sh makes by default. Registered in ctest as
# scripts_readme_ros_lines. Usage: test_readme_ros_lines.sh [PAGE.md...]
set -euo pipefail
source "$(dirname "$0")/harness.sh"
if [ "$#" -gt 0 ]; then
  pages=("$@")
else
  pages=("$AF_ROOT/README.md" "$AF_ROOT"/doc/*.md)
fi
mkdir -p "$tmp/cwd"

# The lines, one per output line: kind <TAB> expected exit <TAB> page:line
# <TAB> the command with placeholders filled (shell-quoted).
/usr/bin/python3 - "$AF_ROOT" "$tmp" "${pages[@]}" >"$tmp/lines" <<'PY'
import os, re, shlex, sys
root, tmp, pages = sys.argv[1], sys.argv[2], sys.argv[3:]
NODES = {'firmness_node'}
PREFIXES = ('rosrun acoustic_firmness ', 'roslaunch acoustic_firmness ')
candidates = []
for page in pages:
    in_code = False
    name = os.path.relpath(page, root)
    for no, line in enumerate(open(page, encoding='utf-8'), 1):
        where = '%s:%d' % (name, no)
        if line.lstrip().startswith('```'):
            in_code = not in_code
            continue
        if in_code:
            text = line.strip()
            if text.startswith(PREFIXES) and not line.startswith('$ '):
                cmd, _, comment = text.partition(' #')
                candidates.append((where, cmd.strip(), comment))
        else:
            for span in re.findall(r'`([^`]+)`', line):
                if span.startswith(PREFIXES):
                    candidates.append((where, span.strip(), ''))
files = 0


def fill_path(value):
    global files
    if value == 'FILE':
        files += 1
        return os.path.join(tmp, 'readme_file_%d.bag' % files)
    if value.startswith('/path/to/'):
        name = os.path.basename(value)
        name = 'jonagold.yaml' if name == 'cultivar.yaml' else name
        shipped = os.path.join(root, 'config', name)
        return shipped if os.path.isfile(shipped) else os.path.join(tmp, name)
    return {'N': '3', 'S': '1', 'NAME': 'lane1'}.get(value, value)


seen = set()
for no, cmd, comment in candidates:
    if cmd in seen:
        continue
    seen.add(cmd)
    cmd = re.sub(r'<[^>]*>', 'FILE', re.sub(r'\s*\[[^\]]*\]', '', cmd))
    words = shlex.split(cmd)
    words = [w.split(':=')[0] + ':=' + fill_path(w.split(':=', 1)[1]) if ':=' in w else fill_path(w)
             for w in words]
    status = re.search(r'\bexit (?:code |status )?(\d+)', comment)
    kind = 'launch' if words[0] == 'roslaunch' else 'node' if words[2] in NODES else 'cli'
    print('%s\t%s\t%s\t%s' % (kind, status.group(1) if status else '0', no, shlex.join(words)))
PY

# Resolves a roslaunch command line (roslaunch's own loader) and finds every
# node it would start; exit 1 naming what does not resolve.
cat >"$tmp/resolve.py" <<'PY'
import sys
import roslaunch.config, roslaunch.core, roslaunch.rlutil, roslib.packages
args = sys.argv[2:]  # package, launch file, name:=value...
try:
    files = roslaunch.rlutil.resolve_launch_arguments(args)
    config = roslaunch.config.load_config_default([(files[0], args)], None, verbose=False)
except roslaunch.core.RLException as e:
    sys.exit('does not resolve: %s' % e)
errors = list(config.config_errors)
for n in config.nodes:
    if not roslib.packages.find_node(n.package, n.type):
        errors.append('node %s/%s not found' % (n.package, n.type))
if errors:
    sys.exit('; '.join(errors))
print('  resolves: %s; nodes %s' % (files[0], ', '.join('%s/%s' % (n.package, n.type) for n in config.nodes)))
PY

fail=0 ran=0 port=""
bad() { fail=1; echo "FAIL: $*" >&2; }
core_pid=""
cleanup_master() {
  if [ -n "$core_pid" ]; then
    kill "$core_pid" 2>/dev/null || true
    wait "$core_pid" 2>/dev/null || true
    core_pid=""
  fi
}
trap 'cleanup_master; rm -rf "$tmp"' EXIT

while IFS=$'\t' read -r kind expect no cmd; do
  ran=$((ran + 1))
  echo "$no: $cmd"
  words=()
  eval "words=($cmd)"
  status=0
  case "$kind" in
    cli)
      (cd "$tmp/cwd" && timeout -k 5 60 "${words[@]}") >"$tmp/out" 2>&1 || status=$?
      if [ "$status" -ne "$expect" ]; then
        tail -5 "$tmp/out" >&2
        bad "$no: '$cmd' exited $status, expected $expect"
      fi
      ;;
    node)
      if [ -z "$core_pid" ]; then
        port=$(af_free_port)
        af_start_master "$port" "$tmp/roscore.log" || { core_pid=$AF_MASTER_PID; exit 1; }
        core_pid=$AF_MASTER_PID
      fi
      (cd "$tmp/cwd" && timeout -s INT -k 5 3 "${words[@]}") >"$tmp/out" 2>&1 || status=$?
      if [ "$status" -ne 124 ]; then
        tail -5 "$tmp/out" >&2
        bad "$no: '$cmd' exited $status within 3 s; a node should keep running"
      fi
      ;;
    launch)
      /usr/bin/python3 "$tmp/resolve.py" "${words[@]}" || bad "$no: '$cmd' does not resolve"
      ;;
  esac
done <"$tmp/lines"
[ "$ran" -gt 0 ] || bad "no rosrun or roslaunch line found"

# A page's setup file is the devel space of a default build.
default_devel=$(unset AF_BUILD_DIR AF_DEVEL_DIR && source "$AF_ROOT/scripts/env.sh" && echo "${AF_DEVEL#"$AF_ROOT"/}")
while IFS=: read -r page no text; do
  for path in $(grep -oE 'source [^ `;]*setup\.bash' <<<"$text" | cut -d' ' -f2); do
    [ "$path" = "$default_devel/setup.bash" ] ||
      bad "${page#"$AF_ROOT"/}:$no: 'source $path', but a default build's devel space is $default_devel/"
  done
done < <(grep -Hn 'source [^ `;]*setup\.bash' "${pages[@]}" || true)

if [ -n "$core_pid" ]; then
  cleanup_master
  unset ROS_MASTER_URI
  af_check_stopped "$port" || fail=1
fi
[ "$fail" -eq 0 ] && echo "test_readme_ros_lines: $ran lines of README.md and doc/*.md passed"
exit "$fail"
