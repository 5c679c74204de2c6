// audio_common.cpp — audio_common_msgs subscribed through
// topic_tools::ShapeShifter, checked and read without their generated
// headers (af_audio.h).
#include "af_audio.h"
#include "convert.hpp"
#include "ros_handle.hpp"

#include <cstring>
#include <sstream>

#include <boost/make_shared.hpp>
#include <topic_tools/shape_shifter.h>

namespace
{

using Event = ros::MessageEvent<topic_tools::ShapeShifter const>;

// The serialized bytes, read with every length checked against the rest.
class reader
{
public:
  reader(const uint8_t *p, std::size_t n) : p_(p), n_(n) {}
  bool u8(uint8_t &v)
  {
    if (n_ < 1)
      return false;
    v = *p_++, n_--;
    return true;
  }
  bool u32(uint32_t &v)
  {
    if (n_ < 4)
      return false;
    v = uint32_t(p_[0]) | uint32_t(p_[1]) << 8 | uint32_t(p_[2]) << 16 | uint32_t(p_[3]) << 24;
    p_ += 4, n_ -= 4;
    return true;
  }
  // A uint32 length and that many bytes (a string or a uint8[]).
  bool bytes(const uint8_t *&data, std::size_t &n)
  {
    uint32_t len;
    if (!u32(len) || len > n_)
      return false;
    data = p_, n = len;
    p_ += len, n_ -= len;
    return true;
  }
  template <std::size_t N> bool string(char (&dst)[N])
  {
    const uint8_t *d;
    std::size_t n;
    if (!bytes(d, n))
      return false;
    const std::size_t k = n < N - 1 ? n : N - 1;
    std::memcpy(dst, d, k);
    dst[k] = '\0';
    return true;
  }
  std::size_t left() const
  {
    return n_;
  }

private:
  const uint8_t *p_;
  std::size_t n_;
};

// "type name" per field line: comments, blanks and the dependencies dropped.
std::string fields_of(const std::string &definition)
{
  std::istringstream in(definition);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.compare(0, 5, "=====") == 0)
      break;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos)
      line.resize(hash);
    std::istringstream words(line);
    std::string type, name;
    if (words >> type >> name)
      out += type + " " + name + "\n";
  }
  return out;
}

// The subscription's scratch: the message's bytes (its capacity kept).
struct audio_sub {
  af_ros *owner = nullptr;
  bool info = false; // AudioInfo; else AudioData(Stamped)
  af_audio_data_fn data_fn = nullptr;
  af_audio_info_fn info_fn = nullptr;
  af_audio_refused_fn refused = nullptr;
  const std::size_t *max_bytes = nullptr; // the caller's cap; null: none
  void *user = nullptr;
  std::vector<uint8_t> buf;
  ros::Subscriber sub;
};

void refuse(const audio_sub &s, const std::string &type, const std::string &md5,
            const std::string &why, bool oversized = false)
{
  af_audio_refusal r{};
  r.oversized = oversized;
  af_shim::copy_string(type, r.datatype);
  af_shim::copy_string(md5, r.md5);
  af_shim::copy_string(why, r.why);
  if (s.refused)
    s.refused(&r, s.user);
}

void refuse(const audio_sub &s, const topic_tools::ShapeShifter &m, const std::string &why)
{
  refuse(s, m.getDataType(), m.getMD5Sum(), why);
}

// roscpp's helper with the message's size checked against the cap before
// the ShapeShifter copies it (and on_message copies it again): a message of
// hundreds of MB is dropped, told, and never held by us.
class capped_helper : public ros::SubscriptionCallbackHelperT<const Event &>
{
public:
  using base = ros::SubscriptionCallbackHelperT<const Event &>;
  capped_helper(const base::Callback &cb, audio_sub *s) : base(cb), s_(s) {}

  ros::VoidConstPtr deserialize(const ros::SubscriptionCallbackHelperDeserializeParams &p) override
  {
    const std::size_t cap = s_->max_bytes ? *s_->max_bytes : 0;
    if (cap == 0 || p.length <= cap)
      return base::deserialize(p);
    std::string type, md5;
    if (p.connection_header) {
      auto t = p.connection_header->find("type"), m = p.connection_header->find("md5sum");
      type = t != p.connection_header->end() ? t->second : "";
      md5 = m != p.connection_header->end() ? m->second : "";
    }
    refuse(*s_, type, md5,
           s_->sub.getTopic() + ": oversized: a " + type + " of " + std::to_string(p.length) +
               " bytes, above the cap of " + std::to_string(cap) +
               " bytes (the audio ring's samples in this format; a longer chunk can never be used)",
           true);
    return ros::VoidConstPtr();
  }

private:
  audio_sub *s_;
};

// Type, md5 and (when sent) definition of m against one expected message.
// "" when they match; else why not.
std::string check_type(const topic_tools::ShapeShifter &m, const char *type, const char *md5,
                       const char *definition)
{
  if (m.getDataType() != type || m.getMD5Sum() != md5)
    return "";
  if (!m.getMessageDefinition().empty() &&
      !af_audio_definition_matches(m.getMessageDefinition().c_str(), definition))
    return std::string("its definition differs from ") + type + "'s: '" +
           fields_of(m.getMessageDefinition()) + "'";
  return "ok";
}

void on_message(audio_sub &s, const Event &ev)
{
  const topic_tools::ShapeShifter &m = *ev.getConstMessage();
  s.buf.resize(m.size());
  ros::serialization::OStream out(s.buf.data(), static_cast<uint32_t>(s.buf.size()));
  m.write(out);
  reader rd(s.buf.data(), s.buf.size());
  const std::string topic = s.sub.getTopic();
  if (s.info) {
    std::string t = check_type(m, AF_AUDIO_INFO_TYPE, AF_AUDIO_INFO_MD5, AF_AUDIO_INFO_DEFINITION);
    if (t != "ok")
      return refuse(s, m,
                    t.empty() ? topic + " carries " + m.getDataType() + " (md5 " + m.getMD5Sum() +
                                    "), not " AF_AUDIO_INFO_TYPE " (md5 " + AF_AUDIO_INFO_MD5 ")"
                              : topic + ": " + t);
    af_audio_info c{};
    if (!rd.u8(c.channels) || !rd.u32(c.sample_rate_hz) || !rd.string(c.sample_format) ||
        !rd.u32(c.bitrate_bit_s) || !rd.string(c.coding_format) || rd.left() != 0)
      return refuse(s, m,
                    topic + ": a malformed AudioInfo of " + std::to_string(m.size()) + " bytes");
    s.info_fn(&c, s.user);
    return;
  }
  std::string plain =
      check_type(m, AF_AUDIO_DATA_TYPE, AF_AUDIO_DATA_MD5, AF_AUDIO_DATA_DEFINITION);
  std::string stamped = check_type(m, AF_AUDIO_DATA_STAMPED_TYPE, AF_AUDIO_DATA_STAMPED_MD5,
                                   AF_AUDIO_DATA_STAMPED_DEFINITION);
  if (plain != "ok" && stamped != "ok")
    return refuse(s, m,
                  !plain.empty() || !stamped.empty()
                      ? topic + ": " + plain + stamped
                      : topic + " carries " + m.getDataType() + " (md5 " + m.getMD5Sum() +
                            "), not " AF_AUDIO_DATA_STAMPED_TYPE " (md5 " AF_AUDIO_DATA_STAMPED_MD5
                            ") or " AF_AUDIO_DATA_TYPE " (md5 " AF_AUDIO_DATA_MD5 ")");
  af_audio_data c{};
  c.stamped = stamped == "ok";
  c.definition_sent = !m.getMessageDefinition().empty();
  af_shim::from_ros(ev.getReceiptTime(), c.receipt);
  bool ok = true;
  if (c.stamped) {
    uint32_t seq;
    ok = rd.u32(seq) && rd.u32(c.header.stamp.sec) && rd.u32(c.header.stamp.nsec) &&
         rd.string(c.header.frame_id);
  }
  ok = ok && rd.bytes(c.data, c.n_bytes) && rd.left() == 0;
  if (!ok)
    return refuse(s, m,
                  topic + ": a malformed " + m.getDataType() + " of " + std::to_string(m.size()) +
                      " bytes (a length beyond the message)");
  s.data_fn(&c, s.user);
}

af_status subscribe(af_ros *r, const char *topic, unsigned queue, std::shared_ptr<audio_sub> s)
{
  ros::SubscribeOptions ops;
  audio_sub *sp = s.get();
  // Nothing may escape into roscpp's queue (af_ros_spin_once would fail).
  auto cb = [sp](const Event &ev) {
    try {
      on_message(*sp, ev);
    } catch (...) {
      af_shim::status_from_exception(sp->owner);
    }
  };
  ops.initByFullCallbackType<const Event &>(topic, queue, cb);
  ops.helper = boost::make_shared<capped_helper>(cb, sp);
  s->sub = r->nh->subscribe(ops);
  if (!s->sub)
    return af_shim::invalid(r, std::string("could not subscribe to ") + topic);
  r->extras.push_back(s);
  return AF_OK;
}

} // namespace

extern "C" {

bool af_audio_definition_matches(const char *sent, const char *expected)
{
  return sent != nullptr && expected != nullptr && fields_of(sent) == fields_of(expected);
}

af_status af_ros_subscribe_audio(af_ros *r, const char *topic, unsigned queue, af_audio_data_fn fn,
                                 af_audio_refused_fn refused, const size_t *max_bytes, void *user)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_subscribe_audio: r is NULL");
    if (topic == nullptr || topic[0] == '\0' || fn == nullptr || queue < 1)
      return af_shim::invalid(r, "af_ros_subscribe_audio: topic, fn or queue missing");
    auto s = std::make_shared<audio_sub>();
    s->owner = r, s->data_fn = fn, s->refused = refused, s->user = user;
    s->max_bytes = max_bytes;
    return subscribe(r, topic, queue, s);
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_subscribe_audio_info(af_ros *r, const char *topic, af_audio_info_fn fn,
                                      af_audio_refused_fn refused, void *user)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_subscribe_audio_info: r is NULL");
    if (topic == nullptr || topic[0] == '\0' || fn == nullptr)
      return af_shim::invalid(r, "af_ros_subscribe_audio_info: topic or fn missing");
    auto s = std::make_shared<audio_sub>();
    s->owner = r, s->info = true, s->info_fn = fn, s->refused = refused, s->user = user;
    return subscribe(r, topic, 10, s);
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

} // extern "C"
