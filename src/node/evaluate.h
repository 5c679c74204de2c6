/* evaluate.h — the node's ~evaluate service (srv/Evaluate.srv): the impact
 * model on demand for an apple and a strike given by a rig script, with the
 * node's configured hammer, criteria and cultivar unless the request
 * overrides them. Every request value is checked against the range of its
 * row of the one parameter table (src/core/params/settings.h), then the model's own
 * check runs; a refusal is an answer (ok false, one line naming the field,
 * its value and the accepted range), never a failed call.
 *
 * The model workspace is made in af_evaluate_create; a call allocates
 * nothing. Not thread-safe: the node's one spinning thread. */
#ifndef AF_NODE_EVALUATE_H
#define AF_NODE_EVALUATE_H

#include "af_ros.h"
#include "af_srv.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_evaluate af_evaluate;

/* Advertises ~evaluate. cfg must outlive it (its lane configuration is read
 * at each call, so a reconfigured node answers with its new settings). *out
 * NULL on error, *what naming the part that failed. */
af_status af_evaluate_create(af_ros *ros, const af_node_config *cfg, af_evaluate **out,
                             const char **what);
void af_evaluate_destroy(af_evaluate *e); /* NULL-safe */

/* Answers one request (the service's handler; also callable directly). */
void af_evaluate_execute(af_evaluate *e, const af_evaluate_request *req, af_evaluate_response *res);

/* Adds the service's keys (calls, refused, last refusal) to d. */
void af_evaluate_diag(const af_evaluate *e, af_diag_status *d);

#ifdef __cplusplus
}
#endif
#endif
