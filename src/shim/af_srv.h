/* af_srv.h — the node's ROS services behind the C API (service.cpp): the
 * request and response of srv/Evaluate.srv as C structs, and the call that
 * advertises it. Conventions of af_ros.h: the handler is plain C and runs
 * only inside af_ros_spin_once, on the caller's thread; nothing throws. */
#ifndef AF_SRV_H
#define AF_SRV_H

#include <stdbool.h>
#include <stdint.h>

#include "af_msgs.h"
#include "af_ros.h"

#ifdef __cplusplus
extern "C" {
#endif

/* acoustic_firmness/Evaluate request: 0 in an optional field = configured. */
typedef struct {
  double mass_kg;         /* required */
  double strike_radius_m; /* R2, required */
  double modulus_pa;
  double restitution;
  double velocity_m_s;
  double hammer_mass_kg;
} af_evaluate_request;

/* acoustic_firmness/Evaluate response. */
typedef struct {
  bool ok;
  char error[AF_TEXT_MAX];
  double modulus_pa, restitution, velocity_m_s, hammer_mass_kg; /* what the model ran with */
  double contact_time_s, peak_force_n, max_deformation_m, delivered_restitution;
  uint8_t lobe;
  double band_low_hz, band_high_hz;
  double resonance_hz, resonance_low_hz, resonance_high_hz;
  double excitation_at_resonance_db;
  double max_contact_pressure_pa, max_shear_stress_pa, yield_shear_stress_pa;
  double min_strike_radius_m; /* 0 = none in the search bracket */
  bool excites_mode, no_damage, reliable;
  char reason[AF_TEXT_MAX];
} af_evaluate_response;

/* Fills *res (zeroed by the shim) for *req. */
typedef void (*af_evaluate_fn)(const af_evaluate_request *req, af_evaluate_response *res,
                               void *user);

/* Advertises service name (private when it starts with '~', e.g. "~evaluate")
 * of type acoustic_firmness/Evaluate; fn answers each call. The service
 * belongs to r. AF_OK; AF_EINVAL for a NULL or empty argument; AF_EROS. */
af_status af_ros_advertise_evaluate(af_ros *r, const char *name, af_evaluate_fn fn, void *user);

#ifdef __cplusplus
}
#endif
#endif
