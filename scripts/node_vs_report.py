"""The node's output against firmness_report's on the same bag, strike by strike.

The node's StrikeReport and measured Reliability messages (a bag recorded by
af_replay_record, scripts/env.sh) and firmness_report --json of the bag it was
fed must give the same strikes (matched by stamp: header.stamp = stamp_ns),
and every field of those messages must have the same value in the report's
field that the serializer's table maps to it (firmness_report --fields
--json: `resonance_hz` is StrikeReport.resonance, `stamp_ns` is
StrikeReport.header.stamp in ns, ...; src/core/io/serialize.c): the same apple,
frame, verdicts, reasons, grades, and every figure the same double (the
report writes the fewest digits that read back exactly; NaN is null). The
mapping comes from that table only: every message field must be mapped (but
Reliability's header, apple_id and source, checked here against the
StrikeReport's stamp, its apple_id and "measured"), and every field of a
report's strike must be a table row (mapped or report-only) or one of
firmness_report's own per-apple fields (src/report/output.c).

  /usr/bin/python3 scripts/node_vs_report.py REPORT.json OUT.bag N [FIRMNESS_REPORT]
prints "report_vs_node: N strikes, R reliable; node and firmness_report: ..."
and exits 1 on any difference. FIRMNESS_REPORT: the executable to ask for
the table (default: $AF_FIRMNESS_REPORT, else the package's, found as rosrun
does). compare() and compare_strike() serve the tests that check more.
"""
import json
import math
import os
import subprocess
import sys

import rosbag

# firmness_report's own fields of a strike: what the station knew of its apple
# (src/report/output.c, not the serializer's table).
REPORT_APPLE = ('apple_stamp_ns', 'mass_kg', 'predicted')
# The measured Reliability's fields that no row carries, each checked here:
# its stamp is the strike's (how it is matched), its apple_id StrikeReport's,
# its source "measured".
RELIABILITY_OWN = ('header', 'apple_id', 'source')
MESSAGES = ('StrikeReport', 'Reliability')
TOLERANCE = 0.0  # relative: the report's digits give the same double back


def firmness_report_path(exe=None):
    """The firmness_report executable: exe, $AF_FIRMNESS_REPORT, or the package's."""
    exe = exe or os.environ.get('AF_FIRMNESS_REPORT')
    if exe:
        return exe
    import roslib.packages
    found = roslib.packages.find_node('acoustic_firmness', 'firmness_report')
    if not found:
        raise RuntimeError('firmness_report not found (built? or set AF_FIRMNESS_REPORT)')
    return found[0]


def load_fields(exe=None):
    """The serializer's table: a list of {name, type, unit, message, message_field, meaning}."""
    out = subprocess.run([firmness_report_path(exe), '--fields', '--json'], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def check_mapping(fields, msg_slots):
    """Problems of the table against the messages' fields (msg_slots: message name ->
    its __slots__): every message field mapped exactly once (header by header.stamp and
    header.frame_id), none mapped that does not exist."""
    bad = []
    mapped = {}
    for f in fields:
        if f['message'] is None:
            continue
        if f['message'] not in msg_slots:
            bad.append('field %s: unknown message %s' % (f['name'], f['message']))
            continue
        top = f['message_field'].split('.')[0]
        if top not in msg_slots[f['message']]:
            bad.append('field %s: %s has no field %s' % (f['name'], f['message'], top))
        key = f['message'] + '.' + f['message_field']
        if key in mapped:
            bad.append('%s mapped twice: %s and %s' % (key, mapped[key], f['name']))
        mapped[key] = f['name']
    for msg, slots in msg_slots.items():
        for s in slots:
            if msg == 'Reliability' and s in RELIABILITY_OWN:
                continue
            if not any(k == msg + '.' + s or k.startswith(msg + '.' + s + '.') for k in mapped):
                bad.append('%s.%s: no field of the report maps it' % (msg, s))
    return bad


def message_value(msg, path):
    """The value of msg's field path ("resonance", "header.stamp": a time as ns)."""
    v = msg
    for part in path.split('.'):
        v = getattr(v, part)
    return v.to_nsec() if hasattr(v, 'to_nsec') else v


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


def compare_strike(stamp, o, r, m, bad, fields):
    """The worst relative difference of report strike o against the node's StrikeReport r and
    measured Reliability m, field by field through the table fields; every difference
    appended to bad."""
    worst = 0.0
    msgs = {'StrikeReport': r, 'Reliability': m}
    for f in fields:
        if f['message'] is None:
            continue
        name = '%s.%s' % (f['message'], f['message_field'])
        if f['name'] not in o:
            bad.append('%s: no field %s in the report' % (name, f['name']))
            continue
        a = message_value(msgs[f['message']], f['message_field'])
        ok, d = same(a, o[f['name']])
        worst = max(worst, d if math.isfinite(d) else worst)
        if not ok:
            bad.append('%s (%s) at %d: node %r, report %r' % (name, f['name'], stamp, a,
                                                             o[f['name']]))
    if m.header.stamp.to_nsec() != r.header.stamp.to_nsec() or m.apple_id != r.apple_id or \
            m.source != 'measured':
        bad.append('Reliability at %d: stamp %d, apple %d, source %r; StrikeReport: stamp %d, '
                   'apple %d' % (stamp, m.header.stamp.to_nsec(), m.apple_id, m.source,
                                 r.header.stamp.to_nsec(), r.apple_id))
    known = {f['name'] for f in fields} | set(REPORT_APPLE)
    for key in sorted(set(o) - known):
        bad.append('report field %s: neither a field of firmness_report --fields nor one of its '
                   'apple fields' % key)
    return worst


def compare(report_json, out_bag, count, exe=None):
    """(offline strikes by stamp [ns], list of differences, worst relative difference)."""
    fields = load_fields(exe)
    rep = json.load(open(report_json))
    reports, measured = {}, {}
    for topic, m, _ in rosbag.Bag(out_bag).read_messages():
        if topic.endswith('strike_report'):
            reports[m.header.stamp.to_nsec()] = m
        elif m.source == 'measured':
            measured[m.header.stamp.to_nsec()] = m
    offline = {o['stamp_ns']: o for o in rep['strikes']}
    bad, worst = [], 0.0
    if reports and measured:
        bad += check_mapping(fields, {'StrikeReport': next(iter(reports.values())).__slots__,
                                      'Reliability': next(iter(measured.values())).__slots__})
    if not (len(offline) == len(reports) == len(measured) == count):
        bad.append('counts: report %d, node %d StrikeReports, %d measured Reliabilities, expected %d'
                   % (len(offline), len(reports), len(measured), count))
    for stamp, o in sorted(offline.items()):
        r, m = reports.get(stamp), measured.get(stamp)
        if r is None or m is None:
            bad.append('strike at %d: not in the node output' % stamp)
            continue
        worst = max(worst, compare_strike(stamp, o, r, m, bad, fields))
    return offline, bad, worst


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit('usage: node_vs_report.py REPORT.json OUT.bag N [FIRMNESS_REPORT]')
    offline, bad, worst = compare(sys.argv[1], sys.argv[2], int(sys.argv[3]),
                                  sys.argv[4] if len(sys.argv) == 5 else None)
    rel = sum(o['reliable'] for o in offline.values())
    print('report_vs_node: %d strikes, %d reliable; node and firmness_report: %s; worst relative '
          'difference %.3g' % (len(offline), rel, 'the same apples, verdicts, reasons, grades and '
                               'figures' if not bad else '%d DIFFERENCES' % len(bad), worst))
    for line in bad[:10]:
        print('  ' + line)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
