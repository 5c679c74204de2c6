/* fuzz_bag.c — libFuzzer harness: the shim's rosbag reader (af_bag.h: what
 * firmness_report and the desk tools read a recorded session with) on
 * arbitrary file contents, every message read to the end. A malformed bag
 * must give AF_EIO (or AF_EINVAL) with its message, never a crash, a hang,
 * an unbounded allocation or a sanitizer report. Seeds: small bags made by
 * strike_bag. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "af_bag.h"
#include "fuzz_scratch.h"

/* The input goes to a file (the reader takes a path; fuzz_scratch.h). */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = af_fuzz_scratch(0, "bag", "bag");
  FILE *f = fopen(path, "wb");
  if (f == NULL)
    return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  af_bag_reader *r = NULL;
  if (af_bag_open_read(path, NULL, 0, &r) != AF_OK) {
    if (af_bag_reader_error(NULL) == NULL)
      abort();
    return 0;
  }
  af_bag_message m;
  size_t n = 0;
  while (n < 100000 && af_bag_read_next(r, &m) == AF_OK) {
    if (m.type == AF_MSG_SIGNAL_CHUNK && m.msg.chunk.n > 0 && m.msg.chunk.data == NULL)
      abort();
    n++;
  }
  af_bag_close_read(r);
  return 0;
}
