/* reconfigure.c — the rows that may change while the node runs (reconfigure.h). */
#include "reconfigure.h"

static const af_reconfigure_row rows[] = {
    /* the criterion: the model's strike and criteria, the cultivar's calibrations */
    {AF_SETTING_DAMPING_LAW, "criterion"},
    {AF_SETTING_LOBE, "criterion"},
    {AF_SETTING_BAND_LEVEL, "criterion"},
    {AF_SETTING_SHEAR_RATIO, "criterion"},
    {AF_SETTING_STRIKE_VELOCITY_M_S, "criterion"},
    {AF_SETTING_LATITUDE_TOLERANCE_DEG, "criterion"},
    {AF_SETTING_MODULUS_NOMINAL_PA, "criterion"},
    {AF_SETTING_RESTITUTION, "criterion"},
    {AF_SETTING_YIELD_RATIO, "criterion"},
    {AF_SETTING_MODULUS_FACTOR, "criterion"},
    /* the measurement's thresholds */
    {AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR, "thresholds"},
    {AF_SETTING_STRIKE_THRESHOLD_MIN_N, "thresholds"},
    {AF_SETTING_MEASURE_SNR_THRESHOLD_DB, "thresholds"},
    {AF_SETTING_MEASURE_RANGE_MARGIN, "thresholds"},
    /* the sorter's classes */
    {AF_SETTING_GRADE_QUANTITY, "grades"},
    {AF_SETTING_GRADE_CLASSES, "grades"},
};

const af_reconfigure_row *af_reconfigure_rows(size_t *n)
{
  *n = sizeof rows / sizeof rows[0];
  return rows;
}

bool af_reconfigure_allowed(af_setting_id id)
{
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++)
    if (rows[k].id == id)
      return true;
  return false;
}
