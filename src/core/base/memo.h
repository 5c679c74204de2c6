/* memo.h — the outputs of pure functions, computed once per process and
 * copied to every later caller with the same arguments.
 *
 * Why: making a lane (and deriving its configuration) computes tables that
 * depend on the configuration alone — the response's phase factors, Lamb's
 * sphere modes (spherical Bessel roots) — and a process makes many lanes
 * (a fuzzer one per input, firmness_report one per bag). The copy is the
 * bytes the first computation produced, so every result stays bit for bit
 * what the function itself gives.
 *
 * A value is looked up by its kind (a static string naming the function, by
 * address) and its key (the bytes of the arguments: pass a struct without
 * padding, or a double). At most AF_MEMO_ENTRIES values and AF_MEMO_BYTES
 * bytes are kept; beyond that the function simply runs. Thread-safe: the
 * store is guarded by one lock, never held while a function runs.
 */
#ifndef AF_MEMO_H
#define AF_MEMO_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_MEMO_ENTRIES 64
#define AF_MEMO_BYTES ((size_t)16 << 20)

/* Computes the value of key into out[0..size) [bytes]; AF_OK or a failure
 * (a failure is not kept). */
typedef af_status af_memo_fn(const void *key, void *out);

/* out[0..size) = fn(key, out), or the kept copy of the first AF_OK result
 * for the same kind, key and size. Returns fn's status (AF_OK for a copy).
 * No allocation when the value is kept; one when it is first stored. */
af_status af_memo_get(const char *kind, const void *key, size_t key_bytes, af_memo_fn *fn,
                      void *out, size_t size);

/* The kept value itself, read-only and shared by every caller for the
 * process's life (computed by fn on the first call): for tables too large
 * to copy per caller (a lane made per fuzz input paid a page fault per 4 kB
 * of the copy). NULL when it cannot be kept (the store full, no memory, fn
 * failed): the caller then computes its own. */
const void *af_memo_ref(const char *kind, const void *key, size_t key_bytes, af_memo_fn *fn,
                        size_t size);

#ifdef __cplusplus
}
#endif
#endif
