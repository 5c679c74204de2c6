// reconfigure.cpp — a dynamic_reconfigure server over the generated
// StationConfig, its values handed to C by name (af_reconfigure.h).
//
// Not dynamic_reconfigure::Server: that one clamps every request to the
// description's min and max before its callback sees it, so `lobe 99` would
// reach the node as 8 and be taken in silence. This server speaks the same
// protocol (the ~set_parameters service, latched ~parameter_descriptions and
// ~parameter_updates, the values mirrored on the parameter server) with the
// description's ranges unchanged (rqt_reconfigure's sliders stay the
// table's), but hands the request to C as sent: the parameter table refuses
// a value outside its range with the reason, and the answer carries the
// values still in force.
#include "af_reconfigure.h"
#include "ros_handle.hpp"

#include <boost/any.hpp>
#include <dynamic_reconfigure/ConfigDescription.h>
#include <dynamic_reconfigure/Reconfigure.h>

#include <acoustic_firmness/StationConfig.h>

namespace
{

using Config = acoustic_firmness::StationConfig;

struct server {
  af_ros *owner = nullptr;
  af_rc_fn fn = nullptr;
  void *user = nullptr;
  ros::NodeHandle nh;
  ros::ServiceServer set_service;
  ros::Publisher descriptions, updates;
  Config accepted; // what the node runs with
};

// Every value of config to C; AF_OK when C takes them.
af_status hand_to_c(server &s, const Config &config, bool initial)
{
  std::vector<af_rc_value> values;
  std::vector<std::string> texts; // owns the strings during the call
  const auto &params = Config::__getParamDescriptions__();
  texts.reserve(params.size());
  for (const auto &p : params) {
    boost::any v;
    p->getValue(config, v);
    af_rc_value c{};
    c.name = p->name.c_str();
    if (p->type == "double")
      c.type = AF_RC_DOUBLE, c.number = boost::any_cast<double>(v);
    else if (p->type == "int")
      c.type = AF_RC_INT, c.number = boost::any_cast<int>(v);
    else if (p->type == "bool")
      c.type = AF_RC_BOOL, c.flag = boost::any_cast<bool>(v);
    else {
      texts.push_back(boost::any_cast<std::string>(v));
      c.type = AF_RC_STRING, c.text = texts.back().c_str();
    }
    values.push_back(c);
  }
  char err[512] = "";
  return s.fn(values.data(), values.size(), initial, s.user, err, sizeof err);
}

// The values in force on the parameter server and ~parameter_updates.
void publish_accepted(server &s)
{
  s.accepted.__toServer__(s.nh);
  dynamic_reconfigure::Config msg;
  s.accepted.__toMessage__(msg);
  s.updates.publish(msg);
}

bool on_set(server &s, dynamic_reconfigure::Reconfigure::Request &req,
            dynamic_reconfigure::Reconfigure::Response &rsp)
{
  try {
    Config next = s.accepted; // what the request leaves out stays
    next.__fromMessage__(req.config);
    if (hand_to_c(s, next, false) == AF_OK) {
      s.accepted = next;
      publish_accepted(s);
    }
  } catch (...) {
    af_shim::status_from_exception(s.owner);
  }
  s.accepted.__toMessage__(rsp.config); // refused: the values still in force
  return true;
}

} // namespace

extern "C" {

af_status af_ros_reconfigure_create(af_ros *r, af_rc_fn fn, void *user)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_reconfigure_create: r is NULL");
    if (fn == nullptr)
      return af_shim::invalid(r, "af_ros_reconfigure_create: fn is NULL");
    auto s = std::make_shared<server>();
    s->owner = r, s->fn = fn, s->user = user;
    s->nh = *r->pnh; // the private handle: its services run on the node's queue
    s->descriptions =
        s->nh.advertise<dynamic_reconfigure::ConfigDescription>("parameter_descriptions", 1, true);
    s->descriptions.publish(Config::__getDescriptionMessage__());
    s->updates = s->nh.advertise<dynamic_reconfigure::Config>("parameter_updates", 1, true);
    // The start: the node's own values from the parameter server (already
    // checked by the node's start-up), taken whatever C says of them.
    s->accepted = Config::__getDefault__();
    s->accepted.__fromServer__(s->nh);
    (void)hand_to_c(*s, s->accepted, true);
    publish_accepted(*s);
    server *sp = s.get();
    s->set_service = s->nh.advertiseService<dynamic_reconfigure::Reconfigure::Request,
                                            dynamic_reconfigure::Reconfigure::Response>(
        "set_parameters",
        [sp](dynamic_reconfigure::Reconfigure::Request &req,
             dynamic_reconfigure::Reconfigure::Response &rsp) { return on_set(*sp, req, rsp); });
    r->extras.push_back(s);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

} // extern "C"
