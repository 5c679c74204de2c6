"""The node's output against firmness_report's on the same bag, strike by strike.

The node's StrikeReport and measured Reliability messages (a bag recorded by
af_replay_record, scripts/env.sh) and firmness_report --json of the bag it was
fed must give the same strikes (matched by stamp), apple ids, verdicts and
reasons, and every figure within 1e-9 relative.

  /usr/bin/python3 scripts/node_vs_report.py REPORT.json OUT.bag N
prints "report_vs_node: N strikes, R reliable; node and firmness_report: ..."
and exits 1 on any difference. compare() serves the tests that check more.
"""
import json
import math
import sys

import rosbag

# StrikeReport field -> firmness_report JSON key (unit-suffixed).
FIELDS = (('contact_time', 'contact_time_s'), ('peak_force', 'peak_force_N'), ('impulse', 'impulse_Ns'),
          ('band_low', 'band_low_Hz'), ('band_high', 'band_high_Hz'), ('resonance', 'resonance_Hz'),
          ('resonance_q', 'resonance_q'), ('snr_db', 'snr_dB'), ('stiffness_factor', 'stiffness_factor'),
          ('modulus_from_resonance', 'modulus_from_resonance_Pa'), ('fitted_modulus', 'fitted_modulus_Pa'),
          ('fitted_restitution', 'fitted_restitution'), ('fit_residual', 'fit_residual'))
TOLERANCE = 1e-9  # relative


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
        if r.apple_id != o['apple_id'] or m.reason != o['reason'] or m.reliable != o['reliable'] \
                or m.excites_mode != o['excites_mode'] or m.no_damage != o['no_damage']:
            bad.append('strike at %d: apple/verdict/reason differ' % stamp)
        for f, key in FIELDS:
            a, b = getattr(r, f), o[key]
            if b is None:
                if not math.isnan(a):
                    bad.append('%s at %d: node %r, report NaN' % (f, stamp, a))
                continue
            d = abs(a - b) / max(abs(b), 1e-300)
            worst = max(worst, d)
            if d > TOLERANCE:
                bad.append('%s at %d: node %r, report %r' % (f, stamp, a, b))
    return offline, bad, worst


def main():
    offline, bad, worst = compare(sys.argv[1], sys.argv[2], int(sys.argv[3]))
    rel = sum(o['reliable'] for o in offline.values())
    print('report_vs_node: %d strikes, %d reliable; node and firmness_report: %s; worst relative '
          'difference %.3g' % (len(offline), rel, 'the same apples, verdicts and reasons' if not bad
                              else '%d DIFFERENCES' % len(bad), worst))
    for line in bad[:10]:
        print('  ' + line)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
