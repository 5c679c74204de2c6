/* lane_config.h — everything one station lane is configured with, outside
 * ROS: the strike and the criteria (the model template), the cultivar, the
 * force and audio streams, the strike detector, the measurement and the
 * pending queue. The node (src/node/params.c, from its private parameters)
 * and the desk tools (from the same YAML files) fill it through the one
 * parameter table (settings.h) and af_lane_config_derive, so that a
 * recording is judged with exactly the figures the node uses. */
#ifndef AF_LANE_CONFIG_H
#define AF_LANE_CONFIG_H

#include <stdbool.h>
#include <stddef.h>

#include "factor_learn.h"
#include "grade.h"
#include "hammer_health.h"
#include "onset.h"
#include "rate_status.h"
#include "measure.h"
#include "model.h"
#include "settings.h"
#include "strike.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_LANE_NAME_MAX AF_SETTINGS_NAME_MAX /* cultivar name, with its NUL */
#define AF_LANE_UNIT_MAX 16 /* a stream unit, with its NUL (= SignalChunk.unit's cap) */

/* One sampled input stream (force or audio). */
typedef struct {
  double sample_rate_hz;           /* expected rate; other rates are refused and counted [Hz] */
  double buffer_s;                 /* ring length [s] */
  size_t capacity_samples;         /* ceil(buffer_s * sample_rate_hz) */
  size_t max_chunk_samples;        /* the longest chunk the station takes, the node on the wire and
                                      firmness_report in a bag alike: the ring (a longer chunk could
                                      not be held whole) */
  char units[2][AF_LANE_UNIT_MAX]; /* accepted units ("" = unused slot) */
  double to_si; /* each sample times this into the ring and the detector: 1 = as sent; a force
                   in V: 1 / force_sensitivity_v_per_n [N/V] */
  double clock_step_s; /* a chunk stamped further than this from where the samples put it is a
                          clock step (stream_clock_step_s) [s] */
} af_stream_config;

/* The measured strikes: the detector on the force stream, the measurement of
 * each strike, the queue of strikes waiting for their audio and apple. */
typedef struct {
  af_strike_config strike;          /* strike_*; sample rate = force_sample_rate_hz */
  af_measure_config measure;        /* measure_*; response and fit sized from them */
  size_t pending_size;              /* strike_pending_size: strikes waiting for audio */
  size_t pulse_capacity_samples;    /* longest event span the detector can emit */
  size_t audio_window_samples;      /* round(measure_audio_window_s * audio rate) */
  size_t noise_window_samples;      /* round(measure_noise_window_s * audio rate); 0 = none */
  double apple_stale_after_s;       /* a strike matches an apple stamped at most this long before */
  double apple_wait_s;              /* a strike waits this long for its own apple's estimate [s] */
  double apple_transit_s;           /* a strike comes this long after its estimate's stamp [s] */
  double apple_transit_tolerance_s; /* ... within this [s] */
  bool audio_lag_learn;   /* align the audio window by the learned audio lag (audio_lag.h) */
  double audio_lag_max_s; /* the onset searched within this of the contact start [s] */
  bool single_apple;      /* desk tools: one apple stands for a whole recording, so a second strike
                             on it is expected, not a doubtful match; false (0) in the node */
  bool tap_only;          /* tap_only: strikes from the audio onset, no force input (onset.h) */
  af_onset_config onset;  /* onset_*: the audio onset detector, at the audio rate */
} af_strikes_config;

typedef struct {
  /* --- the strike and the criteria --- */
  af_model_params model;         /* template: per-apple mass and R2 filled in later */
  double latitude_tolerance_rad; /* strike latitudes beyond this are advised to rotate [rad] */
  double r2_search_low_m;        /* bracket of af_model_min_strike_radius [m] */
  double r2_search_high_m;
  double strike_radius_min_m; /* accepted AppleEstimate.strike_radius (when not 0) [m] */
  double strike_radius_max_m;
  /* --- streams --- */
  af_stream_config force, audio;
  double stream_stale_after_s; /* a stream silent this long is stale [s] */
  double stream_absent_warn_s; /* warn when a stream sent nothing this long after start; 0 = never
                                  [s] */
  /* The inputs' rate and stamp checks on /diagnostics (rate_status.h): chunks
   * per second from the sample rate and *_chunk_samples (min = max, as
   * velodyne_driver's packets; 0 samples: min 0, max INFINITY, only a
   * silence warns), apples from apple_rate_*_hz. */
  af_rate_config force_rate, audio_rate, apple_rate;
  af_stamp_config stream_stamps, apple_stamps; /* force and audio; apple estimates */
  /* --- measured strikes --- */
  af_strikes_config strikes;
  /* --- cultivar --- */
  char cultivar[AF_LANE_NAME_MAX];
  double modulus_min_pa, modulus_max_pa; /* firmness range of the resonance band [Pa] */
  double mass_min_kg, mass_max_kg;
  double equatorial_radius_min_m, equatorial_radius_max_m;
  double aspect_ratio_min, aspect_ratio_max; /* polar / equatorial semi-axis */
  double resonance_xi;                       /* Lamb root of the cultivar's Poisson ratio */
  af_grade_config grade; /* firmness classes of measured strikes (grade_quantity, grade_classes) */
  /* --- hammer health --- */
  af_hammer_health_config health;      /* hammer_health_* with the model's hammer, velocity, e */
  af_factor_learn_config factor_learn; /* the modulus factor learned on the line
                                          (modulus_factor_learn_*; initial = modulus_factor) */
} af_lane_config;

/* Fills *out from the settings s (every row present: the hammer's mass and
 * tip radius too, which the node takes from the URDF unless overridden) and
 * runs every check across parameters: the min < max pairs (the noise band's
 * too), the nominal modulus within its range, ring sizes (at most 1e8
 * samples), the detector's windows and event span (at most 2^24 samples),
 * the audio windows (at least 8 samples, within the audio ring), the hum and
 * the noise band's low end below the audio Nyquist frequency, the memory the
 * lane would take (at most AF_LANE_MEMORY_MAX_BYTES, checked before anything
 * is allocated), trial creates of the strike detector and the measurement,
 * Lamb's 0S2 root, the model's own check over the corners the lane
 * evaluates (extreme masses, moduli, both ends of the R2 search), and the
 * settings that cannot work together: the audio ring against what a strike's
 * audio must wait (noise reference, apple_wait_s or the window, and
 * stream_stale_after_s), the force ring against one strike's event (the
 * largest chunk taken is the ring), the noise band against the cultivar's
 * 0S2 search range, the equatorial-radius range against the masses, density
 * and aspect ratios. Derived:
 * ring capacities ceil(s x rate), the latitude tolerance in rad, the
 * detector's longest event span, the audio and noise windows round(s x
 * rate), the response window (the longer) and FFT size (power of two >=
 * measure_fft_padding x window), its hum and noise band (measure_hum_*,
 * measure_noise_band_*), the fit's max samples (>= longest contact + 2); the
 * measurement's unexposed fields keep af_measure_config_default's. Allocates
 * only inside the trial creates (start-up). AF_OK; AF_EINVAL with one line
 * naming the parameters (with s's name prefix), their values and what is
 * accepted; AF_ENOMEM. *out is zeroed first, and holds nothing to free. */
af_status af_lane_config_derive(const af_settings *s, af_lane_config *out, char *err, size_t len);

/* The most one lane may allocate (af_lane_create): af_lane_config_derive
 * refuses a configuration whose estimate is above, before anything is
 * allocated. The defaults take about 2 MiB; 256 MiB holds, e.g., two rings
 * of 30 s at 1 MHz. */
#define AF_LANE_MEMORY_MAX_BYTES ((size_t)256 << 20)

/* What af_lane_create allocates for a derived configuration, estimated from
 * above [bytes] (test_settings checks it against the heap a lane takes). */
typedef struct {
  double rings;          /* force and audio rings */
  double detector_queue; /* the strike detector, the pending queue, the audio windows */
  double microphone;     /* the microphone analysis (FFT of the audio window) */
  double fit_spectrum;   /* the pulse fit and the pulse's spectrum */
  double fixed;          /* the model workspace and the objects */
  double total;
} af_lane_memory;
void af_lane_config_memory(const af_lane_config *c, af_lane_memory *m);

#ifdef __cplusplus
}
#endif
#endif
