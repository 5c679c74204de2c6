/* closeout.h — every write of a command-line tool checked, stdout included.
 *
 * A tool whose standard output cannot be written (a full disk, `> /dev/full`,
 * a file-size limit, a closed descriptor) must not exit 0 with its answer
 * lost or cut: stdio only reports such failures through ferror() and the
 * final flush, which an exit from main never checks. */
#ifndef AF_CLOSEOUT_H
#define AF_CLOSEOUT_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Called first in main. Ignores SIGXFSZ, so that a write beyond a file-size
 * limit (ulimit -f) fails with EFBIG and is reported, instead of killing the
 * tool with a core dump and a cut file; and registers an exit handler that
 * flushes and closes stdout: when any write to it failed, the handler prints
 * one line "TOOL: cannot write standard output: CAUSE" on stderr and the
 * exit status becomes 1, whatever main returned. tool must outlive the
 * process (a string literal). */
void af_closeout_install(const char *tool);

/* Closes f, a file the tool wrote at path: 0 when every write to it and the
 * close succeeded; otherwise 1 after one line "TOOL: cannot write PATH:
 * CAUSE" on stderr (the tool of af_closeout_install, "af" before it). f is
 * closed either way; NULL f returns 0. */
int af_closeout_file(FILE *f, const char *path);

#ifdef __cplusplus
}
#endif
#endif
