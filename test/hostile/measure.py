#!/usr/bin/python3
"""Runs one command of the hostile suite under a wall-time bound and reports
how it ended, on one line: `exit=N wall_s=T rss_mib=M timed_out=0|1`.
  measure.py TIMEOUT_S STDOUT_FILE STDERR_FILE -- CMD ARG...
The command's stdin is /dev/null. On the bound the whole process group is
killed (SIGKILL) and timed_out=1. Peak RSS is the child's ru_maxrss (the
largest of the processes it waited for)."""
import os, resource, signal, subprocess, sys, time

timeout_s, out_path, err_path = float(sys.argv[1]), sys.argv[2], sys.argv[3]
cmd = sys.argv[sys.argv.index('--') + 1:]
t0 = time.monotonic()
with open(out_path, 'wb') as out, open(err_path, 'wb') as err, open(os.devnull, 'rb') as nul:
    p = subprocess.Popen(cmd, stdin=nul, stdout=out, stderr=err, start_new_session=True)
    timed_out = 0
    try:
        rc = p.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        timed_out = 1
        os.killpg(p.pid, signal.SIGKILL)
        rc = p.wait()
wall = time.monotonic() - t0
rss_mib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
print('exit=%d wall_s=%.3f rss_mib=%.1f timed_out=%d' % (rc, wall, rss_mib, timed_out))
