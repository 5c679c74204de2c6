/* params.c — firmness_node's parameters: every row of the one parameter
 * table (src/core/params/settings.h) from the private namespace, checked by the
 * table; then the URDF (the hammer); then af_lane_config_derive, which makes
 * the lane's configuration and runs every cross-check in the core, exactly
 * as `firmness_model analyze` does from the same YAML files. No range and no
 * default is written here. */
#include "params.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "settings.h"
#include "text.h"

/* Room for one reason from the table or the derivation. */
#define AF_WHY_MAX 512

/* The table's one-line reason, as the node says it. */
static af_status refuse(af_status st, const char *why, char *err, size_t len)
{
  af_text(err, len, "parameter %s", why);
  return st;
}

/* One row from ~name into s. AF_ENODATA when absent (the required check
 * names it later); AF_EINVAL with the reason in err. A value of the wrong
 * type is read as the type it has, so that the table names it. */
static af_status load_row(af_ros *r, af_settings *s, af_setting_id id, char *err, size_t len)
{
  const af_setting_def *d = af_setting_def_of(id);
  char why[AF_WHY_MAX], text[AF_SETTINGS_TEXT_MAX];
  double number;
  bool flag;
  af_status st;
  switch (d->kind) {
  case AF_SETTING_NUMBER:
  case AF_SETTING_WHOLE: st = af_ros_param_double(r, d->name, &number); break;
  case AF_SETTING_BOOL: st = af_ros_param_bool(r, d->name, &flag); break;
  default: st = af_ros_param_string(r, d->name, text, sizeof text); break;
  }
  if (st == AF_ENODATA)
    return AF_ENODATA;
  if (st == AF_ESIZE) {
    af_text(err, len, "parameter ~%s is longer than %zu characters", d->name, sizeof text - 1);
    return AF_EINVAL;
  }
  if (st == AF_OK) {
    if (d->kind == AF_SETTING_NUMBER || d->kind == AF_SETTING_WHOLE)
      st = af_settings_set_number(s, id, number, why, sizeof why);
    else if (d->kind == AF_SETTING_BOOL)
      st = af_settings_set_bool(s, id, flag, why, sizeof why);
    else
      st = af_settings_set_string(s, id, text, why, sizeof why);
    return st == AF_OK ? AF_OK : refuse(st, why, err, len);
  }
  /* Another type: read it as what it is, for the table's message. */
  if (af_ros_param_double(r, d->name, &number) == AF_OK)
    st = af_settings_set_number(s, id, number, why, sizeof why);
  else if (af_ros_param_bool(r, d->name, &flag) == AF_OK)
    st = af_settings_set_bool(s, id, flag, why, sizeof why);
  else if (af_ros_param_string(r, d->name, text, sizeof text) == AF_OK)
    st = af_settings_set_string(s, id, text, why, sizeof why);
  else
    af_text(why, sizeof why, "~%s has the wrong type or could not be read: %s", d->name,
            af_ros_last_error(r));
  return st == AF_OK ? AF_OK : refuse(AF_EINVAL, why, err, len); /* (never AF_OK: another kind) */
}

/* Every row of the table from ~, then the required ones checked. */
static af_status load_settings(af_ros *r, af_settings *s, char *err, size_t len)
{
  af_settings_reset(s);
  af_settings_set_name_prefix(s, "~");
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_status st = load_row(r, s, (af_setting_id)k, err, len);
    if (st != AF_OK && st != AF_ENODATA)
      return st;
  }
  char why[AF_WHY_MAX];
  af_status st = af_settings_check_required(s, AF_SETTINGS_ALL, why, sizeof why);
  return st == AF_OK ? AF_OK : refuse(st, why, err, len);
}

/* The directory part of the node's resolved name, e.g. "/lane1/". */
static void node_namespace(const af_ros *r, char *buf, size_t len)
{
  snprintf(buf, len, "%s", af_ros_node_name(r));
  char *slash = strrchr(buf, '/');
  if (slash)
    slash[1] = '\0';
}

/* Reads the URDF from ~urdf_file or robot_description into cfg->urdf. */
static af_status read_urdf(af_ros *r, af_node_config *c, char *uerr, size_t ulen)
{
  if (c->urdf_file[0]) {
    af_text(c->urdf_source, sizeof c->urdf_source, "file %s (~urdf_file)", c->urdf_file);
    return af_urdf_load(c->urdf_file, &c->urdf, uerr, ulen);
  }
  char ns[AF_SOURCE_TEXT_MAX / 2];
  node_namespace(r, ns, sizeof ns);
  af_text(c->urdf_source, sizeof c->urdf_source, "parameter %srobot_description", ns);
  size_t size = af_ros_param_string_bytes(r, "robot_description", false);
  if (size == 0) {
    af_text(uerr, ulen, "not set (and ~urdf_file is empty)");
    return AF_ENODATA;
  }
  char *xml = malloc(size); /* start-up only */
  if (!xml)
    return AF_ENOMEM;
  af_status st = af_ros_param_string_global(r, "robot_description", xml, size);
  if (st == AF_OK)
    st = af_urdf_parse(xml, &c->urdf, uerr, ulen);
  else
    af_text(uerr, ulen, "parameter %srobot_description could not be read as a string: %s", ns,
            af_ros_last_error(r));
  free(xml);
  return st;
}

/* The rig's frame as robot_state_publisher publishes it under its
 * tf_prefix (tf::resolve): "PREFIX/frame", the prefix's leading and trailing
 * slashes dropped; an empty prefix leaves it. AF_EINVAL when the result
 * does not fit a frame id. */
static af_status prefix_frame(const char *prefix, char *frame, size_t size, char *err, size_t len)
{
  while (*prefix == '/')
    prefix++;
  size_t n = strlen(prefix);
  while (n > 0 && prefix[n - 1] == '/')
    n--;
  if (n == 0)
    return AF_OK;
  const char *f = frame[0] == '/' ? frame + 1 : frame;
  char out[AF_FRAME_ID_MAX];
  int w = snprintf(out, sizeof out, "%.*s/%s", (int)n, prefix, f);
  if (w < 0 || (size_t)w >= sizeof out || (size_t)w >= size) {
    af_text(err, len, "frame_prefix '%s': the frame '%.*s/%s' is longer than %zu characters",
            prefix, (int)n, prefix, f, (size_t)AF_FRAME_ID_MAX - 1);
    return AF_EINVAL;
  }
  memcpy(frame, out, (size_t)w + 1);
  return AF_OK;
}

/* The hammer: the URDF, or the overrides ~hammer_mass_kg and
 * ~hammer_tip_radius_m; what the URDF gives goes into s (checked by the
 * table like a parameter). */
static af_status load_hammer(af_ros *r, af_node_config *c, af_settings *s, char *err, size_t len)
{
  snprintf(c->hammer_link, sizeof c->hammer_link, "%s",
           af_settings_string(s, AF_SETTING_HAMMER_LINK));
  snprintf(c->urdf_file, sizeof c->urdf_file, "%s", af_settings_string(s, AF_SETTING_URDF_FILE));
  snprintf(c->hardware_id, sizeof c->hardware_id, "%s",
           af_settings_string(s, AF_SETTING_HARDWARE_ID));
  bool mass_given = af_settings_present(s, AF_SETTING_HAMMER_MASS_KG);
  bool tip_given = af_settings_present(s, AF_SETTING_HAMMER_TIP_RADIUS_M);

  char uerr[AF_TEXT_MAX] = "";
  af_status st = read_urdf(r, c, uerr, sizeof uerr);
  if (st == AF_OK)
    st = af_urdf_hammer(c->urdf, c->hammer_link, &c->hammer, uerr, sizeof uerr);
  if (st == AF_ENOMEM)
    return st;
  c->hammer_axis_known = st == AF_OK;
  if (st == AF_OK &&
      prefix_frame(af_settings_string(s, AF_SETTING_FRAME_PREFIX), c->hammer.mount_frame,
                   sizeof c->hammer.mount_frame, err, len) != AF_OK)
    return AF_EINVAL;
  if (st != AF_OK) {
    af_urdf_destroy(c->urdf);
    c->urdf = NULL;
    memset(&c->hammer, 0, sizeof c->hammer);
    if (!(mass_given && tip_given)) {
      af_text(err, len,
              "URDF from %s: %s; the hammer%s%s must come from it unless ~hammer_mass_kg "
              "and ~hammer_tip_radius_m are both given",
              c->urdf_source, uerr, mass_given ? "" : "'s mass",
              tip_given ? "" : (mass_given ? "'s tip radius" : " and tip radius"));
      return st == AF_EINVAL ? AF_EINVAL : AF_ENODATA;
    }
    /* Runs on parameters alone; the strike axis stays unknown. */
    char why[AF_SOURCE_TEXT_MAX];
    af_text(why, sizeof why, "none (%s: %s)", c->urdf_source, uerr);
    af_text(c->urdf_source, sizeof c->urdf_source, "%s", why);
  }
  snprintf(c->hammer_mass_source, sizeof c->hammer_mass_source, "%s%s",
           mass_given ? "parameter ~hammer_mass_kg" : "URDF link ",
           mass_given ? "" : c->hammer_link);
  snprintf(c->hammer_tip_source, sizeof c->hammer_tip_source, "%s%s",
           tip_given ? "parameter ~hammer_tip_radius_m" : "URDF link ",
           tip_given ? "" : c->hammer_link);
  /* The URDF's values enter the lane through the table like the overrides. */
  char why[AF_WHY_MAX];
  if (!mass_given && af_settings_set_number(s, AF_SETTING_HAMMER_MASS_KG, c->hammer.mass_kg, why,
                                            sizeof why) != AF_OK) {
    af_text(err, len, "URDF link %s: hammer mass: %s", c->hammer_link, why);
    return AF_EINVAL;
  }
  if (!tip_given && af_settings_set_number(s, AF_SETTING_HAMMER_TIP_RADIUS_M,
                                           c->hammer.tip_radius_m, why, sizeof why) != AF_OK) {
    af_text(err, len, "URDF link %s: hammer tip radius: %s", c->hammer_link, why);
    return AF_EINVAL;
  }
  c->hammer.mass_kg = af_settings_number(s, AF_SETTING_HAMMER_MASS_KG);
  c->hammer.tip_radius_m = af_settings_number(s, AF_SETTING_HAMMER_TIP_RADIUS_M);
  return AF_OK;
}

af_status af_params_load(af_ros *ros, af_node_config *cfg, char *err, size_t err_len)
{
  memset(cfg, 0, sizeof *cfg);
  af_settings s;
  af_status st = load_settings(ros, &s, err, err_len);
  if (st != AF_OK)
    return st;
  cfg->markers_enabled = af_settings_bool(&s, AF_SETTING_MARKERS_ENABLED);
  cfg->marker_lifetime_s = af_settings_number(&s, AF_SETTING_MARKER_LIFETIME_S);
  cfg->marker_strike_distance_m = af_settings_number(&s, AF_SETTING_MARKER_STRIKE_DISTANCE_M);
  cfg->marker_arrow_length_m = af_settings_number(&s, AF_SETTING_MARKER_ARROW_LENGTH_M);
  cfg->audio_common = af_settings_number(&s, AF_SETTING_AUDIO_INPUT) == 1.0; /* audio_common */
  cfg->audio_channel = (unsigned)af_settings_number(&s, AF_SETTING_AUDIO_CHANNEL);
  cfg->audio_full_scale = af_settings_number(&s, AF_SETTING_AUDIO_FULL_SCALE);
  cfg->strike_plot_width_px = (int)af_settings_number(&s, AF_SETTING_STRIKE_PLOT_WIDTH_PX);
  cfg->strike_plot_height_px = (int)af_settings_number(&s, AF_SETTING_STRIKE_PLOT_HEIGHT_PX);
  st = load_hammer(ros, cfg, &s, err, err_len);
  if (st == AF_OK) {
    char why[AF_WHY_MAX];
    st = af_lane_config_derive(&s, &cfg->lane, why, sizeof why);
    if (st != AF_OK)
      refuse(st, why, err, err_len);
    else
      cfg->settings = s; /* the base of a reconfigure (src/node/live_settings.c) */
  }
  if (st != AF_OK)
    af_params_destroy(cfg);
  return st;
}

void af_params_destroy(af_node_config *cfg)
{
  af_urdf_destroy(cfg->urdf);
  cfg->urdf = NULL;
}
