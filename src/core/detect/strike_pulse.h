/* strike_pulse.h — the measurement of one strike's pulse: pure functions on a
 * span of raw force samples, no detector state. The detector (strike.c)
 * copies each event's span out of its history ring and hands it here with
 * what it knew when the strike triggered; anything else (a test, a tool) can
 * do the same with samples of its own.
 *
 * The method (baseline line through quiet windows either side of the
 * contact, placed twice; contact start and end from the edge law
 * a1 s^1.5 + a2 s^4 or, for short pulses, from the crossings of
 * max(3 noise RMS, 2 % of the peak) by the band-limited reconstruction;
 * the peak from a least-squares quartic or the reconstruction; the impulse
 * by trapezoids over [t0, t1]) and its precision are in strike.h's header.
 *
 * Indices are span-relative sample numbers (x[0] is sample 0), fractional
 * where sub-sample; long, as windows may run off the span's ends. */
#ifndef AF_STRIKE_PULSE_H
#define AF_STRIKE_PULSE_H

#include <stdbool.h>
#include <stddef.h>

#include "status.h"
#include "strike.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One span and what is known about its strike. */
typedef struct {
  const double *x;           /* raw force x[0..n) [N]; NaN where a sample was lost */
  long n;                    /* span length [samples], >= 1 */
  long trigger;              /* first sample above the trigger threshold, in [0, n) */
  long contact_end;          /* first quiet sample after the first contact (coarse; n when
                                it had not ended) */
  long clean_end;            /* the signal after the first contact is clean before this
                                sample (a bounce's trigger; n without one), in [1, n] */
  long window;               /* baseline window [samples], >= 1 */
  double tracker_baseline_n; /* baseline when it triggered [N]: the coarse contact is the
                                run of samples above it by more than release_n, and the
                                baseline when neither window holds 4 finite samples */
  double release_n;          /* >= 0 [N], see tracker_baseline_n */
  double noise_rms_n;        /* >= 0: noise floor [N]; the crossings' level is at least 3x */
  double rise_fit_level;     /* (0, 1): rising-edge fit up to this fraction of the peak */
  double fall_fit_level;     /* (0, 1): falling-edge fit from this fraction of the peak */
  double sample_rate_hz;     /* > 0 */
  double full_scale_n;       /* > 0: a raw sample with |F| >= this is clipped [N] */
} af_strike_pulse_input;

/* The figures measured. */
typedef struct {
  double start;            /* contact start t0 [samples] */
  double end;              /* contact end t1 [samples] */
  double peak_at;          /* time of the peak [samples] */
  double peak_n;           /* refined peak of the baseline-removed force [N] */
  double contact_time_s;   /* (t1 - t0) / sample rate */
  double impulse_n_s;      /* trapezoid integral of the baseline-removed force over [t0, t1],
                              the force taken as 0 at both [N s] */
  double baseline_n;       /* baseline line b0 + slope k: its value at k = 0 [N] ... */
  double baseline_slope_n; /* ... and its slope [N/sample] */
  af_strike_edges start_edge, end_edge; /* which method gave t0 and t1 */
  double edge_level_n;                  /* level of the crossings [N] */
  bool clipped;      /* a raw sample of the contact (coarse or measured) at or beyond
                        +-full_scale_n */
  long coarse_start; /* coarse contact: first sample ... */
  long coarse_end;   /* ... and first sample after it (at most n) */
  long first;        /* pulse r[first .. first + n_samples): the samples in [t0, t1] */
  size_t n_samples;
  size_t baseline_before_samples; /* finite samples averaged before the contact (0: none) */
  size_t baseline_after_samples;  /* ... and after it (0: none) */
} af_strike_pulse;

/* Measures the strike in in->x: writes the baseline-removed span into
 * r[0..in->n) (lost samples filled by the straight line between their
 * neighbours) and the figures into *out. AF_EINVAL for NULL pointers or a
 * field of *in outside its range (*out untouched). No allocation, no state:
 * the same input gives the same output, bit for bit. */
af_status af_strike_pulse_measure(const af_strike_pulse_input *in, double *r, af_strike_pulse *out);

#ifdef __cplusplus
}
#endif
#endif
