// service.cpp — the node's services (af_srv.h): ~evaluate.
#include "af_srv.h"
#include "convert.hpp"
#include "ros_handle.hpp"

#include <acoustic_firmness/Evaluate.h>

namespace
{

void to_ros(const af_evaluate_response &c, acoustic_firmness::Evaluate::Response &m)
{
  m.ok = c.ok;
  af_shim::assign_string(c.error, m.error);
  m.modulus = c.modulus_pa;
  m.restitution = c.restitution;
  m.velocity = c.velocity_m_s;
  m.hammer_mass = c.hammer_mass_kg;
  m.contact_time = c.contact_time_s;
  m.peak_force = c.peak_force_n;
  m.max_deformation = c.max_deformation_m;
  m.delivered_restitution = c.delivered_restitution;
  m.lobe = c.lobe;
  m.band_low = c.band_low_hz;
  m.band_high = c.band_high_hz;
  m.resonance = c.resonance_hz;
  m.resonance_low = c.resonance_low_hz;
  m.resonance_high = c.resonance_high_hz;
  m.excitation_at_resonance_db = c.excitation_at_resonance_db;
  m.max_contact_pressure = c.max_contact_pressure_pa;
  m.max_shear_stress = c.max_shear_stress_pa;
  m.yield_shear_stress = c.yield_shear_stress_pa;
  m.min_strike_radius = c.min_strike_radius_m;
  m.excites_mode = c.excites_mode;
  m.no_damage = c.no_damage;
  m.reliable = c.reliable;
  af_shim::assign_string(c.reason, m.reason);
}

} // namespace

extern "C" {

af_status af_ros_advertise_evaluate(af_ros *r, const char *name, af_evaluate_fn fn, void *user)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_advertise_evaluate: r is NULL");
    if (name == nullptr || name[0] == '\0' || fn == nullptr)
      return af_shim::invalid(r, "af_ros_advertise_evaluate: name or fn is NULL or empty");
    // "~x" is private: the node's private handle and "x".
    const bool priv = name[0] == '~';
    ros::NodeHandle &nh = priv ? *r->pnh : *r->nh;
    const std::string service = priv ? std::string(name + 1) : std::string(name);
    auto server = std::make_shared<ros::ServiceServer>(
        nh.advertiseService<acoustic_firmness::Evaluate::Request,
                            acoustic_firmness::Evaluate::Response>(
            service, [r, fn, user](acoustic_firmness::Evaluate::Request &q,
                                   acoustic_firmness::Evaluate::Response &a) {
              af_evaluate_request req{q.mass,        q.strike_radius, q.modulus,
                                      q.restitution, q.velocity,      q.hammer_mass};
              af_evaluate_response res{};
              try {
                fn(&req, &res, user);
              } catch (...) {
                af_shim::status_from_exception(r);
                res = af_evaluate_response{};
                af_shim::copy_string("the node failed: " + std::string(af_ros_last_error(r)),
                                     res.error);
              }
              to_ros(res, a);
              return true; // a refusal is an answer (ok false), not a failed call
            }));
    if (!*server)
      return af_shim::invalid(r, "af_ros_advertise_evaluate: could not advertise " + service);
    r->extras.push_back(server);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

} // extern "C"
