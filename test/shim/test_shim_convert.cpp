// test_shim_convert.cpp — the C struct <-> ROS message conversions of the shim
// (convert.hpp), every field both ways, without a ROS master: each test
// fills one side with distinct values, converts, checks every field of the
// other side, and converts back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "convert.hpp"

namespace
{

// Fills a C struct with a byte pattern, so that a field the conversion
// forgets shows up as garbage rather than as a lucky zero.
template <class C> void poison(C &c)
{
  std::memset(static_cast<void *>(&c), 0xA5, sizeof c);
}

af_header c_header(uint32_t sec, uint32_t nsec, const char *frame)
{
  af_header h;
  poison(h);
  h.stamp.sec = sec;
  h.stamp.nsec = nsec;
  std::snprintf(h.frame_id, sizeof h.frame_id, "%s", frame);
  return h;
}

void expect_header(const std_msgs::Header &m, uint32_t sec, uint32_t nsec, const char *frame)
{
  EXPECT_EQ(m.stamp.sec, sec);
  EXPECT_EQ(m.stamp.nsec, nsec);
  EXPECT_EQ(m.frame_id, frame);
}

void expect_header(const af_header &c, uint32_t sec, uint32_t nsec, const char *frame)
{
  EXPECT_EQ(c.stamp.sec, sec);
  EXPECT_EQ(c.stamp.nsec, nsec);
  EXPECT_STREQ(c.frame_id, frame);
}

} // namespace

TEST(Header, BothWaysAndTruncation)
{
  const af_header c = c_header(1700000000u, 999999999u, "camera_optical_frame");
  std_msgs::Header m;
  af_shim::to_ros(c, m);
  expect_header(m, 1700000000u, 999999999u, "camera_optical_frame");

  af_header back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back, 1700000000u, 999999999u, "camera_optical_frame");

  // A frame_id longer than the C array is cut at AF_FRAME_ID_MAX - 1.
  m.frame_id = std::string(100, 'f');
  af_shim::from_ros(m, back);
  EXPECT_EQ(std::strlen(back.frame_id), static_cast<size_t>(AF_FRAME_ID_MAX - 1));
  EXPECT_EQ(std::string(back.frame_id), std::string(AF_FRAME_ID_MAX - 1, 'f'));

  // Exactly AF_FRAME_ID_MAX - 1 characters fit whole.
  m.frame_id = std::string(AF_FRAME_ID_MAX - 1, 'g');
  af_shim::from_ros(m, back);
  EXPECT_EQ(std::string(back.frame_id), m.frame_id);

  // A C array without its NUL is read up to its end, not beyond.
  af_header full = c;
  std::memset(full.frame_id, 'h', sizeof full.frame_id);
  af_shim::to_ros(full, m);
  EXPECT_EQ(m.frame_id, std::string(AF_FRAME_ID_MAX, 'h'));
}

TEST(SignalChunk, CToRos)
{
  const float data[5] = {0.5f, -1.25f, 3.0f, 1e-3f, -7.5f};
  af_signal_chunk c;
  poison(c);
  c.header = c_header(12u, 345u, "force_transducer");
  c.first_sample = 12345678901234ull;
  c.sample_rate_hz = 51200.0;
  std::snprintf(c.unit, sizeof c.unit, "N");
  c.data = data;
  c.n = 5;

  acoustic_firmness::SignalChunk m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 12u, 345u, "force_transducer");
  EXPECT_EQ(m.first_sample, 12345678901234ull);
  EXPECT_EQ(m.sample_rate, 51200.0);
  EXPECT_EQ(m.unit, "N");
  ASSERT_EQ(m.data.size(), 5u);
  for (size_t i = 0; i < 5; i++)
    EXPECT_EQ(m.data[i], data[i]);

  // The message is reused by the publisher: a shorter chunk replaces the
  // data, an empty one (data may then be NULL) clears it.
  c.n = 2;
  af_shim::to_ros(c, m);
  EXPECT_EQ(m.data.size(), 2u);
  c.data = nullptr;
  c.n = 0;
  af_shim::to_ros(c, m);
  EXPECT_TRUE(m.data.empty());

  // n > 0 without data cannot be published.
  c.n = 3;
  EXPECT_THROW(af_shim::to_ros(c, m), std::invalid_argument);
}

TEST(SignalChunk, RosToCBorrowsData)
{
  acoustic_firmness::SignalChunk m;
  m.header.stamp = ros::Time(7, 8);
  m.header.frame_id = "microphone";
  m.first_sample = 42;
  m.sample_rate = 44100.0;
  m.unit = "Pa";
  m.data = {1.0f, 2.0f, 3.0f};

  af_signal_chunk c;
  poison(c);
  af_shim::from_ros(m, c);
  expect_header(c.header, 7u, 8u, "microphone");
  EXPECT_EQ(c.first_sample, 42u);
  EXPECT_EQ(c.sample_rate_hz, 44100.0);
  EXPECT_STREQ(c.unit, "Pa");
  // Borrowed, not copied: the very storage of the message.
  EXPECT_EQ(c.data, m.data.data());
  EXPECT_EQ(c.n, 3u);

  // And back to ROS, for the round trip.
  acoustic_firmness::SignalChunk again;
  af_shim::to_ros(c, again);
  EXPECT_EQ(again.header.frame_id, "microphone");
  EXPECT_EQ(again.first_sample, 42u);
  EXPECT_EQ(again.unit, "Pa");
  EXPECT_EQ(again.data, m.data);

  // A unit longer than AF_UNIT_MAX - 1 is cut.
  m.unit = "Pa (calibrated, A-weighted)";
  af_shim::from_ros(m, c);
  EXPECT_EQ(std::string(c.unit), m.unit.substr(0, AF_UNIT_MAX - 1));

  // A NUL inside the unit is shown as '?', never an early end: "N\0x" is
  // not the unit "N".
  m.unit = std::string("N\0x", 3);
  af_shim::from_ros(m, c);
  EXPECT_STREQ(c.unit, "N?x");
  m.header.frame_id = std::string("mic\0rophone", 11);
  af_shim::from_ros(m, c);
  EXPECT_STREQ(c.header.frame_id, "mic?rophone");

  // No samples: NULL and 0.
  m.data.clear();
  af_shim::from_ros(m, c);
  EXPECT_EQ(c.data, nullptr);
  EXPECT_EQ(c.n, 0u);
}

TEST(AppleEstimate, BothWays)
{
  af_apple_estimate c;
  poison(c);
  c.header = c_header(100u, 200u, "camera_optical_frame");
  c.apple_id = 4000000000u;
  c.mass_kg = 0.182;
  c.equatorial_radius_m = 0.0375;
  c.strike_radius_m = 0.041;
  c.stem_axis = af_vec3{0.1, -0.2, 0.97};
  c.confidence = 0.87;

  acoustic_firmness::AppleEstimate m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 100u, 200u, "camera_optical_frame");
  EXPECT_EQ(m.apple_id, 4000000000u);
  EXPECT_EQ(m.mass, 0.182);
  EXPECT_EQ(m.equatorial_radius, 0.0375);
  EXPECT_EQ(m.strike_radius, 0.041);
  EXPECT_EQ(m.stem_axis.x, 0.1);
  EXPECT_EQ(m.stem_axis.y, -0.2);
  EXPECT_EQ(m.stem_axis.z, 0.97);
  EXPECT_EQ(m.confidence, 0.87);

  af_apple_estimate back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back.header, 100u, 200u, "camera_optical_frame");
  EXPECT_EQ(back.apple_id, 4000000000u);
  EXPECT_EQ(back.mass_kg, 0.182);
  EXPECT_EQ(back.equatorial_radius_m, 0.0375);
  EXPECT_EQ(back.strike_radius_m, 0.041);
  EXPECT_EQ(back.stem_axis.x, 0.1);
  EXPECT_EQ(back.stem_axis.y, -0.2);
  EXPECT_EQ(back.stem_axis.z, 0.97);
  EXPECT_EQ(back.confidence, 0.87);
}

TEST(ExcitationBand, BothWays)
{
  af_excitation_band c;
  poison(c);
  c.header = c_header(1u, 2u, "rig_base");
  c.apple_id = 17;
  c.contact_time_s = 2.4e-4;
  c.peak_force_n = 23.5;
  c.lobe = 2;
  c.band_low_hz = 310.0;
  c.band_high_hz = 2950.0;
  c.resonance_hz = 1250.0;
  c.resonance_low_hz = 900.0;
  c.resonance_high_hz = 1600.0;
  c.excitation_at_resonance_db = -4.5;

  acoustic_firmness::ExcitationBand m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 1u, 2u, "rig_base");
  EXPECT_EQ(m.apple_id, 17u);
  EXPECT_EQ(m.contact_time, 2.4e-4);
  EXPECT_EQ(m.peak_force, 23.5);
  EXPECT_EQ(m.lobe, 2u);
  EXPECT_EQ(m.band_low, 310.0);
  EXPECT_EQ(m.band_high, 2950.0);
  EXPECT_EQ(m.resonance, 1250.0);
  EXPECT_EQ(m.resonance_low, 900.0);
  EXPECT_EQ(m.resonance_high, 1600.0);
  EXPECT_EQ(m.excitation_at_resonance_db, -4.5);

  af_excitation_band back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back.header, 1u, 2u, "rig_base");
  EXPECT_EQ(back.apple_id, 17u);
  EXPECT_EQ(back.contact_time_s, 2.4e-4);
  EXPECT_EQ(back.peak_force_n, 23.5);
  EXPECT_EQ(back.lobe, 2u);
  EXPECT_EQ(back.band_low_hz, 310.0);
  EXPECT_EQ(back.band_high_hz, 2950.0);
  EXPECT_EQ(back.resonance_hz, 1250.0);
  EXPECT_EQ(back.resonance_low_hz, 900.0);
  EXPECT_EQ(back.resonance_high_hz, 1600.0);
  EXPECT_EQ(back.excitation_at_resonance_db, -4.5);
}

TEST(StrikeAdvice, BothWaysAndTruncation)
{
  af_strike_advice c;
  poison(c);
  c.header = c_header(5u, 6u, "camera_optical_frame");
  c.apple_id = 99;
  c.strike_radius_m = 0.038;
  c.min_strike_radius_m = 0.045;
  c.strike_latitude_rad = 0.35;
  c.rotate = true;
  c.rotation_axis = af_vec3{0.0, 1.0, 0.0};
  c.rotation_angle_rad = -0.35;
  std::snprintf(c.text, sizeof c.text, "turn the apple by 20 degrees");

  acoustic_firmness::StrikeAdvice m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 5u, 6u, "camera_optical_frame");
  EXPECT_EQ(m.apple_id, 99u);
  EXPECT_EQ(m.strike_radius, 0.038);
  EXPECT_EQ(m.min_strike_radius, 0.045);
  EXPECT_EQ(m.strike_latitude, 0.35);
  EXPECT_TRUE(m.rotate);
  EXPECT_EQ(m.rotation_axis.x, 0.0);
  EXPECT_EQ(m.rotation_axis.y, 1.0);
  EXPECT_EQ(m.rotation_axis.z, 0.0);
  EXPECT_EQ(m.rotation_angle, -0.35);
  EXPECT_EQ(m.text, "turn the apple by 20 degrees");

  af_strike_advice back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back.header, 5u, 6u, "camera_optical_frame");
  EXPECT_EQ(back.apple_id, 99u);
  EXPECT_EQ(back.strike_radius_m, 0.038);
  EXPECT_EQ(back.min_strike_radius_m, 0.045);
  EXPECT_EQ(back.strike_latitude_rad, 0.35);
  EXPECT_TRUE(back.rotate);
  EXPECT_EQ(back.rotation_axis.x, 0.0);
  EXPECT_EQ(back.rotation_axis.y, 1.0);
  EXPECT_EQ(back.rotation_axis.z, 0.0);
  EXPECT_EQ(back.rotation_angle_rad, -0.35);
  EXPECT_STREQ(back.text, "turn the apple by 20 degrees");

  m.rotate = false;
  m.text = std::string(300, 't');
  af_shim::from_ros(m, back);
  EXPECT_FALSE(back.rotate);
  EXPECT_EQ(std::string(back.text), std::string(AF_TEXT_MAX - 1, 't'));
}

TEST(Reliability, BothWaysAndTruncation)
{
  af_reliability c;
  poison(c);
  c.header = c_header(9u, 10u, "rig_base");
  c.apple_id = 7;
  std::snprintf(c.source, sizeof c.source, "measured");
  c.reliable = false;
  c.excites_mode = true;
  c.no_damage = false;
  c.max_shear_stress_pa = 2.1e5;
  c.yield_shear_stress_pa = 1.8e5;
  std::snprintf(c.reason, sizeof c.reason, "max shear above yield");

  acoustic_firmness::Reliability m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 9u, 10u, "rig_base");
  EXPECT_EQ(m.apple_id, 7u);
  EXPECT_EQ(m.source, "measured");
  EXPECT_FALSE(m.reliable);
  EXPECT_TRUE(m.excites_mode);
  EXPECT_FALSE(m.no_damage);
  EXPECT_EQ(m.max_shear_stress, 2.1e5);
  EXPECT_EQ(m.yield_shear_stress, 1.8e5);
  EXPECT_EQ(m.reason, "max shear above yield");

  af_reliability back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back.header, 9u, 10u, "rig_base");
  EXPECT_EQ(back.apple_id, 7u);
  EXPECT_STREQ(back.source, "measured");
  EXPECT_FALSE(back.reliable);
  EXPECT_TRUE(back.excites_mode);
  EXPECT_FALSE(back.no_damage);
  EXPECT_EQ(back.max_shear_stress_pa, 2.1e5);
  EXPECT_EQ(back.yield_shear_stress_pa, 1.8e5);
  EXPECT_STREQ(back.reason, "max shear above yield");

  m.reliable = true;
  m.no_damage = true;
  m.excites_mode = false;
  m.source = "predicted-by-the-model";
  m.reason = std::string(1000, 'r');
  af_shim::from_ros(m, back);
  EXPECT_TRUE(back.reliable);
  EXPECT_TRUE(back.no_damage);
  EXPECT_FALSE(back.excites_mode);
  EXPECT_EQ(std::string(back.source), m.source.substr(0, AF_SOURCE_MAX - 1));
  EXPECT_EQ(std::string(back.reason), std::string(AF_TEXT_MAX - 1, 'r'));
}

TEST(StrikeReport, BothWaysAndNaN)
{
  af_strike_report c;
  poison(c);
  c.header = c_header(1700000123u, 456789u, "force_transducer");
  c.apple_id = 4000000001u;
  c.contact_time_s = 1.4375e-3;
  c.peak_force_n = 35.26;
  c.impulse_n_s = 0.02245;
  c.band_low_hz = 0.0;
  c.band_high_hz = 722.2;
  c.resonance_hz = 681.6;
  c.resonance_q = 31.5;
  c.snr_db = 28.75;
  c.stiffness_factor = 1.457e5;
  c.modulus_from_resonance_pa = 8.01e6;
  c.fitted_modulus_pa = 7.95e6;
  c.fitted_restitution = 0.598;
  c.fit_residual = 0.0123;
  c.delivered_energy_j = 9.8e-3;
  c.absorbed_energy_j = 6.3e-3;
  c.double_hit = true;
  c.clipped = false;
  c.lost_samples = 4000000002u;
  c.audio_clipped = true;
  c.audio_lag_s = 0.05013;
  c.audio_lag_applied_s = 0.0501;
  c.grade_index = 3;
  std::strcpy(c.grade, "very firm");
  std::strcpy(c.grade_reason, "");
  c.tap_only = true;
  std::strcpy(c.judged_from_model, "excitation judged from the model only");

  acoustic_firmness::StrikeReport m;
  af_shim::to_ros(c, m);
  expect_header(m.header, 1700000123u, 456789u, "force_transducer");
  EXPECT_EQ(m.apple_id, 4000000001u);
  EXPECT_EQ(m.contact_time, 1.4375e-3);
  EXPECT_EQ(m.peak_force, 35.26);
  EXPECT_EQ(m.impulse, 0.02245);
  EXPECT_EQ(m.band_low, 0.0);
  EXPECT_EQ(m.band_high, 722.2);
  EXPECT_EQ(m.resonance, 681.6);
  EXPECT_EQ(m.resonance_q, 31.5);
  EXPECT_EQ(m.snr_db, 28.75);
  EXPECT_EQ(m.stiffness_factor, 1.457e5);
  EXPECT_EQ(m.modulus_from_resonance, 8.01e6);
  EXPECT_EQ(m.fitted_modulus, 7.95e6);
  EXPECT_EQ(m.fitted_restitution, 0.598);
  EXPECT_EQ(m.fit_residual, 0.0123);
  EXPECT_EQ(m.delivered_energy, 9.8e-3);
  EXPECT_EQ(m.absorbed_energy, 6.3e-3);
  EXPECT_TRUE(m.double_hit);
  EXPECT_FALSE(m.clipped);
  EXPECT_EQ(m.lost_samples, 4000000002u);
  EXPECT_TRUE(m.audio_clipped);
  EXPECT_EQ(m.audio_lag, 0.05013);
  EXPECT_EQ(m.audio_lag_applied, 0.0501);
  EXPECT_EQ(m.grade_index, 3u);
  EXPECT_EQ(m.grade, "very firm");
  EXPECT_EQ(m.grade_reason, "");
  EXPECT_TRUE(m.tap_only);
  EXPECT_EQ(m.judged_from_model, "excitation judged from the model only");

  af_strike_report back;
  poison(back);
  af_shim::from_ros(m, back);
  expect_header(back.header, 1700000123u, 456789u, "force_transducer");
  EXPECT_EQ(back.apple_id, 4000000001u);
  EXPECT_EQ(back.contact_time_s, 1.4375e-3);
  EXPECT_EQ(back.peak_force_n, 35.26);
  EXPECT_EQ(back.impulse_n_s, 0.02245);
  EXPECT_EQ(back.band_low_hz, 0.0);
  EXPECT_EQ(back.band_high_hz, 722.2);
  EXPECT_EQ(back.resonance_hz, 681.6);
  EXPECT_EQ(back.resonance_q, 31.5);
  EXPECT_EQ(back.snr_db, 28.75);
  EXPECT_EQ(back.stiffness_factor, 1.457e5);
  EXPECT_EQ(back.modulus_from_resonance_pa, 8.01e6);
  EXPECT_EQ(back.fitted_modulus_pa, 7.95e6);
  EXPECT_EQ(back.fitted_restitution, 0.598);
  EXPECT_EQ(back.fit_residual, 0.0123);
  EXPECT_EQ(back.delivered_energy_j, 9.8e-3);
  EXPECT_EQ(back.absorbed_energy_j, 6.3e-3);
  EXPECT_TRUE(back.double_hit);
  EXPECT_FALSE(back.clipped);
  EXPECT_EQ(back.lost_samples, 4000000002u);
  EXPECT_TRUE(back.audio_clipped);
  EXPECT_EQ(back.audio_lag_s, 0.05013);
  EXPECT_EQ(back.audio_lag_applied_s, 0.0501);
  EXPECT_TRUE(back.tap_only);
  EXPECT_STREQ(back.judged_from_model, "excitation judged from the model only");

  // A strike without an apple: the model-dependent figures are NaN and stay
  // NaN both ways (no conversion turns them into 0).
  c.apple_id = 0;
  c.resonance_hz = c.resonance_q = c.snr_db = c.stiffness_factor = NAN;
  c.modulus_from_resonance_pa = c.fitted_modulus_pa = c.fitted_restitution = NAN;
  c.fit_residual = NAN;
  c.double_hit = false;
  c.clipped = true;
  c.lost_samples = 0;
  c.audio_clipped = false;
  c.audio_lag_s = NAN;
  af_shim::to_ros(c, m);
  EXPECT_EQ(m.apple_id, 0u);
  EXPECT_TRUE(std::isnan(m.resonance));
  EXPECT_TRUE(std::isnan(m.resonance_q));
  EXPECT_TRUE(std::isnan(m.snr_db));
  EXPECT_TRUE(std::isnan(m.stiffness_factor));
  EXPECT_TRUE(std::isnan(m.modulus_from_resonance));
  EXPECT_TRUE(std::isnan(m.fitted_modulus));
  EXPECT_TRUE(std::isnan(m.fitted_restitution));
  EXPECT_TRUE(std::isnan(m.fit_residual));
  EXPECT_FALSE(m.double_hit);
  EXPECT_TRUE(m.clipped);
  EXPECT_EQ(m.lost_samples, 0u);
  poison(back);
  af_shim::from_ros(m, back);
  EXPECT_TRUE(std::isnan(back.resonance_hz));
  EXPECT_TRUE(std::isnan(back.fitted_modulus_pa));
  EXPECT_TRUE(std::isnan(back.fit_residual));
  EXPECT_FALSE(back.double_hit);
  EXPECT_TRUE(back.clipped);
  EXPECT_EQ(back.contact_time_s, 1.4375e-3);
  EXPECT_EQ(back.grade_index, 3u);
  EXPECT_STREQ(back.grade, "very firm");
  EXPECT_STREQ(back.grade_reason, "");
  // A name longer than the C array is cut, NUL-terminated.
  m.grade = std::string(100, 'g');
  af_shim::from_ros(m, back);
  EXPECT_EQ(std::string(back.grade), std::string(AF_GRADE_NAME_TEXT - 1, 'g'));
}

namespace
{

af_marker arrow_marker()
{
  af_marker a;
  poison(a);
  a.header = c_header(20u, 30u, "rig_base");
  std::snprintf(a.ns, sizeof a.ns, "strike");
  a.id = 3;
  a.type = AF_MARKER_ARROW;
  a.delete_marker = false;
  a.position = af_vec3{0.1, 0.2, 0.3};
  a.orientation[0] = 0.0;
  a.orientation[1] = 0.0;
  a.orientation[2] = 0.70710678118654757;
  a.orientation[3] = 0.70710678118654757;
  a.scale = af_vec3{0.002, 0.004, 0.006};
  a.rgba[0] = 1.0f;
  a.rgba[1] = 0.5f;
  a.rgba[2] = 0.25f;
  a.rgba[3] = 0.75f;
  a.lifetime_s = 1.5;
  a.text[0] = '\0';
  a.points[0] = af_vec3{0.0, 0.0, 0.15};
  a.points[1] = af_vec3{0.0, 0.0, 0.10};
  a.n_points = 2;
  return a;
}

} // namespace

TEST(MarkerArray, CToRos)
{
  af_marker markers[3];
  markers[0] = arrow_marker();

  // A text marker to be deleted, zero-initialised otherwise.
  std::memset(static_cast<void *>(&markers[1]), 0, sizeof markers[1]);
  markers[1].header = c_header(21u, 31u, "camera_optical_frame");
  std::snprintf(markers[1].ns, sizeof markers[1].ns, "advice");
  markers[1].id = -4;
  markers[1].type = AF_MARKER_TEXT;
  markers[1].delete_marker = true;
  std::snprintf(markers[1].text, sizeof markers[1].text, "reliable");

  // The remaining types map to their visualization_msgs constants.
  std::memset(static_cast<void *>(&markers[2]), 0, sizeof markers[2]);
  markers[2].type = AF_MARKER_LINE_STRIP;
  markers[2].n_points = AF_MARKER_MAX_POINTS;
  for (size_t i = 0; i < AF_MARKER_MAX_POINTS; i++)
    markers[2].points[i] = af_vec3{static_cast<double>(i), -static_cast<double>(i), 0.5};

  const af_marker_array c = {markers, 3};
  visualization_msgs::MarkerArray m;
  af_shim::to_ros(c, m);
  ASSERT_EQ(m.markers.size(), 3u);

  const visualization_msgs::Marker &a = m.markers[0];
  expect_header(a.header, 20u, 30u, "rig_base");
  EXPECT_EQ(a.ns, "strike");
  EXPECT_EQ(a.id, 3);
  EXPECT_EQ(a.type, visualization_msgs::Marker::ARROW);
  EXPECT_EQ(a.action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(a.pose.position.x, 0.1);
  EXPECT_EQ(a.pose.position.y, 0.2);
  EXPECT_EQ(a.pose.position.z, 0.3);
  EXPECT_EQ(a.pose.orientation.x, 0.0);
  EXPECT_EQ(a.pose.orientation.y, 0.0);
  EXPECT_EQ(a.pose.orientation.z, 0.70710678118654757);
  EXPECT_EQ(a.pose.orientation.w, 0.70710678118654757);
  EXPECT_EQ(a.scale.x, 0.002);
  EXPECT_EQ(a.scale.y, 0.004);
  EXPECT_EQ(a.scale.z, 0.006);
  EXPECT_EQ(a.color.r, 1.0f);
  EXPECT_EQ(a.color.g, 0.5f);
  EXPECT_EQ(a.color.b, 0.25f);
  EXPECT_EQ(a.color.a, 0.75f);
  EXPECT_EQ(a.lifetime, ros::Duration(1.5));
  EXPECT_FALSE(a.frame_locked);
  EXPECT_EQ(a.text, "");
  ASSERT_EQ(a.points.size(), 2u);
  EXPECT_EQ(a.points[0].z, 0.15);
  EXPECT_EQ(a.points[1].z, 0.10);
  EXPECT_TRUE(a.colors.empty());

  const visualization_msgs::Marker &t = m.markers[1];
  expect_header(t.header, 21u, 31u, "camera_optical_frame");
  EXPECT_EQ(t.ns, "advice");
  EXPECT_EQ(t.id, -4);
  EXPECT_EQ(t.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(t.action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(t.text, "reliable");
  // The all-zero quaternion of a zeroed struct becomes the identity.
  EXPECT_EQ(t.pose.orientation.x, 0.0);
  EXPECT_EQ(t.pose.orientation.y, 0.0);
  EXPECT_EQ(t.pose.orientation.z, 0.0);
  EXPECT_EQ(t.pose.orientation.w, 1.0);
  EXPECT_EQ(t.lifetime, ros::Duration(0.0)); // forever
  EXPECT_TRUE(t.points.empty());

  const visualization_msgs::Marker &l = m.markers[2];
  EXPECT_EQ(l.type, visualization_msgs::Marker::LINE_STRIP);
  ASSERT_EQ(l.points.size(), static_cast<size_t>(AF_MARKER_MAX_POINTS));
  EXPECT_EQ(l.points[AF_MARKER_MAX_POINTS - 1].x, AF_MARKER_MAX_POINTS - 1.0);
  EXPECT_EQ(l.points[AF_MARKER_MAX_POINTS - 1].y, -(AF_MARKER_MAX_POINTS - 1.0));
  EXPECT_EQ(l.points[AF_MARKER_MAX_POINTS - 1].z, 0.5);

  // The publisher reuses its message: a shorter array leaves nothing of the
  // longer one behind.
  const af_marker_array one = {markers + 1, 1};
  af_shim::to_ros(one, m);
  ASSERT_EQ(m.markers.size(), 1u);
  EXPECT_EQ(m.markers[0].ns, "advice");
  EXPECT_TRUE(m.markers[0].points.empty());
  const af_marker_array none = {nullptr, 0};
  af_shim::to_ros(none, m);
  EXPECT_TRUE(m.markers.empty());
}

TEST(MarkerArray, TypesAndInvalidInput)
{
  af_marker k = arrow_marker();
  visualization_msgs::Marker m;
  k.type = AF_MARKER_CUBE;
  af_shim::to_ros(k, m);
  EXPECT_EQ(m.type, visualization_msgs::Marker::CUBE);
  k.type = AF_MARKER_SPHERE;
  af_shim::to_ros(k, m);
  EXPECT_EQ(m.type, visualization_msgs::Marker::SPHERE);
  k.type = AF_MARKER_CYLINDER;
  af_shim::to_ros(k, m);
  EXPECT_EQ(m.type, visualization_msgs::Marker::CYLINDER);

  // The ns array is read up to its end when it has no NUL.
  std::memset(k.ns, 'n', sizeof k.ns);
  af_shim::to_ros(k, m);
  EXPECT_EQ(m.ns, std::string(sizeof k.ns, 'n'));

  k.n_points = AF_MARKER_MAX_POINTS + 1;
  EXPECT_THROW(af_shim::to_ros(k, m), std::invalid_argument);
  k.n_points = 2;
  k.type = static_cast<af_marker_type>(7); // no such af_marker_type
  EXPECT_THROW(af_shim::to_ros(k, m), std::invalid_argument);

  visualization_msgs::MarkerArray ma;
  const af_marker_array missing = {nullptr, 2};
  EXPECT_THROW(af_shim::to_ros(missing, ma), std::invalid_argument);
}

int main(int argc, char **argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
