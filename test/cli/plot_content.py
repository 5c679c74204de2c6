"""What firmness_model plot drew, read back with Debian's python3 alone (a
PNG decoded by ImageMagick's convert into PPM; an SVG parsed as XML):

  png FILE W H STATE  the size W x H px; three panels (pulse, spectrum,
                      shear), each framed, with the blue series (31, 119,
                      180) across at least half its width (not blank); the
                      pulse one-humped, starting and ending at zero force;
                      the spectrum with the red 0S2 rule and the orange
                      band; the shear with the red yield rule and the
                      curve's top on the dashed tau_max rule (Hertz's axis
                      shear peaks at tau_max) within 2 px. STATE says where
                      the red rules lie: "safe" (0S2 inside the band, the
                      yield above the curve) or "bruise" (0S2 right of the
                      band, the yield below the curve's top).
  svg FILE W H        the size W x H pt; one long blue path (>= 50 points)
                      in each third of the width (the three series); the red
                      rules; at least 300 glyphs (the titles, axis labels and
                      legends; cairo writes text as glyphs, not <text>).

One line per failure on stderr; exit 1 if any.
Usage: plot_content.py png FILE W H safe|bruise | svg FILE W H"""
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

BLUE, RED = (31, 119, 180), (214, 39, 40)
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


def near(c, ref, tol=30):
    return all(abs(a - b) <= tol for a, b in zip(c, ref))


def load_png(path):
    raw = subprocess.run(['convert', path, '-depth', '8', 'ppm:-'], capture_output=True,
                         check=True).stdout
    magic, size, _maxval, data = raw.split(b'\n', 3)  # convert writes no comments
    w, h = map(int, size.split())
    return w, h, data


def png(path, want_w, want_h, state):
    w, h, d = load_png(path)
    check((w, h) == (want_w, want_h), 'PNG %dx%d, expected %dx%d' % (w, h, want_w, want_h))
    if fails:
        return

    def px(x, y):
        i = 3 * (y * w + x)
        return tuple(d[i:i + 3])

    def ink(c):  # the frame's grey
        return max(c) < 170 and max(c) - min(c) < 12
    third = w // 3
    frames = []
    for p in range(3):
        x0, x1 = p * third, (p + 1) * third
        rows = [y for y in range(h) if sum(ink(px(x, y)) for x in range(x0, x1)) > 0.5 * third]
        top = rows[0] if rows else None
        bottom = next((y for y in rows if y > top + 50), None) if rows else None
        check(bottom is not None, 'panel %d: no frame' % (p + 1))
        if bottom is None:
            return
        blue = [(x, y) for y in range(top + 1, bottom) for x in range(x0, x1) if near(px(x, y), BLUE, 40)]
        xs = {x for x, _ in blue}
        check(len(blue) >= 200 and len(xs) >= 0.5 * (max(xs, default=0) - x0) and
              max(xs, default=x0) - min(xs, default=x0) >= third / 2,
              'panel %d: the blue series is missing or short (%d px over %d columns)' % (p + 1, len(blue), len(xs)))
        frames.append((x0, x1, top, bottom, blue))
    if fails:
        return
    # Pulse: the topmost blue pixel per column rises, then falls (one hump),
    # and the curve reaches the bottom (zero force) at both ends.
    x0, x1, top, bottom, blue = frames[0]
    tops = {}
    for x, y in blue:
        tops[x] = min(tops.get(x, bottom), y)
    cols = sorted(tops)
    ys = [tops[x] for x in cols]
    k = ys.index(min(ys))
    rises = sum(b > a + 1 for a, b in zip(ys[:k], ys[1:k + 1]))  # a step down the page before the peak
    falls = sum(b < a - 1 for a, b in zip(ys[k:], ys[k + 1:]))
    check(rises == 0 and falls == 0 and 0 < k < len(ys) - 1, 'pulse: not one hump (%d, %d)' % (rises, falls))
    check(ys[0] >= bottom - 4 and ys[-1] >= bottom - 4, 'pulse: does not start and end at zero force')
    # Spectrum: the red 0S2 rule (a column red over most of the frame) against
    # the orange band's right edge (along the frame's bottom row the band's
    # light tint has red above blue, the lobes' and the 0S2 range's blue above
    # red; green above 150 leaves out the ticks and the red rule's edges).
    x0, x1, top, bottom, _ = frames[1]
    red = [x for x in range(x0, x1) if sum(near(px(x, y), RED) for y in range(top, bottom)) > 0.8 * (bottom - top)]
    check(red, 'spectrum: no red 0S2 rule')
    y = bottom - 3
    tinted = [x for x in range(x0, x1) if px(x, y)[0] > px(x, y)[2] + 10 and px(x, y)[1] > 150]
    check(tinted, 'spectrum: no orange band')
    if red and tinted:
        edge, rule = max(tinted), max(red)
        check((rule < edge) == (state == 'safe'),
              'spectrum: the 0S2 rule at x %d, the band ends at x %d: expected %s' % (rule, edge, state))
    # Shear: a red row (the yield) and a dashed blue row (tau_max) across the
    # frame; the curve's top on the dashed row; the yield above or below it.
    x0, x1, top, bottom, blue = frames[2]
    width = x1 - x0
    red_rows = [y for y in range(top + 1, bottom) if sum(near(px(x, y), RED) for x in range(x0, x1)) > 0.6 * width]
    dash_rows = [y for y in range(top + 1, bottom) if 0.25 * width < sum(near(px(x, y), BLUE, 40) for x in range(x0, x1)) < 0.9 * width]
    check(red_rows, 'shear: no red yield rule')
    check(dash_rows, 'shear: no dashed tau_max rule')
    peak = min(yy for xx, yy in blue if yy not in dash_rows) if blue else None
    if dash_rows and peak is not None:
        check(abs(peak - max(dash_rows)) <= 2 or abs(peak - min(dash_rows)) <= 2,
              'shear: the curve tops at y %d, the tau_max rule at y %d-%d' % (peak, min(dash_rows), max(dash_rows)))
    if red_rows and peak is not None:
        check((max(red_rows) < peak) == (state == 'safe'),
              'shear: the yield at y %d, the curve tops at y %d: expected %s' % (max(red_rows), peak, state))


def svg(path, want_w, want_h):
    root = ET.parse(path).getroot()
    ns = '{http://www.w3.org/2000/svg}'
    check(root.tag == ns + 'svg', 'not an SVG: %s' % root.tag)
    check((root.get('width'), root.get('height')) == ('%dpt' % want_w, '%dpt' % want_h),
          'SVG %s x %s, expected %dpt x %dpt' % (root.get('width'), root.get('height'), want_w, want_h))
    long_blue, red = [], 0
    for p in root.iter(ns + 'path'):
        style = p.get('style', '')
        if 'stroke:rgb(12.156863%,46.666667%,70.588235%)' in style:
            pts = [float(x) for x in re.findall(r'[ML] ([-\d.]+) [-\d.]+', p.get('d', ''))]
            if len(pts) >= 50:
                long_blue.append((min(pts), max(pts)))
        red += 'stroke:rgb(83.921569%,15.294118%,15.686275%)' in style
    third = want_w / 3
    for k in range(3):
        check(any(k * third <= lo and hi <= (k + 1) * third for lo, hi in long_blue),
              'SVG: no blue series in panel %d (%s)' % (k + 1, long_blue))
    check(red >= 2, 'SVG: %d red rules, expected the 0S2 and the yield' % red)
    glyphs = sum(1 for _ in root.iter(ns + 'use'))
    check(glyphs >= 300, 'SVG: %d glyphs, expected the labels (>= 300)' % glyphs)


if sys.argv[1] == 'png':
    png(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5])
else:
    svg(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
for f in fails:
    print('plot_content: FAIL ' + f, file=sys.stderr)
sys.exit(1 if fails else 0)
