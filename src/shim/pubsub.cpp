// pubsub.cpp — publishers and subscribers of the C message types.
#include "convert.hpp"
#include "ros_handle.hpp"
#include "wire.hpp"

#include <boost/make_shared.hpp>

namespace
{

// The message is kept between calls: after the first publish its vectors
// (SignalChunk data, marker points) keep their capacity. publish(const M &)
// serialises at once, so reusing it on the next call is safe.
template <class C, class M>
void advertise_as(ros::NodeHandle &nh, const std::string &topic, unsigned queue, bool latch,
                  af_ros_pub &p)
{
  p.pub = nh.advertise<M>(topic, queue, latch);
  auto msg = boost::make_shared<M>();
  ros::Publisher *pub = &p.pub;
  p.send = [pub, msg](const void *c) {
    af_shim::to_ros(*static_cast<const C *>(c), *msg);
    pub->publish(*msg);
  };
}

// Whether roscpp may deserialize these bytes as an M: every type but
// SignalChunk has no vector a length prefix could blow up (wire.hpp). A
// SignalChunk is walked strictly, against the subscriber's cap.
template <class M>
af_shim::chunk_wire check(const uint8_t *, std::size_t, const af_ros_sub &, std::string *)
{
  return af_shim::chunk_wire::ok;
}
template <>
af_shim::chunk_wire check<acoustic_firmness::SignalChunk>(const uint8_t *p, std::size_t n,
                                                          const af_ros_sub &s, std::string *why)
{
  uint32_t samples;
  return af_shim::signal_chunk_check(p, n, s.max_samples.load(), &samples, why);
}

// roscpp's callback helper with the bytes checked first: a message that
// would make the deserializer allocate what it does not hold, a cut or empty
// one, or a chunk longer than the cap is dropped (roscpp skips a null
// message), counted, told to the subscriber and logged, never allocated.
template <class M>
class checked_helper : public ros::SubscriptionCallbackHelperT<const boost::shared_ptr<const M> &>
{
public:
  using base = ros::SubscriptionCallbackHelperT<const boost::shared_ptr<const M> &>;
  checked_helper(const typename base::Callback &cb, af_ros_sub *s) : base(cb), s_(s) {}

  ros::VoidConstPtr deserialize(const ros::SubscriptionCallbackHelperDeserializeParams &p) override
  {
    std::string why;
    af_shim::chunk_wire w = check<M>(p.buffer, p.length, *s_, &why);
    if (w == af_shim::chunk_wire::ok)
      return base::deserialize(p);
    const bool oversized = w == af_shim::chunk_wire::oversized;
    unsigned long long n = oversized ? ++s_->oversized : ++s_->malformed;
    const std::string line = s_->sub.getTopic() + ": dropped " + why;
    if ((n & (n - 1)) == 0) // the 1st, 2nd, 4th, 8th ...
      ROS_WARN("%s; %llu %s so far", line.c_str(), n, oversized ? "oversized" : "malformed");
    if (s_->refused)
      s_->refused(oversized, line.c_str(), s_->user);
    return ros::VoidConstPtr();
  }

private:
  af_ros_sub *s_;
};

// The C struct lives on the stack of the callback, its strings copied into
// fixed arrays and its arrays borrowed from m: nothing is allocated per
// message beyond what roscpp itself does.
template <class M, class C>
void subscribe_as(ros::NodeHandle &nh, const std::string &topic, unsigned queue, af_ros_sub &s)
{
  af_ros_sub *sp = &s;
  ros::SubscribeOptions ops;
  auto cb = [sp](const boost::shared_ptr<const M> &m) {
    C c{};
    af_shim::from_ros(*m, c);
    sp->cb(&c, sp->user);
  };
  ops.template init<M>(topic, queue, cb);
  ops.helper = boost::make_shared<checked_helper<M>>(cb, sp);
  s.sub = nh.subscribe(ops);
}

} // namespace

extern "C" {

af_status af_ros_advertise(af_ros *r, const char *topic, af_msg_type type, unsigned queue,
                           bool latch, af_ros_pub **out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_advertise: out is NULL");
    *out = nullptr;
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_advertise: r is NULL");
    if (topic == nullptr || topic[0] == '\0')
      return af_shim::invalid(r, "af_ros_advertise: topic is NULL or empty");
    if (queue < 1)
      return af_shim::invalid(r, std::string("af_ros_advertise: queue must be >= 1 for ") + topic);
    std::unique_ptr<af_ros_pub> p(new af_ros_pub);
    p->owner = r;
    p->type = type;
    ros::NodeHandle &nh = *r->nh;
    using namespace acoustic_firmness;
    switch (type) {
    case AF_MSG_SIGNAL_CHUNK:
      advertise_as<af_signal_chunk, SignalChunk>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_APPLE_ESTIMATE:
      advertise_as<af_apple_estimate, AppleEstimate>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_EXCITATION_BAND:
      advertise_as<af_excitation_band, ExcitationBand>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_STRIKE_ADVICE:
      advertise_as<af_strike_advice, StrikeAdvice>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_RELIABILITY:
      advertise_as<af_reliability, Reliability>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_MARKER_ARRAY:
      advertise_as<af_marker_array, visualization_msgs::MarkerArray>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_IMAGE:
      advertise_as<af_image, sensor_msgs::Image>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_STRIKE_REPORT:
      advertise_as<af_strike_report, StrikeReport>(nh, topic, queue, latch, *p);
      break;
    case AF_MSG_TEXT:
      advertise_as<af_text_msg, std_msgs::String>(nh, topic, queue, latch, *p);
      break;
    default:
      return af_shim::invalid(r, "af_ros_advertise: unknown message type " +
                                     std::to_string(static_cast<int>(type)) + " for " + topic);
    }
    if (!p->pub)
      return af_shim::invalid(r, std::string("af_ros_advertise: could not advertise ") + topic);
    r->pubs.push_back(std::move(p));
    *out = r->pubs.back().get();
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_publish(af_ros_pub *p, const void *msg)
{
  af_ros *r = p != nullptr ? p->owner : nullptr;
  try {
    if (p == nullptr)
      return af_shim::invalid(nullptr, "af_ros_publish: p is NULL");
    if (msg == nullptr)
      return af_shim::invalid(r, "af_ros_publish: msg is NULL on " + p->pub.getTopic());
    p->send(msg);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

unsigned long long af_ros_sub_malformed(const af_ros_sub *s)
{
  return s != nullptr ? s->malformed.load() : 0ull;
}

af_status af_ros_sub_limit(af_ros_sub *s, size_t max_samples, af_ros_refused_fn fn)
{
  if (s == nullptr || s->type != AF_MSG_SIGNAL_CHUNK)
    return af_shim::invalid(s ? s->owner : nullptr,
                            "af_ros_sub_limit: not a SignalChunk subscriber");
  s->max_samples = max_samples;
  s->refused = fn;
  return AF_OK;
}

unsigned long long af_ros_sub_oversized(const af_ros_sub *s)
{
  return s != nullptr ? s->oversized.load() : 0ull;
}

unsigned long long af_ros_malformed(const af_ros *r)
{
  unsigned long long n = 0;
  if (r != nullptr)
    for (const auto &s : r->subs)
      n += s->malformed.load();
  return n;
}

unsigned af_ros_pub_subscribers(const af_ros_pub *p)
{
  try {
    return p != nullptr ? static_cast<unsigned>(p->pub.getNumSubscribers()) : 0u;
  } catch (...) {
    af_shim::status_from_exception(p != nullptr ? p->owner : nullptr);
    return 0;
  }
}

af_status af_ros_subscribe(af_ros *r, const char *topic, af_msg_type type, unsigned queue,
                           af_ros_callback cb, void *user, af_ros_sub **out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_subscribe: out is NULL");
    *out = nullptr;
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_subscribe: r is NULL");
    if (topic == nullptr || topic[0] == '\0')
      return af_shim::invalid(r, "af_ros_subscribe: topic is NULL or empty");
    if (cb == nullptr)
      return af_shim::invalid(r, std::string("af_ros_subscribe: cb is NULL for ") + topic);
    if (queue < 1)
      return af_shim::invalid(r, std::string("af_ros_subscribe: queue must be >= 1 for ") + topic);
    std::unique_ptr<af_ros_sub> s(new af_ros_sub);
    s->owner = r;
    s->type = type;
    s->cb = cb;
    s->user = user;
    ros::NodeHandle &nh = *r->nh;
    using namespace acoustic_firmness;
    switch (type) {
    case AF_MSG_SIGNAL_CHUNK:
      subscribe_as<SignalChunk, af_signal_chunk>(nh, topic, queue, *s);
      break;
    case AF_MSG_APPLE_ESTIMATE:
      subscribe_as<AppleEstimate, af_apple_estimate>(nh, topic, queue, *s);
      break;
    case AF_MSG_EXCITATION_BAND:
      subscribe_as<ExcitationBand, af_excitation_band>(nh, topic, queue, *s);
      break;
    case AF_MSG_STRIKE_ADVICE:
      subscribe_as<StrikeAdvice, af_strike_advice>(nh, topic, queue, *s);
      break;
    case AF_MSG_RELIABILITY: subscribe_as<Reliability, af_reliability>(nh, topic, queue, *s); break;
    case AF_MSG_STRIKE_REPORT:
      subscribe_as<StrikeReport, af_strike_report>(nh, topic, queue, *s);
      break;
    case AF_MSG_IMAGE:
      return af_shim::invalid(r, std::string("af_ros_subscribe: Image is publish-only (") + topic +
                                     ")");
    case AF_MSG_MARKER_ARRAY:
      return af_shim::invalid(r, std::string("af_ros_subscribe: MarkerArray is publish-only (") +
                                     topic + ")");
    default:
      return af_shim::invalid(r, "af_ros_subscribe: unknown message type " +
                                     std::to_string(static_cast<int>(type)) + " for " + topic);
    }
    if (!s->sub)
      return af_shim::invalid(r, std::string("af_ros_subscribe: could not subscribe to ") + topic);
    r->subs.push_back(std::move(s));
    *out = r->subs.back().get();
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

} // extern "C"
