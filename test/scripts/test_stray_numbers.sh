#!/usr/bin/env bash
# The parameter table (src/core/settings.c) is the only source of the
# lane's numbers (issue 16): the shipped defaults below may appear only in
# the table and in what is generated from it (config/station.yaml,
# config/jonagold.yaml and doc/parameters.md's generated part, which
# scripts_doc_parameters checks; doc/paper.md, written by `firmness_model
# paper`, quotes the paper). Any other line of src/, config/, launch/,
# doc/, msg/ or README.md that states one as a default fails, unless
# the allow-list below names it with its reason. Then the scanner is run on
# a scratch tree with a planted stray, which it must report (so this test
# can fail). Registered in ctest as scripts_stray_numbers.
#   bash test/scripts/test_stray_numbers.sh
set -euo pipefail
source "$(dirname "$0")/harness.sh"

# The allow-list: "path | a fixed part of the line", one per line; '#' starts
# a comment. An entry that matches no line is reported (not failed: the
# i16-settings lines go away when that branch is merged).
cat >"$tmp/allow" <<'ALLOW'
# moved by i16-settings: the core *_default() bodies become generated macros
src/core/response.c | c.hum_hz = 50.0;
src/core/response.c | c.snr_threshold_db = 15.0;
src/core/impact.c | .velocity_m_s = 1.4,
src/core/model.c | #define AF_MODEL_YIELD_RATIO 0.0414
src/core/model.c | #define AF_MODEL_YIELD_EXPONENT 0.70
src/core/model.c | tau_y = 0.0414 E_ref (E2/E_ref)^0.70 with E_ref 8 MPa
src/core/model.h | yield law tau_y = 0.0414 x 8 MPa x (E2 / 8 MPa)^0.70
src/core/impact.h | 1.4 m/s, rigid (nu1 0.3 unused while rigid)
src/core/impact.h | af_setting_rig_value: 10 g, flat face
src/core/response.h | hum 50 Hz with 3 harmonics
src/core/response.h | threshold 15 dB (noise-only
src/core/response.h | 15 dB in none of 2e4
# not a default: what the table's rows document (the rig's value, YAML syntax)
src/core/settings.h | e.g. 0.010 for hammer_mass_kg [kg]
# the rig itself: its URDF (test_urdf checks it equals the table's rig value)
config/rig.urdf | <mass value="0.010"/>
# quotes of the paper: its claim and its deviations (doc/deviations.md)
src/tools/paper.c | "below the yield at 10 g, 1.4 m/s",
doc/deviations.md | 0.536 = 0.75/1.4 is the Lankarani
doc/deviations.md | shipped 0.0414 × 8 MPa × (E2/8 MPa)^0.70
doc/deviations.md | 0.0414 with exponent 0.70 in the c
doc/figures.md | elastic contact time (m1 10 g, v0 1.4 m/s
# prose quoting the shipped value: the doc pages the lead merges (README.md
# is rewritten by another helper); to be cited from the table, then dropped
README.md | (default 1.4 m/s, the paper's
README.md | shipped 0.0414 ×
README.md | 8 MPa × (E2/8 MPa)^0.70 (0.331 MPa
doc/model.md | Shipped: **0.0414 × 8 MPa × (E2/8 MPa)^0.70**
doc/model.md | p = 0.70 below the computed shear's
doc/model.md | R2 40 mm, 10 g at 1.4 m/s) the shipped profile
doc/model.md | law shipped now (0.0414 × 8 MPa × (E2/8 MPa)^0.70
doc/model.md | the shipped exponent 0.70, below
doc/cli.md | (calibration) (default 0.0414)
doc/cli.md | 15 dB none of 2e4) [dB] (default 15
doc/cli.md | (default 0.0414, range [0.001, 1]
doc/cli.md | config/rig.urdf: 10 g,
doc/cli.md | The paper's 10 g at 1.4 m/s is not feasible
doc/cli.md | (10 g rigid flat hammer at 1.4 m/s, e 0.6
doc/cli.md | peak, 50 Hz hum, offset and drift
doc/parameters.md | The shipped rig's hammer (10 g, a flat face)
doc/parameters.md | **yield_ratio** (double, 0.0414, [0.001, 1], –), **yield_exponent** (double, 0.70
doc/parameters.md | 50 Hz hum + 3 harmonics removed
doc/parameters.md | 12 dB let about 0.1 % of noise-only windows through as a resonance, 15 dB none of
doc/parameters.md | 12 dB and `analyze` with 15 dB until
doc/report.md | the shipped rig's hammer (10 g, flat face)
doc/tests.md | (the value stays 15 dB;
doc/parameters.md | - **strike_velocity_m_s** (double, 1.4, [0.05, 10], m/s): contact velocity.
# example output: printed by the tools from the table (scripts_doc_examples
# re-runs each and compares)
doc/cli.md | contact velocity [m/s] (default 1.4)
doc/cli.md | contact velocity (the paper's optimum) [m/s] (default 1.4, range
doc/lane.md | 'measure_snr_threshold_db': 15.0
ALLOW

# scan ROOT ALLOW: prints each stray as "path:line: default (text)"; exit 1
# when there is one.
scan() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import os, re, sys
root, allow_path = sys.argv[1], sys.argv[2]
# Each default: its name and a regex of a line stating it (case-insensitive):
# the number in a context that makes it that default (a bare "1.4" may be
# anything; "1.4 m/s" or "velocity ... 1.4" is the strike velocity).
DEFAULTS = [
    ('yield_ratio 0.0414', r'\b0\.0414\b'),
    ('yield_exponent 0.70', r'(yield|exponent|\^|\bp\b).*\b0\.70\b|\b0\.70\b.*(yield|exponent)'),
    ('hammer_mass_kg 0.010 (10 g)',
     r'(hammer|\bm1\b|\brig\b|mass).{0,40}(\b0\.010\b|\b10 ?g\b)|(\b0\.010\b|\b10 ?g\b).{0,20}(hammer|\bkg\b)'),
    ('measure_snr_threshold_db 15', r'\b15(\.0)? ?dB\b|snr\w*\W?\s*[:=]\s*15(\.0)?(?![.\d])'),
    ('hum 50 Hz', r'\b50(\.0)? ?Hz\b|hum_hz\W?\s*[:=]\s*50(\.0)?(?![.\d])'),
    ('strike_velocity_m_s 1.4', r'\b1\.4 ?m/s\b|(velocity|\bv0).{0,40}\b1\.4(?![.\d]| ?ms)'),
]
# The table and what is generated from it (checked by scripts_doc_parameters
# and cli_test_paper): not scanned.
SKIP = {'src/core/settings.c', 'src/core/settings_table.c', 'config/station.yaml',
        'config/jonagold.yaml', 'doc/paper.md'}
GEN_BEGIN = '<!-- generated by af_settings_doc (scripts/docs.sh): do not edit -->'
GEN_END = '<!-- end of generated -->'
allow = []
for line in open(allow_path, encoding='utf-8'):
    line = line.strip()
    if line and not line.startswith('#'):
        path, _, part = line.partition(' | ')
        allow.append([path.strip(), part, 0])
files = []
for top in ('src', 'config', 'launch', 'doc', 'msg'):
    for d, _, names in os.walk(os.path.join(root, top)):
        files += [os.path.join(d, n) for n in names]
if os.path.exists(os.path.join(root, 'README.md')):
    files.append(os.path.join(root, 'README.md'))
strays = 0
for f in sorted(files):
    rel = os.path.relpath(f, root)
    if rel in SKIP or rel.startswith('doc/notes/'):
        continue
    try:
        lines = open(f, encoding='utf-8').read().split('\n')
    except (UnicodeDecodeError, OSError):
        continue  # figures (png), not text
    generated = False
    for k, text in enumerate(lines, 1):
        if text.strip() == GEN_BEGIN: generated = True
        if text.strip() == GEN_END: generated = False
        if generated:
            continue
        for name, regex in DEFAULTS:
            if not re.search(regex, text, re.I):
                continue
            hit = [a for a in allow if a[0] == rel and a[1] in text]
            for a in hit:
                a[2] += 1
            if not hit:
                strays += 1
                print('%s:%d: %s typed outside the table: %s' % (rel, k, name, text.strip()[:160]))
for path, part, used in allow:
    if not used and os.path.exists(os.path.join(root, path)):
        print('note: allow-list entry matches no line (drop it): %s | %s' % (path, part))
sys.exit(1 if strays else 0)
PY
}

if scan "$AF_ROOT" "$tmp/allow" >"$tmp/out"; then
  grep '^note:' "$tmp/out" || true
  echo "test_stray_numbers: no default outside the table ($(grep -cv '^#\|^$' "$tmp/allow") allowed lines)"
else
  cat "$tmp/out" >&2
  bad "defaults typed outside the parameter table (take them from it, or allow-list with a reason)"
fi

# The scanner must see a planted stray: a tool starting from its own 1.4 m/s.
mkdir -p "$tmp/plant/src/tools"
printf 'static const double v0 = 1.4; /* strike velocity [m/s] */\n' >"$tmp/plant/src/tools/planted.c"
if scan "$tmp/plant" "$tmp/allow" >"$tmp/plant.out"; then
  bad "a planted 1.4 m/s in src/tools/planted.c was not reported"
else
  grep -q '^src/tools/planted.c:1: strike_velocity_m_s' "$tmp/plant.out" ||
    bad "the planted stray was reported wrongly: $(cat "$tmp/plant.out")"
fi
exit "$fail"
