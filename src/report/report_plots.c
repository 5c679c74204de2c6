/* report_plots.c — temporary */
#include "report_plots.h"
#include <stdio.h>
af_status af_report_plots_create(const char *dir, const af_lane_config *cfg, af_report_plots **out,
                                 char *err, size_t len)
{
  (void)dir;
  (void)cfg;
  (void)err;
  (void)len;
  *out = NULL;
  return AF_EINVAL;
}
void af_report_plots_destroy(af_report_plots *p)
{
  (void)p;
}
void af_report_plots_strike(const af_lane_strike *s, const af_lane *lane, void *user)
{
  (void)s;
  (void)lane;
  (void)user;
}
af_status af_report_plots_session(af_report_plots *p, const af_session *s, const af_summary *m,
                                  char *err, size_t len)
{
  (void)p;
  (void)s;
  (void)m;
  (void)err;
  (void)len;
  return AF_OK;
}
