// time.cpp — ROS time and its conversions to and from seconds.
#include "ros_handle.hpp"

#include <cmath>
#include <cstdint>

extern "C" {

af_time af_ros_now(const af_ros *r)
{
  af_time t = {0, 0};
  try {
    // ros::Time::now() is the simulated clock when /use_sim_time is set.
    const ros::Time now = ros::Time::now();
    t.sec = now.sec;
    t.nsec = now.nsec;
  } catch (...) {
    af_shim::status_from_exception(r);
  }
  return t;
}

double af_time_to_s(af_time t)
{
  return static_cast<double>(t.sec) + 1e-9 * static_cast<double>(t.nsec);
}

af_time af_time_from_s(double s)
{
  af_time t = {0, 0};
  // Outside ROS's time range (negative, NaN, past 2106) the nearest end is
  // returned rather than throwing as ros::Time(double) would.
  if (!(s > 0.0))
    return t;
  const double max_s = 4294967295.0;
  if (s >= max_s) {
    t.sec = UINT32_MAX;
    t.nsec = 999999999u;
    return t;
  }
  double sec = std::floor(s);
  long long nsec = std::llround((s - sec) * 1e9);
  if (nsec >= 1000000000LL) {
    sec += 1.0;
    nsec -= 1000000000LL;
  }
  t.sec = static_cast<uint32_t>(sec);
  t.nsec = static_cast<uint32_t>(nsec);
  return t;
}

} // extern "C"
