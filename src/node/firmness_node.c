/* firmness_node — the acoustic firmness station of one lane, in C over the
 * shim (src/shim/af_ros.h). Loads and checks every parameter and the rig's
 * URDF, then spins: apples in, excitation band, strike advice and
 * reliability out; force and audio buffered; diagnostics on /diagnostics.
 * A bad parameter or URDF stops the node at start-up with exit status 1. */
#include <stdio.h>
#include <stdlib.h>

#include "af_ros.h"
#include "params.h"
#include "station.h"

/* Callbacks wait at most this long [s], so diagnostics stay on time. */
#define AF_SPIN_TIMEOUT_S 0.05

int main(int argc, char **argv)
{
  af_ros *ros = NULL;
  af_status s = af_ros_create(&argc, argv, "firmness_node", &ros);
  if (s != AF_OK) {
    fprintf(stderr, "firmness_node: ROS start-up failed: %s %s\n", af_strerror(s),
            ros ? af_ros_last_error(ros) : "");
    af_ros_destroy(ros);
    return EXIT_FAILURE;
  }
  af_node_config cfg;
  char err[512];
  s = af_params_load(ros, &cfg, err, sizeof err);
  if (s != AF_OK) {
    af_ros_log(ros, AF_LOG_FATAL, "%s", err);
    af_ros_destroy(ros);
    return EXIT_FAILURE;
  }
  af_ros_log(ros, AF_LOG_INFO, "cultivar %s; URDF %s; hammer %g kg (%s), tip radius %g m (%s)",
             cfg.lane.cultivar, cfg.urdf_source, cfg.hammer.mass_kg, cfg.hammer_mass_source,
             cfg.hammer.tip_radius_m, cfg.hammer_tip_source);
  if (!cfg.hammer_axis_known)
    af_ros_log(ros, AF_LOG_WARN,
               "no hammer axis: strike latitude unknown, R2 from the equatorial "
               "radius unless the vision system measures it");
  af_station *st = NULL;
  s = af_station_create(ros, &cfg, &st);
  while (s == AF_OK && af_ros_ok(ros)) {
    s = af_ros_spin_once(ros, AF_SPIN_TIMEOUT_S);
    if (s != AF_OK)
      af_ros_log(ros, AF_LOG_FATAL, "spin failed: %s %s", af_strerror(s), af_ros_last_error(ros));
    else
      af_station_update(st);
  }
  af_station_destroy(st);
  af_params_destroy(&cfg);
  af_ros_destroy(ros);
  return s == AF_OK ? EXIT_SUCCESS : EXIT_FAILURE;
}
