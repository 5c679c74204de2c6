/* lane_replay — the lane of the core (src/core/lane.h) driven offline over a
 * bag, for the rostest that checks the node and the desk judge a recording
 * alike (test_strikes.py).
 *
 *   lane_replay BAG NS CONFIG CULTIVAR
 *
 * Reads /NS/force, /NS/audio and /NS/apple in bag-time order through the
 * shim's reader, configures the lane from the two YAML files as the node is
 * configured (the hammer: config/rig.urdf's, 10 g with a flat face; the
 * strike direction unknown: the bag's apples give their strike radius, so
 * the measurement does not depend on it), with the lane's clock at each
 * message's bag time (what /clock says when `rosbag play` publishes it), and
 * prints one JSON object per measured strike on stdout: every StrikeReport
 * field (%.17g), the verdict flags and the reason. Exit 0, 2 on bad input. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "af_bag.h"
#include "lane.h"
#include "settings.h"

static void number(const char *key, double v, const char *sep)
{
  if (isfinite(v))
    printf("\"%s\": %.17g%s", key, v, sep);
  else
    printf("\"%s\": null%s", key, sep);
}

static void on_strike(const af_lane_strike *s, void *user)
{
  (void)user;
  const af_measure_report *r = &s->report;
  printf("{\"stamp_ns\": %" PRId64 ", \"apple_id\": %u, ", s->start_ns, s->apple_id);
  number("contact_time", r->contact_time_s, ", ");
  number("peak_force", r->peak_force_n, ", ");
  number("impulse", r->impulse_n_s, ", ");
  number("band_low", r->band_low_hz, ", ");
  number("band_high", r->band_high_hz, ", ");
  number("resonance", r->resonance_hz, ", ");
  number("resonance_q", r->resonance_q, ", ");
  number("snr_db", r->snr_db, ", ");
  number("stiffness_factor", r->stiffness_factor, ", ");
  number("modulus_from_resonance", r->modulus_from_resonance_pa, ", ");
  number("fitted_modulus", r->fitted_modulus_pa, ", ");
  number("fitted_restitution", r->fitted_restitution, ", ");
  number("fit_residual", r->fit_residual, ", ");
  number("max_shear_stress", r->max_shear_stress_pa, ", ");
  number("yield_shear_stress", r->yield_shear_stress_pa, ", ");
  printf("\"double_hit\": %s, \"clipped\": %s, \"lost_samples\": %u, ",
         r->double_hit ? "true" : "false", r->clipped ? "true" : "false", r->lost_samples);
  printf("\"excites_mode\": %s, \"no_damage\": %s, \"reliable\": %s, \"flags\": %u, ",
         r->excites_mode ? "true" : "false", r->no_damage ? "true" : "false",
         r->reliable ? "true" : "false", r->verdict.flags);
  printf("\"reason\": \"");
  for (const char *c = r->reason; *c; c++)
    printf(*c == '"' || *c == '\\' ? "\\%c" : "%c", *c);
  printf("\"}\n");
}

static int fail(const char *what, const char *why)
{
  fprintf(stderr, "lane_replay: %s: %s\n", what, why);
  return 2;
}

static int replay(af_bag_reader *bag, const char *ns, af_lane *lane)
{
  char force[128], audio[128], apple[128];
  snprintf(force, sizeof force, "/%s/force", ns);
  snprintf(audio, sizeof audio, "/%s/audio", ns);
  snprintf(apple, sizeof apple, "/%s/apple", ns);
  af_bag_message m;
  af_status st;
  while ((st = af_bag_read_next(bag, &m)) == AF_OK) {
    int64_t now = (int64_t)m.bag_time.sec * 1000000000LL + m.bag_time.nsec;
    if (m.type == AF_MSG_SIGNAL_CHUNK) {
      const af_signal_chunk *c = &m.msg.chunk;
      af_chunk k = {(int64_t)c->header.stamp.sec * 1000000000LL + c->header.stamp.nsec,
                    c->first_sample,
                    c->sample_rate_hz,
                    c->unit,
                    c->header.frame_id,
                    c->data,
                    c->n};
      if (strcmp(m.topic, force) == 0)
        af_lane_force(lane, &k, now, NULL);
      else if (strcmp(m.topic, audio) == 0)
        af_lane_audio(lane, &k, now, NULL);
    } else if (m.type == AF_MSG_APPLE_ESTIMATE && strcmp(m.topic, apple) == 0) {
      const af_apple_estimate *e = &m.msg.apple;
      af_apple a;
      memset(&a, 0, sizeof a);
      a.apple_id = e->apple_id;
      a.stamp_ns = (int64_t)e->header.stamp.sec * 1000000000LL + e->header.stamp.nsec;
      a.mass_kg = e->mass_kg;
      a.equatorial_radius_m = e->equatorial_radius_m;
      a.strike_radius_m = e->strike_radius_m;
      a.stem_axis[0] = e->stem_axis.x, a.stem_axis[1] = e->stem_axis.y;
      a.stem_axis[2] = e->stem_axis.z;
      a.confidence = e->confidence;
      snprintf(a.direction_note, sizeof a.direction_note, "offline: strike direction unknown");
      (void)af_lane_apple(lane, &a, now, NULL);
    }
  }
  af_lane_finish(lane);
  return st == AF_ENODATA ? 0 : fail("bag", af_bag_reader_error(bag));
}

int main(int argc, char **argv)
{
  if (argc != 5)
    return fail("usage", "lane_replay BAG NS CONFIG CULTIVAR");
  char err[512];
  af_settings s;
  af_lane_config cfg;
  af_settings_init(&s);
  if (af_settings_load_yaml(&s, argv[3], err, sizeof err) != AF_OK ||
      af_settings_load_yaml(&s, argv[4], err, sizeof err) != AF_OK ||
      af_settings_set_arg(&s, "hammer_mass_kg=0.010", err, sizeof err) != AF_OK ||
      af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, sizeof err) != AF_OK ||
      af_lane_config_derive(&s, &cfg, err, sizeof err) != AF_OK)
    return fail("settings", err);
  af_lane *lane = NULL;
  const char *what = "";
  af_status st = af_lane_create(&cfg, on_strike, NULL, &lane, &what);
  if (st != AF_OK)
    return fail(what, af_strerror(st));
  af_bag_reader *bag = NULL;
  if (af_bag_open_read(argv[1], NULL, 0, &bag) != AF_OK) {
    af_lane_destroy(lane);
    return fail(argv[1], af_bag_reader_error(NULL));
  }
  int code = replay(bag, argv[2], lane);
  af_bag_close_read(bag);
  af_lane_destroy(lane);
  return code;
}
