/* file_read.c — a bounded whole-file read (see file_read.h). */
#define _POSIX_C_SOURCE 200809L /* open, fstat, read */
#include "file_read.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "text.h"

static const char *file_kind(mode_t m)
{
  return S_ISDIR(m)    ? "a directory"
         : S_ISFIFO(m) ? "a FIFO"
         : S_ISCHR(m)  ? "a character device"
         : S_ISBLK(m)  ? "a block device"
         : S_ISSOCK(m) ? "a socket"
                       : "not a regular file";
}

/* The file's bounds: a regular file of at most max_bytes. */
static af_status check_file(int fd, const char *path, size_t max_bytes, const char *what,
                            struct stat *st, char *err, size_t len)
{
  if (fstat(fd, st) != 0) {
    af_text_line(err, len, "%s: cannot be read: %s", path, strerror(errno));
    return AF_EIO;
  }
  if (!S_ISREG(st->st_mode)) {
    af_text_line(err, len, "%s: is %s; %s must be a regular file of at most %zu bytes", path,
                 file_kind(st->st_mode), what, max_bytes);
    return AF_EINVAL;
  }
  if ((unsigned long long)st->st_size > max_bytes) {
    af_text_line(err, len, "%s: %lld bytes is outside the accepted size of %s, [0, %zu] bytes",
                 path, (long long)st->st_size, what, max_bytes);
    return AF_EINVAL;
  }
  return AF_OK;
}

/* Up to room bytes of fd into buf; *n the bytes read. */
static af_status read_all(int fd, const char *path, char *buf, size_t room, size_t *n, char *err,
                          size_t len)
{
  *n = 0;
  while (*n < room) {
    ssize_t got = read(fd, buf + *n, room - *n);
    if (got < 0 && errno == EINTR)
      continue;
    if (got < 0) {
      af_text_line(err, len, "%s: read error: %s", path, strerror(errno));
      return AF_EIO;
    }
    if (got == 0)
      break;
    *n += (size_t)got;
  }
  return AF_OK;
}

af_status af_file_read_whole(const char *path, size_t max_bytes, const char *what, char **data,
                             size_t *size, char *err, size_t len)
{
  /* O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below. */
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    af_text_line(err, len, "%s: cannot be opened: %s", path, strerror(errno));
    return AF_EIO;
  }
  struct stat st;
  char *buf = NULL;
  size_t n = 0;
  af_status status = check_file(fd, path, max_bytes, what, &st, err, len);
  /* As long as fstat says + 1 (a file that grew after fstat is still
   * bounded, and refused); never the cap itself, which would cost a cap's
   * allocation per file read. */
  const size_t room = status == AF_OK ? (size_t)st.st_size + 1 : 0;
  if (status == AF_OK && (buf = malloc(room)) == NULL) {
    af_text_line(err, len, "%s: no memory to read it", path);
    status = AF_ENOMEM;
  }
  if (status == AF_OK)
    status = read_all(fd, path, buf, room, &n, err, len);
  if (status == AF_OK && n == room) {
    af_text_line(err, len, "%s: grew past its %lld bytes while read", path, (long long)st.st_size);
    status = AF_EINVAL;
  }
  close(fd);
  if (status != AF_OK) {
    free(buf);
    return status;
  }
  buf[n] = '\0';
  *data = buf;
  *size = n;
  return AF_OK;
}
