/* memo.c — pure functions' outputs kept for the process (see memo.h). */
#include "memo.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

/* Longest key kept [bytes]: a few arguments. */
#define AF_MEMO_KEY_MAX 64

typedef struct {
  const char *kind;
  unsigned char key[AF_MEMO_KEY_MAX];
  size_t key_bytes;
  size_t size;
  void *value; /* size bytes, never freed (the process's life) */
} entry;

static entry entries[AF_MEMO_ENTRIES];
static size_t n_entries;
static size_t bytes_kept;
static mtx_t lock;
static bool lock_ok;
static once_flag lock_once = ONCE_FLAG_INIT;

static void lock_init(void)
{
  lock_ok = mtx_init(&lock, mtx_plain) == thrd_success;
}

static bool same(const entry *e, const char *kind, const void *key, size_t key_bytes, size_t size)
{
  return e->kind == kind && e->key_bytes == key_bytes && e->size == size &&
         memcmp(e->key, key, key_bytes) == 0;
}

/* The kept value of kind and key, or NULL. Under the lock. */
static const void *lookup_locked(const char *kind, const void *key, size_t key_bytes, size_t size)
{
  for (size_t k = 0; k < n_entries; k++)
    if (same(&entries[k], kind, key, key_bytes, size))
      return entries[k].value;
  return NULL;
}

/* Copies the kept value into out; false when there is none. Under the lock. */
static bool find_locked(const char *kind, const void *key, size_t key_bytes, void *out, size_t size)
{
  const void *kept = lookup_locked(kind, key, key_bytes, size);
  if (kept != NULL)
    memcpy(out, kept, size);
  return kept != NULL;
}

/* Keeps value (malloc'd, size bytes; the store owns it then) when there is
 * room; false when not. Under the lock. */
static bool add_locked(const char *kind, const void *key, size_t key_bytes, void *value,
                       size_t size)
{
  if (n_entries == AF_MEMO_ENTRIES || size > AF_MEMO_BYTES - bytes_kept)
    return false;
  entry *e = &entries[n_entries++];
  e->kind = kind;
  memcpy(e->key, key, key_bytes);
  e->key_bytes = key_bytes;
  e->size = size;
  e->value = value;
  bytes_kept += size;
  return true;
}

/* Keeps a copy of value when there is room and no other thread kept it
 * first. Under the lock. */
static void keep_locked(const char *kind, const void *key, size_t key_bytes, const void *value,
                        size_t size)
{
  if (lookup_locked(kind, key, key_bytes, size) != NULL)
    return;
  void *copy = malloc(size);
  if (copy == NULL)
    return; /* not kept: the next caller computes it again */
  memcpy(copy, value, size);
  if (!add_locked(kind, key, key_bytes, copy, size))
    free(copy);
}

const void *af_memo_ref(const char *kind, const void *key, size_t key_bytes, af_memo_fn *fn,
                        size_t size)
{
  call_once(&lock_once, lock_init);
  if (!lock_ok || key_bytes > AF_MEMO_KEY_MAX || size == 0 || size > AF_MEMO_BYTES ||
      mtx_lock(&lock) != thrd_success)
    return NULL;
  const void *kept = lookup_locked(kind, key, key_bytes, size);
  mtx_unlock(&lock);
  if (kept != NULL)
    return kept;
  void *value = malloc(size); /* computed outside the lock, kept as it is */
  if (value == NULL || fn(key, value) != AF_OK || mtx_lock(&lock) != thrd_success) {
    free(value);
    return NULL;
  }
  kept = lookup_locked(kind, key, key_bytes, size); /* another thread's, meanwhile */
  if (kept == NULL && add_locked(kind, key, key_bytes, value, size)) {
    kept = value;
    value = NULL;
  }
  mtx_unlock(&lock);
  free(value);
  return kept;
}

af_status af_memo_get(const char *kind, const void *key, size_t key_bytes, af_memo_fn *fn,
                      void *out, size_t size)
{
  call_once(&lock_once, lock_init);
  const bool usable = lock_ok && key_bytes <= AF_MEMO_KEY_MAX && size > 0;
  if (usable && mtx_lock(&lock) == thrd_success) {
    bool found = find_locked(kind, key, key_bytes, out, size);
    mtx_unlock(&lock);
    if (found)
      return AF_OK;
  }
  af_status st = fn(key, out);
  if (st == AF_OK && usable && mtx_lock(&lock) == thrd_success) {
    keep_locked(kind, key, key_bytes, out, size);
    mtx_unlock(&lock);
  }
  return st;
}
