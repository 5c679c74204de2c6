/* model_table.h — the model's parameters as the one parameter table
 * (settings.h) sets them, for the desk tools (firmness_model and its
 * subcommands, strike_bag): the same figures the node and firmness_report
 * derive through af_lane_config_derive, so that no tool starts from numbers
 * of its own. */
#ifndef AF_MODEL_TABLE_H
#define AF_MODEL_TABLE_H

#include <stddef.h>

#include "model.h"
#include "settings.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The model of s: af_lane_config_for_tool's (tool_config.h) model template, whose per-apple
 * figures (the fruit's mass and the strike radius R2, which each
 * AppleEstimate gives the node, no table row) are model.c's example apple
 * (af_model_params_default's). AF_OK; AF_EINVAL with its one line in err. */
af_status af_model_params_from_settings(const af_settings *s, af_model_params *out, char *err,
                                        size_t len);

/* af_model_params_from_settings of the table's defaults. */
af_status af_model_params_table(af_model_params *out, char *err, size_t len);

/* The paper-literal profile on top of p (af_model_params_paper's choices:
 * its damping law, lobe, band level and shear ratio; the numbers stay p's). */
af_model_params af_model_params_paper_of(const af_model_params *p);

#ifdef __cplusplus
}
#endif
#endif
