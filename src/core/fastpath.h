/* fastpath.h — a strike evaluated by scaling and interpolation.
 *
 * After scaling (impact.c: D = (5 m1 v0^2 / (4 K))^(2/5), T = D / v0,
 * F0 = m1 v0^2 / D), the pulse depends only on the damping chi and the
 * gravity number gamma = g D / v0^2; the ODE path (model.c) samples it with a
 * step of the elastic contact time / 128, which is the same in units of T,
 * so its sampled pulse, spectrum, lobes and band edges scale exactly:
 * time with T, force with F0, frequency with 1/T, |X| with F0 T, the centre
 * pressure with F0 / (R D). af_fastpath_create runs the ODE path once per
 * node of a (chi, gamma) grid and keeps the normalised figures and |X| on a
 * frequency grid; af_fastpath_execute interpolates them (bicubic in chi and
 * gamma, cubic in frequency) and scales them back. The resonance and the
 * shear ratio are closed forms or cached.
 *
 * The ODE path stays the reference: a strike outside the grid (chi > 5,
 * gamma > 0.3, the 0S2 beyond 1.6 / T), one whose lobes change number inside
 * the interpolation stencil (damping fills a null in), whose selected band
 * edge is clipped to its lobe at some nodes of the stencil and not at
 * others, or whose selected band edges disagree between two cubic stencils
 * by more than 3e-4 is evaluated by af_model_execute, counted as a
 * fallback.
 * Accuracy: test/core/test_fastpath.c (within 0.1 % of the ODE path).
 */
#ifndef AF_FASTPATH_H
#define AF_FASTPATH_H

#include <stddef.h>

#include "model.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The table is one per process: built by the first execute of any handle
 * (or by af_fastpath_table_build; C11 call_once, about 1,300 ODE pulses and
 * spectra, ~0.3 s of CPU and ~5 MB) and read-only after, shared by every
 * handle on every thread; never freed. A handle (af_fastpath) is one user's:
 * the table's address, the caches of chi(e), xi and the shear ratio, the
 * ODE fallback (its af_model, made at the first fallback) and the counts.
 * Handles may be made, used and destroyed on several threads at once; one
 * handle is used by one thread at a time. */
typedef struct af_fastpath af_fastpath;

/* Builds the process's table if no call has yet (the others wait for it)
 * and returns the status of that build; *build_cpu_s (may be NULL): the CPU
 * time [s] the build took, on the thread that ran it. Call it at start-up
 * to pay the build there rather than at the first execute. */
af_status af_fastpath_table_build(double *build_cpu_s);

/* A handle: a few small allocations (microseconds); neither the table nor
 * the fallback's af_model is made here. */
af_status af_fastpath_create(af_fastpath **out);
void af_fastpath_destroy(af_fastpath *f); /* NULL-safe; the table stays */

/* As af_model_execute (same checks, same result fields; impact.n_samples
 * is the ODE path's sample count, no pulse is written). No allocation but
 * once per process the table and once per handle the fallback's af_model
 * (AF_ENOMEM if that fails). Without a table (its build failed) every
 * strike is a fallback. */
af_status af_fastpath_execute(af_fastpath *f, const af_model_params *p, af_model_result *r);

/* af_model_min_strike_radius on this path: the same search (r2_search.h),
 * the same statuses. */
af_status af_fastpath_min_strike_radius(af_fastpath *f, const af_model_params *p, double r_lo_m,
                                        double r_hi_m, double *r_min_m);

/* The ODE path's model (the fallback; made on the first call), e.g. to
 * draw a pulse; NULL out of memory. */
af_model *af_fastpath_model(af_fastpath *f);

/* Evaluations from the table and by the fallback since create. */
void af_fastpath_counts(const af_fastpath *f, size_t *from_table, size_t *fallbacks);

#ifdef __cplusplus
}
#endif
#endif
