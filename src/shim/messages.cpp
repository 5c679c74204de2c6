// messages.cpp — C struct <-> ROS message, one pair per af_msg_type.
#include "convert.hpp"

#include <cmath>
#include <stdexcept>

namespace af_shim
{

void to_ros(const af_time &c, ros::Time &m)
{
  m.sec = c.sec;
  m.nsec = c.nsec;
}

void from_ros(const ros::Time &m, af_time &c)
{
  c.sec = m.sec;
  c.nsec = m.nsec;
}

void to_ros(const af_header &c, std_msgs::Header &m)
{
  to_ros(c.stamp, m.stamp);
  assign_string(c.frame_id, m.frame_id);
}

void from_ros(const std_msgs::Header &m, af_header &c)
{
  from_ros(m.stamp, c.stamp);
  copy_string(m.frame_id, c.frame_id);
}

void to_ros(const af_vec3 &c, geometry_msgs::Vector3 &m)
{
  m.x = c.x;
  m.y = c.y;
  m.z = c.z;
}

void from_ros(const geometry_msgs::Vector3 &m, af_vec3 &c)
{
  c.x = m.x;
  c.y = m.y;
  c.z = m.z;
}

void to_ros(const af_signal_chunk &c, acoustic_firmness::SignalChunk &m)
{
  if (c.n > 0 && c.data == nullptr)
    throw std::invalid_argument("SignalChunk: data is NULL with n = " + std::to_string(c.n));
  to_ros(c.header, m.header);
  m.first_sample = c.first_sample;
  m.sample_rate = c.sample_rate_hz;
  assign_string(c.unit, m.unit);
  if (c.n > 0)
    m.data.assign(c.data, c.data + c.n);
  else
    m.data.clear();
}

void from_ros(const acoustic_firmness::SignalChunk &m, af_signal_chunk &c)
{
  from_ros(m.header, c.header);
  c.first_sample = m.first_sample;
  c.sample_rate_hz = m.sample_rate;
  copy_string(m.unit, c.unit);
  c.data = m.data.empty() ? nullptr : m.data.data();
  c.n = m.data.size();
}

void to_ros(const af_apple_estimate &c, acoustic_firmness::AppleEstimate &m)
{
  to_ros(c.header, m.header);
  m.apple_id = c.apple_id;
  m.mass = c.mass_kg;
  m.equatorial_radius = c.equatorial_radius_m;
  m.strike_radius = c.strike_radius_m;
  to_ros(c.stem_axis, m.stem_axis);
  m.confidence = c.confidence;
}

void from_ros(const acoustic_firmness::AppleEstimate &m, af_apple_estimate &c)
{
  from_ros(m.header, c.header);
  c.apple_id = m.apple_id;
  c.mass_kg = m.mass;
  c.equatorial_radius_m = m.equatorial_radius;
  c.strike_radius_m = m.strike_radius;
  from_ros(m.stem_axis, c.stem_axis);
  c.confidence = m.confidence;
}

void to_ros(const af_excitation_band &c, acoustic_firmness::ExcitationBand &m)
{
  to_ros(c.header, m.header);
  m.apple_id = c.apple_id;
  m.contact_time = c.contact_time_s;
  m.peak_force = c.peak_force_n;
  m.lobe = c.lobe;
  m.band_low = c.band_low_hz;
  m.band_high = c.band_high_hz;
  m.resonance = c.resonance_hz;
  m.resonance_low = c.resonance_low_hz;
  m.resonance_high = c.resonance_high_hz;
  m.excitation_at_resonance_db = c.excitation_at_resonance_db;
}

void from_ros(const acoustic_firmness::ExcitationBand &m, af_excitation_band &c)
{
  from_ros(m.header, c.header);
  c.apple_id = m.apple_id;
  c.contact_time_s = m.contact_time;
  c.peak_force_n = m.peak_force;
  c.lobe = m.lobe;
  c.band_low_hz = m.band_low;
  c.band_high_hz = m.band_high;
  c.resonance_hz = m.resonance;
  c.resonance_low_hz = m.resonance_low;
  c.resonance_high_hz = m.resonance_high;
  c.excitation_at_resonance_db = m.excitation_at_resonance_db;
}

void to_ros(const af_strike_advice &c, acoustic_firmness::StrikeAdvice &m)
{
  to_ros(c.header, m.header);
  m.apple_id = c.apple_id;
  m.strike_radius = c.strike_radius_m;
  m.min_strike_radius = c.min_strike_radius_m;
  m.strike_latitude = c.strike_latitude_rad;
  m.rotate = c.rotate;
  to_ros(c.rotation_axis, m.rotation_axis);
  m.rotation_angle = c.rotation_angle_rad;
  assign_string(c.text, m.text);
}

void from_ros(const acoustic_firmness::StrikeAdvice &m, af_strike_advice &c)
{
  from_ros(m.header, c.header);
  c.apple_id = m.apple_id;
  c.strike_radius_m = m.strike_radius;
  c.min_strike_radius_m = m.min_strike_radius;
  c.strike_latitude_rad = m.strike_latitude;
  c.rotate = m.rotate != 0;
  from_ros(m.rotation_axis, c.rotation_axis);
  c.rotation_angle_rad = m.rotation_angle;
  copy_string(m.text, c.text);
}

void to_ros(const af_text_msg &c, std_msgs::String &m)
{
  m.data = c.data != nullptr ? c.data : "";
}

void to_ros(const af_reliability &c, acoustic_firmness::Reliability &m)
{
  to_ros(c.header, m.header);
  m.apple_id = c.apple_id;
  assign_string(c.source, m.source);
  m.reliable = c.reliable;
  m.excites_mode = c.excites_mode;
  m.no_damage = c.no_damage;
  m.max_shear_stress = c.max_shear_stress_pa;
  m.yield_shear_stress = c.yield_shear_stress_pa;
  assign_string(c.reason, m.reason);
}

void from_ros(const acoustic_firmness::Reliability &m, af_reliability &c)
{
  from_ros(m.header, c.header);
  c.apple_id = m.apple_id;
  copy_string(m.source, c.source);
  c.reliable = m.reliable != 0;
  c.excites_mode = m.excites_mode != 0;
  c.no_damage = m.no_damage != 0;
  c.max_shear_stress_pa = m.max_shear_stress;
  c.yield_shear_stress_pa = m.yield_shear_stress;
  copy_string(m.reason, c.reason);
}

void to_ros(const af_strike_report &c, acoustic_firmness::StrikeReport &m)
{
  to_ros(c.header, m.header);
  m.apple_id = c.apple_id;
  m.contact_time = c.contact_time_s;
  m.peak_force = c.peak_force_n;
  m.impulse = c.impulse_n_s;
  m.band_low = c.band_low_hz;
  m.band_high = c.band_high_hz;
  m.resonance = c.resonance_hz;
  m.resonance_q = c.resonance_q;
  m.snr_db = c.snr_db;
  m.stiffness_factor = c.stiffness_factor;
  m.modulus_from_resonance = c.modulus_from_resonance_pa;
  m.fitted_modulus = c.fitted_modulus_pa;
  m.fitted_restitution = c.fitted_restitution;
  m.fit_residual = c.fit_residual;
  m.delivered_energy = c.delivered_energy_j;
  m.absorbed_energy = c.absorbed_energy_j;
  m.double_hit = c.double_hit;
  m.clipped = c.clipped;
  m.lost_samples = c.lost_samples;
  m.audio_clipped = c.audio_clipped;
  m.audio_lag = c.audio_lag_s;
  m.audio_lag_applied = c.audio_lag_applied_s;
  m.grade_index = c.grade_index;
  assign_string(c.grade, m.grade);
  assign_string(c.grade_reason, m.grade_reason);
  m.tap_only = c.tap_only;
  assign_string(c.judged_from_model, m.judged_from_model);
}

void from_ros(const acoustic_firmness::StrikeReport &m, af_strike_report &c)
{
  from_ros(m.header, c.header);
  c.apple_id = m.apple_id;
  c.contact_time_s = m.contact_time;
  c.peak_force_n = m.peak_force;
  c.impulse_n_s = m.impulse;
  c.band_low_hz = m.band_low;
  c.band_high_hz = m.band_high;
  c.resonance_hz = m.resonance;
  c.resonance_q = m.resonance_q;
  c.snr_db = m.snr_db;
  c.stiffness_factor = m.stiffness_factor;
  c.modulus_from_resonance_pa = m.modulus_from_resonance;
  c.fitted_modulus_pa = m.fitted_modulus;
  c.fitted_restitution = m.fitted_restitution;
  c.fit_residual = m.fit_residual;
  c.delivered_energy_j = m.delivered_energy;
  c.absorbed_energy_j = m.absorbed_energy;
  c.double_hit = m.double_hit != 0;
  c.clipped = m.clipped != 0;
  c.lost_samples = m.lost_samples;
  c.audio_clipped = m.audio_clipped != 0;
  c.audio_lag_s = m.audio_lag;
  c.audio_lag_applied_s = m.audio_lag_applied;
  c.grade_index = m.grade_index;
  copy_string(m.grade, c.grade);
  copy_string(m.grade_reason, c.grade_reason);
  c.tap_only = m.tap_only != 0;
  copy_string(m.judged_from_model, c.judged_from_model);
}

namespace
{

int32_t marker_type(af_marker_type t)
{
  using visualization_msgs::Marker;
  switch (t) {
  case AF_MARKER_ARROW: return Marker::ARROW;
  case AF_MARKER_CUBE: return Marker::CUBE;
  case AF_MARKER_SPHERE: return Marker::SPHERE;
  case AF_MARKER_CYLINDER: return Marker::CYLINDER;
  case AF_MARKER_LINE_STRIP: return Marker::LINE_STRIP;
  case AF_MARKER_TEXT: return Marker::TEXT_VIEW_FACING;
  }
  throw std::invalid_argument("Marker: unknown type " + std::to_string(static_cast<int>(t)));
}

} // namespace

void to_ros(const af_marker &c, visualization_msgs::Marker &m)
{
  if (c.n_points > AF_MARKER_MAX_POINTS)
    throw std::invalid_argument("Marker: n_points = " + std::to_string(c.n_points) +
                                " exceeds AF_MARKER_MAX_POINTS");
  to_ros(c.header, m.header);
  assign_string(c.ns, m.ns);
  m.id = c.id;
  m.type = marker_type(c.type);
  m.action = c.delete_marker ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
  m.pose.position.x = c.position.x;
  m.pose.position.y = c.position.y;
  m.pose.position.z = c.position.z;
  // A zero-initialised C marker means "not rotated"; rviz rejects the
  // all-zero quaternion with a warning, so it becomes the identity here.
  const double *q = c.orientation;
  const bool zero_q = q[0] == 0.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0;
  m.pose.orientation.x = q[0];
  m.pose.orientation.y = q[1];
  m.pose.orientation.z = q[2];
  m.pose.orientation.w = zero_q ? 1.0 : q[3];
  to_ros(c.scale, m.scale);
  m.color.r = c.rgba[0];
  m.color.g = c.rgba[1];
  m.color.b = c.rgba[2];
  m.color.a = c.rgba[3];
  m.lifetime =
      ros::Duration(c.lifetime_s > 0.0 && std::isfinite(c.lifetime_s) ? c.lifetime_s : 0.0);
  m.frame_locked = false;
  assign_string(c.text, m.text);
  m.points.resize(c.n_points);
  for (std::size_t i = 0; i < c.n_points; i++) {
    m.points[i].x = c.points[i].x;
    m.points[i].y = c.points[i].y;
    m.points[i].z = c.points[i].z;
  }
  m.colors.clear();
}

void to_ros(const af_marker_array &c, visualization_msgs::MarkerArray &m)
{
  if (c.n > 0 && c.markers == nullptr)
    throw std::invalid_argument("MarkerArray: markers is NULL with n = " + std::to_string(c.n));
  m.markers.resize(c.n);
  for (std::size_t i = 0; i < c.n; i++)
    to_ros(c.markers[i], m.markers[i]);
}

} // namespace af_shim
