"""The node's output against firmness_report's on the same bag, strike by strike.

The node's StrikeReport and measured Reliability messages (a bag recorded by
af_replay_record, scripts/env.sh) and firmness_report --json of the bag it was
fed must give the same strikes (matched by stamp: header.stamp = stamp_ns),
and for every field of those messages the report must have the same-named
field with the same value: the same apple, frame, verdicts, reasons, grades,
and every figure the same double (the report writes %.17g, which reads back
exactly; NaN is null). Every other field of a report's strike must be on the
documented lists below (the serializer's report-only fields, src/core/
serialize.c, and firmness_report's own per-apple fields, src/report/output.c).

  /usr/bin/python3 scripts/node_vs_report.py REPORT.json OUT.bag N
prints "report_vs_node: N strikes, R reliable; node and firmness_report: ..."
and exits 1 on any difference. compare() serves the tests that check more.
"""
import json
import math
import sys

import rosbag

# Fields of a report's strike that no message carries (doc/notes/i16-serial.md).
REPORT_ONLY = ('with_audio', 'flags', 'mode_method', 'mode_confidence', 'mode_ambiguous',
               'mode_text')
# firmness_report's own fields of a strike: what the station knew of its apple.
REPORT_APPLE = ('apple_stamp_ns', 'mass_kg', 'predicted')
# Message fields that are not a strike's figure: the header (stamp_ns and
# frame_id), Reliability's source ("measured") and its apple_id (StrikeReport's).
HEADER = {'header'}
RELIABILITY_SKIP = {'header', 'apple_id', 'source'}
TOLERANCE = 0.0  # relative: %.17g gives the same double back


def same(a, b):
    """(equal, relative difference) of a message's value a and the report's b."""
    if isinstance(a, float):
        if b is None:
            return math.isnan(a), 0.0
        if math.isnan(a) or not isinstance(b, (int, float)) or isinstance(b, bool):
            return False, math.inf
        d = abs(a - b) / max(abs(b), 1e-300)
        return d <= TOLERANCE, d
    return a == b, 0.0


def fields_of(msg, skip):
    return [f for f in msg.__slots__ if f not in skip]


def compare_strike(stamp, o, r, m, bad):
    """The worst relative difference of report strike o against the node's StrikeReport r and
    measured Reliability m; every difference appended to bad."""
    worst = 0.0
    pairs = [('header.frame_id', r.header.frame_id, 'frame_id')]
    pairs += [(f, getattr(r, f), f) for f in fields_of(r, HEADER)]
    pairs += [('Reliability.' + f, getattr(m, f), f) for f in fields_of(m, RELIABILITY_SKIP)]
    for name, a, key in pairs:
        if key not in o:
            bad.append('%s: no field %s in the report' % (name, key))
            continue
        ok, d = same(a, o[key])
        worst = max(worst, d if math.isfinite(d) else worst)
        if not ok:
            bad.append('%s at %d: node %r, report %r' % (name, stamp, a, o[key]))
    known = set(fields_of(r, HEADER)) | set(fields_of(m, RELIABILITY_SKIP)) | \
        {'stamp_ns', 'frame_id'} | set(REPORT_ONLY) | set(REPORT_APPLE)
    for key in sorted(set(o) - known):
        bad.append('report field %s: neither a message field nor on the report-only lists' % key)
    return worst


def compare(report_json, out_bag, count):
    """(offline strikes by stamp [ns], list of differences, worst relative difference)."""
    rep = json.load(open(report_json))
    reports, measured = {}, {}
    for topic, m, _ in rosbag.Bag(out_bag).read_messages():
        if topic.endswith('strike_report'):
            reports[m.header.stamp.to_nsec()] = m
        elif m.source == 'measured':
            measured[m.header.stamp.to_nsec()] = m
    offline = {o['stamp_ns']: o for o in rep['strikes']}
    bad, worst = [], 0.0
    if not (len(offline) == len(reports) == len(measured) == count):
        bad.append('counts: report %d, node %d StrikeReports, %d measured Reliabilities, expected %d'
                   % (len(offline), len(reports), len(measured), count))
    for stamp, o in sorted(offline.items()):
        r, m = reports.get(stamp), measured.get(stamp)
        if r is None or m is None:
            bad.append('strike at %d: not in the node output' % stamp)
            continue
        worst = max(worst, compare_strike(stamp, o, r, m, bad))
    return offline, bad, worst


def main():
    offline, bad, worst = compare(sys.argv[1], sys.argv[2], int(sys.argv[3]))
    rel = sum(o['reliable'] for o in offline.values())
    print('report_vs_node: %d strikes, %d reliable; node and firmness_report: %s; worst relative '
          'difference %.3g' % (len(offline), rel, 'the same apples, verdicts, reasons, grades and '
                               'figures' if not bad else '%d DIFFERENCES' % len(bad), worst))
    for line in bad[:10]:
        print('  ' + line)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
