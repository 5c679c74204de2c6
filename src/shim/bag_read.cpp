// bag_read.cpp — rosbag reading behind the C API of af_bag.h.
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include "af_bag.h"
#include "bag_pool.hpp"
#include "convert.hpp"
#include "errors.hpp"
#include "wire.hpp"

using namespace acoustic_firmness;

extern "C" {
struct af_bag_reader {
  // From the process's pool (bag_pool.hpp): a new rosbag::Bag loads the
  // encryptor plugin, most of the cost of opening a small bag.
  rosbag::Bag *bag = nullptr;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  std::string topic, last_error;
  // The SignalChunk being read: kept until the next call (its arrays are
  // borrowed), deserialized from raw into the same object each time (its
  // data vector keeps its capacity: no allocation per chunk).
  SignalChunk chunk;
  std::vector<uint8_t> raw; // a SignalChunk's bytes, checked before deserializing
  std::map<std::string, size_t> counts;
  std::size_t max_samples = 0; // af_bag_reader_limit; 0: none
  bool listed = false;         // opened with topics: another type on one is refused
};
} // extern "C"

namespace
{

// The error of the last reader-less call (af_bag_open_read) of this thread:
// firmness_report opens bags on several threads at once.
thread_local std::string g_reader_error;

void set_error(af_bag_reader *r, const std::string &msg)
{
  af_shim::save_error(r != nullptr ? r->last_error : g_reader_error, msg);
}

// Called inside a catch (...) block: af_shim::map_exception, with any other
// std::exception (rosbag's file errors, a message that does not
// deserialize) as AF_EIO.
af_status reader_status(af_bag_reader *r) noexcept
{
  auto record = [r](const std::string &msg) { set_error(r, msg); };
  return af_shim::map_exception(record, [&](const std::exception &e) {
    if (dynamic_cast<const ros::serialization::StreamOverrunException *>(&e) != nullptr)
      record(std::string("message does not deserialize: ") + e.what());
    else
      record(e.what());
    return AF_EIO;
  });
}

// The ROS data types this reader converts: their C type and the md5sum of
// their definition as built here.
struct known_type {
  af_msg_type type;
  const char *md5sum;
};

const std::map<std::string, known_type> &known_types()
{
  static const std::map<std::string, known_type> known = {
      {ros::message_traits::datatype<SignalChunk>(),
       {AF_MSG_SIGNAL_CHUNK, ros::message_traits::md5sum<SignalChunk>()}},
      {ros::message_traits::datatype<AppleEstimate>(),
       {AF_MSG_APPLE_ESTIMATE, ros::message_traits::md5sum<AppleEstimate>()}},
      {ros::message_traits::datatype<StrikeReport>(),
       {AF_MSG_STRIKE_REPORT, ros::message_traits::md5sum<StrikeReport>()}},
      {ros::message_traits::datatype<Reliability>(),
       {AF_MSG_RELIABILITY, ros::message_traits::md5sum<Reliability>()}},
  };
  return known;
}

// The C type of a ROS data type this reader converts; false for any other.
bool type_of(const std::string &datatype, af_msg_type &t)
{
  auto k = known_types().find(datatype);
  if (k == known_types().end())
    return false;
  t = k->second.type;
  return true;
}

// A connection of a listed topic whose type is one we read must carry its
// definition as built here: a bag of an older SignalChunk is refused at
// open, in one line, not message by message.
void check_definition(const rosbag::ConnectionInfo &c)
{
  auto t = known_types().find(c.datatype);
  if (t != known_types().end() && c.md5sum != t->second.md5sum)
    throw std::invalid_argument("topic " + c.topic + " has type " + c.datatype + " of md5sum " +
                                c.md5sum + ", not " + t->second.md5sum +
                                " as built here: recorded with another definition of the "
                                "message; read it with the package version that recorded it");
}

// Every listed topic must be in the bag with a type we read, of our
// definition (check_definition).
void check_topics(af_bag_reader *r, const char *const *topics, size_t n)
{
  rosbag::View all(*r->bag);
  std::map<std::string, std::string> types;
  for (const rosbag::ConnectionInfo *c : all.getConnections()) {
    types[c->topic] = c->datatype;
    for (size_t k = 0; k < n; k++)
      if (c->topic == topics[k])
        check_definition(*c);
  }
  for (const rosbag::MessageInstance &m : all)
    r->counts[m.getTopic()]++;
  for (size_t k = 0; k < n; k++) {
    auto t = types.find(topics[k]);
    af_msg_type ignored;
    if (t != types.end() && !type_of(t->second, ignored))
      throw std::invalid_argument(std::string("topic ") + topics[k] + " has type " + t->second +
                                  ", not one this tool reads");
  }
}

// A message refused, reading may go on: AF_ESIZE or AF_EINVAL with its line.
struct refused_message {
  af_status status;
  std::string why;
};

// Bytes of a SignalChunk besides its data: header, first_sample, rate,
// unit, the length prefix; a frame_id and unit of a few KiB at most.
constexpr std::size_t AF_CHUNK_OVERHEAD_BYTES = 8192;

// roscpp's deserializer sizes SignalChunk.data from its length prefix before
// it checks the bytes (wire.hpp): the message's own bytes are checked first,
// and its size against the cap before they are copied (a chunk longer than
// the ring can never be used; copying and deserializing it took three times
// its size).
//
// The bytes are first written into the room raw already has (a stream's
// chunks are of one length, so nearly always enough): rosbag's size() parses
// the record's header as write() does again, the most of a chunk's cost of
// reading. A longer message overruns the room before a byte is copied
// (OStream::advance checks first), and is then sized, checked against the
// cap and written as before; the room never reaches past the cap, so a
// message over it always takes that way.
bool write_into_room(af_bag_reader *r, const rosbag::MessageInstance &mi)
{
  std::size_t room = r->raw.capacity();
  if (r->max_samples > 0 && room > 4 * r->max_samples + AF_CHUNK_OVERHEAD_BYTES)
    room = 4 * r->max_samples + AF_CHUNK_OVERHEAD_BYTES;
  if (room == 0)
    return false;
  r->raw.resize(room);
  ros::serialization::OStream out(r->raw.data(), static_cast<uint32_t>(r->raw.size()));
  try {
    mi.write(out);
  } catch (const ros::serialization::StreamOverrunException &) {
    return false;
  }
  r->raw.resize(static_cast<std::size_t>(out.getData() - r->raw.data()));
  return true;
}

void check_chunk_bytes(af_bag_reader *r, const rosbag::MessageInstance &mi)
{
  if (!write_into_room(r, mi)) {
    const std::size_t size = mi.size();
    if (r->max_samples > 0 && size > 4 * r->max_samples + AF_CHUNK_OVERHEAD_BYTES)
      throw refused_message{AF_ESIZE, mi.getTopic() + ": a SignalChunk of " + std::to_string(size) +
                                          " bytes (about " + std::to_string(size / 4) +
                                          " samples), above the cap of " +
                                          std::to_string(r->max_samples) +
                                          " samples (the ring; a longer chunk can never be used)"};
    r->raw.resize(size);
    ros::serialization::OStream out(r->raw.data(), static_cast<uint32_t>(r->raw.size()));
    mi.write(out);
  }
  uint32_t samples;
  std::string why;
  switch (
      af_shim::signal_chunk_check(r->raw.data(), r->raw.size(), r->max_samples, &samples, &why)) {
  case af_shim::chunk_wire::ok: return;
  case af_shim::chunk_wire::oversized: throw refused_message{AF_ESIZE, mi.getTopic() + ": " + why};
  default:
    throw refused_message{AF_EINVAL, mi.getTopic() + ": " + why +
                                         ": not a SignalChunk as its connection says (a "
                                         "wrong message type on this topic, or cut)"};
  }
}

// A message whose connection's type or md5sum is not M's (a bag edited, or
// written with another definition), refused with its topic.
template <class M> rosbag::BagFormatException not_as_built(const rosbag::MessageInstance &mi)
{
  return rosbag::BagFormatException(
      "a message on " + mi.getTopic() + " of type " + mi.getDataType() + " (md5sum " +
      mi.getMD5Sum() + ") does not match " + ros::message_traits::datatype<M>() + " as built here");
}

// rosbag's instantiate gives a null pointer when the connection is not M's:
// refused, never dereferenced (found by fuzz_bag.c).
template <class M> boost::shared_ptr<M> instantiate(const rosbag::MessageInstance &mi)
{
  boost::shared_ptr<M> m = mi.instantiate<M>();
  if (!m)
    throw not_as_built<M>(mi);
  return m;
}

// The SignalChunk whose bytes check_chunk_bytes left in r->raw, into
// r->chunk: the bytes already read and checked are deserialized, not read
// from the bag a second time (rosbag's instantiate parses the record's
// header again and allocates a new message). The connection's md5sum must
// be SignalChunk's as built here, as instantiate requires (its type was
// matched by type_of).
void read_chunk(af_bag_reader *r, const rosbag::MessageInstance &mi)
{
  if (mi.getMD5Sum() != ros::message_traits::md5sum<SignalChunk>())
    throw not_as_built<SignalChunk>(mi);
  ros::serialization::IStream in(r->raw.data(), static_cast<uint32_t>(r->raw.size()));
  ros::serialization::deserialize(in, r->chunk);
}

} // namespace

extern "C" {

af_status af_bag_open_read(const char *path, const char *const *topics, size_t n_topics,
                           af_bag_reader **out)
{
  if (out == nullptr || path == nullptr || path[0] == '\0' || (topics == nullptr && n_topics)) {
    set_error(nullptr, "af_bag_open_read: NULL or empty argument");
    return AF_EINVAL;
  }
  *out = nullptr;
  af_bag_reader *r = nullptr;
  try {
    // rosbag trusts the lengths the file states (wire.hpp): walk them first.
    std::string why;
    bool reindexable = false;
    if (!af_shim::bag_plausible(path, why, &reindexable)) {
      // One line naming the file once; the way out when there is one.
      set_error(nullptr, std::string(path) + ": not a readable bag: " + why +
                             (reindexable ? std::string("; if it was cut short or not closed, "
                                                        "`rosbag reindex ") +
                                                path + "` may recover it"
                                          : std::string()));
      return AF_EIO;
    }
    r = new af_bag_reader;
    r->bag = af_shim::bag_take();
    r->bag->open(path, rosbag::bagmode::Read);
    check_topics(r, topics, n_topics);
    if (n_topics > 0) {
      r->listed = true;
      std::vector<std::string> list(topics, topics + n_topics);
      r->view.reset(new rosbag::View(*r->bag, rosbag::TopicQuery(list)));
    } else {
      r->view.reset(new rosbag::View(*r->bag));
    }
    r->it = r->view->begin();
    *out = r;
    return AF_OK;
  } catch (...) {
    af_status s = reader_status(nullptr);
    set_error(nullptr,
              std::string(path) + (s == AF_EIO ? ": not a readable bag: " : ": ") + g_reader_error);
    if (r != nullptr) {
      r->view.reset();
      af_shim::bag_give(r->bag);
    }
    delete r;
    return s;
  }
}

af_status af_bag_read_text(const char *path, const char *topic, char *buf, size_t len, bool *found)
{
  if (path == nullptr || topic == nullptr || buf == nullptr || len == 0 || found == nullptr) {
    set_error(nullptr, "af_bag_read_text: NULL or empty argument");
    return AF_EINVAL;
  }
  *found = false;
  rosbag::Bag *bag = nullptr;
  try {
    std::string why;
    bool reindexable = false;
    if (!af_shim::bag_plausible(path, why, &reindexable)) {
      set_error(nullptr, std::string(path) + ": not a readable bag: " + why);
      return AF_EIO;
    }
    bag = af_shim::bag_take();
    bag->open(path, rosbag::bagmode::Read);
    af_status st = AF_OK;
    {
      rosbag::View view(*bag, rosbag::TopicQuery(std::string(topic)));
      for (const rosbag::MessageInstance &mi : view) {
        std_msgs::String::ConstPtr text = mi.instantiate<std_msgs::String>();
        if (!text) {
          set_error(nullptr, std::string(path) + ": " + topic + " has type " + mi.getDataType() +
                                 ", not std_msgs/String");
          st = AF_EINVAL;
        } else if (text->data.size() >= len) {
          set_error(nullptr, std::string(path) + ": " + topic + ": a text of " +
                                 std::to_string(text->data.size()) + " bytes, more than " +
                                 std::to_string(len - 1));
          st = AF_ESIZE;
        } else {
          std::memcpy(buf, text->data.c_str(), text->data.size() + 1);
          *found = true;
        }
        break;
      }
    }
    af_shim::bag_give(bag);
    return st;
  } catch (...) {
    af_status s = reader_status(nullptr);
    set_error(nullptr,
              std::string(path) + (s == AF_EIO ? ": not a readable bag: " : ": ") + g_reader_error);
    if (bag != nullptr)
      af_shim::bag_give(bag);
    return s;
  }
}

af_status af_bag_read_next(af_bag_reader *r, af_bag_message *m)
{
  if (r == nullptr || m == nullptr) {
    set_error(r, "af_bag_read_next: NULL argument");
    return AF_EINVAL;
  }
  try {
    while (r->it != r->view->end()) {
      const rosbag::MessageInstance &mi = *r->it;
      af_msg_type t;
      r->topic = mi.getTopic();
      m->topic = r->topic.c_str();
      af_shim::from_ros(mi.getTime(), m->bag_time);
      const bool known = type_of(mi.getDataType(), t);
      if (!known && !r->listed) {
        ++r->it;
        continue;
      }
      if (!known) {
        ++r->it;
        set_error(r, r->topic + ": a message of type " + mi.getDataType() +
                         ", a wrong message type on this topic");
        return AF_EINVAL;
      }
      m->type = t;
      switch (t) {
      case AF_MSG_SIGNAL_CHUNK: try { check_chunk_bytes(r, mi);
        } catch (const refused_message &no) {
          ++r->it;
          set_error(r, no.why);
          return no.status;
        }
        read_chunk(r, mi);
        af_shim::from_ros(r->chunk, m->msg.chunk);
        break;
      case AF_MSG_APPLE_ESTIMATE:
        af_shim::from_ros(*instantiate<AppleEstimate>(mi), m->msg.apple);
        break;
      case AF_MSG_STRIKE_REPORT:
        af_shim::from_ros(*instantiate<StrikeReport>(mi), m->msg.report);
        break;
      default: af_shim::from_ros(*instantiate<Reliability>(mi), m->msg.reliability); break;
      }
      ++r->it;
      return AF_OK;
    }
    return AF_ENODATA;
  } catch (...) {
    return reader_status(r);
  }
}

void af_bag_reader_limit(af_bag_reader *r, size_t max_samples)
{
  if (r != nullptr)
    r->max_samples = max_samples;
}

size_t af_bag_topic_count(const af_bag_reader *r, const char *topic)
{
  if (r == nullptr || topic == nullptr)
    return 0;
  auto k = r->counts.find(topic);
  return k == r->counts.end() ? 0 : k->second;
}

void af_bag_close_read(af_bag_reader *r)
{
  if (r == nullptr)
    return;
  try {
    r->view.reset();
  } catch (...) {
    (void)reader_status(r);
  }
  af_shim::bag_give(r->bag);
  delete r;
}

const char *af_bag_reader_error(const af_bag_reader *r)
{
  return r != nullptr ? r->last_error.c_str() : g_reader_error.c_str();
}

} // extern "C"
