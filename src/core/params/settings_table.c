/* settings_table.c — the one parameter table: every row of the lane's
 * parameters (name, kind, default, range with its unit, file, help) and the
 * row accessors. It needs nothing but the C library, so that the build-time
 * generators (src/cfg: Station.cfg, af_defaults.h) can be built from it
 * alone. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "settings_private.h"

/* ---- the table ------------------------------------------------------------ */

#define HEALTH_STR_(x) #x
#define HEALTH_STR(x) HEALTH_STR_(x) /* a macro's value as text */
#define S AF_SETTINGS_STATION
#define C AF_SETTINGS_CULTIVAR
#define NUM(name, def, range, file, help)                                                          \
  {                                                                                                \
    name, AF_SETTING_NUMBER, def, range, NULL, file, false, false, NULL, 0, help, NULL             \
  }
#define WHOLE(name, def, range, file, help)                                                        \
  {                                                                                                \
    name, AF_SETTING_WHOLE, def, range, NULL, file, false, false, NULL, 0, help, NULL              \
  }
#define OPTIONAL_NUM(name, range, zero_is_absent, absent, rig, help)                               \
  {                                                                                                \
    name, AF_SETTING_NUMBER, NULL, range, NULL, S, true, zero_is_absent, absent, 0, help, rig      \
  }
#define BOOLEAN(name, def, file, help)                                                             \
  {                                                                                                \
    name, AF_SETTING_BOOL, def, NULL, NULL, file, false, false, NULL, 0, help, NULL                \
  }
#define STRING(name, def, max_chars, file, help)                                                   \
  {                                                                                                \
    name, AF_SETTING_STRING, def, NULL, NULL, file, false, false, NULL, max_chars, help, NULL      \
  }
#define CHOICE(name, def, choices, file, help)                                                     \
  {                                                                                                \
    name, AF_SETTING_CHOICE, def, NULL, choices, file, false, false, NULL, 0, help, NULL           \
  }

/* Every range and default of the lane. The ranges are sanity bounds of a
 * real rig and fruit (a value outside is a typo); af_model_params_check
 * applies the same rows to the model's fields. */
const af_setting_def af_setting_rows[AF_SETTING_COUNT] = {
    [AF_SETTING_HAMMER_LINK] = STRING("hammer_link", "hammer", AF_SETTINGS_NAME_MAX - 1, S,
                                      "URDF link of the hammer head (mass, tip geometry; its "
                                      "parent joint's axis = strike direction)"),
    [AF_SETTING_URDF_FILE] = STRING("urdf_file", "\"\"", AF_SETTINGS_TEXT_MAX - 1, S,
                                    "path of the rig's URDF; empty = the robot_description "
                                    "parameter of the node's namespace"),
    [AF_SETTING_FRAME_PREFIX] = STRING("frame_prefix", "\"\"", AF_SETTINGS_NAME_MAX - 1, S,
                                       "prefix of the rig's TF frames for this lane, as "
                                       "robot_state_publisher's tf_prefix (lane1: lane1/rig_base); "
                                       "empty = none, one rig per TF tree"),
    [AF_SETTING_HARDWARE_ID] = STRING("hardware_id", "\"\"", AF_SETTINGS_NAME_MAX - 1, S,
                                      "the diagnostics' hardware_id: the DAQ's or the force "
                                      "transducer's serial; empty = the node's name"),
    [AF_SETTING_HAMMER_MASS_KG] = OPTIONAL_NUM("hammer_mass_kg", "[0.0005, 1] kg", true,
                                               "from the URDF", "0.010", /* the rig's 10 g head */
                                               "overrides the URDF's hammer mass"),
    [AF_SETTING_HAMMER_TIP_RADIUS_M] =
        OPTIONAL_NUM("hammer_tip_radius_m", "0 or [0.0005, 0.1] m", false, "from the URDF",
                     "0.0", /* the rig's flat face */
                     "overrides the URDF's tip radius; 0 = flat face"),
    [AF_SETTING_HAMMER_MODULUS_PA] =
        NUM("hammer_modulus_pa", "0.0", "0 or [1e5, 1e12] Pa", S, "hammer tip modulus; 0 = rigid"),
    [AF_SETTING_HAMMER_POISSON] = NUM("hammer_poisson", "0.3", "[0, 0.5)", S,
                                      "hammer tip Poisson ratio (unused while rigid)"),
    [AF_SETTING_STRIKE_VELOCITY_M_S] = NUM("strike_velocity_m_s", "1.4", "[0.05, 10] m/s", S,
                                           "contact velocity (the paper's optimum)"),
    [AF_SETTING_GRAVITY_M_S2] =
        NUM("gravity_m_s2", "9.80665", "[0, 20] m/s2", S, "gravity along the strike; 0 = off"),
    [AF_SETTING_DAMPING_LAW] = CHOICE("damping_law", "exact", "paper, exact, hu-guo", S,
                                      "damping law chi(e) (PHYSICS.md 2)"),
    [AF_SETTING_LOBE] =
        WHOLE("lobe", "1", "[1, 8]", S, "spectral lobe of the criterion (1 = main lobe)"),
    [AF_SETTING_BAND_LEVEL] = CHOICE("band_level", "amplitude-half", "power-half, amplitude-half",
                                     S, "half-power reading of the bands (PHYSICS.md 4)"),
    [AF_SETTING_SHEAR_RATIO] = CHOICE("shear_ratio", "exact", "paper, exact", S,
                                      "tau_max / p0: paper (0.31) or exact (Hertz, for the "
                                      "fruit's Poisson ratio)"),
    [AF_SETTING_LATITUDE_TOLERANCE_DEG] = NUM("latitude_tolerance_deg", "15.0", "[0, 90] deg", S,
                                              "strike latitudes beyond this are advised to "
                                              "rotate"),
    [AF_SETTING_R2_SEARCH_LOW_M] = NUM("r2_search_low_m", "0.002", "[0.0005, 1] m", S,
                                       "low end of the minimum reliable strike radius search"),
    [AF_SETTING_R2_SEARCH_HIGH_M] = NUM("r2_search_high_m", "0.5", "[0.0005, 1] m", S,
                                        "high end of that search, above r2_search_low_m"),
    [AF_SETTING_STRIKE_RADIUS_MIN_M] = NUM("strike_radius_min_m", "0.002", "[0.0005, 1] m", S,
                                           "smallest accepted AppleEstimate.strike_radius "
                                           "(when not 0)"),
    [AF_SETTING_STRIKE_RADIUS_MAX_M] = NUM("strike_radius_max_m", "0.5", "[0.0005, 1] m", S,
                                           "largest accepted AppleEstimate.strike_radius, "
                                           "above strike_radius_min_m"),
    [AF_SETTING_FORCE_SAMPLE_RATE_HZ] = NUM("force_sample_rate_hz", "50000.0", "[1000, 1e6] Hz", S,
                                            "force rate; chunks at another rate are refused "
                                            "and counted"),
    [AF_SETTING_FORCE_BUFFER_S] = NUM("force_buffer_s", "2.0", "(0, 3600] s", S,
                                      "force kept in the ring (at most 1e8 samples)"),
    [AF_SETTING_AUDIO_SAMPLE_RATE_HZ] = NUM("audio_sample_rate_hz", "48000.0", "[1000, 1e6] Hz", S,
                                            "audio rate; chunks at another rate are refused "
                                            "and counted"),
    [AF_SETTING_AUDIO_BUFFER_S] = NUM("audio_buffer_s", "2.0", "(0, 3600] s", S,
                                      "audio kept in the ring (at most 1e8 samples)"),
    [AF_SETTING_AUDIO_UNIT] = CHOICE("audio_unit", "Pa", "Pa, V", S,
                                     "the microphone's unit (the force transducer's is N)"),
    [AF_SETTING_AUDIO_INPUT] =
        CHOICE("audio_input", "signal_chunk", "signal_chunk, audio_common", S,
               "what the audio topic carries: acoustic_firmness/SignalChunk, "
               "or audio_common_msgs/AudioData(Stamped) with audio_info"),
    [AF_SETTING_AUDIO_CHANNEL] =
        WHOLE("audio_channel", "0", "[0, 255]", S,
              "the channel taken from audio_common frames (0 = the first)"),
    [AF_SETTING_AUDIO_FULL_SCALE] =
        NUM("audio_full_scale", "1.0", "[1e-6, 1e6]", S,
            "audio_common: the microphone's value at digital full scale, in audio_unit"),
    [AF_SETTING_STREAM_STALE_AFTER_S] = NUM("stream_stale_after_s", "1.0", "(0, 3600] s", S,
                                            "a stream silent this long is reported stale"),
    [AF_SETTING_STREAM_ABSENT_WARN_S] =
        NUM("stream_absent_warn_s", "5.0", "0 or [0.1, 3600] s", S,
            "/diagnostics warns when a stream has sent no chunk this long after the start "
            "(0 = never)"),
    [AF_SETTING_FORCE_CHUNK_SAMPLES] =
        WHOLE("force_chunk_samples", "1024", "[0, 1e6] samples", S,
              "samples per force chunk the DAQ sends: /diagnostics expects force_sample_rate_hz / "
              "this chunks per second (strike_bag: 1024); 0 = any size, the rate not judged"),
    [AF_SETTING_AUDIO_CHUNK_SAMPLES] =
        WHOLE("audio_chunk_samples", "1024", "[0, 1e6] samples", S,
              "samples per audio chunk: /diagnostics expects audio_sample_rate_hz / this chunks "
              "per second (strike_bag: 1024); 0 = any size, the rate not judged"),
    [AF_SETTING_STREAM_RATE_TOLERANCE] =
        NUM("stream_rate_tolerance", "0.1", "[0, 1]", S,
            "fraction by which an input's message rate may leave its expected range before "
            "/diagnostics warns (diagnostic_updater's FrequencyStatus tolerance)"),
    [AF_SETTING_STREAM_STAMP_DELAY_MIN_S] =
        NUM("stream_stamp_delay_min_s", "-1.0", "[-3600, 3600] s", S,
            "earliest accepted receive time - header stamp of a force or audio chunk "
            "(negative: stamped ahead of the node's clock)"),
    [AF_SETTING_STREAM_STAMP_DELAY_MAX_S] =
        NUM("stream_stamp_delay_max_s", "5.0", "[-3600, 3600] s", S,
            "latest accepted receive time - header stamp of a chunk (its stamp is its first "
            "sample: at least the chunk's duration), above stream_stamp_delay_min_s"),
    [AF_SETTING_APPLE_RATE_MIN_HZ] =
        NUM("apple_rate_min_hz", "0.0", "[0, 1000] Hz", S,
            "fewest AppleEstimates per second expected; 0 = the line may stop (no warning "
            "while none come)"),
    [AF_SETTING_APPLE_RATE_MAX_HZ] =
        NUM("apple_rate_max_hz", "20.0", "(0, 1000] Hz", S,
            "most AppleEstimates per second expected, above apple_rate_min_hz"),
    [AF_SETTING_APPLE_STAMP_DELAY_MIN_S] =
        NUM("apple_stamp_delay_min_s", "-1.0", "[-3600, 3600] s", S,
            "earliest accepted receive time - header stamp of an AppleEstimate"),
    [AF_SETTING_APPLE_STAMP_DELAY_MAX_S] =
        NUM("apple_stamp_delay_max_s", "5.0", "[-3600, 3600] s", S,
            "latest accepted receive time - header stamp of an AppleEstimate (cameras stamp "
            "late: the image's exposure, then the vision's work), above "
            "apple_stamp_delay_min_s"),
    [AF_SETTING_DIAGNOSTIC_RATE_WINDOW] =
        WHOLE("diagnostic_rate_window", "10", "[1, 100] updates", S,
              "diagnostic updates the inputs' rates are taken over (diagnostic_updater's "
              "FrequencyStatus window; velodyne_driver's 10)"),
    [AF_SETTING_FORCE_UNIT] = CHOICE("force_unit", "N", "N, V", S,
                                     "the force transducer's unit: N, or V from a DAQ (divided by "
                                     "force_sensitivity_v_per_n at the lane's input)"),
    [AF_SETTING_FORCE_SENSITIVITY_V_PER_N] =
        NUM("force_sensitivity_v_per_n", "0.0", "0 or [1e-4, 10] V/N", S,
            "the transducer's sensitivity with its conditioning; required with force_unit V, "
            "0 = none (force_unit N)"),
    [AF_SETTING_MARKERS_ENABLED] =
        BOOLEAN("markers_enabled", "true", S, "publish the rviz markers"),
    [AF_SETTING_MARKER_LIFETIME_S] =
        NUM("marker_lifetime_s", "0.0", "[0, 3600] s", S, "marker lifetime; 0 = until replaced"),
    [AF_SETTING_MARKER_STRIKE_DISTANCE_M] =
        NUM("marker_strike_distance_m", "0.06", "[0, 10] m", S,
            "hammer link origin to the strike point along the axis (display only)"),
    [AF_SETTING_MARKER_ARROW_LENGTH_M] =
        NUM("marker_arrow_length_m", "0.05", "(0, 10] m", S, "hammer and rotation arrows"),
    [AF_SETTING_STRIKE_PLOT_WIDTH_PX] =
        WHOLE("strike_plot_width_px", "800", "[320, 2048] px", S,
              "width of the last strike's picture on ~strike_plot (sensor_msgs/Image, rgb8)"),
    [AF_SETTING_STRIKE_PLOT_HEIGHT_PX] = WHOLE("strike_plot_height_px", "450", "[240, 2048] px", S,
                                               "height of the last strike's picture"),
    [AF_SETTING_STRIKE_FULL_SCALE_N] = NUM("strike_full_scale_n", "500.0", "(0, 1e6] N", S,
                                           "a raw force sample at or beyond +-this is clipped"),
    [AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR] =
        NUM("strike_threshold_noise_factor", "6.0", "(0, 1000]", S,
            "trigger when the force exceeds the baseline by this many noise RMS and by "
            "strike_threshold_min_n"),
    [AF_SETTING_STRIKE_THRESHOLD_MIN_N] = NUM("strike_threshold_min_n", "0.5", "(0, 1e6] N", S,
                                              "least excess over the baseline that triggers "
                                              "(never 0: after exact-zero silence any flicker "
                                              "would be a strike)"),
    [AF_SETTING_STRIKE_PRE_TRIGGER_S] = NUM("strike_pre_trigger_s", "0.002", "(0, 1] s", S,
                                            "history kept before the trigger, above "
                                            "strike_baseline_window_s"),
    [AF_SETTING_STRIKE_BASELINE_TIME_CONSTANT_S] =
        NUM("strike_baseline_time_constant_s", "0.02", "(0, 10] s", S,
            "idle baseline and noise trackers (also the warm-up)"),
    [AF_SETTING_STRIKE_BASELINE_WINDOW_S] =
        NUM("strike_baseline_window_s", "0.001", "(0, 1] s", S,
            "quiet signal averaged before and after the contact"),
    [AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S] =
        NUM("strike_double_hit_gap_s", "0.005", "[0, 1] s", S,
            "a contact starting this soon after the end is a bounce"),
    [AF_SETTING_STRIKE_MAX_CONTACT_S] = NUM("strike_max_contact_s", "0.01", "(0, 1] s", S,
                                            "a longer contact is not a strike (truncated)"),
    [AF_SETTING_STRIKE_POST_S] = NUM("strike_post_s", "0.005", "(0, 1] s", S,
                                     "wait after the contact, at least strike_double_hit_gap_s "
                                     "and above strike_baseline_window_s"),
    [AF_SETTING_STRIKE_RISE_FIT_LEVEL] = NUM("strike_rise_fit_level", "0.7", "(0, 1)", S,
                                             "rising-edge fit up to this fraction of the peak"),
    [AF_SETTING_STRIKE_FALL_FIT_LEVEL] = NUM("strike_fall_fit_level", "0.5", "(0, 1)", S,
                                             "falling-edge fit from this fraction of the peak"),
    [AF_SETTING_STRIKE_PENDING_SIZE] =
        WHOLE("strike_pending_size", "8", "[1, 1000] strikes", S,
              "strikes waiting for their audio; a full queue measures its oldest without audio"),
    [AF_SETTING_APPLE_STALE_AFTER_S] =
        NUM("apple_stale_after_s", "1.0", "(0, 3600] s", S,
            "an AppleEstimate stamped further than this from the newest force data (tap-only: "
            "audio) is refused and counted: a clock that far off would mismatch every strike"),
    [AF_SETTING_APPLE_WAIT_S] = NUM("apple_wait_s", "0.5", "[0, 10] s", S,
                                    "how long a strike waits for the AppleEstimate that "
                                    "belongs to it"),
    [AF_SETTING_APPLE_TRANSIT_S] =
        NUM("apple_transit_s", "0.2", "[-10, 60] s", S,
            "the conveyor's transit: a strike belongs to the AppleEstimate stamped this long "
            "before its contact start (negative: a camera downstream of the hammer)"),
    [AF_SETTING_STREAM_CLOCK_STEP_S] =
        NUM("stream_clock_step_s", "0.02", "[0.0001, 10] s", S,
            "a chunk stamped further than this from where its samples put it (the chunk before's "
            "stamp + the samples between / rate) is a clock step: named, and the strikes near "
            "it flagged"),
    [AF_SETTING_AUDIO_LAG_LEARN] =
        BOOLEAN("audio_lag_learn", "true", S,
                "align each strike's audio window by the median audio lag (the sound's onset by "
                "the audio's stamps minus the contact start by the force's) once it is stable"),
    [AF_SETTING_AUDIO_LAG_MAX_S] =
        NUM("audio_lag_max_s", "0.25", "[0.005, 1] s", S,
            "the audio lag is searched within this of the contact start (at most half the time "
            "since the strike before)"),
    [AF_SETTING_APPLE_TRANSIT_TOLERANCE_S] =
        NUM("apple_transit_tolerance_s", "0.04", "[0.0001, 60] s", S,
            "how far a strike may lie from its estimate's stamp + apple_transit_s; keep it "
            "under half the apples' spacing, so that one estimate at most fits"),
    [AF_SETTING_MEASURE_FIT_VELOCITY] = BOOLEAN("measure_fit_velocity", "false", S,
                                                "fit the contact velocity too (false: the rig "
                                                "sets it, strike_velocity_m_s)"),
    [AF_SETTING_MEASURE_AUDIO_DELAY_S] =
        NUM("measure_audio_delay_s", "0.0005", "[0, 1] s", S,
            "the analysed audio starts this long after the contact start"),
    [AF_SETTING_MEASURE_AUDIO_WINDOW_S] =
        NUM("measure_audio_window_s", "0.04", "(0, 1] s", S, "analysed audio (at least 8 samples)"),
    [AF_SETTING_MEASURE_NOISE_WINDOW_S] =
        NUM("measure_noise_window_s", "0.02", "[0, 1] s", S,
            "audio before the strike, the noise reference (0 = none, else at least 8 samples)"),
    [AF_SETTING_MEASURE_NOISE_GUARD_S] =
        NUM("measure_noise_guard_s", "0.005", "[0, 1] s", S,
            "the noise reference ends this long before the contact start (stamp jitter)"),
    [AF_SETTING_MEASURE_RANGE_MARGIN] =
        NUM("measure_range_margin", "0.15", "[0, 1)", S,
            "relative widening of the model's 0S2 range for the apple's mass"),
    [AF_SETTING_MEASURE_SNR_THRESHOLD_DB] =
        NUM("measure_snr_threshold_db", "15.0", "[-100, 100] dB", S,
            "a peak below this is not a resonance (response.h: 12 dB lets ~0.1 % of noise-only "
            "windows through, 15 dB none of 2e4)"),
    [AF_SETTING_MEASURE_HUM_HZ] =
        NUM("measure_hum_hz", "50.0", "0 or [10, 1000] Hz", S,
            "mains frequency removed from the audio with its harmonics, below the audio Nyquist "
            "frequency; 0 = off, 60 for a 60 Hz site"),
    [AF_SETTING_MEASURE_HUM_HARMONICS] =
        WHOLE("measure_hum_harmonics", "3", "[0, 8]", S,
              "multiples of measure_hum_hz removed (1 = the fundamental only), each only when at "
              "most 0.8 x the lowest expected 0S2 frequency"),
    [AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ] =
        NUM("measure_noise_band_low_hz", "4000.0", "[0, 5e5] Hz", S,
            "low end of the band of the window's own noise floor (used without a noise "
            "reference), below the audio Nyquist frequency"),
    [AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ] =
        NUM("measure_noise_band_high_hz", "16000.0", "[0, 5e5] Hz", S,
            "high end of that band, above measure_noise_band_low_hz (clipped to Nyquist)"),
    [AF_SETTING_MEASURE_FFT_PADDING] =
        WHOLE("measure_fft_padding", "4", "[1, 16]", S,
              "the audio FFT size is the power of two at least this many times the analysed "
              "window (zero padding: finer bins)"),
    [AF_SETTING_TAP_ONLY] =
        BOOLEAN("tap_only", "false", S,
                "tap-only rig (a microphone, no force transducer): strikes are found in the "
                "audio onset, the 0S2 from the microphone alone; no force input is read"),
    [AF_SETTING_ONSET_SNR_DB] =
        NUM("onset_snr_db", "12.0", "[3, 60] dB", S,
            "tap-only: an onset is an audio frame whose mean square is this far above the "
            "running noise floor"),
    [AF_SETTING_ONSET_HOLDOFF_S] =
        NUM("onset_holdoff_s", "0.05", "[0.001, 10] s", S,
            "tap-only: no new onset this long after one (a bounce of the hammer is no new "
            "strike), at least onset_frame_s; strikes must come further apart"),
    [AF_SETTING_ONSET_FRAME_S] =
        NUM("onset_frame_s", "0.001", "[0.0001, 0.1] s", S,
            "tap-only: the energy frame of the onset detector (at least 4 audio samples)"),
    [AF_SETTING_ONSET_FLOOR_TIME_CONSTANT_S] =
        NUM("onset_floor_time_constant_s", "0.5", "[0.001, 3600] s", S,
            "tap-only: averaging time of the noise floor (frames below the threshold only), "
            "at least onset_frame_s"),
    [AF_SETTING_ONSET_FLOOR] =
        NUM("onset_floor", "2.0e-5", "[1.0e-9, 1]", S,
            "tap-only: the least noise floor, RMS in audio_unit (2e-5 Pa: 0 dB SPL, below any "
            "microphone's self-noise); exact zeros between sounds (a noise gate, padding) "
            "would make it 0. An integer WAV's step raises it"),
    [AF_SETTING_HAMMER_HEALTH_WINDOW] =
        WHOLE("hammer_health_window", "20",
              "[2, " HEALTH_STR(AF_SETTINGS_HEALTH_WINDOW_MAX) "] strikes", S,
              "hammer health: the statistics and checks are taken over this many latest "
              "measured strikes"),
    [AF_SETTING_HAMMER_HEALTH_MIN_STRIKES] =
        WHOLE("hammer_health_min_strikes", "10",
              "[1, " HEALTH_STR(AF_SETTINGS_HEALTH_WINDOW_MAX) "] strikes", S,
              "hammer health: no check before this many strikes (clean ones for the velocity), "
              "at most hammer_health_window; the first ones also set the baseline reference"),
    [AF_SETTING_HAMMER_HEALTH_VELOCITY_BAND] =
        NUM("hammer_health_velocity_band", "0.03", "(0, 1]", S,
            "hammer health: warn when the window's mean contact velocity from the impulse is "
            "further than this fraction from strike_velocity_m_s"),
    [AF_SETTING_HAMMER_HEALTH_BASELINE_DRIFT_N] =
        NUM("hammer_health_baseline_drift_n", "5.0", "(0, 1e6] N", S,
            "hammer health: warn when the window's mean force baseline has moved further than "
            "this from the first strikes' (1 % of the default strike_full_scale_n)"),
    [AF_SETTING_HAMMER_HEALTH_CLIP_RATE] =
        NUM("hammer_health_clip_rate", "0.05", "[0, 1]", S,
            "hammer health: warn when more than this fraction of the window's strikes clipped"),
    [AF_SETTING_MODULUS_FACTOR_LEARN_WINDOW] =
        WHOLE("modulus_factor_learn_window", "200", "[5, 10000]", S,
              "the learned modulus factor is the median of E(0S2) / fitted E2 x the factor in "
              "use over this many newest reliable strikes"),
    [AF_SETTING_MODULUS_FACTOR_LEARN_MIN_STRIKES] =
        WHOLE("modulus_factor_learn_min_strikes", "30", "[3, 10000]", S,
              "reliable strikes before there is an estimate (at most "
              "modulus_factor_learn_window)"),
    [AF_SETTING_MODULUS_FACTOR_LEARN_APPLY] =
        BOOLEAN("modulus_factor_learn_apply", "false", S,
                "the learned factor replaces the cultivar's modulus_factor for the following "
                "strikes (each change logged); false = only published"),
    [AF_SETTING_MODULUS_FACTOR_LEARN_MIN_CHANGE] =
        NUM("modulus_factor_learn_min_change", "0.01", "[0, 0.5]", S,
            "relative change of the learned factor from the applied one before it is applied "
            "(hysteresis)"),
    [AF_SETTING_CULTIVAR] = STRING("cultivar", "Jonagold", AF_SETTINGS_NAME_MAX - 1, C,
                                   "cultivar name, for the diagnostics"),
    [AF_SETTING_MODULUS_NOMINAL_PA] = NUM("modulus_nominal_pa", "8.0e+6", "[1e5, 1e9] Pa", C,
                                          "E2 of the prediction, within [modulus_min_pa, "
                                          "modulus_max_pa]"),
    [AF_SETTING_MODULUS_MIN_PA] =
        NUM("modulus_min_pa", "2.0e+6", "[1e5, 1e9] Pa", C, "softest fruit expected"),
    [AF_SETTING_FRUIT_Q_MIN] =
        NUM("fruit_q_min", "5.0", "[0.5, 1e4]", C,
            "the 0S2 of fruit flesh rings at least this Q (pi f / decay rate): a duller sound "
            "is not the fruit's free mode (a calibration: doc/tap_only.md)"),
    [AF_SETTING_FRUIT_Q_MAX] =
        NUM("fruit_q_max", "80.0", "[0.5, 1e4]", C,
            "and at most this Q: a ring beyond it is an object (ceramic, glass, a fixture), not "
            "fruit flesh, and is never graded (a calibration: doc/tap_only.md)"),
    [AF_SETTING_FRUIT_CONFIDENCE_MIN] = NUM(
        "fruit_confidence_min", "0.05", "[0, 1]", C,
        "the 0S2's identification must reach this confidence (modes.h: the posterior of the "
        "chosen peak) to be graded; 0.05 refuses a choice split among peaks and passes a lone "
        "peak anywhere in the range; 0.5 asks a tap-only strike for its comb (doc/tap_only.md)"),
    [AF_SETTING_FRUIT_NEIGHBOUR_MARGIN_DB] =
        NUM("fruit_neighbour_margin_db", "6.0", "[0, 60] dB", C,
            "tap-only: a peak 1.2 to 2.1 times the 0S2, within this of its SNR or louder, that "
            "no mode of the sphere explains while none of the sphere's is heard there, is "
            "another object's partial: not fruit (doc/tap_only.md)"),
    [AF_SETTING_MODULUS_MAX_PA] =
        NUM("modulus_max_pa", "12.0e+6", "[1e5, 1e9] Pa", C, "firmest fruit expected"),
    [AF_SETTING_MASS_MIN_KG] =
        NUM("mass_min_kg", "0.100", "[0.001, 10] kg", C, "lighter AppleEstimates are refused"),
    [AF_SETTING_MASS_MAX_KG] =
        NUM("mass_max_kg", "0.250", "[0.001, 10] kg", C, "heavier AppleEstimates are refused"),
    [AF_SETTING_EQUATORIAL_RADIUS_MIN_M] =
        NUM("equatorial_radius_min_m", "0.025", "[0.002, 1] m", C,
            "smallest accepted "
            "AppleEstimate.equatorial_radius"),
    [AF_SETTING_EQUATORIAL_RADIUS_MAX_M] =
        NUM("equatorial_radius_max_m", "0.060", "[0.002, 1] m", C,
            "largest accepted "
            "AppleEstimate.equatorial_radius"),
    [AF_SETTING_ASPECT_RATIO_MIN] = NUM("aspect_ratio_min", "0.5", "[0.1, 10]", C,
                                        "smallest polar / equatorial semi-axis implied by mass, "
                                        "density and radius"),
    [AF_SETTING_ASPECT_RATIO_MAX] =
        NUM("aspect_ratio_max", "1.5", "[0.1, 10]", C, "largest polar / equatorial semi-axis"),
    [AF_SETTING_RESTITUTION] = NUM("restitution", "0.6", "[0.01, 1]", C,
                                   "coefficient of restitution e (the exact damping law needs "
                                   "e >= 0.05)"),
    [AF_SETTING_FRUIT_POISSON] =
        NUM("fruit_poisson", "0.35", "[0, 0.5)", C, "Poisson ratio of the flesh"),
    [AF_SETTING_DENSITY_KG_M3] =
        NUM("density_kg_m3", "840.0", "[100, 3000] kg/m3", C, "density of the fruit"),
    [AF_SETTING_YIELD_RATIO] = NUM("yield_ratio", "0.0414", "[0.001, 1]", C,
                                   "yield law tau_y = yield_ratio E_ref (E2/E_ref)^p: "
                                   "tau_y / E2 at E_ref, a calibration (doc/paper.md)"),
    [AF_SETTING_YIELD_EXPONENT] = NUM("yield_exponent", "0.70", "[0, 3]", C,
                                      "p of the yield law; 1 = the ratio law tau_y = "
                                      "yield_ratio E2"),
    [AF_SETTING_YIELD_REFERENCE_MODULUS_PA] =
        NUM("yield_reference_modulus_pa", "8.0e+6", "[1e5, 1e9] Pa", C, "E_ref of the yield law"),
    [AF_SETTING_YIELD_MEASURED] =
        STRING("yield_measured", "\"\"", AF_SETTINGS_TEXT_MAX - 1, C,
               "measured yield shear stress \"E2:tau_y, ...\" [Pa], overriding the law; "
               "\"\" = the law"),
    [AF_SETTING_MODULUS_FACTOR] = NUM("modulus_factor", "1.0", "[0.1, 10]", C,
                                      "dynamic / quasi-static modulus for the 0S2 resonance "
                                      "(a calibration)"),
    [AF_SETTING_GRADE_QUANTITY] =
        CHOICE("grade_quantity", "stiffness_factor",
               "stiffness_factor, modulus_from_resonance, fitted_modulus", C,
               "what the firmness classes are read on (StrikeReport's figure of that name)"),
    [AF_SETTING_GRADE_CLASSES] = STRING(
        "grade_classes", "\"soft | 7.0e+4 | medium | 1.1e+5 | firm | 1.6e+5 | very firm\"", 400, C,
        "firmness classes, softest first, with the boundary between neighbours in "
        "grade_quantity's unit (grade.h); \"\" = no grading"),
    [AF_SETTING_BRUISE_ENERGY_J] =
        NUM("bruise_energy_j", "0.05", "[0.0001, 10] J", C,
            "the second damage reading: a strike whose absorbed energy (1 - e^2) m1 v0^2 / 2 "
            "reaches this bruises; a calibration (doc/model.md), shown beside the shear "
            "criterion, which stays the verdict"),
};

#undef S
#undef C

/* ---- rows and ranges ------------------------------------------------------- */

const af_setting_def *af_setting_def_of(af_setting_id id)
{
  return setting_valid_id(id) ? &af_setting_rows[id] : NULL;
}

af_status af_setting_find(const char *name, af_setting_id *id)
{
  if (name == NULL || id == NULL)
    return AF_EINVAL;
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    if (af_setting_rows[k].name != NULL && strcmp(af_setting_rows[k].name, name) == 0) {
      *id = (af_setting_id)k;
      return AF_OK;
    }
  return AF_EINVAL;
}

/* "(lo, hi] unit" or "0 or [lo, hi] unit": the interval and where the unit
 * starts. */
bool af_setting_parse_range(const char *text, af_setting_range *r, const char **unit)
{
  static const char zero_or[] = "0 or ";
  r->zero = text != NULL && strncmp(text, zero_or, sizeof zero_or - 1) == 0;
  if (r->zero)
    text += sizeof zero_or - 1;
  if (text == NULL || (text[0] != '(' && text[0] != '['))
    return false;
  r->lo_open = text[0] == '(';
  char *end;
  r->lo = strtod(text + 1, &end);
  if (end == text + 1 || *end != ',')
    return false;
  const char *p = end + 1;
  while (*p == ' ')
    p++;
  r->hi = strtod(p, &end);
  if (end == p || (*end != ')' && *end != ']') || isnan(r->lo) || isnan(r->hi) || !(r->lo <= r->hi))
    return false;
  r->hi_open = *end == ')';
  p = end + 1;
  if (*p == ' ' && p[1] != '\0' && p[1] != ' ')
    p++;
  else if (*p != '\0')
    return false;
  if (unit)
    *unit = p;
  return true;
}

af_status af_setting_range_of(af_setting_id id, af_setting_range *out)
{
  if (!setting_valid_id(id) || out == NULL || af_setting_rows[id].range == NULL)
    return AF_EINVAL;
  return af_setting_parse_range(af_setting_rows[id].range, out, NULL) ? AF_OK : AF_EINVAL;
}

bool af_setting_range_contains(const af_setting_range *r, double v)
{
  if (r == NULL || !isfinite(v))
    return false;
  if (r->zero && v == 0.0)
    return true;
  if (r->lo_open ? !(v > r->lo) : !(v >= r->lo))
    return false;
  return r->hi_open ? v < r->hi : v <= r->hi;
}

double af_setting_rig_value(af_setting_id id)
{
  return setting_valid_id(id) && af_setting_rows[id].rig != NULL
             ? strtod(af_setting_rows[id].rig, NULL)
             : NAN;
}

const char *af_setting_unit(af_setting_id id)
{
  af_setting_range r;
  const char *unit = "";
  if (setting_valid_id(id) && af_setting_rows[id].range != NULL &&
      af_setting_parse_range(af_setting_rows[id].range, &r, &unit))
    return unit;
  return "";
}

af_status af_setting_choice_word(af_setting_id id, size_t k, char *buf, size_t len)
{
  if (!setting_valid_id(id) || af_setting_rows[id].kind != AF_SETTING_CHOICE || buf == NULL ||
      len == 0)
    return AF_EINVAL;
  const char *p = af_setting_rows[id].choices;
  for (size_t i = 0; i < k; i++) {
    p = strchr(p, ',');
    if (p == NULL)
      return AF_EINVAL;
    p += 2; /* ", " */
  }
  size_t n = strcspn(p, ",");
  if (n >= len)
    return AF_EINVAL;
  memcpy(buf, p, n);
  buf[n] = '\0';
  return AF_OK;
}
