/* prediction.h — what the station predicts for one apple before it is
 * struck: the apple estimate checked against the cultivar, the strike's
 * geometry (latitude, R2) from the strike direction given as a vector in the
 * apple's frame, the model at the cultivar's nominal modulus (band, 0S2,
 * shear), the smallest reliable R2 and the strike advice.
 *
 * No ROS: the node fills af_apple from an AppleEstimate and the strike
 * direction from its rig description; the desk tools from a recording. The
 * prediction's model parameters are also what a strike on this apple is
 * measured with (lane.h). */
#ifndef AF_PREDICTION_H
#define AF_PREDICTION_H

#include <stdbool.h>
#include <stdint.h>

#include "advice.h"
#include "fastpath.h"
#include "lane_config.h"
#include "model.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_PREDICTION_TEXT_MAX 256

/* One apple as estimated by vision (the fields of AppleEstimate). */
typedef struct {
  uint32_t apple_id;
  int64_t stamp_ns;           /* the estimate's stamp [ns] */
  double mass_kg;             /* > 0 */
  double equatorial_radius_m; /* > 0 */
  double strike_radius_m;     /* measured local radius under the hammer [m]; 0 = unknown */
  double stem_axis[3];        /* in the apple's frame, any length; zero = unknown */
  double confidence;          /* [0, 1] */
  double
      strike_direction[3]; /* hammer's direction of motion in the apple's frame; zero = unknown */
  char direction_note[AF_PREDICTION_TEXT_MAX / 2]; /* why the direction is unknown */
} af_apple;

typedef struct {
  bool valid;                       /* the apple was accepted and the model ran */
  char why[AF_PREDICTION_TEXT_MAX]; /* why not ("invalid AppleEstimate: ...") */
  double polar_semi_axis_m;         /* from mass, density and equatorial radius */
  af_advice_geometry geo;           /* strike latitude, normal, R2 */
  af_model_params params;           /* what the model ran with (and strikes are judged with) */
  af_model_result result;           /* band, 0S2, shear, criteria */
  double resonance_low_hz;          /* 0S2 of this mass over the cultivar's firmness range */
  double resonance_high_hz;
  double min_strike_radius_m;          /* smallest reliable R2; 0 = none in the search bracket */
  af_advice_rotation rotation;         /* the advice */
  bool reliable;                       /* the model's verdict, and R2 known */
  char reason[AF_PREDICTION_TEXT_MAX]; /* "" when reliable */
} af_prediction;

/* Checks a against the cultivar (cfg), locates the strike and evaluates the
 * model with model (its workspace; no allocation). Always fills *out.
 * AF_OK: out->valid; AF_EINVAL: the apple was refused (out->why); a model
 * status when the evaluation failed (out->why says so). */
af_status af_prediction_execute(af_model *model, const af_lane_config *cfg, const af_apple *a,
                                af_prediction *out);

/* An apple's mass [kg] and strike radius [m] (0 = unknown) against the
 * cultivar's and the station's ranges in cfg (mass_min_kg..mass_max_kg,
 * strike_radius_min_m..strike_radius_max_m), in the words
 * af_prediction_execute refuses an AppleEstimate with, `what` leading them
 * ("invalid AppleEstimate"). AF_OK, or AF_EINVAL with one line in why. For
 * what the model is asked about an apple the lane would refuse. */
af_status af_prediction_check_apple(const af_lane_config *cfg, double mass_kg,
                                    double strike_radius_m, const char *what, char *why,
                                    size_t len);

/* The same on the fast path (fastpath.h; what the lane runs): the strike and
 * every step of the R2_min search from the process's shared table, within
 * 0.1 % of the ODE path's figures (test/core/test_prediction_fast.c), a
 * strike outside the table by fast's ODE fallback. About 25 evaluations of
 * ~0.5 us instead of ~20 us each; the first strikes of a process build
 * the table's rows their stencils need (~6 rows, ~5 ms; fastpath.h). */
af_status af_prediction_execute_fast(af_fastpath *fast, const af_lane_config *cfg,
                                     const af_apple *a, af_prediction *out);

#ifdef __cplusplus
}
#endif
#endif
