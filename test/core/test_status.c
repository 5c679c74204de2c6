/* test_status.c — the status strings (status.h): each code's wording, all
 * distinct and never NULL (also for a value outside the enum), and
 * af_status_init turning GSL's aborting error handler off (a GSL domain
 * error then comes back as a status instead of killing the process). */
#include <gsl/gsl_errno.h>
#include <gsl/gsl_sf_log.h>
#include <string.h>

#include "af_test.h"
#include "status.h"

static void test_strings(void)
{
  /* The wording each code promises in status.h, written out by hand. */
  static const struct {
    af_status s;
    const char *text;
  } expected[] = {
      {AF_OK, "success"},
      {AF_EINVAL, "argument outside its accepted range"},
      {AF_ENOMEM, "out of memory"},
      {AF_ENOCONV, "iteration did not converge"},
      {AF_ENOROOT, "no root in the searched bracket"},
      {AF_ENUMERIC, "non-finite value in a computation"},
      {AF_ENOLOBE, "requested spectral lobe does not exist"},
      {AF_ESIZE, "buffer too small"},
      {AF_EIO, "input/output error"},
      {AF_ENODATA, "not enough signal"},
      {AF_EROS, "ROS layer error"},
      {AF_EBUDGET_ODE_STEPS,
       "impact ODE budget exhausted (20000 steps or 1000 elastic contact times: the contact "
       "does not end, a hammer resting on the fruit?)"},
      {AF_EBUDGET_ROOT_ITER, "root-finding iteration budget exhausted"},
      {AF_EBUDGET_FIT_ITER, "fit iteration budget exhausted"},
      {AF_EBUDGET_SEARCH, "R2_min search evaluation budget exhausted"},
  };
  const size_t n = sizeof expected / sizeof expected[0];
  AF_CHECK(n == (size_t)AF_EBUDGET_SEARCH + 1); /* every code of the enum listed */
  for (size_t k = 0; k < n; k++) {
    const char *t = af_strerror(expected[k].s);
    AF_CHECK(t != NULL && strcmp(t, expected[k].text) == 0);
    if (t == NULL || strcmp(t, expected[k].text) != 0)
      fprintf(stderr, "  status %d: '%s'\n", (int)expected[k].s, t ? t : "(null)");
    for (size_t j = 0; j < k; j++) /* distinct: a log line names one cause */
      AF_CHECK(strcmp(af_strerror(expected[j].s), t) != 0);
  }
  /* Outside the enum: a string, never NULL. */
  AF_CHECK(strcmp(af_strerror((af_status)(AF_EBUDGET_SEARCH + 1)), "unknown status") == 0);
  AF_CHECK(strcmp(af_strerror((af_status)-1), "unknown status") == 0);
  AF_CHECK(strcmp(af_strerror((af_status)1000), "unknown status") == 0);
}

/* The enum's values are part of the node's messages (status fields): fixed. */
static void test_values(void)
{
  AF_CHECK(AF_OK == 0 && AF_EINVAL == 1 && AF_ENOMEM == 2 && AF_ENOCONV == 3);
  AF_CHECK(AF_ENOROOT == 4 && AF_ENUMERIC == 5 && AF_ENOLOBE == 6 && AF_ESIZE == 7);
  AF_CHECK(AF_EIO == 8 && AF_ENODATA == 9 && AF_EROS == 10);
  AF_CHECK(AF_EBUDGET_ODE_STEPS == 11 && AF_EBUDGET_SEARCH == 14);
}

static void test_gsl_handler(void)
{
  af_status_init();
  af_status_init(); /* again: harmless */
  gsl_sf_result r;
  /* log(-1) is a domain error: GSL's default handler would abort() here. */
  AF_CHECK(gsl_sf_log_e(-1.0, &r) == GSL_EDOM);
  AF_CHECK(gsl_sf_log_e(1.0, &r) == GSL_SUCCESS && r.val == 0.0);
}

int main(void)
{
  test_strings();
  test_values();
  test_gsl_handler();
  return af_test_summary("test_status");
}
