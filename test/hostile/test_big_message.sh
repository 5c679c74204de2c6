#!/usr/bin/env bash
# The node and messages too long to read (finding 3; af_wire_guard.h):
# two force SignalChunks of 10^8 samples (400 MB each) are dropped unread,
# counted in /diagnostics, the node's VmHWM stays within 256 MiB, and good
# chunks flow again after each (big_message.py checks all of it; its own
# RSS, the publisher's 400 MB message, is the bound's 2048 MiB here).
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/hostile.sh"
hostile_case big_message_dropped_unread 0 \
  'messages too long to read: 2 \(longest 400000047 bytes; cap [0-9]+ bytes' \
  120 2048 -- /usr/bin/python3 "$here/big_message.py" 100000000 2
cat "$tmp/big_message_dropped_unread.out"
hostile_done
