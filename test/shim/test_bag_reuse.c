/* test_bag_reuse.c — the bag reader reuses rosbag::Bag objects for the
 * process (bag_pool.hpp: a new Bag loads the encryptor plugin).
 * A reused Bag must read like a new one:
 * - two bags whose first chunk sits at the same file offset, with other
 *   samples and another length: the second reads its own (rosbag's
 *   Bag::close() keeps the offset of the chunk it decompressed last; without
 *   the reset the second bag's message is read with the first one's
 *   length);
 * - a bag whose header names an encryptor that does not exist, and one that
 *   names rosbag's AES encryptor without its key: each refused (AF_EIO, the
 *   line naming the file), and the good bag read after them reads as sent
 *   (an encryptor left on a reused Bag would "decrypt" it);
 * - readers on two threads at once, each seeing its own open error
 *   (af_bag_reader_error(NULL) is per thread) and its own samples.
 * The bags are written by the shim's writer (af_bag_write); the samples
 * are hand-chosen (k + 0.5 + 1000 * bag). The header edit is done here,
 * by the bag format's record layout (rosbag's own file-header record:
 * header length, fields "name=value" each with its length, data length,
 * padding). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_bag.h"
#include "af_test.h"

#define N_SAMPLES 64
/* Samples of bag `which`'s chunk: the bags' messages differ in length too. */
#define SAMPLES_OF(which) (N_SAMPLES + 8 * (which))
#define TOPIC "/lane1/force"

/* Writes one force chunk of SAMPLES_OF(which): x[k] = k + 0.5 + 1000 * which. */
static void write_bag(const char *path, int which)
{
  float x[SAMPLES_OF(8)];
  for (int k = 0; k < SAMPLES_OF(which); k++)
    x[k] = (float)k + 0.5f + 1000.0f * (float)which;
  af_signal_chunk c;
  memset(&c, 0, sizeof c);
  c.header.stamp.sec = 1700000000u;
  c.first_sample = 0;
  c.sample_rate_hz = 50000.0;
  strcpy(c.unit, "N");
  c.data = x;
  c.n = (size_t)SAMPLES_OF(which);
  af_bag *b = NULL;
  AF_CHECK_STATUS(af_bag_open_write(path, &b), AF_OK);
  af_time t = {1700000000u, 0};
  AF_CHECK_STATUS(af_bag_write(b, TOPIC, AF_MSG_SIGNAL_CHUNK, &c, t), AF_OK);
  AF_CHECK_STATUS(af_bag_close(b), AF_OK);
}

/* Reads path: AF_OK and its one chunk's samples as written by
 * write_bag(which), or the open's status. */
static af_status read_bag(const char *path, int which, int *wrong)
{
  af_bag_reader *r = NULL;
  af_status s = af_bag_open_read(path, NULL, 0, &r);
  if (s != AF_OK)
    return s;
  af_bag_message m;
  int chunks = 0;
  *wrong = 0;
  while (af_bag_read_next(r, &m) == AF_OK) {
    if (m.type != AF_MSG_SIGNAL_CHUNK || m.msg.chunk.n != (size_t)SAMPLES_OF(which)) {
      (*wrong)++;
      continue;
    }
    chunks++;
    for (int k = 0; k < SAMPLES_OF(which); k++)
      *wrong += m.msg.chunk.data[k] != (float)k + 0.5f + 1000.0f * (float)which;
  }
  *wrong += chunks != 1;
  af_bag_close_read(r);
  return AF_OK;
}

/* A copy of src at dst whose file-header record holds one field more,
 * "encryptor=NAME", taken from the record's padding (every offset stays). */
static void with_encryptor(const char *src, const char *dst, const char *name)
{
  FILE *f = fopen(src, "rb");
  AF_CHECK(f != NULL);
  if (f == NULL)
    return;
  static unsigned char b[1 << 16];
  size_t n = fread(b, 1, sizeof b, f);
  fclose(f);
  const size_t at = 13; /* after "#ROSBAG V2.0\n" */
  AF_CHECK(n > at + 8 && memcmp(b, "#ROSBAG V2.0\n", at) == 0);
  uint32_t header_len, data_len;
  memcpy(&header_len, b + at, 4);
  const size_t fields_end = at + 4 + header_len; /* where the data length sits */
  memcpy(&data_len, b + fields_end, 4);
  char field[128];
  int fl = snprintf(field, sizeof field, "encryptor=%s", name);
  const uint32_t add = 4u + (uint32_t)fl;
  AF_CHECK(data_len >= add && fields_end + 4 + data_len <= n);
  if (data_len < add || fields_end + 4 + data_len > n)
    return;
  /* the record as before, the new field after the others, its bytes taken
   * from the padding: the record keeps its length */
  static unsigned char o[sizeof b];
  size_t k = 0;
  memcpy(o, b, fields_end);
  k = fields_end;
  uint32_t v = (uint32_t)fl;
  memcpy(o + k, &v, 4);
  memcpy(o + k + 4, field, (size_t)fl);
  k += add;
  v = data_len - add;
  memcpy(o + k, &v, 4);
  k += 4;
  memset(o + k, ' ', v);
  k += v;
  memcpy(o + k, b + fields_end + 4 + data_len, n - (fields_end + 4 + data_len));
  k += n - (fields_end + 4 + data_len);
  AF_CHECK(k == n);
  v = header_len + add;
  memcpy(o + at, &v, 4);
  f = fopen(dst, "wb");
  AF_CHECK(f != NULL);
  if (f == NULL)
    return;
  AF_CHECK(fwrite(o, 1, n, f) == n);
  fclose(f);
}

static char dir[64];

static void path_of(char *out, size_t len, const char *name)
{
  snprintf(out, len, "%s/%s", dir, name);
}

static void test_same_offset(void)
{
  char a[128], b[128];
  path_of(a, sizeof a, "a.bag");
  path_of(b, sizeof b, "b.bag");
  write_bag(a, 1);
  write_bag(b, 2);
  int wrong = -1;
  for (int round = 0; round < 3; round++) {
    AF_CHECK_STATUS(read_bag(a, 1, &wrong), AF_OK);
    AF_CHECK(wrong == 0);
    AF_CHECK_STATUS(read_bag(b, 2, &wrong), AF_OK);
    AF_CHECK(wrong == 0);
  }
}

static void test_encryptors(void)
{
  char good[128], bogus[128], aes[128];
  path_of(good, sizeof good, "good.bag");
  path_of(bogus, sizeof bogus, "bogus_encryptor.bag");
  path_of(aes, sizeof aes, "aes_no_key.bag");
  write_bag(good, 3);
  with_encryptor(good, bogus, "rosbag/NoSuchEncryptor");
  with_encryptor(good, aes, "rosbag/AesCbcEncryptor");
  int wrong = -1;
  AF_CHECK_STATUS(read_bag(bogus, 3, &wrong), AF_EIO);
  const char *why = af_bag_reader_error(NULL);
  AF_CHECK(strstr(why, bogus) != NULL && strstr(why, "NoSuchEncryptor") != NULL);
  printf("  %s\n", why);
  AF_CHECK_STATUS(read_bag(good, 3, &wrong), AF_OK);
  AF_CHECK(wrong == 0);
  AF_CHECK_STATUS(read_bag(aes, 3, &wrong), AF_EIO);
  why = af_bag_reader_error(NULL);
  AF_CHECK(strstr(why, aes) != NULL);
  printf("  %s\n", why);
  AF_CHECK_STATUS(read_bag(good, 3, &wrong), AF_OK);
  AF_CHECK(wrong == 0);
}

typedef struct {
  int which, failures;
} worker;

/* Opens a missing file (its own name) and reads its own bag, 200 times. */
static void *work(void *arg)
{
  worker *w = arg;
  char missing[128], mine[128], name[32];
  snprintf(name, sizeof name, "missing_%d.bag", w->which);
  path_of(missing, sizeof missing, name);
  snprintf(name, sizeof name, "t%d.bag", w->which);
  path_of(mine, sizeof mine, name);
  for (int k = 0; k < 200; k++) {
    af_bag_reader *r = NULL;
    if (af_bag_open_read(missing, NULL, 0, &r) == AF_OK) {
      af_bag_close_read(r);
      w->failures++;
    } else if (strstr(af_bag_reader_error(NULL), missing) == NULL) {
      w->failures++;
    }
    int wrong = -1;
    if (read_bag(mine, w->which, &wrong) != AF_OK || wrong != 0)
      w->failures++;
  }
  return NULL;
}

static void test_threads(void)
{
  worker w[2] = {{4, 0}, {5, 0}};
  char p[128];
  path_of(p, sizeof p, "t4.bag");
  write_bag(p, 4);
  path_of(p, sizeof p, "t5.bag");
  write_bag(p, 5);
  pthread_t t[2];
  for (int k = 0; k < 2; k++)
    AF_CHECK(pthread_create(&t[k], NULL, work, &w[k]) == 0);
  for (int k = 0; k < 2; k++)
    pthread_join(t[k], NULL);
  AF_CHECK(w[0].failures == 0 && w[1].failures == 0);
}

int main(void)
{
  snprintf(dir, sizeof dir, "/tmp/af_test_bag_reuse_XXXXXX");
  if (mkdtemp(dir) == NULL) {
    perror("mkdtemp");
    return 1;
  }
  test_same_offset();
  test_encryptors();
  test_threads();
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0)
    fprintf(stderr, "could not remove %s\n", dir);
  return af_test_summary("test_bag_reuse");
}
