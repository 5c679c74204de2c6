/* file_read.h — a whole file read into memory within a bound, for the
 * readers of files a user names (the settings files, firmness_report's
 * reports, the node's URDF for its topic): only a regular file (a FIFO,
 * device or folder is refused without blocking on it), at most max_bytes,
 * and refused if it grew past its size while read. */
#ifndef AF_FILE_READ_H
#define AF_FILE_READ_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* path, whole, into *data (malloc'd, *size bytes, NUL-terminated beyond
 * them). what names the file in messages ("a settings file", "a report").
 * AF_OK; else one line in err: AF_EIO (cannot be opened or read),
 * AF_EINVAL (not a regular file, over max_bytes, grew while read),
 * AF_ENOMEM. */
af_status af_file_read_whole(const char *path, size_t max_bytes, const char *what, char **data,
                             size_t *size, char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
