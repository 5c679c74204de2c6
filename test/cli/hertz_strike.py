"""The test signals' strike: a Hertz contact with hysteresis damping
(F = K d^1.5 (1 + chi v / v0)) integrated by classical RK4 at 0.25 us with
Debian's python3 alone, independently of the package's GSL integrator.
hertz_pulse(E2) returns (force_at(s) [N] at s seconds after the touch,
contact time [s], peak force [N])."""
import math


def hertz_pulse(E2, m1=0.010, v0=1.4, g=9.80665, nu=0.35, R=0.04, chi=0.975, h=0.25e-6):
    K = 4.0 / 3.0 * E2 / (1 - nu * nu) * math.sqrt(R)

    def accel(d, v):
        f = K * d ** 1.5 * (1 + chi * v / v0) if d > 0 else 0.0
        return g - f / m1, f

    d, v, t, fine = 0.0, v0, 0.0, [0.0]
    while True:
        k1 = accel(d, v)[0]
        k2 = accel(d + h / 2 * v, v + h / 2 * k1)[0]
        k3 = accel(d + h / 2 * (v + h / 2 * k1), v + h / 2 * k2)[0]
        k4 = accel(d + h * (v + h / 2 * k2), v + h * k3)[0]
        d_new = d + h * v + h * h / 6 * (k1 + k2 + k3)
        v = v + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t += h
        if d_new <= 0:
            tc = t - h + h * d / (d - d_new)  # linear crossing
            break
        d = d_new
        fine.append(max(accel(d, v)[1], 0.0))

    def force_at(s):
        if s <= 0 or s >= tc:
            return 0.0
        u = s / h
        j = int(u)
        if j + 1 < len(fine):
            return fine[j] + (u - j) * (fine[j + 1] - fine[j])
        return fine[-1] * (tc - s) / (tc - (len(fine) - 1) * h)

    return force_at, tc, max(fine)
