/* fuzz_scratch.h — the scratch files of the harnesses whose readers take a
 * path (test/fuzz/: analyze, bag, wav, yaml). Header-only; one harness per
 * binary.
 *
 * A file is made once per process and rewritten for every input: in
 * /dev/shm (tmpfs) when it is writable, else /tmp. On ext4, rewriting a
 * truncated file forces its blocks out at close (auto_da_alloc), a wait on
 * the disk per input. The files are removed when the process exits
 * (atexit: libFuzzer ends its runs with exit()); before this header, every
 * run left its files behind, in memory when they were on tmpfs. */
#ifndef AF_FUZZ_SCRATCH_H
#define AF_FUZZ_SCRATCH_H

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#define AF_FUZZ_SCRATCH_MAX 2   /* files per harness (analyze: force and audio) */
#define AF_FUZZ_SCRATCH_PATH 64 /* bytes of a path */

static char af_fuzz_scratch_paths[AF_FUZZ_SCRATCH_MAX][AF_FUZZ_SCRATCH_PATH];
static int af_fuzz_scratch_count;

static void af_fuzz_scratch_remove(void)
{
  for (int k = 0; k < af_fuzz_scratch_count; k++)
    unlink(af_fuzz_scratch_paths[k]);
}

/* The path of this process's scratch file af_fuzz_<stem>_<pid>.<ext>, made
 * on the first call for it (slot: 0 .. AF_FUZZ_SCRATCH_MAX - 1, a harness's
 * own numbering) and removed at exit. Aborts on a slot out of range. */
static inline const char *af_fuzz_scratch(int slot, const char *stem, const char *ext)
{
  if (slot < 0 || slot >= AF_FUZZ_SCRATCH_MAX)
    abort();
  char *path = af_fuzz_scratch_paths[slot];
  if (path[0] != '\0')
    return path;
  snprintf(path, AF_FUZZ_SCRATCH_PATH, "%s/af_fuzz_%s_%ld.%s",
           access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp", stem, (long)getpid(), ext);
  if (af_fuzz_scratch_count == 0)
    atexit(af_fuzz_scratch_remove);
  if (slot >= af_fuzz_scratch_count)
    af_fuzz_scratch_count = slot + 1;
  return path;
}

#endif
