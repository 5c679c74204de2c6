/* live_settings.c — dynamic_reconfigure of the running node (live_settings.h). */
#include "live_settings.h"

#include <stdlib.h>
#include <string.h>

#include "af_reconfigure.h"
#include "reconfigure.h"
#include "settings.h"
#include "text.h"

#define AF_WHY_MAX 512

struct af_live_settings {
  af_ros *ros;
  af_node_config *cfg;
  af_lane_io *measured;
  af_snapshot *snapshot;  /* published again after a change; may be NULL */
  af_settings next;       /* the request on the node's settings */
  af_lane_config derived; /* its lane configuration */
  af_lane_config before;  /* the one in force, to restore */
  unsigned long long requests, accepted, refused;
  char last_change[AF_TEXT_MAX];
  char last_refusal[AF_WHY_MAX];
};

/* One value of the request into s through its table row; *changed when it
 * differs from what s held. */
static af_status set_row(af_settings *s, const af_rc_value *v, bool *changed, char *err, size_t len)
{
  af_setting_id id;
  char before[AF_SETTINGS_TEXT_MAX], after[AF_SETTINGS_TEXT_MAX];
  if (af_setting_find(v->name, &id) != AF_OK || !af_reconfigure_allowed(id)) {
    af_text(err, len, "~%s cannot be changed while the node runs", v->name);
    return AF_EINVAL;
  }
  af_settings_value_text(s, id, before, sizeof before);
  af_status st;
  switch (v->type) {
  case AF_RC_DOUBLE:
  case AF_RC_INT: st = af_settings_set_number(s, id, v->number, err, len); break;
  case AF_RC_BOOL: st = af_settings_set_bool(s, id, v->flag, err, len); break;
  default: st = af_settings_set_string(s, id, v->text, err, len); break;
  }
  af_settings_value_text(s, id, after, sizeof after);
  *changed = strcmp(before, after) != 0;
  return st;
}

static af_status on_request(const af_rc_value *values, size_t n, bool initial, void *user,
                            char *err, size_t len)
{
  af_live_settings *l = user;
  char why[AF_WHY_MAX] = "", change[AF_TEXT_MAX] = "";
  bool grades = false, any = false;
  /* The server's start hands over the node's own values: not a request. */
  l->requests += !initial;
  l->next = l->cfg->settings;
  af_settings_set_name_prefix(&l->next, "~");
  af_status st = AF_OK;
  for (size_t k = 0; k < n && st == AF_OK; k++) {
    bool changed = false;
    st = set_row(&l->next, &values[k], &changed, why, sizeof why);
    if (st == AF_OK && changed) {
      char text[AF_SETTINGS_TEXT_MAX];
      af_setting_id id;
      af_setting_find(values[k].name, &id);
      af_settings_value_text(&l->next, id, text, sizeof text);
      size_t used = strlen(change);
      af_text(change + used, sizeof change - used, "%s~%s = %s", any ? ", " : "", values[k].name,
              text);
      any = true;
      grades |= id == AF_SETTING_GRADE_QUANTITY || id == AF_SETTING_GRADE_CLASSES;
    }
  }
  if (st == AF_OK && !any) {
    l->accepted += !initial; /* the values in force again: taken, nothing to remake */
    return AF_OK;
  }
  if (st == AF_OK)
    st = af_lane_config_derive(&l->next, &l->derived, why, sizeof why);
  const char *what = "";
  if (st == AF_OK) {
    l->before = l->cfg->lane;
    l->cfg->lane = l->derived;
    st = af_lane_io_reconfigured(l->measured, grades, &what);
    if (st != AF_OK) {
      l->cfg->lane = l->before;
      af_text(why, sizeof why, "could not remake %s: %s", what, af_strerror(st));
    }
  }
  if (st != AF_OK) {
    l->refused += !initial;
    af_text(l->last_refusal, sizeof l->last_refusal, "%s", why);
    af_text(err, len, "%s", why);
    af_ros_log(l->ros, AF_LOG_WARN, "reconfigure refused: %s", why);
    return st;
  }
  l->cfg->settings = l->next;
  af_snapshot_publish(l->snapshot, &l->cfg->settings);
  l->accepted += !initial;
  af_text(l->last_change, sizeof l->last_change, "%s", change);
  af_ros_log(l->ros, AF_LOG_INFO, "reconfigured: %s", change);
  return AF_OK;
}

void af_live_settings_diag(const af_live_settings *l, af_diag_status *d)
{
  if (!l)
    return;
  af_diag_add(d, "reconfigure", "%llu requests: %llu accepted, %llu refused", l->requests,
              l->accepted, l->refused);
  af_diag_add(d, "reconfigure last change", "%s", l->last_change);
  af_diag_add(d, "reconfigure last refusal", "%s", l->last_refusal);
}

af_status af_live_settings_create(af_ros *ros, af_node_config *cfg, af_lane_io *measured,
                                  af_live_settings **out, const char **what)
{
  *out = NULL;
  *what = "the dynamic_reconfigure server";
  af_live_settings *l = calloc(1, sizeof *l);
  if (!l)
    return AF_ENOMEM;
  l->ros = ros;
  l->cfg = cfg;
  l->measured = measured;
  af_status s = af_ros_reconfigure_create(ros, on_request, l);
  if (s != AF_OK) {
    af_live_settings_destroy(l);
    return s;
  }
  *out = l;
  return AF_OK;
}

void af_live_settings_set_snapshot(af_live_settings *l, af_snapshot *snapshot)
{
  if (l != NULL)
    l->snapshot = snapshot;
}

void af_live_settings_destroy(af_live_settings *l)
{
  free(l); /* the server belongs to the af_ros */
}
