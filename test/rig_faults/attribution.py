#!/usr/bin/python3
"""Joins firmness_report's strike CSV with strike_bag's truth CSV by contact
start (nearest within 2 ms) and prints one line of counts:

  strikes N found F reliable R wrong_reliable W wrong_unflagged U no_apple A doubtful D

wrong_reliable: reliable strikes reported under another apple's id;
wrong_unflagged: strikes under another apple's id with neither no_apple nor
apple_doubtful among their flags. Usage: attribution.py TRUTH.csv REPORT.csv
"""
import csv
import sys


def main():
    truth = list(csv.DictReader(open(sys.argv[1])))
    rows = list(csv.DictReader(open(sys.argv[2])))
    starts = [(float(t['contact_start_s']), int(t['apple_id'])) for t in truth]
    found = reliable = wrong_rel = wrong_unflagged = no_apple = doubtful = 0
    for r in rows:
        t_s = int(r['stamp_ns']) * 1e-9
        near = min(starts, key=lambda s: abs(s[0] - t_s))
        if abs(near[0] - t_s) > 2e-3:
            continue
        found += 1
        rel = r['reliable'] == '1' or r['reliable'].lower() == 'true'
        reliable += rel
        flags = r['flags']
        no_apple += 'no_apple' in flags
        doubtful += 'apple_doubtful' in flags
        aid = int(r['apple_id'])
        if aid != 0 and aid != near[1]:
            wrong_rel += rel
            wrong_unflagged += 'apple_doubtful' not in flags and 'no_apple' not in flags
    print('strikes %d found %d reliable %d wrong_reliable %d wrong_unflagged %d no_apple %d '
          'doubtful %d' % (len(truth), found, reliable, wrong_rel, wrong_unflagged, no_apple,
                           doubtful))


if __name__ == '__main__':
    main()
