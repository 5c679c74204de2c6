#!/usr/bin/env bash
# Runs one test command and writes its JUnit result, for catkin's
# `catkin_make run_tests` and `catkin_test_results` (which read
# build/test_results/<package>/*.xml): every test ctest runs is then seen by
# catkin too (cmake/af_tests.cmake registers both).
#   junit.sh [--zero] RESULT.xml NAME COMMAND [ARG...]
# Exit status: the command's; 0 with --zero (catkin's run_tests goes on after
# a failure: catkin_test_results judges). The XML: one testcase NAME, a failure (with the
# exit status and the output's last 100 lines) when the command failed, the
# whole output as system-out.
set -u
zero=0
if [ "${1:-}" = "--zero" ]; then
  zero=1
  shift
fi
result=${1:?RESULT.xml}
name=${2:?NAME}
shift 2
mkdir -p "$(dirname "$result")"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
t0=$(date +%s.%N)
"$@" >"$log" 2>&1
status=$?
t1=$(date +%s.%N)
cat "$log"
/usr/bin/python3 - "$result" "$name" "$status" "$t0" "$t1" "$log" <<'PY' || exit 1
import sys
import xml.etree.ElementTree as ET
result, name, status, t0, t1, log = sys.argv[1:]
out = open(log, encoding='utf-8', errors='replace').read()
# XML 1.0 cannot hold most control characters: shown as '?'.
out = ''.join(c if c in '\t\n\r' or ord(c) >= 0x20 else '?' for c in out)
secs = '%.3f' % (float(t1) - float(t0))
suite = ET.Element('testsuite', name='acoustic_firmness.' + name, tests='1',
                   failures='0' if status == '0' else '1', errors='0', time=secs)
case = ET.SubElement(suite, 'testcase', classname='acoustic_firmness', name=name, time=secs)
if status != '0':
    failure = ET.SubElement(case, 'failure', message='exited with status %s' % status)
    failure.text = '\n'.join(out.splitlines()[-100:])
ET.SubElement(suite, 'system-out').text = out
ET.ElementTree(suite).write(result, encoding='utf-8', xml_declaration=True)
PY
[ "$zero" = 1 ] && exit 0
exit "$status"
