/* af_reconfigure.h — dynamic_reconfigure behind the C API (reconfigure.cpp):
 * one server on the node's private namespace, of the description generated
 * at build time from the parameter table (acoustic_firmness/StationConfig,
 * src/cfg/reconfigure_cfg.c). The handler is plain C and runs inside
 * af_ros_spin_once; it gets every parameter of the request by name and type
 * and accepts it (AF_OK) or refuses it with one line: the server then
 * answers with the values it last accepted, so a client sees the refusal as
 * its values not taken. The values come as the client sent them, not
 * clamped to the description's min and max (dynamic_reconfigure's own server
 * clamps them in silence): the handler refuses what is out of range. The
 * first call (initial true: the server's start, not a client's request)
 * carries the values on the parameter server, i.e. the node's own. Conventions
 * of af_ros.h: nothing throws; the server belongs to the af_ros. */
#ifndef AF_RECONFIGURE_SHIM_H
#define AF_RECONFIGURE_SHIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "af_ros.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_RC_DOUBLE = 0, /* number */
  AF_RC_INT,        /* number (whole) */
  AF_RC_BOOL,       /* flag */
  AF_RC_STRING      /* text */
} af_rc_type;

typedef struct {
  const char *name; /* the parameter (= the table row's name) */
  af_rc_type type;
  double number;
  bool flag;
  const char *text; /* borrowed for the call */
} af_rc_value;

typedef af_status (*af_rc_fn)(const af_rc_value *values, size_t n, bool initial, void *user,
                              char *err, size_t len);

/* Starts the server; fn is called at once with the initial values. AF_OK;
 * AF_EINVAL; AF_EROS. */
af_status af_ros_reconfigure_create(af_ros *r, af_rc_fn fn, void *user);

#ifdef __cplusplus
}
#endif
#endif
