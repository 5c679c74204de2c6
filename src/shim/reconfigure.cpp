// reconfigure.cpp — a dynamic_reconfigure server over the generated
// StationConfig, its values handed to C by name (af_reconfigure.h).
#include "af_reconfigure.h"
#include "ros_handle.hpp"

#include <boost/any.hpp>
#include <dynamic_reconfigure/server.h>

#include <acoustic_firmness/StationConfig.h>

namespace
{

using Config = acoustic_firmness::StationConfig;

struct server {
  af_ros *owner = nullptr;
  af_rc_fn fn = nullptr;
  void *user = nullptr;
  boost::recursive_mutex mutex;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> srv;
  Config accepted; // what the node runs with
  bool have_accepted = false;
};

void on_request(server &s, Config &config)
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
  if (s.fn(values.data(), values.size(), s.user, err, sizeof err) == AF_OK) {
    s.accepted = config;
    s.have_accepted = true;
  } else if (s.have_accepted) {
    config = s.accepted; // the answer: the values still in force
  }
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
    // On the private handle: its services run on the node's queue.
    s->srv.reset(new dynamic_reconfigure::Server<Config>(s->mutex, *r->pnh));
    server *sp = s.get();
    s->srv->setCallback([sp](Config &config, uint32_t) {
      try {
        on_request(*sp, config);
      } catch (...) {
        af_shim::status_from_exception(sp->owner);
        if (sp->have_accepted)
          config = sp->accepted;
      }
    });
    r->extras.push_back(s);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

} // extern "C"
