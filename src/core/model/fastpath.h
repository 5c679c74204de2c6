/* fastpath.h — a strike evaluated by scaling and interpolation.
 *
 * After scaling (impact.c: D = (5 m1 v0^2 / (4 K))^(2/5), T = D / v0,
 * F0 = m1 v0^2 / D), the pulse depends only on the damping chi and the
 * gravity number gamma = g D / v0^2; the ODE path (model.c) samples it with a
 * step of the elastic contact time / 128, which is the same in units of T,
 * so its sampled pulse, spectrum, lobes and band edges scale exactly:
 * time with T, force with F0, frequency with 1/T, |X| with F0 T, the centre
 * pressure with F0 / (R D). The table (below) holds the ODE path run once
 * per node of a (chi, gamma) grid: the normalised figures and |X| on a
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

/* The table is one per process, shared by every handle on every thread and
 * never freed (~5 MB of address space, pages touched as rows are built).
 * Its chi rows (101 of them, 13 ODE pulses and spectra each) are built the
 * first time a strike's interpolation stencil needs them, by whichever
 * thread asks first (C11 call_once for the table, a mutex per build, an
 * atomic flag per row read without it): a process striking near one
 * profile builds about 6 rows (~5 ms of CPU), the whole table takes ~0.08 s.
 * A row's numbers do not depend on when or where it is built. A handle
 * (af_fastpath) is one user's: the table's address, the caches of chi(e),
 * xi and the shear ratio, the ODE fallback (its af_model, made at the first
 * fallback) and the counts. Handles may be made, used and destroyed on
 * several threads at once; one handle is used by one thread at a time. */
typedef struct af_fastpath af_fastpath;

/* Builds every row of the process's table not built yet (other threads
 * wait for or share the work) and returns the status of the first row that
 * failed (AF_OK: none); *build_cpu_s (may be NULL): the CPU time [s] spent
 * building rows in this process so far, on whichever threads built them.
 * For benchmarks, and for a program that would rather pay the whole table
 * at start-up than ~1 ms per new row at its first strikes. */
af_status af_fastpath_table_build(double *build_cpu_s);

/* A handle: a few small allocations (microseconds); no row of the table and
 * not the fallback's af_model is made here. */
af_status af_fastpath_create(af_fastpath **out);
void af_fastpath_destroy(af_fastpath *f); /* NULL-safe; the table stays */

/* As af_model_execute (same checks, same result fields; impact.n_samples
 * is the ODE path's sample count, no pulse is written). No allocation but
 * once per process the table, once per handle the fallback's af_model
 * (AF_ENOMEM if that fails); the rows the strike's stencil needs are built
 * if no call has yet (~0.8 ms of CPU each). Without a table (out of memory)
 * or a row (its build failed) the strike is a fallback. */
af_status af_fastpath_execute(af_fastpath *f, const af_model_params *p, af_model_result *r);

/* af_model_min_strike_radius on this path: the same search (r2_search.h),
 * the same statuses, each radius's verdict af_fastpath_execute's (the same
 * bits, fallbacks and counts). What does not depend on the radius (the
 * checks, chi, the 0S2, the shear ratio, the yield, the chi stencil) is
 * worked out once per search, the gamma stencil's checks once per stencil:
 * an evaluation costs ~0.8 k instructions, the search ~20 k. */
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
