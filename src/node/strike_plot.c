/* strike_plot.c — the last strike's picture on ~strike_plot (see strike_plot.h). */
#include "strike_plot.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lane_io.h" /* af_time_from_ns */
#include "strike_view.h"
#include "text.h"

#define AF_PLOT_QUEUE 2 /* images waiting to be sent; a viewer wants the newest */
/* While a strike waits to be drawn and nobody views the plot, roscpp is asked
 * for the plot's subscribers at most this often [s]: the question (a lookup
 * under roscpp's topic lock) was asked after every spin, ~5 % of the node's
 * callback thread at 2 strikes/s; a viewer that connects sees the strike
 * this much later at most. */
#define AF_PLOT_LOOK_S 0.2

struct af_strike_plot {
  af_ros *ros;
  const af_node_config *cfg;
  af_ros_pub *pub;
  af_strike_view *view; /* the captured strike and the figure's workspaces */
  unsigned char *rgb;   /* width x height x 3, rows top first */
  af_image image;       /* points to rgb */
  bool dirty;           /* captured, not yet drawn */
  double next_look_s;   /* wall time of the next look for a viewer [s] */
  af_header header;     /* of the captured strike: contact start, the force frame */
  /* For the diagnostics. */
  unsigned long long captured, rendered, published, skipped, failed;
  double render_last_ms, render_max_ms, render_sum_ms;
  char last_error[AF_TEXT_MAX];
};

static double wall_s(void)
{
  struct timespec ts;
  if (timespec_get(&ts, TIME_UTC) != TIME_UTC)
    return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

af_status af_strike_plot_create(af_ros *ros, const af_node_config *cfg, af_strike_plot **out,
                                const char **what)
{
  *out = NULL;
  *what = "the strike plot";
  af_strike_plot *p = calloc(1, sizeof *p);
  if (!p)
    return AF_ENOMEM;
  p->ros = ros;
  p->cfg = cfg;
  const size_t w = (size_t)cfg->strike_plot_width_px, h = (size_t)cfg->strike_plot_height_px;
  p->rgb = calloc(w * h, 3);
  af_status s = p->rgb ? af_strike_view_create(&cfg->lane, &p->view) : AF_ENOMEM;
  if (s == AF_OK) {
    *what = "the strike_plot publisher";
    s = af_ros_advertise(ros, "strike_plot", AF_MSG_IMAGE, AF_PLOT_QUEUE, false, &p->pub);
  }
  if (s != AF_OK) {
    af_strike_plot_destroy(p);
    return s;
  }
  p->image.width_px = (uint32_t)w;
  p->image.height_px = (uint32_t)h;
  p->image.step_bytes = (uint32_t)(3 * w);
  af_text(p->image.encoding, sizeof p->image.encoding, "rgb8");
  p->image.data = p->rgb;
  *out = p;
  return AF_OK;
}

void af_strike_plot_destroy(af_strike_plot *p)
{
  if (!p)
    return;
  af_strike_view_destroy(p->view);
  free(p->rgb);
  free(p); /* the publisher belongs to the af_ros */
}

void af_strike_plot_capture(af_strike_plot *p, const af_lane_strike *s, const af_lane *lane)
{
  if (!p || !s)
    return;
  p->skipped += p->dirty; /* a newer strike came before the last was drawn */
  af_strike_view_capture(p->view, s, lane);
  p->header.stamp = af_time_from_ns(s->start_ns);
  af_text(p->header.frame_id, sizeof p->header.frame_id, "%s", s->frame_id);
  p->dirty = true;
  p->captured++;
}

void af_strike_plot_update(af_strike_plot *p)
{
  if (!p || !p->dirty)
    return;
  const double t0 = wall_s();
  if (t0 < p->next_look_s)
    return;
  if (af_ros_pub_subscribers(p->pub) == 0) {
    p->next_look_s = t0 + AF_PLOT_LOOK_S;
    return;
  }
  p->dirty = false;
  af_plot_target t = {AF_PLOT_MEMORY, NULL, p->rgb, p->cfg->strike_plot_width_px,
                      p->cfg->strike_plot_height_px};
  char err[AF_TEXT_MAX] = "";
  af_status s = af_strike_view_prepare(p->view);
  if (s == AF_OK)
    s = af_strike_view_draw(p->view, &t, err, sizeof err);
  const double ms = (wall_s() - t0) * 1e3;
  if (s != AF_OK) {
    p->failed++;
    af_text(p->last_error, sizeof p->last_error, "%s: %s", af_strerror(s), err);
    af_ros_log(p->ros, AF_LOG_WARN, "strike plot not drawn: %s", p->last_error);
    return;
  }
  p->render_last_ms = ms;
  p->render_max_ms = ms > p->render_max_ms ? ms : p->render_max_ms;
  p->render_sum_ms += ms;
  p->rendered++;
  p->image.header = p->header;
  if (af_ros_publish(p->pub, &p->image) != AF_OK) {
    p->failed++;
    af_text(p->last_error, sizeof p->last_error, "%s", af_ros_last_error(p->ros));
    af_ros_log(p->ros, AF_LOG_WARN, "strike_plot not published: %s", p->last_error);
    return;
  }
  p->published++;
}

void af_strike_plot_diag(const af_strike_plot *p, af_diag_status *d)
{
  if (!p)
    return;
  af_diag_add(d, "strike plot images",
              "%llu published of %llu strikes (%llu replaced by a newer "
              "strike before drawing, %llu failed%s%s)",
              p->published, p->captured, p->skipped, p->failed, p->last_error[0] ? ": " : "",
              p->last_error);
  if (p->rendered == 0)
    af_diag_add(d, "strike plot render [ms]", "none yet");
  else
    af_diag_add(d, "strike plot render [ms]", "last %.2f, mean %.2f, max %.2f (%d x %d px)",
                p->render_last_ms, p->render_sum_ms / (double)p->rendered, p->render_max_ms,
                p->cfg->strike_plot_width_px, p->cfg->strike_plot_height_px);
}
