/* test_verdict.c — the reasons of an unreliable strike (verdict.h) against
 * hand-written wording: af_verdict_clear, each flag alone with hand-chosen
 * values, every audio cause, the "; " order of several flags, the criteria
 * flags at and around their boundaries (worded by criteria.h), the flag
 * names, and a reason cut to a short buffer. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "verdict.h"

static int says(const af_verdict *v, const char *expected)
{
  char buf[1024];
  memset(buf, '#', sizeof buf);
  af_verdict_format(v, buf, sizeof buf);
  if (strcmp(buf, expected) != 0) {
    fprintf(stderr, "  verdict 0x%x: got '%s'\n  expected '%s'\n", v->flags, buf, expected);
    return 0;
  }
  return 1;
}

static af_verdict with(uint32_t flags)
{
  af_verdict v;
  af_verdict_clear(&v);
  v.flags = flags;
  return v;
}

static void test_clear(void)
{
  af_verdict v;
  memset(&v, 0x5a, sizeof v);
  af_verdict_clear(&v);
  AF_CHECK(v.flags == 0 && v.apple_id == 0 && v.lost_samples == 0 && v.lobe == 0);
  AF_CHECK(v.apple_why[0] == '\0' && v.mode_text[0] == '\0');
  AF_CHECK(isnan(v.fit_residual) && isnan(v.snr_db) && isnan(v.resonance_hz));
  AF_CHECK(isnan(v.band_low_hz) && isnan(v.max_shear_pa) && isnan(v.audio_seconds));
  AF_CHECK(v.measure_status == AF_OK && v.audio_cause == AF_AUDIO_NOT_GIVEN);
  AF_CHECK(says(&v, "")); /* no flag: reliable, no words */
}

static void test_station_flags(void)
{
  af_verdict v = with(AF_VERDICT_NO_APPLE);
  v.apple_stale_s = 0.5;
  AF_CHECK(says(&v, "no apple estimate within 0.5 s before the strike"));
  v = with(AF_VERDICT_NO_PREDICTION);
  v.apple_id = 17;
  strcpy(v.apple_why, "invalid AppleEstimate: mass = -1 kg");
  AF_CHECK(says(&v, "apple 17 got no prediction: invalid AppleEstimate: mass = -1 kg"));
  v = with(AF_VERDICT_APPLE_DOUBTFUL);
  v.apple_id = 4;
  strcpy(v.doubtful_why, "struck twice");
  AF_CHECK(says(&v, "doubtful apple match (apple 4: struck twice)"));
  /* A line: the transit window, and the estimate nearest the strike. */
  v = with(AF_VERDICT_NO_APPLE);
  v.apple_transit_s = 0.2;
  v.apple_tolerance_s = 0.04;
  AF_CHECK(says(&v, "no apple estimate stamped 0.2 +- 0.04 s before the strike"));
  v.nearest_apple_id = 9;
  v.nearest_apple_lag_s = -0.05;
  AF_CHECK(says(&v, "no apple estimate stamped 0.2 +- 0.04 s before the strike (the nearest, "
                    "apple 9, is stamped 0.050 s after it)"));
  v = with(AF_VERDICT_CLOCK_FAULT);
  strcpy(v.clock_why, "force clock stepped +0.3 s");
  AF_CHECK(says(&v, "judged across a clock fault, not the fruit's: force clock stepped +0.3 s"));
}

static void test_rig_flags(void)
{
  af_verdict v = with(AF_VERDICT_AUDIO_CLIPPED);
  v.audio_clip_samples = 60;
  v.audio_clip_tops = 12;
  v.audio_clip_max = 0.3;
  v.audio_clip_min = -0.3;
  AF_CHECK(says(&v, "microphone clipped (60 samples at its extremes 0.3 and -0.3, 12 flat tops): "
                    "lower the microphone gain"));
  v = with(AF_VERDICT_NOT_FRUIT);
  v.resonance_q = 295.0;
  v.resonance_hz = 478.0;
  v.fruit_q_min = 5.0;
  v.fruit_q_max = 100.0;
  v.not_fruit = AF_NOT_FRUIT_Q;
  AF_CHECK(says(&v, "Q 295 at 478 Hz: a ringing object, not fruit flesh (fruit_q_min..fruit_q_max "
                    "5..100)"));
  v.resonance_q = 2.0;
  AF_CHECK(
      says(&v, "Q 2 at 478 Hz: a dull thud, not fruit flesh (fruit_q_min..fruit_q_max 5..100)"));
  v.not_fruit = AF_NOT_FRUIT_NEIGHBOURS | AF_NOT_FRUIT_CONFIDENCE;
  v.stray_hz = 621.4;
  v.stray_db = 3.2;
  v.mode_confidence = 0.031;
  v.fruit_confidence_min = 0.05;
  AF_CHECK(says(&v, "a partial at 1.30x the 478 Hz mode (+3 dB), none of the sphere's: not fruit; "
                    "0S2 478 Hz at confidence 0.03, below fruit_confidence_min 0.05"));
  v = with(AF_VERDICT_DOUBLE_HIT);
  v.bounce_impulse_excess = 0.2;
  AF_CHECK(says(&v, "double hit (a second impact inside the contact: the impulse is 20 % above "
                    "the hammer's recent strikes, beyond their spread)"));
}

static void test_pulse_flags(void)
{
  af_verdict v = with(AF_VERDICT_MEASURE_FAILED);
  v.measure_status = AF_ENODATA;
  AF_CHECK(says(&v, "measurement failed: not enough signal"));
  AF_CHECK(says(&(af_verdict){.flags = AF_VERDICT_DOUBLE_HIT}, "double hit"));
  AF_CHECK(says(&(af_verdict){.flags = AF_VERDICT_CLIPPED}, "clipped at full scale"));
  v = with(AF_VERDICT_LOST_SAMPLES);
  v.lost_samples = 12345678901ULL; /* beyond 32 bits */
  AF_CHECK(says(&v, "12345678901 samples lost"));
  AF_CHECK(says(&(af_verdict){.flags = AF_VERDICT_TRUNCATED}, "contact truncated"));
  v = with(AF_VERDICT_SPECTRUM_FAILED);
  v.spectrum_status = AF_ENOLOBE;
  AF_CHECK(says(&v, "excitation spectrum failed: requested spectral lobe does not exist"));
  /* The fit's own words per status, with the residual when it ran. */
  v = with(AF_VERDICT_FIT_FAILED);
  v.fit_status = AF_ENOCONV;
  AF_CHECK(says(&v, "fit failed: not converged"));
  v.fit_residual = 0.237;
  AF_CHECK(says(&v, "fit failed: not converged (residual 24 % of the peak)"));
  v.fit_residual = NAN;
  v.fit_status = AF_EINVAL;
  AF_CHECK(says(&v, "fit failed: pulse too short or not finite"));
  v.fit_status = AF_ESIZE;
  AF_CHECK(says(&v, "fit failed: pulse longer than the fit's max_samples"));
  v.fit_status = AF_ENODATA;
  AF_CHECK(says(&v, "fit failed: the model does not explain the pulse"));
  v.fit_status = AF_ENUMERIC;
  AF_CHECK(says(&v, "fit failed: numerical failure"));
  v.fit_status = AF_EBUDGET_FIT_ITER; /* others: the status string */
  AF_CHECK(says(&v, "fit failed: fit iteration budget exhausted"));
  v = with(AF_VERDICT_POISSON);
  v.judge_status = AF_ENOROOT;
  AF_CHECK(says(&v, "Poisson ratio: no root in the searched bracket"));
}

static void test_audio_causes(void)
{
  af_verdict v = with(AF_VERDICT_NO_AUDIO);
  v.audio_first = 1000;
  v.audio_last = 5095;
  v.audio_end = 900;
  v.n_audio = 37;
  v.queue_size = 8;
  v.audio_seconds = 0.25;
  v.audio_cause = AF_AUDIO_NOT_GIVEN;
  AF_CHECK(says(&v, "no audio"));
  v.audio_cause = AF_AUDIO_TOO_SHORT;
  AF_CHECK(says(&v, "no audio (37 samples)"));
  v.audio_cause = AF_AUDIO_NONE_RECEIVED;
  AF_CHECK(says(&v, "no audio (no audio chunk received within 0.25 s of the strike)"));
  v.audio_cause = AF_AUDIO_STREAM_STALE;
  AF_CHECK(says(&v, "no audio (audio stream stale (silent for more than 0.25 s))"));
  v.audio_cause = AF_AUDIO_BEFORE_STREAM;
  AF_CHECK(says(&v, "no audio (audio window starts 0.2500 s before the audio stream's first "
                    "sample)"));
  v.audio_cause = AF_AUDIO_NOT_RECEIVED;
  AF_CHECK(says(&v, "no audio (audio window (samples 1000..5095) not received within 0.25 s of "
                    "the strike (audio at sample 900))"));
  v.audio_cause = AF_AUDIO_LEFT_RING;
  AF_CHECK(says(&v, "no audio (audio window (sample 1000) no longer in the 0.25 s audio ring)"));
  v.audio_cause = AF_AUDIO_UNREADABLE;
  AF_CHECK(
      says(&v, "no audio (audio window (samples 1000..5095) could not be read from the ring)"));
  v.audio_cause = AF_AUDIO_LOST_IN_WINDOW;
  AF_CHECK(says(&v, "no audio (audio window holds 37 lost samples)"));
  v.audio_cause = AF_AUDIO_QUEUE_FULL;
  AF_CHECK(says(&v, "no audio (strike queue full (8 strikes waiting for audio))"));
  v.audio_cause = AF_AUDIO_STREAM_ENDED;
  AF_CHECK(says(&v, "no audio (the audio recording ends at sample 900, before the window "
                    "1000..5095)"));

  /* The causes' names, without values. */
  AF_CHECK(strcmp(af_audio_cause_name(AF_AUDIO_NOT_GIVEN), "no audio given") == 0);
  AF_CHECK(strcmp(af_audio_cause_name(AF_AUDIO_STREAM_STALE), "audio stream stale") == 0);
  AF_CHECK(strcmp(af_audio_cause_name(AF_AUDIO_QUEUE_FULL), "strike queue full") == 0);
  AF_CHECK(strcmp(af_audio_cause_name(AF_AUDIO_STREAM_ENDED),
                  "recording ends before the audio window") == 0);
  AF_CHECK(strcmp(af_audio_cause_name((af_audio_cause)99), "unknown") == 0);
  for (int a = AF_AUDIO_NOT_GIVEN; a <= AF_AUDIO_REFUSED_IN_WINDOW; a++)
    for (int b = AF_AUDIO_NOT_GIVEN; b < a; b++)
      AF_CHECK(strcmp(af_audio_cause_name((af_audio_cause)a),
                      af_audio_cause_name((af_audio_cause)b)) != 0);
}

static void test_audio_flags(void)
{
  af_verdict v = with(AF_VERDICT_NO_RESONANCE);
  v.snr_threshold_db = 10.0;
  v.snr_db = 7.46;
  v.f_lo_hz = 598.7;
  v.f_hi_hz = 1401.2;
  AF_CHECK(says(&v, "no 0S2 resonance above the SNR threshold (10 dB; best 7.5 dB in [599, "
                    "1401] Hz)"));
  v.snr_db = -INFINITY; /* no candidate at all */
  AF_CHECK(says(&v, "no 0S2 resonance above the SNR threshold (10 dB; silence in [599, 1401] Hz)"));
  v.snr_db = NAN;
  AF_CHECK(says(&v, "no 0S2 resonance above the SNR threshold (10 dB; silence in [599, 1401] Hz)"));
  /* a resonance just outside the range: named with the E2 it implies */
  v.outside_hz = 1650.4;
  v.outside_snr_db = 31.2;
  v.outside_modulus_pa = 16.64e6;
  v.modulus_min_pa = 4e6;
  v.modulus_max_pa = 12.5e6;
  AF_CHECK(says(&v, "a 31 dB peak at 1650 Hz lies above the cultivar's 0S2 range [599, 1401] Hz: "
                    "E2 16.6 MPa by Lamb, outside modulus_min_pa..modulus_max_pa 4..12.5 MPa"));
  v.outside_hz = 550.0;
  v.outside_modulus_pa = 3.5e6;
  AF_CHECK(says(&v, "a 31 dB peak at 550 Hz lies below the cultivar's 0S2 range [599, 1401] Hz: "
                    "E2 3.5 MPa by Lamb, outside modulus_min_pa..modulus_max_pa 4..12.5 MPa"));
  v.outside_hz = v.outside_snr_db = v.outside_modulus_pa = NAN;
  v.flags = AF_VERDICT_RANGE_NYQUIST;
  AF_CHECK(says(&v, "0S2 range [599, 1401] Hz beyond the audio's Nyquist frequency"));
  v.flags = AF_VERDICT_AUDIO_FAILED;
  v.audio_status = AF_ENOMEM;
  AF_CHECK(says(&v, "audio analysis failed: out of memory"));
  v.flags = AF_VERDICT_MODE_AMBIGUOUS;
  strcpy(v.mode_text, "ambiguous 0S2: 850 Hz or 990 Hz");
  AF_CHECK(says(&v, "ambiguous 0S2: 850 Hz or 990 Hz"));
}

/* The criteria flags: only the set ones are worded, whatever the values. */
static void test_criteria_flags(void)
{
  af_verdict v = with(AF_VERDICT_OUTSIDE_BAND);
  v.lobe = 1;
  v.band_low_hz = 612.4;
  v.band_high_hz = 1187.6;
  v.resonance_hz = 1250.0;
  v.max_shear_pa = 0.9e6; /* above the yield, but DAMAGE is not set */
  v.yield_shear_pa = 0.3312e6;
  AF_CHECK(says(&v, "resonance 1250 Hz outside the half-power band [612, 1188] Hz of lobe 1"));
  /* Just outside each edge (what the measurement flags): still worded. */
  v.resonance_hz = nextafter(612.4, 0.0);
  AF_CHECK(says(&v, "resonance 612 Hz outside the half-power band [612, 1188] Hz of lobe 1"));
  /* A flag with a value that meets the criterion after all gives no words
   * for it: the format does not invent a reason. */
  v.resonance_hz = 612.4;
  AF_CHECK(says(&v, ""));
  v = with(AF_VERDICT_DAMAGE);
  v.resonance_hz = 5000.0; /* outside any band, but OUTSIDE_BAND is not set */
  v.max_shear_pa = 0.3312e6;
  v.yield_shear_pa = 0.3312e6;
  AF_CHECK(says(&v, "max shear 0.331 MPa not below yield 0.331 MPa (bruise risk)"));
  v.max_shear_pa = nextafter(0.3312e6, 0.0); /* below the yield: no damage words */
  AF_CHECK(says(&v, ""));
  v = with(AF_VERDICT_NO_LOBE | AF_VERDICT_DAMAGE);
  v.lobe = 2;
  v.max_shear_pa = 0.5e6;
  v.yield_shear_pa = 0.25e6;
  AF_CHECK(says(&v, "spectrum has no lobe 2; max shear 0.500 MPa not below yield 0.250 MPa "
                    "(bruise risk)"));
}

static void test_order_and_cut(void)
{
  /* Or-ed in reverse: worded in flag order, "; "-separated. */
  af_verdict v = with(AF_VERDICT_DAMAGE | AF_VERDICT_NO_AUDIO | AF_VERDICT_TRUNCATED |
                      AF_VERDICT_DOUBLE_HIT | AF_VERDICT_NO_APPLE);
  v.apple_stale_s = 1.0;
  v.audio_cause = AF_AUDIO_NOT_GIVEN;
  v.max_shear_pa = 0.4e6;
  v.yield_shear_pa = 0.3e6;
  AF_CHECK(says(&v, "no apple estimate within 1 s before the strike; double hit; contact "
                    "truncated; no audio; max shear 0.400 MPa not below yield 0.300 MPa (bruise "
                    "risk)"));
  /* Into 20 bytes: cut, NUL-terminated, nothing written past it. */
  char buf[32];
  memset(buf, '#', sizeof buf);
  af_verdict_format(&v, buf, 20);
  AF_CHECK(strlen(buf) == 19 && strncmp(buf, "no apple estimate w", 19) == 0);
  AF_CHECK(buf[20] == '#');
  /* Every cut length keeps the text a prefix of the whole and inside len. */
  char whole[512];
  af_verdict_format(&v, whole, sizeof whole);
  int all_prefix = 1;
  for (size_t len = 1; len < strlen(whole) + 2; len++) {
    char cut[512];
    memset(cut, '#', sizeof cut);
    af_verdict_format(&v, cut, len);
    size_t n = 0;
    while (n < sizeof cut && cut[n] != '\0')
      n++;
    if (n >= len || strncmp(cut, whole, n) != 0 || cut[len] != '#') {
      fprintf(stderr, "  cut at %zu: '%.*s'\n", len, (int)len, cut);
      all_prefix = 0;
    }
  }
  AF_CHECK(all_prefix);
  /* NULL verdict: "", NULL or empty buffer: nothing. */
  buf[0] = '#';
  af_verdict_format(NULL, buf, sizeof buf);
  AF_CHECK(buf[0] == '\0');
  buf[0] = '#';
  af_verdict_format(&v, buf, 0);
  AF_CHECK(buf[0] == '#');
  af_verdict_format(&v, NULL, 8); /* no crash */
}

static void test_flag_names(void)
{
  static const char *const names[] = {
      "no_apple",       "no_prediction", "apple_doubtful", "measure_failed",  "double_hit",
      "clipped",        "lost_samples",  "truncated",      "spectrum_failed", "fit_failed",
      "poisson",        "no_audio",      "no_resonance",   "range_nyquist",   "audio_failed",
      "mode_ambiguous", "no_lobe",       "outside_band",   "damage",          "refused_samples",
      "audio_clipped",  "clock_fault",   "not_fruit"};
  for (unsigned k = 0; k < sizeof names / sizeof names[0]; k++)
    AF_CHECK(strcmp(af_verdict_flag_name((af_verdict_flag)(1u << k)), names[k]) == 0);
  AF_CHECK(strcmp(af_verdict_flag_name((af_verdict_flag)(1u << 23)), "unknown") == 0);
  AF_CHECK(strcmp(af_verdict_flag_name((af_verdict_flag)0), "unknown") == 0);
  AF_CHECK(strcmp(af_verdict_flag_name((af_verdict_flag)3), "unknown") == 0); /* two bits */
}

int main(void)
{
  test_rig_flags();
  test_clear();
  test_station_flags();
  test_pulse_flags();
  test_audio_causes();
  test_audio_flags();
  test_criteria_flags();
  test_order_and_cut();
  test_flag_names();
  return af_test_summary("test_verdict");
}
