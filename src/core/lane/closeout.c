/* closeout.c — the exit-time check of stdout and the checked close of files
 * (see closeout.h). */
#define _POSIX_C_SOURCE 200809L
#include "closeout.h"

#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/sysmacros.h>
#include <unistd.h>

static const char *g_tool = "af";

/* The cause of a write error that stdio did not keep: a large write goes
 * past the buffer straight to the descriptor, and when it fails its data is
 * dropped, so the final flush has nothing left to fail on. Told from what
 * the descriptor is: a regular file at the file-size limit (EFBIG) or on a
 * full filesystem (ENOSPC), or /dev/full (ENOSPC). 0 when none fits. */
static int diagnose(int fd)
{
  struct stat st;
  if (fd < 0 || fstat(fd, &st) != 0)
    return EBADF;
  if (S_ISCHR(st.st_mode) && major(st.st_rdev) == 1 && minor(st.st_rdev) == 7)
    return ENOSPC; /* /dev/full */
  if (!S_ISREG(st.st_mode))
    return 0;
  struct rlimit lim;
  if (getrlimit(RLIMIT_FSIZE, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY &&
      (rlim_t)st.st_size >= lim.rlim_cur)
    return EFBIG;
  struct statvfs fs;
  if (fstatvfs(fd, &fs) == 0 && fs.f_bavail == 0)
    return ENOSPC;
  return 0;
}

/* Flushes and closes f; the cause of the first failure in *err (0 when
 * stdio kept no errno: an earlier write failed and its data was dropped). */
static bool close_checked(FILE *f, int *err)
{
  /* glibc keeps a buffer whose write failed and tries it again on the
   * next flush, so this flush names the cause (ENOSPC, EFBIG, EBADF). */
  errno = 0;
  bool ok = fflush(f) == 0;
  *err = ok ? 0 : errno;
  if (ferror(f)) {
    ok = false;
    if (*err == 0)
      *err = diagnose(fileno(f));
  }
  errno = 0;
  if (fclose(f) != 0 && ok) {
    ok = false;
    *err = errno;
  }
  return ok;
}

static const char *cause(int err)
{
  return err != 0 ? strerror(err) : "an earlier write failed";
}

static void check_stdout(void)
{
  int err = 0;
  if (close_checked(stdout, &err))
    return;
  fprintf(stderr, "%s: cannot write standard output: %s\n", g_tool, cause(err));
  /* _exit: the exit status is already decided, and the remaining handlers
   * would only try the dead stream again. */
  _exit(1);
}

void af_closeout_install(const char *tool)
{
  if (tool != NULL)
    g_tool = tool;
  signal(SIGXFSZ, SIG_IGN);
  atexit(check_stdout);
}

int af_closeout_file(FILE *f, const char *path)
{
  int err = 0;
  if (f == NULL || close_checked(f, &err))
    return 0;
  fprintf(stderr, "%s: cannot write %s: %s\n", g_tool, path != NULL ? path : "a file", cause(err));
  return 1;
}
