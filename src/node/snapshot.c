/* snapshot.c — the node's settings and URDF, latched (see snapshot.h). */
#include "snapshot.h"

#include <stdlib.h>

#include "file_read.h"
#include "snapshot_text.h"

/* The URDF is read again for the topic, bounded like the settings' text. */
#define AF_URDF_TEXT_MAX_BYTES (16u << 20)

struct af_snapshot {
  af_ros *ros;
  af_ros_pub *settings_pub, *urdf_pub;
  char *text; /* AF_SNAPSHOT_MAX_BYTES */
};

void af_snapshot_publish(af_snapshot *p, const af_settings *s)
{
  if (p == NULL)
    return;
  if (af_settings_snapshot(s, p->text, AF_SNAPSHOT_MAX_BYTES) != AF_OK)
    af_ros_log(p->ros, AF_LOG_WARN, "settings snapshot cut: longer than %zu bytes",
               (size_t)AF_SNAPSHOT_MAX_BYTES);
  af_text_msg m = {p->text};
  if (af_ros_publish(p->settings_pub, &m) != AF_OK)
    af_ros_log(p->ros, AF_LOG_WARN, "settings snapshot not published: %s",
               af_ros_last_error(p->ros));
}

/* The URDF's text: the file's bytes, or the parameter's (allocated; NULL
 * when there is none or it cannot be read). */
static char *urdf_text(af_ros *ros, const af_node_config *cfg)
{
  if (cfg->urdf_file[0] == '\0') {
    size_t size = af_ros_param_string_bytes(ros, "robot_description", false);
    char *xml = size > 0 && size <= AF_URDF_TEXT_MAX_BYTES ? malloc(size) : NULL;
    if (xml && af_ros_param_string_global(ros, "robot_description", xml, size) != AF_OK) {
      free(xml);
      xml = NULL;
    }
    return xml;
  }
  char *xml = NULL, err[AF_TEXT_MAX];
  size_t n;
  if (af_file_read_whole(cfg->urdf_file, AF_URDF_TEXT_MAX_BYTES, "a URDF", &xml, &n, err,
                         sizeof err) != AF_OK)
    af_ros_log(ros, AF_LOG_WARN, "robot_description topic: %s", err);
  return xml;
}

static void publish_urdf(af_snapshot *p, const af_node_config *cfg)
{
  char *xml = urdf_text(p->ros, cfg); /* start-up only */
  af_text_msg m = {xml ? xml : ""};
  if (!xml)
    af_ros_log(p->ros, AF_LOG_WARN,
               "robot_description topic empty: the URDF (%s) could not be "
               "read again",
               cfg->urdf_source);
  (void)af_ros_publish(p->urdf_pub, &m);
  free(xml);
}

af_status af_snapshot_create(af_ros *ros, const af_node_config *cfg, af_snapshot **out)
{
  *out = NULL;
  af_snapshot *p = calloc(1, sizeof *p);
  if (!p || !(p->text = malloc(AF_SNAPSHOT_MAX_BYTES))) {
    af_snapshot_destroy(p);
    return AF_ENOMEM;
  }
  p->ros = ros;
  af_status s = af_ros_advertise(ros, "settings", AF_MSG_TEXT, 1, true, &p->settings_pub);
  if (s == AF_OK)
    s = af_ros_advertise(ros, "robot_description", AF_MSG_TEXT, 1, true, &p->urdf_pub);
  if (s != AF_OK) {
    af_snapshot_destroy(p);
    return s;
  }
  af_snapshot_publish(p, &cfg->settings);
  publish_urdf(p, cfg);
  *out = p;
  return AF_OK;
}

void af_snapshot_destroy(af_snapshot *p)
{
  if (p == NULL)
    return;
  free(p->text);
  free(p);
}
