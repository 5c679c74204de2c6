"""The apples of a cultivar's domain that one strike (a rigid flat hammer of
m1 kg at v0 m/s) does not make reliable, computed with Debian's python3
alone from PHYSICS.md, independently of the package (design.c's domain, the
shipped profile):

  domain  E2 over [2, 12] MPa (6 values) x mass over [100, 250] g (4) x R2
          from the equatorial radius of a sphere of that mass at 840 kg/m3
          down to 25 mm (3, geometric): 72 apples;
  pulse   the damped Hertz contact of hertz_strike.py (RK4, its own
          integrator), chi = 0.975, the exact damping for e = 0.6 (§2);
  band    the main lobe of the pulse's amplitude spectrum (a direct Fourier
          sum) down to half its peak (-6 dB, §4);
  0S2     Lamb's frequency of the free sphere: E = C f^2 m^(2/3) rho^(1/3),
          C = 5.833 at nu 0.35 (§5);
  damage  tau_max = 0.2987 p0 at nu 0.35 (§6), p0 = 3 F / (2 pi a^2),
          a^2 = R d, its largest over the contact, against the yield law
          0.0414 x 8 MPa x (E2 / 8 MPa)^0.70 (the cultivar's YAML).

Prints the count of apples not reliable, how many of them and how many of
the reliable ones lie within NEAR = 0.5 % of a limit (0S2 / edge and shear /
yield: a 0.5 % difference in the pulse could flip them), and the worst
apple's yield / shear; then one line per apple given up. A tip of radius R1 (TIP_M > 0) makes the
contact radius 1 / (1 / R2 + 1 / R1) (§1).
Usage: design_domain.py M1_KG V0_M_S [TIP_M]"""
import cmath
import math
import sys

RHO, NU, CHI, G = 840.0, 0.35, 0.975, 9.80665
NEAR = 0.005


def pulse(E2, R, m1, v0, h=0.5e-6):
    """Force samples [N] every h seconds of the damped Hertz contact, and the
    largest F / d over the contact [N/m] (p0 = 3 F / (2 pi a^2) with
    a^2 = R d: the damping makes it peak before the force does)."""
    K = 4.0 / 3.0 * E2 / (1 - NU * NU) * math.sqrt(R)

    def acc(d, v):
        return G - (K * d ** 1.5 * (1 + CHI * v / v0) if d > 0 else 0.0) / m1

    d, v, f, f_per_d = 0.0, v0, [0.0], 0.0
    while True:
        k1 = acc(d, v)
        k2 = acc(d + h / 2 * v, v + h / 2 * k1)
        k3 = acc(d + h / 2 * (v + h / 2 * k1), v + h / 2 * k2)
        k4 = acc(d + h * (v + h / 2 * k2), v + h * k3)
        d += h * v + h * h / 6 * (k1 + k2 + k3)
        v += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        if d <= 0:
            return f, f_per_d, h
        force = max(K * d ** 1.5 * (1 + CHI * v / v0), 0.0)
        f_per_d = max(f_per_d, force / d)
        f.append(force)


def spectrum(f, h, freq):
    return abs(sum(x * cmath.exp(-2j * math.pi * freq * k * h) for k, x in enumerate(f))) * h


def half_edge(f, h):
    """The frequency [Hz] where the main lobe falls to half its peak (at 0 Hz,
    a one-signed pulse), by bisection between 0 and 1/t_c (the edge lies
    near 0.93/t_c, §4)."""
    top = spectrum(f, h, 0.0)
    lo, hi = 0.0, 1.5 / (len(f) * h)
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if spectrum(f, h, mid) > top / 2 else (lo, mid)
    return (lo + hi) / 2


def main():
    m1, v0 = float(sys.argv[1]), float(sys.argv[2])
    tip = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
    given_up, near_out, near_in, worst = [], 0, 0, math.inf
    for i in range(6):
        E2 = 2e6 + 10e6 * i / 5
        for j in range(4):
            mass = 0.100 + 0.150 * j / 3
            r_eq = (3 * mass / (4 * math.pi * RHO)) ** (1 / 3)
            f0s2 = math.sqrt(E2 / (5.833 * mass ** (2 / 3) * RHO ** (1 / 3)))
            for k in range(3):
                R2 = r_eq * (min(0.025, r_eq) / r_eq) ** (k / 2)
                R = 1 / (1 / R2 + 1 / tip) if tip > 0 else R2
                f, f_per_d, h = pulse(E2, R, m1, v0)
                edge = half_edge(f, h)
                shear = 0.2987 * 3 * f_per_d / (2 * math.pi * R)
                yld = 0.0414 * 8e6 * (E2 / 8e6) ** 0.70
                worst = min(worst, yld / shear)
                limit = max(f0s2 / edge, shear / yld)  # > 1: not reliable
                if limit <= 1:
                    near_in += limit > 1 - NEAR
                else:
                    near_out += limit < 1 + NEAR
                    given_up.append('E2 %5.2f MPa, %3.0f g, R2 %4.1f mm: 0S2 %.0f Hz, edge %.0f Hz, '
                                    'yield/shear %.3f' % (E2 / 1e6, mass * 1e3, R2 * 1e3, f0s2, edge,
                                                          yld / shear))
    print('%d %d %d %.4f' % (len(given_up), near_out, near_in, worst))
    for line in given_up:
        print(line)


main()
